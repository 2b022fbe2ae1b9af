// The tuner (runtime/tune_cache.hpp) with a stand-in measurement: a choice is measured once per
// key and read back from its file, a damaged file is measured again and rewritten, the cache can
// be turned off and a choice forced, and an unwritable cache folder costs only the cache.
#include "catch.hpp"
#include "test_files.hpp"

#include "runtime/tune_cache.hpp"

#include <clvis/error.hpp>

#include <fstream>
#include <map>
#include <string>

using namespace clvis;
using namespace clvis::detail;

namespace {

/// A request over candidates "slow" (2 ms) and "fast" (1 ms) keyed by `tile`, counting measurements.
struct Counted {
    int calls = 0;
    std::map<std::string, double> ms{{"slow", 2.0}, {"fast", 1.0}};
    TuneRequest request(const std::string& tile)
    {
        TuneRequest r;
        r.name = "test_mapping";
        r.key = {{"device", "Test Device"}, {"tile", tile}};
        r.candidates = {"slow", "fast"};
        r.measure = [this](const std::string& c) {
            ++calls;
            return ms.at(c);
        };
        return r;
    }
};

TuneSettings in(const std::filesystem::path& dir)
{
    TuneSettings s;
    s.dir = dir;
    return s;
}

std::string read_all(const std::filesystem::path& file)
{
    std::ifstream f(file);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

} // namespace

TEST_CASE("a tuned choice is measured once, then read back from its file")
{
    auto dir = test::fresh_temp_dir("clvis-tune-roundtrip");
    Counted c;
    TuneResult first = tune(c.request("16"), in(dir));
    CHECK(first.source == TuneSource::Measured);
    CHECK(first.choice == "fast");
    REQUIRE(first.times.size() == 2);
    CHECK(first.times[0].candidate == "slow");
    CHECK(first.times[0].ms == 2.0);
    CHECK(c.calls == 2);
    CHECK(std::filesystem::exists(tune_file(dir, "test_mapping", c.request("16").key)));
    c.ms = {{"slow", 0.5}, {"fast", 1.0}}; // would change the choice, were it measured again
    TuneResult again = tune(c.request("16"), in(dir));
    CHECK(again.source == TuneSource::Cache);
    CHECK(again.choice == "fast");
    REQUIRE(again.times.size() == 2);
    CHECK(again.times[1].ms == 1.0);
    CHECK(c.calls == 2);
    auto listed = cached_tunings(dir);
    REQUIRE(listed.size() == 1);
    CHECK(listed[0].name == "test_mapping");
    CHECK(listed[0].key == c.request("16").key);
    CHECK(listed[0].result.choice == "fast");
}

TEST_CASE("a tuned choice under another key is measured again")
{
    auto dir = test::fresh_temp_dir("clvis-tune-keys");
    Counted c;
    tune(c.request("16"), in(dir));
    c.ms = {{"slow", 0.5}, {"fast", 1.0}};
    TuneResult other = tune(c.request("8"), in(dir));
    CHECK(other.source == TuneSource::Measured);
    CHECK(other.choice == "slow");
    CHECK(c.calls == 4);
    CHECK(tune(c.request("16"), in(dir)).choice == "fast");
    CHECK(cached_tunings(dir).size() == 2);
}

TEST_CASE("a damaged or foreign tune file is measured again and rewritten")
{
    auto dir = test::fresh_temp_dir("clvis-tune-corrupt");
    Counted c;
    std::filesystem::path file = tune_file(dir, "test_mapping", c.request("16").key);
    tune(c.request("16"), in(dir));
    const std::string good = read_all(file);
    std::string other_key = good, unknown = good, bad_time = good;
    other_key.replace(other_key.find("tile 16"), 7, "tile 32");
    unknown.replace(unknown.find("choice fast"), 11, "choice warp");
    bad_time.replace(bad_time.find("time fast 1"), 11, "time fast x");
    for (const std::string& bytes : {std::string(), std::string("\x01\xff garbage\n"), good.substr(0, good.size() / 2),
                                     good.substr(0, good.find("choice")), other_key, unknown, bad_time}) {
        INFO("file: " << bytes);
        std::ofstream(file, std::ios::trunc) << bytes;
        int before = c.calls;
        TuneResult r = tune(c.request("16"), in(dir));
        CHECK(r.source == TuneSource::Measured);
        CHECK(r.choice == "fast");
        CHECK(c.calls == before + 2);
        CHECK(read_all(file) == good);
        CHECK(tune(c.request("16"), in(dir)).source == TuneSource::Cache);
    }
    std::filesystem::remove(file);
    std::filesystem::create_directories(file); // a folder where the file should be: unreadable
    CHECK(tune(c.request("16"), in(dir)).source == TuneSource::Measured);
}

TEST_CASE("the tuner measures every time with the cache off, and nothing with a forced choice")
{
    auto dir = test::fresh_temp_dir("clvis-tune-off");
    Counted c;
    TuneSettings off = in(dir);
    off.use_cache = false;
    CHECK(tune(c.request("16"), off).source == TuneSource::Measured);
    CHECK(tune(c.request("16"), off).source == TuneSource::Measured);
    CHECK(c.calls == 4);
    CHECK(cached_tunings(dir).empty());
    TuneSettings forced = in(dir);
    forced.forced = "slow";
    TuneResult r = tune(c.request("16"), forced);
    CHECK(r.source == TuneSource::Forced);
    CHECK(r.choice == "slow");
    CHECK(r.times.empty());
    CHECK(c.calls == 4);
    forced.forced = "warp";
    CHECK_THROWS_AS(tune(c.request("16"), forced), Error);
}

TEST_CASE("the tuner keeps choices in the process when the cache folder is unusable")
{
    Counted c;
    // No folder: measured once, then kept for the process.
    CHECK(tune(c.request("no-folder"), in({})).source == TuneSource::Measured);
    CHECK(tune(c.request("no-folder"), in({})).source == TuneSource::Cache);
    CHECK(c.calls == 2);
    // A file where the folder should be: nothing can be written, every call measures, none fails.
    auto parent = test::fresh_temp_dir("clvis-tune-unwritable");
    std::ofstream(parent / "not-a-folder") << "x";
    CHECK(tune(c.request("16"), in(parent / "not-a-folder")).choice == "fast");
    CHECK(tune(c.request("16"), in(parent / "not-a-folder")).source == TuneSource::Measured);
}

TEST_CASE("the tuner reads its switches from the environment")
{
    Counted c;
    TuneRequest r = c.request("16");
    {
        test::ScopedEnv cache("CLVIS_TUNE_CACHE", nullptr), force("CLVIS_TUNE_TEST_MAPPING", nullptr),
            dir("CLVIS_CACHE_DIR", "/tmp/clvis-tune-env");
        TuneSettings s = TuneSettings::from_environment(r);
        CHECK(s.use_cache);
        CHECK(s.forced.empty());
        CHECK(s.dir == "/tmp/clvis-tune-env");
    }
    {
        test::ScopedEnv cache("CLVIS_TUNE_CACHE", "0"), force("CLVIS_TUNE_TEST_MAPPING", "slow");
        TuneSettings s = TuneSettings::from_environment(r);
        CHECK(!s.use_cache);
        CHECK(s.forced == "slow");
    }
    {
        test::ScopedEnv force("CLVIS_TUNE_TEST_MAPPING", "warp");
        CHECK_THROWS_WITH(TuneSettings::from_environment(r), Catch::Contains("CLVIS_TUNE_TEST_MAPPING") &&
                                                                 Catch::Contains("slow, fast"));
    }
    {
        test::ScopedEnv cache("CLVIS_TUNE_CACHE", "off");
        CHECK_THROWS_WITH(TuneSettings::from_environment(r), Catch::Contains("CLVIS_TUNE_CACHE"));
    }
}

TEST_CASE("the tuner refuses requests its files cannot hold")
{
    Counted c;
    TuneRequest bad = c.request("16");
    bad.name = "Raster Mapping";
    CHECK_THROWS_AS(tune(bad, {}), Error);
    bad = c.request("16");
    bad.candidates = {"two words"};
    CHECK_THROWS_WITH(tune(bad, {}), Catch::Contains("'two words'"));
    bad = c.request("16");
    bad.key.emplace_back("tile size", "16");
    CHECK_THROWS_WITH(tune(bad, {}), Catch::Contains("'tile size'"));
    CHECK(c.calls == 0);
}

TEST_CASE("the tuner takes the first of equally fast candidates")
{
    auto dir = test::fresh_temp_dir("clvis-tune-ties");
    Counted c;
    c.ms = {{"slow", 1.0}, {"fast", 1.0}};
    CHECK(tune(c.request("16"), in(dir)).choice == "slow");
}
