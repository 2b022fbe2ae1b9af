// Brute force on a scene with instances (issue 34, "Instances that never expand"): Path::Brute
// (one frame, several samples, a region, a batch of views) and ray queries with `brute` set read
// the meshes once and a record per item (kernels/shared/brute_scene.h), never Scene::world_positions()
// of the expansion on the host or the device, and answer with the expansion's bits: its keys,
// its hits, and the BVH walk's.
#include "catch.hpp"
#include "render/renderer_probe.hpp"
#include "scene/scene_probe.hpp"

#include <clvis/clvis.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <vector>

using namespace clvis;

namespace {

Mat4 placed(double yaw, Vec3 offset, Vec3 scale)
{
    Mat4 m;
    double c = std::cos(yaw), s = std::sin(yaw);
    double r[3][3] = {{c, 0, s}, {0, 1, 0}, {-s, 0, c}};
    double k[3] = {scale.x, scale.y, scale.z}, t[3] = {offset.x, offset.y, offset.z};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) m(i, j) = r[i][j] * k[j];
        m(i, 3) = t[i];
    }
    return m;
}

/// Spheres: an instance with the identity (its prototype's own bits), rotated, scaled and
/// mirrored ones, two coincident (ties go to the lower id), between plain meshes (one moved by a
/// transform, one not) and two instances of a quad sharing an edge: instanced, or written out.
Scene balls(bool instanced)
{
    MeshData ball = make_uv_sphere(500);
    MeshData quad;
    quad.name = "quad";
    quad.positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    quad.indices = {0, 1, 2, 0, 2, 3};
    Scene s;
    std::size_t p = instanced ? s.add_prototype(ball) : 0, q = instanced ? s.add_prototype(quad) : 0;
    auto place = [&](std::size_t proto, const MeshData& m, const Mat4& t) {
        instanced ? s.add_instance(proto, t) : s.add_mesh(m, t);
    };
    s.add_mesh(quad, placed(0, {0, 0, -3}, {6, 6, 6}));
    place(p, ball, Mat4{});
    place(p, ball, placed(0.4, {2.2, 0.3, 0.5}, {0.8, 1.2, 0.8}));
    place(p, ball, placed(2.0, {-2.1, -0.2, 0.2}, {-0.9, 0.9, 0.9})); // mirrored
    s.add_mesh(ball);                                                    // plain, no transform
    place(p, ball, placed(-1.1, {0.3, 1.9, 1.0}, {0.5, 0.5, -0.5}));   // mirrored
    place(p, ball, placed(-1.1, {0.3, 1.9, 1.0}, {0.5, 0.5, -0.5}));   // coincident with the one before
    place(q, quad, placed(0, {-1, -2, 1.5}, {1, 1, 1}));
    place(q, quad, placed(0, {1, -2, 1.5}, {1, 1, 1})); // shares the edge x = 0
    return s;
}

std::uint64_t expansions() { return detail::expansion_vertices_built.load(); }

bool same_bytes(const void* a, const void* b, std::size_t bytes) { return std::memcmp(a, b, bytes) == 0; }

/// Rays from above (z = 8), from inside the balls, and straight down through the small quads' shared
/// edge (the last 100).
std::vector<RayRecord> probe_rays()
{
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<RayRecord> rays;
    for (int i = 0; i < 600; ++i)
        rays.push_back({u(rng) * 2.5f, u(rng) * 2.5f, 8, 0, u(rng) * 0.3f, u(rng) * 0.3f, -1, 100});
    for (int i = 0; i < 600; ++i) {
        const float o[4][3] = {{0, 0, 0}, {2.2f, 0.3f, 0.5f}, {-2.1f, -0.2f, 0.2f}, {0.3f, 1.9f, 1.0f}};
        const float* c = o[i % 4];
        rays.push_back({c[0], c[1], c[2], i % 3 == 0 ? 0.05f : 0.0f, u(rng), u(rng), u(rng), i % 5 == 0 ? 0.4f : 100});
    }
    for (int i = 0; i < 100; ++i) rays.push_back({0, -2 + u(rng) * 0.9f, 4, 0, 0, 0, -1, 100});
    return rays;
}

/// Closest, any, count and all hits (with their counts) of `q` for `rays`, as bytes.
std::vector<unsigned char> answers(RayQuery& q, const std::vector<RayRecord>& rays)
{
    std::size_t n = rays.size();
    std::vector<HitRecord> hits(n), all(n * 5);
    std::vector<std::uint8_t> flags(n);
    std::vector<std::uint32_t> counts(n), all_counts(n);
    q.closest({rays.data(), n}, hits.data());
    q.occluded({rays.data(), n}, flags.data());
    q.count({rays.data(), n}, counts.data());
    q.all({rays.data(), n}, 5, all.data(), all_counts.data());
    std::vector<unsigned char> out;
    auto add = [&](const void* p, std::size_t bytes) {
        out.insert(out.end(), static_cast<const unsigned char*>(p), static_cast<const unsigned char*>(p) + bytes);
    };
    add(hits.data(), n * sizeof(HitRecord));
    add(flags.data(), n);
    add(counts.data(), n * 4);
    add(all.data(), all.size() * sizeof(HitRecord));
    add(all_counts.data(), n * 4);
    return out;
}

} // namespace

