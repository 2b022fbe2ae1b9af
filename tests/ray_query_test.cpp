// Ray queries on the device: the BVH walk answers exactly as the brute force over every triangle,
// and acceptably to a double-precision oracle, on random, grazing, axis-parallel and edge/vertex
// rays and on invalid ones; occlusion agrees with closest hits; hit counts have the right parity
// on closed meshes, through shared edges and vertices; split batches, layouts and device buffers
// give the same answers; ambient occlusion is reproducible.
#include "catch.hpp"
#include "ray_oracle.hpp"
#include "ray_query_check.hpp"

#include <CL/cl.h>
#include <clvis/clvis.hpp>
#include <clvis/ray_query.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>

using namespace clvis;
using clvis::test::bits;
using clvis::test::same_hit;
using clvis::test::Answers;
using clvis::test::answer;
using clvis::test::check_scene;

namespace {

const float inf = std::numeric_limits<float>::infinity();
const float nan_f = std::numeric_limits<float>::quiet_NaN();

Scene scene_of(MeshData m)
{
    Scene s;
    s.add_mesh(std::move(m));
    return s;
}

/// A closed box [0, n]^3 made of unit squares, two triangles each, wound outwards: integer
/// coordinates, so axis-parallel rays at integer coordinates pass exactly through its vertices
/// and edges.
MeshData closed_box(int n)
{
    MeshData m;
    m.name = "box";
    auto vertex = [&](float x, float y, float z) {
        m.positions.insert(m.positions.end(), {x, y, z});
        return std::uint32_t(m.positions.size() / 3 - 1);
    };
    // each face: axis a fixed at 0 or n, (b, c) spanning it; outward winding by the face's sign
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    std::uint32_t q[4];
                    int corners[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
                    for (int k = 0; k < 4; ++k) {
                        float p[3];
                        p[a] = float(side * n);
                        p[(a + 1) % 3] = float(corners[k][0]);
                        p[(a + 2) % 3] = float(corners[k][1]);
                        q[k] = vertex(p[0], p[1], p[2]);
                    }
                    bool flip = side == 0;
                    bool diag = (i + j) % 2 == 0;
                    std::uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
                    if (!diag) {
                        std::uint32_t u[6] = {q[0], q[1], q[3], q[1], q[2], q[3]};
                        std::memcpy(t, u, sizeof t);
                    }
                    for (int k = 0; k < 6; k += 3) {
                        if (flip) m.indices.insert(m.indices.end(), {t[k], t[k + 2], t[k + 1]});
                        else m.indices.insert(m.indices.end(), {t[k], t[k + 1], t[k + 2]});
                    }
                }
    return m;
}

RayRecord ray(float ox, float oy, float oz, float dx, float dy, float dz, float tmin = 0, float tmax = inf)
{
    return RayRecord{ox, oy, oz, tmin, dx, dy, dz, tmax};
}

/// Random rays around `scene`: origins in its box grown by half, directions uniform, toward
/// vertices and edge midpoints, axis-parallel through vertex coordinates, lying in triangles'
/// planes, with zero-length ranges, and invalid ones (tmin > tmax, NaN, inf, zero direction).
std::vector<RayRecord> mixed_rays(const Scene& scene, std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    Bounds b = scene.bounds();
    Vec3 c = (b.lo + b.hi) * 0.5, e = (b.hi - b.lo) * 0.75;
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<std::uint32_t> pick_tri(0, std::uint32_t(scene.triangle_count() - 1));
    std::vector<RayRecord> out;
    float v[9];
    for (std::size_t i = 0; i < n; ++i) {
        float o[3] = {float(c.x + e.x * u(rng)), float(c.y + e.y * u(rng)), float(c.z + e.z * u(rng))};
        scene.triangle(pick_tri(rng), v);
        int k = int(i % 10), corner = int(i % 3);
        float target[3];
        for (int a = 0; a < 3; ++a) target[a] = v[3 * corner + a];
        if (k == 2)
            for (int a = 0; a < 3; ++a) target[a] = 0.5f * (v[3 * corner + a] + v[3 * ((corner + 1) % 3) + a]);
        RayRecord r = ray(o[0], o[1], o[2], float(u(rng)), float(u(rng)), float(u(rng)));
        if (k == 1 || k == 2) r = ray(o[0], o[1], o[2], target[0] - o[0], target[1] - o[1], target[2] - o[2]);
        if (k == 3) { // axis-parallel through a vertex's two coordinates
            int a = int(i / 10 % 3);
            float p[3] = {target[0], target[1], target[2]}, d[3] = {0, 0, 0};
            p[a] = o[a];
            d[a] = i % 2 ? 1.0f : -1.0f;
            r = ray(p[0], p[1], p[2], d[0], d[1], d[2]);
        }
        if (k == 4) // from a vertex along an edge: in the triangle's plane
            r = ray(v[0], v[1], v[2], v[3] - v[0], v[4] - v[1], v[5] - v[2], 0.0f, 2.0f);
        if (k == 5) { r.tmin = 0.5f; r.tmax = 0.5f; }
        if (k == 6) { r.tmin = float(u(rng) * 0.5 + 0.5); r.tmax = r.tmin * float(u(rng) * 0.5 + 1.5); }
        if (k == 7) { r.tmin = 2; r.tmax = 1; }
        if (k == 8) {
            float bad[4] = {nan_f, inf, -inf, 0};
            int which = int(i / 10 % 4);
            if (which == 3) r.dx = r.dy = r.dz = 0;
            else (&r.ox)[i / 40 % 8] = bad[which];
            if (which == 1 && i / 40 % 8 == 7) r.tmin = -1; // tmax = +inf is valid: make it invalid otherwise
        }
        out.push_back(r);
    }
    return out;
}

} // namespace

