// Every file one clvis run writes (CONVENTIONS.md "Output files"): named up front ({view} and the
// -raster/-ray suffixes resolved), checked before anything is rendered (format by extension,
// folder, one name per file), written under temporary names in the same folder and renamed only
// when the whole run succeeded; a run that fails leaves no new file behind.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace clvis::cli {

/// The kinds of output file and the extensions (lowercase, no dot) each takes.
enum class OutputKind {
    Ids,        ///< id buffers (image layer: id_extensions())
    Depth,      ///< depth buffers (depth_extensions())
    Floats,     ///< float channels: barycentrics, normals, positions (.exr)
    Image,      ///< colour images (image_extensions())
    Text,       ///< --visible: one id per line (.txt)
    RayAnswers, ///< clvis rays --hits: .npy, or raw records as .bin or .raw
};

/// "out.png" -> "out-ray.png" (the suffix before the extension; appended where there is none).
std::string with_suffix(const std::string& file, const std::string& suffix);

/// The extension of `file`, lowercase, without the dot ("" when none).
std::string extension_of(const std::string& file);

/// The run's files. Add every file before rendering (each add checks it), write each through
/// temporary(), then commit(). Destroyed without commit() (an error, an exception), it removes
/// every temporary it named.
class OutputPlan {
public:
    OutputPlan() = default;
    OutputPlan(const OutputPlan&) = delete;
    OutputPlan& operator=(const OutputPlan&) = delete;
    ~OutputPlan();

    /// Adds `file` for `flag` (named in every error): Error(InvalidArgument) when its extension
    /// is not one `kind` writes, when its folder does not exist or is not writable, or when
    /// another output has the same name.
    void add(const std::string& flag, const std::string& file, OutputKind kind);
    /// Refuses (Error(InvalidArgument), naming `flag` and --views or `spread`) a name without
    /// "{view}" when `count` > 1 files come from it.
    static void need_view_key(const std::string& flag, const std::string& file, int count, const std::string& why);

    /// The name to write `file` (as added) under until commit(): same folder, ".tmp-PID" before
    /// the extension, so that writers still pick the format by extension.
    const std::string& temporary(const std::string& file) const;
    /// Renames every temporary to its file (Error(Io) naming the file when one fails; the
    /// temporaries not yet renamed are removed). Returns the files, in the order added.
    std::vector<std::string> commit();
    /// Removes every temporary now (also what the destructor does).
    void discard();

    bool empty() const { return files_.empty(); }

private:
    struct Entry {
        std::string flag, file, temporary;
    };
    std::vector<Entry> files_;
    std::map<std::string, std::string> canonical_; ///< each file's canonical path -> its flag
    bool committed_ = false;
};

/// The number of processes mpirun (Open MPI, MPICH, PMIx) started this one among, from the
/// environment, without initialising MPI: 1 outside mpirun.
int mpi_world_size_from_environment();

} // namespace clvis::cli