TEST_CASE("Path::Brute draws an instanced scene from its items with the expansion's keys", "[device][instances][brute]")
{
    Device device = Device::open();
    Scene a = balls(true), b = balls(false);
    REQUIRE(a.triangle_count() == b.triangle_count());
    Camera cam = Camera::framing(b.bounds());
    std::uint64_t before = expansions();
    for (Cull cull : {Cull::None, Cull::Back}) {
        for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
            RenderOptions o;
            o.cull = cull;
            o.coverage = coverage;
            Renderer ra(device, a, o), rb(device, b, o);
            INFO("cull " << int(cull) << " " << to_string(coverage));
            std::vector<std::uint64_t> keys = ra.render(cam, 48, 36, Path::Brute).read_keys();
            CHECK(keys == rb.render(cam, 48, 36, Path::Brute).read_keys());
            CHECK(keys == ra.render(cam, 48, 36, Path::Ray).read_keys()); // the BVH walk's
            std::size_t covered = 0;
            std::set<std::size_t> seen; // items
            for (std::uint64_t k : keys) {
                covered += std::uint32_t(k) != background_id;
                if (std::uint32_t(k) != background_id) seen.insert(a.mesh_of(std::uint32_t(k)));
            }
            CHECK(covered > 48 * 36 / 8);
            CHECK(seen.size() >= 5);
            CHECK_FALSE(detail::expansion_uploaded(ra));
        }
    }
    // Several samples per pixel, a region, a batch of views; then a moved instance.
    RenderOptions four;
    four.samples = 4;
    Renderer r4(device, a, four), r4b(device, b, four);
    CHECK(r4.render(cam, 24, 18, Path::Brute).read_keys() == r4b.render(cam, 24, 18, Path::Brute).read_keys());
    RenderOptions part;
    part.region = Region{5, 7, 17, 11};
    Renderer rr(device, a, part), rrb(device, b, part);
    CHECK(rr.render(cam, 40, 30, Path::Brute).read_keys() == rrb.render(cam, 40, 30, Path::Brute).read_keys());
    Renderer ra(device, a), rb(device, b);
    std::vector<Camera> cams{cam, Camera::framing(b.bounds(), Projection::Orthographic)};
    VisibilityBatch va(device, 2, 31, 23), vb(device, 2, 31, 23);
    render_views(ra, cams, Path::Brute, va);
    render_views(rb, cams, Path::Brute, vb);
    for (int v = 0; v < 2; ++v) {
        std::vector<std::uint64_t> ka, kb;
        va.view(v).read_keys(ka);
        vb.view(v).read_keys(kb);
        CHECK(ka == kb);
    }
    std::vector<std::uint64_t> still = ra.render(cam, 32, 24, Path::Brute).read_keys();
    Mat4 moved = placed(0.9, {-0.5, 0.4, 1.2}, {1.1, 0.7, 1.1});
    a.set_transform(2, moved);
    b.set_transform(2, moved);
    ra.update(a);
    rb.update(b);
    std::vector<std::uint64_t> now = ra.render(cam, 32, 24, Path::Brute).read_keys();
    CHECK(now == rb.render(cam, 32, 24, Path::Brute).read_keys());
    CHECK(now != still);
    CHECK_FALSE(detail::expansion_uploaded(r4));
    CHECK_FALSE(detail::expansion_uploaded(rr));
    CHECK_FALSE(detail::expansion_uploaded(ra));
    CHECK(expansions() == before); // only the plain scenes' own arrays were built
}

TEST_CASE("brute-force ray queries on an instanced scene read its items and answer as its expansion",
          "[device][instances][brute][ray_query]")
{
    Device device = Device::open();
    Scene a = balls(true), b = balls(false);
    std::vector<RayRecord> rays = probe_rays();
    std::uint64_t before = expansions();
    Renderer ra(device, a), rb(device, b);
    RayQueryOptions brute;
    brute.brute = true;
    brute.batch_rays = 500; // several batches
    RayQuery qa(ra, brute), qb(rb, brute), walk(ra);
    std::vector<unsigned char> got = answers(qa, rays), want = answers(qb, rays), walked = answers(walk, rays);
    REQUIRE(got.size() == want.size());
    CHECK(same_bytes(got.data(), want.data(), got.size()));
    REQUIRE(walked.size() == got.size());
    CHECK(same_bytes(walked.data(), got.data(), got.size()));
    std::size_t n = rays.size(), hit = 0, several = 0;
    for (std::size_t i = 0; i < n; ++i) {
        HitRecord h;
        std::memcpy(&h, got.data() + i * sizeof h, sizeof h);
        hit += h.id != background_id;
        std::uint32_t c;
        std::memcpy(&c, got.data() + n * sizeof h + n + 4 * i, 4);
        several += c > 1;
        if (i >= n - 100) CHECK(c == 2); // the small quads' shared edge once, then the big quad
    }
    CHECK(hit > n / 2);
    CHECK(several > 100);
    // A moved instance: the brute queries see it as the moved expansion does.
    Mat4 moved = placed(-0.6, {0.2, -0.3, 0.9}, {1.2, 1.2, 1.2});
    a.set_transform(1, moved);
    b.set_transform(1, moved);
    ra.update(a);
    rb.update(b);
    std::vector<unsigned char> got2 = answers(qa, rays), want2 = answers(qb, rays);
    CHECK(same_bytes(got2.data(), want2.data(), got2.size()));
    CHECK_FALSE(same_bytes(got2.data(), got.data(), got.size()));
    CHECK_FALSE(detail::expansion_uploaded(ra));
    CHECK(expansions() == before);
}