TEST_CASE("ray queries through the BVH equal brute force and the oracle", "[device][rays]")
{
    SECTION("spot") { check_scene(load_scene({CLVIS_SOURCE_DIR "/scenes/spot.obj"}), mixed_rays(load_scene({CLVIS_SOURCE_DIR "/scenes/spot.obj"}), 3000, 1), true); }
    SECTION("suzanne") { check_scene(load_scene({CLVIS_SOURCE_DIR "/scenes/suzanne.obj"}), mixed_rays(load_scene({CLVIS_SOURCE_DIR "/scenes/suzanne.obj"}), 3000, 2), true); }
    SECTION("sphere") {
        Scene s = scene_of(make_uv_sphere(2000));
        check_scene(s, mixed_rays(s, 3000, 3), true);
    }
    SECTION("box") {
        Scene s = scene_of(closed_box(4));
        check_scene(s, mixed_rays(s, 3000, 4), true);
    }
    SECTION("soup") {
        Scene s = scene_of(make_soup(20000, 5));
        check_scene(s, mixed_rays(s, 2000, 5), false);
    }
}

TEST_CASE("ray queries on the bunny and a grid equal brute force", "[device][rays][slow]")
{
    Scene bunny = load_scene({CLVIS_SOURCE_DIR "/scenes/stanford-bunny.obj"});
    check_scene(bunny, mixed_rays(bunny, 4000, 6), false);
    Scene grid = scene_of(make_grid(50000, 7));
    check_scene(grid, mixed_rays(grid, 4000, 7), true);
}

/// Parity of the counts from `origins` along `dirs` (unbounded rays): odd exactly when `inside`.
void check_parity(RayQuery& q, const std::vector<RayRecord>& rays, const std::vector<bool>& inside)
{
    std::vector<std::uint32_t> counts(rays.size());
    q.count({rays.data(), rays.size()}, counts.data());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if ((counts[i] % 2 == 1) != inside[i]) {
            ++wrong;
            UNSCOPED_INFO("ray " << i << " from (" << rays[i].ox << ", " << rays[i].oy << ", " << rays[i].oz << ") along ("
                                 << rays[i].dx << ", " << rays[i].dy << ", " << rays[i].dz << ") counts " << counts[i]);
        }
    }
    CHECK(wrong == 0);
}

