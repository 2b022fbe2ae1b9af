// Rasterization or ray casting (bench/bench_crossover.cpp): the raster/ray ratio, the BVH build
// amortised over frames, the answer in words, and the legend of every column of the bench table.
// Made-up medians: nothing is timed.
#include "catch.hpp"

#include "bench_crossover.hpp"

#include <string>

using namespace clvis::bench;

namespace {

Crossover medians(double raster, double ray, double build)
{
    Crossover c;
    c.raster_ms = raster;
    c.ray_ms = ray;
    c.build_ms = build;
    return c;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

} // namespace

TEST_CASE("Ray casting pays from the frame where its build is made up", "[bench]")
{
    // 4 ms raster, 3 ms ray, a 10 ms build: 10 + 3 N < 4 N from N = 11 on (N = 10 ties).
    Crossover c = medians(4, 3, 10);
    CHECK(c.raster_over_ray() == Approx(4.0 / 3));
    CHECK(c.build_in_raster_frames() == Approx(2.5));
    CHECK(c.ray_pays_from() == 11);
    CHECK(pays_cell(c) == "from 11");
    CHECK(std::string(pays_word(c)) == "after");
    // A build smaller than one frame's saving: the first frame already pays.
    CHECK(medians(4, 1, 2).ray_pays_from() == 1);
    CHECK(pays_cell(medians(4, 1, 2)) == "always");
    CHECK(pays_cell(medians(4, 1, 0)) == "always");
    // A ray frame no faster: never, whatever the build.
    CHECK(medians(2, 3.2, 9).ray_pays_from() == 0);
    CHECK(medians(3, 3, 0).ray_pays_from() == 0);
    CHECK(pays_cell(medians(2, 3.2, 9)) == "never");
    CHECK(std::string(pays_word(medians(2, 3.2, 9))) == "never");
    // A failed path: no answer.
    CHECK_FALSE(medians(0, 3, 9).valid());
    CHECK(pays_cell(medians(4, 0, 9)) == "-");
    CHECK(std::string(pays_word(medians(4, 0, 9))).empty());
}

TEST_CASE("The answer in words names the faster path, the factor and the build in raster frames", "[bench]")
{
    std::string raster = crossover_words("bunny", 1920, 1080, medians(2, 3.2, 9));
    CHECK(raster == "bunny 1920x1080: rasterization is 1.60x faster per frame (2.00 vs 3.20 ms): rasterize; ray "
                    "casting never catches up (its BVH build, 9.0 ms, costs another 4.5 raster frames).");
    // A spread of raster / ray that holds 1 is said: the factor is within the noise.
    Crossover noisy = medians(2, 2.1, 9);
    noisy.lo = 0.63;
    noisy.hi = 1.54;
    CHECK(has(crossover_words("suzanne", 192, 108, noisy),
              "The spread of raster/ray (0.63-1.54) holds 1: per frame the two are not told apart here."));
    noisy.hi = 0.99;
    CHECK_FALSE(has(crossover_words("suzanne", 192, 108, noisy), "holds 1"));
    std::string after = crossover_words("sphere", 640, 480, medians(4, 3, 10));
    CHECK(has(after, "sphere 640x480: ray casting is 1.33x faster per frame (4.00 vs 3.00 ms)"));
    CHECK(has(after, "its BVH build (10.0 ms) costs 2.5 raster frames: it pays from frame 11 on"));
    CHECK(has(after, "rasterize fewer than 11 frames of this scene, ray-cast more."));
    CHECK(has(crossover_words("grid", 320, 240, medians(4, 1, 2)), "paid back by the first frame: ray-cast."));
    CHECK(has(crossover_words("grid", 320, 240, medians(0, 1, 2)), "no answer"));
}

TEST_CASE("Every column of the bench table has a legend line", "[bench]")
{
    const auto& columns = ratio_table_columns();
    std::string text = legend(columns);
    for (const Column& c : columns) {
        INFO(c.name);
        CHECK(std::string(c.meaning).size() > 5);
        CHECK(has(text, "  " + std::string(c.name) + " "));
    }
    // The abbreviations that were never defined, and the referee columns that read like speeds.
    for (const char* name : {"r/gl", "e-16", "b/e", "e-1", "raster/ray", "ray pays", "raster|ray", "brute|ray"}) {
        INFO(name);
        bool found = false;
        for (const Column& c : columns) found = found || std::string(c.name) == name;
        CHECK(found);
    }
    CHECK(has(text, "referee verdict raster vs ray"));
    CHECK(has(text, "not a speed"));
}
