// A visibility buffer rendered into again: the raster path's frame must leave exactly the keys of
// a fresh buffer, whatever the buffer held before (another camera's frame, the other depth
// test's, keys written by the caller's own code), under both depth tests, with samples and depth
// layers, and at sizes whose clear streams its lines past the cache (kernels/shared/raster_stream.h:
// at least a quarter of the device's reported cache, 8 MiB on PoCL's 32 MiB) and sizes whose
// clear does not.
#include "catch.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>

#include <CL/cl.h>

#include <cstdint>
#include <string>
#include <vector>

using namespace clvis;

namespace {

/// Fills every key of `target` with `key` on the device's queue (the caller's own writes).
void fill_keys(const Device& d, const VisibilityBuffer& target, std::uint64_t key)
{
    cl_int err = clEnqueueFillBuffer(d.queue(), target.keys(), &key, sizeof key, 0,
                                     target.key_count() * sizeof(std::uint64_t), 0, nullptr, nullptr);
    REQUIRE(err == CL_SUCCESS);
    REQUIRE(clFinish(d.queue()) == CL_SUCCESS);
}

/// A close-up of the scene from the other side of the framing camera's view.
Camera other_side(const Camera& framing, const Bounds& b)
{
    Vec3 back = framing.eye - framing.target;
    Vec3 eye = framing.target + Vec3{-back.x, back.y, back.z} * 0.5;
    double dist = length(eye - framing.target), radius = length(b.extent()) / 2;
    return test::look(eye, framing.target, 50, 0.05 * dist, 1.1 * (dist + radius));
}

} // namespace

TEST_CASE("a reused visibility buffer holds the last frame's keys alone, whatever it held",
          "[device][raster][reuse]")
{
    Device d = Device::open();
    Scene s = test::scene_file("spot.obj");
    Bounds b = s.bounds();
    const Camera a = Camera::framing(b), c = other_side(a, b);
    struct Case { int w, h, samples, layers; };
    // 1024 x 1024 keys of 8 bytes: 8 MiB, a streamed clear on PoCL, as are 512 x 512 x 4 samples
    // and 1024 x 768 x 2 layers; the odd sizes cut squares and spans at the image's edges and do
    // not stream. (Samples and layers do not combine.)
    for (Case k : {Case{1024, 1024, 1, 1}, Case{203, 117, 1, 1}, Case{97, 61, 4, 1}, Case{512, 512, 4, 1},
                   Case{203, 117, 1, 3}, Case{1024, 768, 1, 2}}) {
        // Keys compared by same_bytes: a failed == would print a million keys.
        for (RasterAtomics mode : {RasterAtomics::Auto, RasterAtomics::Off}) {
            INFO(k.w << "x" << k.h << ", " << k.samples << " sample(s), " << k.layers << " layer(s), atomics "
                      << to_string(mode));
            RenderOptions o;
            o.raster_atomics = mode;
            o.samples = k.samples;
            o.layers = k.layers;
            Renderer r(d, s, o);
            const std::vector<std::uint64_t> fresh_c = r.render(c, k.w, k.h, Path::Raster).read_keys();
            const std::vector<std::uint64_t> fresh_a = r.render(a, k.w, k.h, Path::Raster).read_keys();
            REQUIRE(test::covered(split_keys(fresh_c.data(), k.w, k.h, k.samples, k.layers)) > 0);
            REQUIRE(!test::same_bytes(fresh_a, fresh_c)); // the two cameras see different pixels

            VisibilityBuffer target(d, k.w, k.h, k.samples, k.layers);
            r.render(a, Path::Raster, target);
            CHECK(test::same_bytes(target.read_keys(), fresh_a));
            r.render(c, Path::Raster, target); // camera A's keys were there
            CHECK(test::same_bytes(target.read_keys(), fresh_c));
            r.render(a, Path::Raster, target); // and back
            CHECK(test::same_bytes(target.read_keys(), fresh_a));

            // Keys the caller wrote, nearer than any the frame draws (a depth of about 1e-45 and id
            // 1): a pixel left as it was would keep them under the atomic test's minimum.
            fill_keys(d, target, 0x0000000100000001ull);
            r.render(c, Path::Raster, target);
            CHECK(test::same_bytes(target.read_keys(), fresh_c));

            // The other depth test's renderer drew there last.
            RenderOptions other = o;
            other.raster_atomics = mode == RasterAtomics::Off ? RasterAtomics::Auto : RasterAtomics::Off;
            Renderer(d, s, other).render(a, Path::Raster, target);
            CHECK(test::same_bytes(target.read_keys(), fresh_a));
            r.render(c, Path::Raster, target);
            CHECK(test::same_bytes(target.read_keys(), fresh_c));
        }
    }
}