TEST_CASE("hit counts through edges and vertices of a closed box give parity", "[device][rays]")
{
    const int n = 4;
    Scene s = scene_of(closed_box(n));
    Renderer renderer(Device::open(), s);
    RayQuery q(renderer);
    std::vector<RayRecord> rays;
    std::vector<bool> inside;
    // axis-parallel rays at every integer and half-integer lattice point: through vertices, edges
    // (grid lines and face diagonals) and face interiors, from inside and outside, both ways
    for (int a = 0; a < 3; ++a)
        for (int i = -1; i <= 2 * n + 1; ++i)
            for (int j = -1; j <= 2 * n + 1; ++j)
                for (int start : {-1, 1, 2 * n - 1, 2 * n + 1})
                    for (float dir : {1.0f, -1.0f}) {
                        float o[3], d[3] = {0, 0, 0};
                        o[a] = float(start) * 0.5f;
                        o[(a + 1) % 3] = float(i) * 0.5f;
                        o[(a + 2) % 3] = float(j) * 0.5f;
                        d[a] = dir;
                        if (i == 0 || j == 0 || i == 2 * n || j == 2 * n) continue; // in a face's plane
                        rays.push_back(ray(o[0], o[1], o[2], d[0], d[1], d[2]));
                        bool in = true;
                        for (int k = 0; k < 3; ++k) in = in && o[k] > 0 && o[k] < float(n);
                        inside.push_back(in);
                    }
    // diagonal rays through the box's corners and edge points, from inside and outside
    for (int i = 0; i <= n; ++i)
        for (float s0 : {-0.5f, 0.5f, 1.5f}) {
            rays.push_back(ray(s0, s0, float(i) + s0 - 0.0f, 1, 1, 1));
            inside.push_back(s0 > 0 && s0 < float(n) && float(i) + s0 > 0 && float(i) + s0 < float(n));
        }
    check_parity(q, rays, inside);
}

TEST_CASE("hit counts on closed meshes tell inside from outside", "[device][rays]")
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1, 1);
    SECTION("sphere, rays toward vertices and in random directions")
    {
        MeshData m = make_uv_sphere(5000);
        Scene s = scene_of(m);
        Renderer renderer(Device::open(), s);
        RayQuery q(renderer);
        std::vector<RayRecord> rays;
        std::vector<bool> inside;
        for (int i = 0; i < 4000; ++i) {
            float r = i % 2 ? 0.8f : 1.3f, o[3];
            do {
                for (float& x : o) x = u(rng) * r;
            } while (std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]) > r);
            float len = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
            if (i % 2 == 0 && len < 1.1f) continue;
            std::size_t v = std::size_t(rng() % m.vertex_count());
            float d[3] = {u(rng), u(rng), u(rng)};
            if (i % 4 < 2)
                for (int k = 0; k < 3; ++k) d[k] = m.positions[3 * v + k] - o[k];
            rays.push_back(ray(o[0], o[1], o[2], d[0], d[1], d[2]));
            inside.push_back(i % 2 == 1);
        }
        check_parity(q, rays, inside);
    }
    SECTION("spot, from outside through its vertices along the axes")
    {
        Scene s = load_scene({CLVIS_SOURCE_DIR "/scenes/spot.obj"});
        Renderer renderer(Device::open(), s);
        RayQuery q(renderer);
        Bounds b = s.bounds();
        std::vector<RayRecord> rays;
        std::vector<bool> inside;
        float v[9];
        for (std::uint32_t id = 0; id < s.triangle_count(); id += 3) {
            s.triangle(id, v);
            int a = int(id % 3);
            float o[3] = {v[0], v[1], v[2]}, d[3] = {0, 0, 0};
            o[a] = float((id / 3) % 2 ? (&b.lo.x)[a] - 1 : (&b.hi.x)[a] + 1);
            d[a] = (id / 3) % 2 ? 1.0f : -1.0f;
            rays.push_back(ray(o[0], o[1], o[2], d[0], d[1], d[2]));
            inside.push_back(false);
        }
        check_parity(q, rays, inside);
    }
}

