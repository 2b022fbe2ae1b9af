// The on-disk program cache (see program_cache.hpp).
#include "runtime/program_cache.hpp"

#include "runtime/cache_dir.hpp"

#include <fstream>
#include <iterator>
#include <vector>

namespace clvis::detail {


ProgramCache::ProgramCache(const std::string& name, const std::string& key, bool driver_caches)
    : driver_caches_(driver_caches)
{
    std::filesystem::path dir = cache_dir();
    if (!dir.empty()) binary_ = dir / (name + "-" + key + ".bin");
}

std::optional<cl::Program> ProgramCache::load(const cl::Context& context, const cl::Device& device,
                                              const std::string& options) const
{
    if (binary_.empty()) return std::nullopt;
    std::ifstream in(binary_, std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), {});
    try {
        cl::Program program(context, {device}, cl::Program::Binaries{bytes});
        program.build({device}, options.c_str());
        return program;
    } catch (const cl::Error&) {
        return std::nullopt; // a stale, truncated or foreign binary: the caller builds from source
    }
}

void ProgramCache::built(const cl::Program& program) const
{
    if (binary_.empty()) return;
    if (driver_caches_) {
        std::filesystem::path seen = binary_;
        seen.replace_extension(".seen");
        std::error_code ec;
        if (!std::filesystem::exists(seen, ec)) {
            write_cache_file(seen, nullptr, 0);
            return;
        }
    }
    try {
        auto binaries = program.getInfo<CL_PROGRAM_BINARIES>();
        if (!binaries.empty() && !binaries[0].empty()) write_cache_file(binary_, binaries[0].data(), binaries[0].size());
    } catch (const cl::Error&) {
        // The cache is an optimisation: a driver that will not hand out its binary builds from
        // source next time.
    }
}

} // namespace clvis::detail
