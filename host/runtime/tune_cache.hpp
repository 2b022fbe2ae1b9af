// A choice between equivalent ways to run a kernel (a mapping of work onto work-items), made per
// device by measurement and kept on disk: the first time a key (device, driver, kernel sources,
// the options that matter) is met, every candidate is measured and the fastest kept in the cache
// folder (cache_dir.hpp); later runs read it. Used by render/raster_tune.cpp and render/ray_tune.cpp.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace clvis::detail {

/// Where a tuned choice came from.
enum class TuneSource {
    Cache,    ///< a measurement kept on disk (or earlier in this process, without a cache folder)
    Measured, ///< measured now
    Forced,   ///< named by CLVIS_TUNE_<NAME>, nothing measured
};

const char* to_string(TuneSource source) noexcept;

struct TuneTime {
    std::string candidate;
    double ms = 0; ///< the candidate's best time on the workload (lower is better)
};

struct TuneResult {
    std::string choice; ///< one of the request's candidates
    TuneSource source = TuneSource::Measured;
    std::vector<TuneTime> times; ///< every candidate's, as measured (now or when cached); empty when forced
};

/// What a choice depends on: (field, value) pairs, e.g. ("device", "NVIDIA H200"). Fields are one
/// word; line breaks in values are replaced by spaces.
using TuneKey = std::vector<std::pair<std::string, std::string>>;

struct TuneRequest {
    std::string name;                    ///< the choice, [a-z0-9_]: "raster_mapping"
    TuneKey key;
    std::vector<std::string> candidates; ///< at least one
    /// The time of one candidate on a deterministic workload, in ms. Errors pass through tune().
    std::function<double(const std::string& candidate)> measure;
};

struct TuneSettings {
    std::filesystem::path dir; ///< the cache folder; empty: results are kept for this process only
    bool use_cache = true;     ///< false: measure every time, read and write nothing
    std::string forced;        ///< a candidate taken without measuring; empty: none

    /// CLVIS_TUNE_CACHE (0: measure every time, 1 or unset: use the cache), cache_dir(), and
    /// CLVIS_TUNE_<NAME> (the name upper-cased) forcing a candidate. Throws Error(InvalidArgument)
    /// naming the variable for any other value.
    static TuneSettings from_environment(const TuneRequest& request);
};

/// The request's choice: forced, else cached under its key, else measured (every candidate in
/// order, the fastest wins, ties to the first) and stored, written to a temporary file and renamed
/// so that readers never see half a file. A cache file that cannot be read, is malformed, or names
/// another key or an unknown candidate counts as absent and is rewritten; one that cannot be
/// written is left alone (the cache is an optimisation). Calls are serialised in the process, so
/// that two renderers never measure at once. Throws Error(InvalidArgument) for a forced value that
/// is not a candidate, or a request without a name of [a-z0-9_], candidates of one word, key
/// fields of one word or a measure.
TuneResult tune(const TuneRequest& request, const TuneSettings& settings);

/// FNV-1a (64 bits) of `text` as 16 hex digits: the same from every build and machine (std::hash
/// is not), for key values such as a hash of kernel sources.
std::string stable_hash(const std::string& text);

/// The file of `name` under `key` in `dir`: tune-<name>-<hash of the key>.txt.
std::filesystem::path tune_file(const std::filesystem::path& dir, const std::string& name, const TuneKey& key);

struct TuneEntry {
    std::string name;
    TuneKey key;
    TuneResult result; ///< source Cache
};

/// Every well-formed tuned choice kept in `dir` (none when it does not exist), by file name.
std::vector<TuneEntry> cached_tunings(const std::filesystem::path& dir);

} // namespace clvis::detail