TEST_CASE("split batches, layouts and device buffers answer as one batch", "[device][rays]")
{
    Scene s = load_scene({CLVIS_SOURCE_DIR "/scenes/spot.obj"});
    std::vector<RayRecord> rays = mixed_rays(s, 1000, 9);
    Renderer renderer(Device::open(), s);
    RayQuery whole(renderer), split(renderer, RayQueryOptions{37, false});
    Answers a = answer(whole, rays), b = answer(split, rays);
    CHECK(a.stats.batches == 1);
    CHECK(b.stats.batches == (rays.size() + 36) / 37);
    // the kernels' count of invalid rays (a device word, or host memory the device works on in
    // place) against the host's own judgement of each ray
    std::size_t invalid = std::size_t(
        std::count_if(rays.begin(), rays.end(), [](const RayRecord& r) { return !ray_is_valid(r); }));
    REQUIRE(invalid > 0);
    CHECK(a.stats.invalid == invalid);
    CHECK(b.stats.invalid == a.stats.invalid);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        REQUIRE(same_hit(a.hits[i], b.hits[i]));
        REQUIRE(a.flags[i] == b.flags[i]);
        REQUIRE(a.counts[i] == b.counts[i]);
    }
    // structure of arrays on the host
    std::vector<float> f[8];
    for (int k = 0; k < 8; ++k)
        for (const RayRecord& r : rays) f[k].push_back((&r.ox)[k]);
    RaySoA soa{f[0].data(), f[1].data(), f[2].data(), f[3].data(), f[4].data(), f[5].data(), f[6].data(), f[7].data()};
    std::vector<float> t(rays.size()), hu(rays.size()), hv(rays.size());
    std::vector<std::uint32_t> id(rays.size());
    split.closest({soa, rays.size()}, HitSoA{t.data(), id.data(), hu.data(), hv.data()});
    for (std::size_t i = 0; i < rays.size(); ++i)
        REQUIRE(same_hit(a.hits[i], HitRecord{t[i], id[i], hu[i], hv[i]}));
    // rays and hits in the caller's cl_mem, SoA with a stride larger than the count
    cl_context ctx = renderer.device().context();
    cl_int err = 0;
    std::size_t stride = rays.size() + 5;
    std::vector<float> planes(8 * stride, 0.0f);
    for (int k = 0; k < 8; ++k) std::copy(f[k].begin(), f[k].end(), planes.begin() + std::ptrdiff_t(k * stride));
    cl_mem in = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, planes.size() * 4, planes.data(), &err);
    REQUIRE(err == CL_SUCCESS);
    cl_mem out = clCreateBuffer(ctx, CL_MEM_READ_WRITE, rays.size() * sizeof(HitRecord), nullptr, &err);
    REQUIRE(err == CL_SUCCESS);
    RayQueryStats st = split.closest(DeviceRays{in, RayLayout::SoA, rays.size(), stride}, DeviceResults{out, RayLayout::AoS, 0});
    CHECK(st.invalid == a.stats.invalid);
    std::vector<HitRecord> back(rays.size());
    REQUIRE(clEnqueueReadBuffer(renderer.device().queue(), out, CL_TRUE, 0, back.size() * sizeof(HitRecord), back.data(), 0,
                                nullptr, nullptr) == CL_SUCCESS);
    for (std::size_t i = 0; i < rays.size(); ++i) REQUIRE(same_hit(a.hits[i], back[i]));
    // the same rays from the host as planes back to back in one array (read in place on PoCL's
    // CPU device), and as the planes above, spaced alike but apart (read through the staging
    // buffers: the memory between them is not the caller's array)
    std::vector<float> packed;
    for (int k = 0; k < 8; ++k) packed.insert(packed.end(), f[k].begin(), f[k].end());
    const std::size_t n = rays.size();
    const float *p = packed.data(), *q = planes.data();
    RaySoA back_to_back{p, p + n, p + 2 * n, p + 3 * n, p + 4 * n, p + 5 * n, p + 6 * n, p + 7 * n};
    RaySoA apart{q, q + stride, q + 2 * stride, q + 3 * stride, q + 4 * stride, q + 5 * stride, q + 6 * stride,
                 q + 7 * stride};
    std::vector<HitRecord> from_packed(n), from_apart(n);
    CHECK(split.closest({back_to_back, n}, from_packed.data()).invalid == a.stats.invalid);
    CHECK(whole.closest({apart, n}, from_apart.data()).invalid == a.stats.invalid);
    for (std::size_t i = 0; i < n; ++i) {
        REQUIRE(same_hit(a.hits[i], from_packed[i]));
        REQUIRE(same_hit(a.hits[i], from_apart[i]));
    }
    // a buffer too small for the count is refused before any launch
    CHECK_THROWS_AS(split.count(DeviceRays{in, RayLayout::AoS, stride + 1, 0}, DeviceResults{out, RayLayout::AoS, 0}), Error);
    clReleaseMemObject(in);
    clReleaseMemObject(out);
}

