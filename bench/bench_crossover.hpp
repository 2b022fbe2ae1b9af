// Rasterization or ray casting for this scene and size, from one point's medians: how many times
// faster one path's frame is, what the ray path's BVH build costs in raster frames, and from
// which frame count ray casting, its build included, costs less than rasterization. Also the
// legend of every column of the bench table. Pure arithmetic and text, tested in
// tests/bench_crossover_test.cpp; bench_table.cpp and bench_report.cpp print and store it.
#pragma once

#include <string>
#include <vector>

namespace clvis::bench {

/// The medians of one point (ms); 0 where a path has no figure.
struct Crossover {
    double raster_ms = 0, ray_ms = 0, build_ms = 0;
    double lo = 0, hi = 0; ///< the spread of raster / ray (0 0: unknown)

    bool valid() const { return raster_ms > 0 && ray_ms > 0; }
    /// Raster frame time over ray frame time: below 1 rasterization is faster per frame.
    double raster_over_ray() const { return valid() ? raster_ms / ray_ms : 0; }
    /// The BVH build in raster frames.
    double build_in_raster_frames() const { return raster_ms > 0 ? build_ms / raster_ms : 0; }
    /// The fewest frames N at which build + N ray frames cost less than N raster frames: 1 when the
    /// first frame already does ("always"), 0 when no N does ("never": a ray frame is not faster).
    long long ray_pays_from() const;
};

/// The table's cell: "never", "always" or "from N" (frames); "-" without both paths.
std::string pays_cell(const Crossover& c);
/// "never", "always" or "after" (bench.json's crossover.ray_pays); "" without both paths.
const char* pays_word(const Crossover& c);
/// The answer in words, e.g. "bunny 1920x1080: rasterization is 1.60x faster per frame (2.00 vs
/// 3.20 ms): rasterize; ray casting never catches up (its BVH build, 9.0 ms, costs another 4.5
/// raster frames)."; a spread of raster / ray that holds 1 is said to leave the two untold apart.
std::string crossover_words(const std::string& mesh, int width, int height, const Crossover& c);

/// A column of the bench table and what it holds.
struct Column {
    const char* name;
    const char* meaning;
};
/// Every column of the table of medians and ratios, in printed order.
const std::vector<Column>& ratio_table_columns();
/// The legend printed under that table: one "  name  meaning" line per column.
std::string legend(const std::vector<Column>& columns);

} // namespace clvis::bench
