// The tuner (tune_cache.hpp): forced, cached or measured choices, and their files. A file holds
// one choice as lines of text: "clvis-tune 1", "name N", "key FIELD VALUE" per key field,
// "choice C", then "time C MS" per measured candidate.
#include "runtime/tune_cache.hpp"

#include "runtime/cache_dir.hpp"

#include <clvis/device.hpp>
#include <clvis/error.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>

namespace clvis::detail {

namespace {

constexpr const char* file_magic = "clvis-tune 1";

std::string one_line(std::string s)
{
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    return s;
}

/// The key as it is hashed and compared: "field value" lines.
std::string key_text(const TuneKey& key)
{
    std::string text;
    for (const auto& [field, value] : key) text += one_line(field) + " " + one_line(value) + "\n";
    return text;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

/// A file's entry, or nothing when it is unreadable or malformed in any way.
std::optional<TuneEntry> read_entry(const std::filesystem::path& file)
{
    std::ifstream in(file);
    std::string line;
    if (!in || !std::getline(in, line) || line != file_magic) return std::nullopt;
    TuneEntry e;
    e.result.source = TuneSource::Cache;
    if (!std::getline(in, line) || !starts_with(line, "name ")) return std::nullopt;
    e.name = line.substr(5);
    while (std::getline(in, line)) {
        if (starts_with(line, "key ")) {
            auto space = line.find(' ', 4);
            if (space == std::string::npos || !e.result.choice.empty()) return std::nullopt;
            e.key.emplace_back(line.substr(4, space - 4), line.substr(space + 1));
        } else if (starts_with(line, "choice ") && e.result.choice.empty()) {
            e.result.choice = line.substr(7);
        } else if (starts_with(line, "time ") && !e.result.choice.empty()) {
            std::istringstream fields(line.substr(5));
            TuneTime t;
            if (!(fields >> t.candidate >> t.ms) || !(fields >> std::ws).eof()) return std::nullopt;
            e.result.times.push_back(t);
        } else {
            return std::nullopt;
        }
    }
    if (e.name.empty() || e.result.choice.empty()) return std::nullopt;
    return e;
}

bool is_candidate(const TuneRequest& request, const std::string& name)
{
    return std::find(request.candidates.begin(), request.candidates.end(), name) != request.candidates.end();
}

/// The cached choice for `request` in `file`, when the file is well formed and matches it.
std::optional<TuneResult> read_cached(const std::filesystem::path& file, const TuneRequest& request)
{
    std::optional<TuneEntry> e = read_entry(file);
    if (!e || e->name != request.name || key_text(e->key) != key_text(request.key) ||
        !is_candidate(request, e->result.choice))
        return std::nullopt;
    for (const TuneTime& t : e->result.times)
        if (!is_candidate(request, t.candidate)) return std::nullopt;
    return e->result;
}

/// Writes the choice to a temporary file beside `file` and renames it over `file`; a failure
/// leaves the cache as it was.
void write_cached(const std::filesystem::path& file, const TuneRequest& request, const TuneResult& result)
{
    std::ostringstream out;
    out << file_magic << "\nname " << request.name << "\n";
    for (const auto& [field, value] : request.key) out << "key " << one_line(field) << " " << one_line(value) << "\n";
    out << "choice " << result.choice << "\n";
    char ms[32];
    for (const TuneTime& t : result.times) {
        std::snprintf(ms, sizeof ms, "%.17g", t.ms);
        out << "time " << t.candidate << " " << ms << "\n";
    }
    const std::string text = out.str();
    write_cache_file(file, text.data(), text.size());
}

TuneResult measure_all(const TuneRequest& request)
{
    TuneResult r;
    r.source = TuneSource::Measured;
    for (const std::string& c : request.candidates) r.times.push_back({c, request.measure(c)});
    // The first of the fastest: min_element keeps the earliest of equal times.
    r.choice = std::min_element(r.times.begin(), r.times.end(), [](const TuneTime& a, const TuneTime& b) {
                   return a.ms < b.ms;
               })->candidate;
    return r;
}

void check_request(const TuneRequest& request)
{
    bool plain = !request.name.empty() && std::all_of(request.name.begin(), request.name.end(), [](unsigned char c) {
        return std::islower(c) || std::isdigit(c) || c == '_';
    });
    if (!plain || request.candidates.empty() || !request.measure)
        throw Error(Error::Kind::InvalidArgument, "tune: a request needs a name of [a-z0-9_], candidates and a measure");
    auto one_word = [](const std::string& w) { return !w.empty() && w.find_first_of(" \n\r") == std::string::npos; };
    for (const std::string& c : request.candidates)
        if (!one_word(c))
            throw Error(Error::Kind::InvalidArgument, "tune: candidate '" + c + "' of " + request.name + " is not one word");
    for (const auto& [field, value] : request.key)
        if (!one_word(field))
            throw Error(Error::Kind::InvalidArgument, "tune: key field '" + field + "' of " + request.name + " is not one word");
}

} // namespace

std::string stable_hash(const std::string& text)
{
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

const char* to_string(TuneSource source) noexcept
{
    switch (source) {
    case TuneSource::Cache: return "cache";
    case TuneSource::Measured: return "measured";
    case TuneSource::Forced: return "forced";
    }
    return "unknown";
}

TuneSettings TuneSettings::from_environment(const TuneRequest& request)
{
    TuneSettings s;
    s.dir = cache_dir();
    if (const char* v = std::getenv("CLVIS_TUNE_CACHE"); v && *v) {
        if (std::string(v) != "0" && std::string(v) != "1")
            throw Error(Error::Kind::InvalidArgument, std::string("CLVIS_TUNE_CACHE must be 0 or 1, got '") + v + "'");
        s.use_cache = std::string(v) == "1";
    }
    std::string variable = "CLVIS_TUNE_";
    for (unsigned char c : request.name) variable += char(std::toupper(c));
    if (const char* v = std::getenv(variable.c_str()); v && *v) {
        if (!is_candidate(request, v)) {
            std::string names;
            for (const std::string& c : request.candidates) names += (names.empty() ? "" : ", ") + c;
            throw Error(Error::Kind::InvalidArgument, variable + " must name one of " + names + ", got '" + v + "'");
        }
        s.forced = v;
    }
    return s;
}

std::filesystem::path tune_file(const std::filesystem::path& dir, const std::string& name, const TuneKey& key)
{
    return dir / ("tune-" + name + "-" + stable_hash(name + "\n" + key_text(key)) + ".txt");
}

TuneResult tune(const TuneRequest& request, const TuneSettings& settings)
{
    check_request(request);
    if (!settings.forced.empty()) {
        if (!is_candidate(request, settings.forced))
            throw Error(Error::Kind::InvalidArgument,
                        "tune: '" + settings.forced + "' is not a candidate of " + request.name);
        TuneResult r;
        r.choice = settings.forced;
        r.source = TuneSource::Forced;
        return r;
    }
    // One tuning at a time: measurements running side by side would time each other. Recursive:
    // a measurement may itself meet a choice to tune.
    static std::recursive_mutex mutex;
    static std::map<std::string, TuneResult> in_process; // without a cache folder
    std::lock_guard<std::recursive_mutex> lock(mutex);
    if (!settings.use_cache) return measure_all(request);
    std::string memo_key = request.name + "\n" + key_text(request.key);
    if (settings.dir.empty()) {
        if (auto it = in_process.find(memo_key); it != in_process.end()) return it->second;
        TuneResult r = measure_all(request);
        TuneResult kept = r;
        kept.source = TuneSource::Cache;
        in_process.emplace(memo_key, kept);
        return r;
    }
    std::filesystem::path file = tune_file(settings.dir, request.name, request.key);
    if (std::optional<TuneResult> cached = read_cached(file, request)) return *cached;
    TuneResult r = measure_all(request);
    write_cached(file, request, r);
    return r;
}

std::vector<TuneEntry> cached_tunings(const std::filesystem::path& dir)
{
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::string name = it->path().filename().string();
        if (starts_with(name, "tune-") && it->path().extension() == ".txt") files.push_back(it->path());
    }
    std::sort(files.begin(), files.end());
    std::vector<TuneEntry> entries;
    for (const auto& f : files)
        if (std::optional<TuneEntry> e = read_entry(f)) entries.push_back(std::move(*e));
    return entries;
}

} // namespace clvis::detail

namespace clvis {

std::vector<TunedChoice> tuned_choices(const DeviceInfo& device)
{
    std::vector<TunedChoice> found;
    std::filesystem::path dir = detail::cache_dir();
    if (dir.empty()) return found;
    for (detail::TuneEntry& e : detail::cached_tunings(dir)) {
        TunedChoice c{e.name, {}, e.result.choice, {}};
        int matched = 0;
        for (auto& [field, value] : e.key) {
            if (field == "device" || field == "platform" || field == "driver")
                matched += value == (field == "device" ? device.name : field == "platform" ? device.platform
                                                                                             : device.driver_version);
            else
                c.key.emplace_back(field, value);
        }
        for (const detail::TuneTime& t : e.result.times) c.times_ms.emplace_back(t.candidate, t.ms);
        if (matched == 3) found.push_back(std::move(c));
    }
    return found;
}

} // namespace clvis