TEST_CASE("rays walked interleaved in one work-item answer as rays walked alone", "[device][rays]")
{
    // Work-items walk `lanes` rays at once and take their next ray as one ends: odd counts leave
    // a work-item fewer rays than lanes (one, or none past the first), and the mixed rays end at
    // every depth (invalid at once, misses near the root, hits deep, any-hits early).
    Scene s = scene_of(make_soup(3000, 11));
    std::vector<RayRecord> rays = mixed_rays(s, 1001, 12);
    Renderer renderer(Device::open(), s);
    RayQuery alone(renderer, RayQueryOptions{std::size_t(1) << 20, false, 1});
    for (std::size_t n : {std::size_t(1), std::size_t(2), std::size_t(7), rays.size()}) {
        std::vector<RayRecord> some(rays.begin(), rays.begin() + std::ptrdiff_t(n));
        Answers a = answer(alone, some);
        for (int lanes : {2, 3, 8}) {
            for (std::size_t batch : {std::size_t(1) << 20, std::size_t(37)}) {
                INFO(n << " rays, " << lanes << " lanes, batches of " << batch);
                RayQuery q(renderer, RayQueryOptions{batch, false, lanes});
                Answers b;
                b.hits.assign(n, HitRecord{-1.0f, 12345u, -1.0f, -1.0f}); // not an answer: must be overwritten
                b.flags.assign(n, 7);
                b.counts.assign(n, 99999u);
                b.stats = q.closest({some.data(), n}, b.hits.data());
                q.occluded({some.data(), n}, b.flags.data());
                q.count({some.data(), n}, b.counts.data());
                CHECK(b.stats.invalid == a.stats.invalid);
                for (std::size_t i = 0; i < n; ++i) {
                    INFO("ray " << i);
                    REQUIRE(same_hit(a.hits[i], b.hits[i]));
                    REQUIRE(a.flags[i] == b.flags[i]);
                    REQUIRE(a.counts[i] == b.counts[i]);
                }
            }
        }
    }
    std::size_t hits = 0;
    Answers all = answer(alone, rays);
    for (const HitRecord& h : all.hits) hits += h.id != background_id;
    CHECK(hits > rays.size() / 20); // the soup is hit, so walks end at different depths
}

