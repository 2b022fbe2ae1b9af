// Many views per call (include/clvis/batch.hpp): each view of a batch is bit-identical to the
// same view rendered alone, on every path and camera kind; the batch's views work wherever a
// visibility buffer does; bad batches are refused.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <cmath>
#include <string>
#include <vector>

using namespace clvis;

TEST_CASE("each view of a batch is bit-identical to the view rendered alone", "[device][batch]")
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"));
    Device device = Device::open();
    Renderer renderer(device, s);
    Camera framing = Camera::framing(s.bounds());
    std::vector<Camera> cams;
    for (int i = 0; i < 5; ++i) {
        Camera c = framing;
        double a = 1.2 * i;
        Vec3 d = framing.eye - s.bounds().center();
        c.eye = s.bounds().center() + Vec3{d.x * std::cos(a) - d.z * std::sin(a), d.y, d.x * std::sin(a) + d.z * std::cos(a)};
        if (i == 3) c = Camera::framing(s.bounds(), Projection::Orthographic);
        if (i == 4) c.intrinsics = Intrinsics{70, 60, 20.5, 30}; // off-centre
        cams.push_back(c);
    }
    const int w = 61, h = 47; // not a multiple of any group or alignment
    VisibilityBatch batch(device, int(cams.size()), w, h);
    CHECK(batch.stride() >= std::size_t(w) * h);
    for (Path p : {Path::Raster, Path::Ray, Path::Brute}) {
        render_views(renderer, cams, p, batch);
        CHECK(renderer.last_frame().frame_ms > 0);
        for (int v = 0; v < batch.views(); ++v) {
            INFO(to_string(p) << " view " << v);
            std::vector<std::uint64_t> alone = renderer.render(cams[std::size_t(v)], w, h, p).read_keys();
            std::vector<std::uint64_t> in_batch;
            batch.view(v).read_keys(in_batch);
            CHECK(in_batch == alone);
        }
    }
    // A view is a visibility buffer: attributes and visible sets take it.
    AttributeRequest req;
    req.barycentrics = true;
    CHECK(resolve(renderer, batch.view(2), cams[2], req).read(Attribute::Barycentrics).size() == std::size_t(w * h * 2));
    VisibleSet set(device, std::uint32_t(s.triangle_count()));
    for (int v = 0; v < batch.views(); ++v) set.mark(batch.view(v));
    CHECK(set.read_ids().size() > 100);
    CHECK_THROWS_AS(render_views(renderer, {framing}, Path::Ray, batch), Error);
    CHECK_THROWS_AS(batch.view(5), Error);
    CHECK_THROWS_AS(VisibilityBatch(device, 0, w, h), Error);
}
