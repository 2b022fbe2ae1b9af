// The output plan of a clvis run (output_plan.hpp): names checked before rendering, temporaries
// beside their files, renamed together at the end or removed.
#include "output_plan.hpp"

#include <clvis/clvis.hpp>
#if CLVIS_WITH_IMAGE_IO
#include <clvis/image_io.hpp>
#endif

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace clvis::cli {

namespace {

[[noreturn]] void refuse(const std::string& why) { throw Error(Error::Kind::InvalidArgument, why); }

std::vector<std::string> extensions_of(const std::string& flag, OutputKind kind)
{
    switch (kind) {
    case OutputKind::Text: return {"txt"};
    case OutputKind::RayAnswers: return {"npy", "bin", "raw"};
    default: break;
    }
#if CLVIS_WITH_IMAGE_IO
    (void)flag;
    switch (kind) {
    case OutputKind::Ids: return id_extensions();
    case OutputKind::Depth: return depth_extensions();
    case OutputKind::Floats: return {"exr"};
    default: return image_extensions();
    }
#else
    refuse(flag + ": this clvis was built without OpenImageIO (CLVIS_WITH_IMAGE_IO=OFF)");
#endif
}

std::string listed(const std::vector<std::string>& extensions)
{
    std::string s;
    for (const auto& e : extensions) s += (s.empty() ? "." : ", .") + e;
    return s;
}

/// Where the extension of `file` starts (its dot), or npos.
std::size_t extension_at(const std::string& file)
{
    auto dot = file.find_last_of('.');
    auto slash = file.find_last_of('/');
    if (dot == std::string::npos || dot == 0 || (slash != std::string::npos && dot <= slash + 1))
        return std::string::npos;
    return dot;
}

} // namespace

std::string with_suffix(const std::string& file, const std::string& suffix)
{
    auto dot = extension_at(file);
    if (dot == std::string::npos) return file + "-" + suffix;
    return file.substr(0, dot) + "-" + suffix + file.substr(dot);
}

std::string extension_of(const std::string& file)
{
    auto dot = extension_at(file);
    if (dot == std::string::npos) return "";
    std::string e = file.substr(dot + 1);
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

OutputPlan::~OutputPlan() { discard(); }

void OutputPlan::add(const std::string& flag, const std::string& file, OutputKind kind)
{
    std::vector<std::string> allowed = extensions_of(flag, kind);
    if (std::find(allowed.begin(), allowed.end(), extension_of(file)) == allowed.end())
        refuse(flag + ": cannot write '" + file + "': the formats written are " + listed(allowed));
    namespace fs = std::filesystem;
    fs::path folder = fs::path(file).parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        refuse(flag + ": cannot write '" + file + "': no folder " + folder.string());
    if (::access(folder.c_str(), W_OK) != 0)
        refuse(flag + ": cannot write '" + file + "': the folder " + folder.string() + " is not writable");
    if (fs::is_directory(file, ec)) refuse(flag + ": cannot write '" + file + "': it is a folder");
    std::string canonical = fs::weakly_canonical(fs::absolute(file, ec), ec).string();
    if (auto [it, fresh] = canonical_.emplace(canonical, flag); !fresh)
        refuse(flag + ": '" + file + "' is also the file of " + it->second + "; give each output its own name");
    auto dot = std::min(extension_at(file), file.size());
    std::string tmp = ".tmp-" + std::to_string(::getpid());
    files_.push_back({flag, file, file.substr(0, dot) + tmp + file.substr(dot)});
}

void OutputPlan::need_view_key(const std::string& flag, const std::string& file, int count, const std::string& why)
{
    if (count > 1 && !file.empty() && file.find("{view}") == std::string::npos)
        refuse(flag + ": '" + file + "' would be written " + std::to_string(count) + " times (" + why +
               "); put {view} in the name");
}

const std::string& OutputPlan::temporary(const std::string& file) const
{
    for (const Entry& e : files_)
        if (e.file == file) return e.temporary;
    throw std::logic_error("output plan: '" + file + "' was not named before rendering");
}

std::vector<std::string> OutputPlan::commit()
{
    std::vector<std::string> done;
    for (const Entry& e : files_) {
        if (std::rename(e.temporary.c_str(), e.file.c_str()) != 0) {
            // Those renamed stay (the run is all but done); the rest are removed by discard().
            std::string why = e.flag + ": cannot rename " + e.temporary + " to " + e.file;
            files_.erase(files_.begin(), files_.begin() + std::ptrdiff_t(done.size()));
            throw Error(Error::Kind::Io, why);
        }
        done.push_back(e.file);
    }
    committed_ = true;
    return done;
}

void OutputPlan::discard()
{
    if (committed_) return;
    for (const Entry& e : files_) std::remove(e.temporary.c_str());
}

int mpi_world_size_from_environment()
{
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) { // Open MPI; MPICH's Hydra
        const char* v = std::getenv(name);
        if (v && *v) return std::max(1, std::atoi(v));
    }
    return 1;
}

} // namespace clvis::cli
