// Rays generated from a visibility buffer (host/query/ray_generate.cpp, kernels/ray_generate.cl)
// are made and traced for covered pixels only, and give the values of tracing every pixel's rays:
// the reference here is the old way, each pixel's rays (ambient_occlusion_rays, the background's
// of zero direction) answered by the any-hit query and averaged, compared bit for bit. Shadows
// trace one ray per covered pixel; an empty frame traces none.
#include "catch.hpp"

#include <clvis/clvis.hpp>
#include <clvis/ray_query.hpp>

#include <cstring>
#include <vector>

using namespace clvis;

namespace {

/// Ambient occlusion as it was computed before covered pixels were compacted: every pixel's rays
/// traced, background pixels 1.
std::vector<float> ao_every_pixel(RayQuery& q, const VisibilityBuffer& vis, const Camera& cam, const AoOptions& o,
                                  const HostVisibility& hv)
{
    std::vector<RayRecord> rays = q.ambient_occlusion_rays(vis, cam, o);
    std::vector<std::uint8_t> flags(rays.size());
    q.occluded({rays.data(), rays.size()}, flags.data());
    std::size_t per = std::size_t(o.rays);
    std::vector<float> value(hv.ids.size(), 1.0f);
    for (std::size_t i = 0; i < value.size(); ++i) {
        if (hv.ids[i] == background_id) continue;
        int open = 0;
        for (std::size_t k = 0; k < per; ++k) open += flags[per * i + k] == 0;
        value[i] = float(open) / float(o.rays);
    }
    return value;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b)
{
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

} // namespace

TEST_CASE("ambient occlusion traces covered pixels only and equals tracing every pixel", "[device][ray_generate]")
{
    Scene s = load_scene({CLVIS_SOURCE_DIR "/scenes/stanford-bunny.obj"});
    Renderer renderer(Device::open(), s);
    Camera cam = Camera::framing(s.bounds());
    const int w = 240, h = 135;
    VisibilityBuffer vis = renderer.render(cam, w, h, Path::Ray);
    HostVisibility hv = vis.read();
    std::size_t covered = 0;
    for (std::uint32_t id : hv.ids) covered += id != background_id;
    REQUIRE(covered > 0);
    REQUIRE(covered < hv.ids.size() / 2); // most of the frame is background: the case compaction is for
    // one chunk, and chunks smaller than the covered list (of 11 pixels: batches of 77 rays)
    for (std::size_t batch : {std::size_t(1) << 20, std::size_t(1000), std::size_t(77)}) {
        RayQuery q(renderer, RayQueryOptions{batch, false});
        AoOptions o;
        o.rays = 7;
        o.seed = 5;
        PixelRays ao = q.ambient_occlusion(vis, cam, o);
        CHECK(ao.stats.rays == covered * 7);
        CHECK(ao.stats.invalid == 0);
        REQUIRE(same_bits(ao.value, ao_every_pixel(q, vis, cam, o, hv)));
    }
}

TEST_CASE("shadow rays trace covered pixels only, and an empty frame none", "[device][ray_generate]")
{
    Scene s = load_scene({CLVIS_SOURCE_DIR "/scenes/spot.obj"});
    Renderer renderer(Device::open(), s);
    Camera cam = Camera::framing(s.bounds());
    VisibilityBuffer vis = renderer.render(cam, 160, 100, Path::Ray);
    HostVisibility hv = vis.read();
    RayQuery q(renderer);
    PixelRays sh = q.shadows(vis, cam, Vec3{0, 100, 0});
    std::size_t covered = 0, lit = 0, dark = 0;
    for (std::size_t i = 0; i < hv.ids.size(); ++i) {
        if (hv.ids[i] == background_id) {
            REQUIRE(sh.value[i] == 1.0f);
            continue;
        }
        ++covered;
        lit += sh.value[i] == 1.0f;
        dark += sh.value[i] == 0.0f;
    }
    CHECK(sh.stats.rays == covered);
    CHECK(lit + dark == covered);
    CHECK(lit > 0);
    CHECK(dark > 0);
    // an empty frame: no rays at all, every value 1
    Camera away = Camera::perspective({0, 0, 50}, {0, 0, 100}, {0, 1, 0}, 30, 0.1, 10);
    VisibilityBuffer empty = renderer.render(away, 32, 16, Path::Ray);
    AoOptions o;
    PixelRays none = q.ambient_occlusion(empty, away, o);
    CHECK(none.stats.rays == 0);
    CHECK(none.value == std::vector<float>(32 * 16, 1.0f));
}
