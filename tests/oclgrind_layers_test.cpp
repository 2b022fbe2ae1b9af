// Depth layers (RenderOptions::layers) on Oclgrind's simulated device: the raster path's layer
// kernels (the atomic cascade in setup, raster_fine's and raster_fine_pixel's sorted inserts,
// merged or written whole under tile ownership) and the ray path's (packets and single rays, both
// coverage modes) at K = 2, 3 and 4, on two nested spheres (up to four surfaces under a pixel),
// each run clean and equal to PoCL's layers bit for bit. Run by the "oclgrind" CTest entry with
// oclgrind_test.cpp, which fails on any report.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <string>

using namespace clvis;

namespace {

/// A sphere with a smaller one inside it: front and back of each under the middle pixels.
Scene nested_spheres()
{
    Scene s;
    MeshData sphere = make_uv_sphere(160);
    s.add_mesh(sphere);
    Mat4 inner;
    inner(0, 0) = inner(1, 1) = inner(2, 2) = 0.5;
    inner(0, 3) = 0.1;
    s.add_mesh(sphere, inner);
    return s;
}

/// `path` under `o` on a fresh Oclgrind device and on PoCL: every layer the same, and some pixel
/// with a key in the deepest layer.
void check_layers_on_grind(const Scene& s, Path path, const RenderOptions& o)
{
    const int w = 27, h = 19;
    Camera cam = Camera::framing(s.bounds());
    Renderer on_grind(Device::open("oclgrind"), s, o), on_pocl(Device::open("portable computing language"), s, o);
    auto a = on_grind.render(cam, w, h, path).read_keys();
    auto b = on_pocl.render(cam, w, h, path).read_keys();
    REQUIRE(b.size() == std::size_t(w) * h * std::size_t(o.layers));
    CHECK(a == b);
    std::size_t deepest = 0;
    for (std::size_t i = b.size() - std::size_t(w) * h; i < b.size(); ++i)
        deepest += std::uint32_t(b[i]) != background_id;
    CHECK(deepest > 0);
}

} // namespace

TEST_CASE("depth layers run clean on Oclgrind on both paths and match PoCL", "[.oclgrind]")
{
    Scene s = nested_spheres();
    // Each K with another pairing, every mapping, depth test and coverage mode met at least once.
    struct Run {
        int layers;
        RasterMapping raster;
        RasterAtomics atomics;
        RayMapping ray;
        Coverage coverage;
    };
    for (const Run& run : {Run{2, RasterMapping::Square, RasterAtomics::Auto, RayMapping::Packet, Coverage::Watertight},
                           Run{3, RasterMapping::Pixel, RasterAtomics::Off, RayMapping::Single, Coverage::RasterRule},
                           Run{4, RasterMapping::Pixel, RasterAtomics::Auto, RayMapping::Single, Coverage::Watertight},
                           Run{4, RasterMapping::Square, RasterAtomics::Off, RayMapping::Packet, Coverage::RasterRule}}) {
        RenderOptions o;
        o.layers = run.layers;
        o.raster_mapping = run.raster;
        o.raster_atomics = run.atomics;
        o.ray_mapping = run.ray;
        o.coverage = run.coverage;
        INFO("K " << run.layers << ", raster " << to_string(run.raster) << " atomics " << to_string(run.atomics)
                  << ", ray " << to_string(run.ray) << " " << to_string(run.coverage));
        check_layers_on_grind(s, Path::Raster, o);
        check_layers_on_grind(s, Path::Ray, o);
    }
}
