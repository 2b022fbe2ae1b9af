// The raster path's list of triangles to bin and its bins keep their capacities from frame to
// frame and are sized without a read-back during the frame: a sample whose list or bins
// overflowed is grown and drawn again, with the keys of a frame that never overflowed.
#include "catch.hpp"
#include "test_meshes.hpp"

#include "raster/raster_pipeline.hpp"

#include <clvis/clvis.hpp>

#include <string>
#include <vector>

using namespace clvis;

namespace {

/// First capacities forced for the raster pipelines made while it lives (then the defaults).
struct FirstCapacities {
    FirstCapacities(std::size_t tris, std::size_t entries) { detail::set_raster_first_capacities(tris, entries); }
    ~FirstCapacities() { detail::set_raster_first_capacities(0, 0); }
};

std::vector<std::uint64_t> keys(const Device& d, const Scene& s, const Camera& c, RasterAtomics mode, int samples,
                                int frames = 1)
{
    RenderOptions o;
    o.raster_atomics = mode;
    o.samples = samples;
    Renderer r(d, s, o);
    std::vector<std::uint64_t> k;
    for (int f = 0; f < frames; ++f) k = r.render(c, 203, 117, Path::Raster).read_keys();
    return k;
}

/// A bundled mesh, the cameras the cases draw it from (framing, and a close-up from inside that
/// clips), and the depth tests the device offers.
struct Setting {
    Scene scene;
    std::vector<Camera> cameras;
    std::vector<RasterAtomics> modes = {RasterAtomics::Off};
};

Setting setting(const Device& d, const char* mesh)
{
    Setting t;
    t.scene.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + mesh));
    Bounds b = t.scene.bounds();
    t.cameras = {Camera::framing(b),
                 test::look(b.center() + Vec3{0.05, 0.1, 0.3}, b.center() + Vec3{0, 0, -1}, 90, 0.01, 10)};
    if (d.info().int64_atomics) t.modes.push_back(RasterAtomics::On);
    return t;
}

} // namespace

TEST_CASE("lists and bins past their first capacity are grown and redrawn",
          "[device][raster][rusticl][rusticl_long]")
{
    Device d = Device::open();
    Setting t = setting(d, "spot.obj");
    const Scene& s = t.scene;
    const std::vector<RasterAtomics>& modes = t.modes;
    for (const Camera& c : t.cameras) {
        for (int samples : {1, 4}) {
            INFO(c.to_flags() << ", " << samples << " samples");
            std::vector<std::uint64_t> want = keys(d, s, c, RasterAtomics::Auto, samples);
            CHECK(test::covered(split_keys(want.data(), 203, 117 * samples)) > 0);
            FirstCapacities tiny(1, 1); // one triangle, one bin entry: every first sample overflows
            for (RasterAtomics mode : modes) {
                INFO(to_string(mode));
                CHECK(keys(d, s, c, mode, samples) == want);
                CHECK(keys(d, s, c, mode, samples, 3) == want); // capacities kept from frame to frame
            }
        }
    }
}

TEST_CASE("small frames binned in one launch give the keys of the three launches", "[device][raster][rusticl]")
{
    // raster_bin_small (one work-group: counts, offsets and entries) against raster_bin_count,
    // raster_bin_scan and raster_bin_fill, forced either way on whatever device runs the tests
    // (Suzanne's 968 triangles over 104 tiles: within the one launch's bound), overflowing lists
    // and bins included.
    struct SmallFrames {
        explicit SmallFrames(int use) { detail::set_raster_small_frames(use); }
        ~SmallFrames() { detail::set_raster_small_frames(-1); }
    };
    Device d = Device::open();
    Setting t = setting(d, "suzanne.obj");
    const Scene& s = t.scene;
    for (const Camera& c : t.cameras) {
        for (int samples : {1, 4}) {
            for (RasterAtomics mode : t.modes) {
                INFO(c.to_flags() << ", " << samples << " samples, " << to_string(mode));
                std::vector<std::uint64_t> three, one, one_grown;
                {
                    SmallFrames off(0);
                    three = keys(d, s, c, mode, samples);
                }
                CHECK(test::covered(split_keys(three.data(), 203, 117 * samples)) > 0);
                {
                    SmallFrames on(1);
                    one = keys(d, s, c, mode, samples, 2);
                    FirstCapacities tiny(1, 1); // every first sample overflows its list and bins
                    one_grown = keys(d, s, c, mode, samples, 2);
                }
                CHECK(one == three);
                CHECK(one_grown == three);
            }
        }
    }
}