TEST_CASE("ray queries refuse null arrays and bad options", "[device][rays]")
{
    Scene s = scene_of(make_uv_sphere(100));
    Renderer renderer(Device::open(), s);
    CHECK_THROWS_AS(RayQuery(renderer, RayQueryOptions{0, false}), Error);
    CHECK_THROWS_AS(RayQuery(renderer, RayQueryOptions{64, false, 9}), Error);
    CHECK_THROWS_AS(RayQuery(renderer, RayQueryOptions{64, false, -1}), Error);
    RayQuery q(renderer);
    HitRecord h;
    CHECK_THROWS_AS(q.closest({static_cast<const RayRecord*>(nullptr), 1}, &h), Error);
    RayRecord r = ray(0, 0, 5, 0, 0, -1);
    CHECK_THROWS_AS(q.closest({&r, 1}, static_cast<HitRecord*>(nullptr)), Error);
    CHECK(q.closest({&r, 0}, static_cast<HitRecord*>(nullptr)).rays == 0);
    CHECK(q.closest({&r, 1}, &h).invalid == 0);
    CHECK(h.id != background_id);
    CHECK(h.t == Approx(4.0f).margin(0.06)); // a coarse sphere
    CHECK(h.u >= 0.0f);
    CHECK(h.v >= 0.0f);
    CHECK(h.u + h.v <= 1.0f);
    CHECK(std::string(to_string(ray_query_kind_from_string("count"))) == "count");
    CHECK_THROWS_AS(ray_query_kind_from_string("nearest"), Error);
}

TEST_CASE("ambient occlusion and shadows from a visibility buffer are reproducible", "[device][rays]")
{
    Scene s = load_scene({CLVIS_SOURCE_DIR "/scenes/spot.obj"});
    Renderer renderer(Device::open(), s);
    Camera cam = Camera::framing(s.bounds());
    VisibilityBuffer vis = renderer.render(cam, 120, 90, Path::Ray);
    RayQuery q(renderer), small(renderer, RayQueryOptions{1000, false});
    AoOptions o;
    o.rays = 8;
    PixelRays a = q.ambient_occlusion(vis, cam, o), b = small.ambient_occlusion(vis, cam, o);
    CHECK(a.value == b.value);
    CHECK(a.stats.invalid == 0);
    // the rays it traced, as the caller may fetch them, answer the same
    std::vector<RayRecord> traced = q.ambient_occlusion_rays(vis, cam, o);
    REQUIRE(traced.size() == a.value.size() * 8);
    std::vector<std::uint8_t> flags(traced.size());
    q.occluded({traced.data(), traced.size()}, flags.data());
    for (std::size_t i = 0; i < a.value.size(); ++i) {
        int open = 0;
        for (std::size_t k = 0; k < 8; ++k) open += flags[8 * i + k] == 0;
        REQUIRE(a.value[i] == float(open) / 8.0f);
    }
    HostVisibility hv = vis.read();
    std::size_t covered_pixels = 0;
    for (std::uint32_t id : hv.ids) covered_pixels += id != background_id;
    CHECK(a.stats.rays == covered_pixels * 8u); // rays for covered pixels only
    std::size_t open = 0, dark = 0, covered = 0;
    for (std::size_t i = 0; i < a.value.size(); ++i) {
        if (hv.ids[i] == background_id) {
            REQUIRE(a.value[i] == 1.0f);
            continue;
        }
        ++covered;
        open += a.value[i] == 1.0f;
        dark += a.value[i] < 0.5f;
    }
    CHECK(open > covered / 10); // most of a convex-ish surface sees the sky
    CHECK(dark > 0);            // creases (legs, ears) are occluded
    o.seed = 2;
    CHECK(q.ambient_occlusion(vis, cam, o).value != a.value);
    o.rays = 0;
    CHECK_THROWS_AS(q.ambient_occlusion(vis, cam, o), Error);
    // a light far above: the underside of spot is in shadow, its back lit
    PixelRays sh = q.shadows(vis, cam, Vec3{0, 100, 0});
    std::size_t lit = 0, shadowed = 0;
    for (std::size_t i = 0; i < sh.value.size(); ++i) {
        if (hv.ids[i] == background_id) continue;
        lit += sh.value[i] == 1.0f;
        shadowed += sh.value[i] == 0.0f;
    }
    CHECK(lit > 0);
    CHECK(shadowed > 0);
}
