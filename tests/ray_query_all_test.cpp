// All hits of a ray (CONVENTIONS.md "Depth layers", last bullet; RayQuery::all): the BVH walk's
// lists equal the brute force's bit for bit, with and without counts (pruning against the K-th
// hit changes nothing), K = 1 is the closest hit, a shorter list is a longer one's head, and every
// list and count is acceptable to the double-precision oracle of ray_oracle.hpp; rays through
// shared edges and vertices of closed meshes meet every triangle there; instances answer as
// their expansion.
#include "catch.hpp"
#include "ray_oracle.hpp"
#include "ray_query_check.hpp"

#include <CL/cl.h>
#include <clvis/clvis.hpp>
#include <clvis/procedural.hpp>
#include <clvis/ray_query.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

using namespace clvis;
using clvis::test::same_hit;

namespace {

const float inf = std::numeric_limits<float>::infinity();

Scene scene_of(MeshData m)
{
    Scene s;
    s.add_mesh(std::move(m));
    return s;
}

RayRecord ray(float ox, float oy, float oz, float dx, float dy, float dz, float tmin = 0, float tmax = inf)
{
    return RayRecord{ox, oy, oz, tmin, dx, dy, dz, tmax};
}

/// Rays around `scene`: random directions, aimed at vertices and at edge midpoints, with bounded
/// intervals, and a few invalid ones.
std::vector<RayRecord> rays_around(const Scene& scene, std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    Bounds b = scene.bounds();
    Vec3 c = (b.lo + b.hi) * 0.5, e = (b.hi - b.lo) * 0.9;
    std::uniform_real_distribution<double> u(-1, 1);
    std::uniform_int_distribution<std::uint32_t> pick(0, std::uint32_t(scene.triangle_count() - 1));
    std::vector<RayRecord> out;
    float v[9];
    for (std::size_t i = 0; i < n; ++i) {
        float o[3] = {float(c.x + e.x * u(rng)), float(c.y + e.y * u(rng)), float(c.z + e.z * u(rng))};
        scene.triangle(pick(rng), v);
        int k = int(i % 6), corner = int(i % 3);
        float t[3];
        for (int a = 0; a < 3; ++a) t[a] = k == 2 ? 0.5f * (v[3 * corner + a] + v[3 * ((corner + 1) % 3) + a])
                                                  : v[3 * corner + a];
        RayRecord r = ray(o[0], o[1], o[2], float(u(rng)), float(u(rng)), float(u(rng)));
        if (k == 1 || k == 2) r = ray(o[0], o[1], o[2], t[0] - o[0], t[1] - o[1], t[2] - o[2]);
        if (k == 3) r.tmin = float(u(rng) * 0.5 + 0.5), r.tmax = r.tmin * 3.0f;
        if (k == 4 && i % 60 == 4) r.dx = r.dy = r.dz = 0; // invalid: answered as misses
        out.push_back(r);
    }
    return out;
}

struct Lists {
    std::vector<HitRecord> hits;
    std::vector<std::uint32_t> counts;
    RayQueryStats stats;
};

Lists all_hits(RayQuery& q, const std::vector<RayRecord>& rays, int k, bool counts)
{
    Lists l;
    l.hits.resize(rays.size() * std::size_t(k));
    if (counts) l.counts.resize(rays.size());
    l.stats = q.all({rays.data(), rays.size()}, k, l.hits.data(), counts ? l.counts.data() : nullptr);
    return l;
}

void require_same(const Lists& a, const Lists& b)
{
    REQUIRE(a.hits.size() == b.hits.size());
    for (std::size_t i = 0; i < a.hits.size(); ++i) {
        INFO("hit slot " << i);
        REQUIRE(same_hit(a.hits[i], b.hits[i]));
    }
}

/// The oracle's acceptance of ray r's list of k hits and its count: ordered by (t, id), distinct
/// ids, each hit not clearly out and at its t, every clearly-in triangle nearer than the list's
/// last kept hit present (all of them while the list is not full), misses after the hits only,
/// and the count between the clear hits and the clear plus ambiguous ones. Returns a failure or "".
std::string judge_list(const RayRecord& r, const Scene& scene, const HitRecord* h, int k, std::uint32_t count)
{
    std::ostringstream why;
    float v[9];
    int kept = 0;
    while (kept < k && h[kept].id != background_id) ++kept;
    for (int j = kept; j < k; ++j)
        if (h[j].id != background_id || h[j].t != inf || h[j].u != 0.0f || h[j].v != 0.0f)
            return "a miss slot after the hits is not a miss";
    for (int j = 0; j < kept; ++j) {
        if (h[j].id >= scene.triangle_count()) return "id out of range";
        if (j > 0 && !(h[j - 1].t < h[j].t || (h[j - 1].t == h[j].t && h[j - 1].id < h[j].id)))
            return "hits out of (t, id) order";
        scene.triangle(h[j].id, v);
        test::Judged jt = test::judge_triangle(r, v);
        if (jt.verdict == test::Verdict::Out) return "hit " + std::to_string(h[j].id) + " is clearly out";
        if (!jt.any_t && std::fabs(double(h[j].t) - jt.t) > jt.t_tol) return "hit at the wrong t";
    }
    std::uint32_t in = 0, ambiguous = 0;
    double last = kept == k ? double(h[k - 1].t) : std::numeric_limits<double>::infinity();
    for (std::uint32_t id = 0; id < scene.triangle_count(); ++id) {
        scene.triangle(id, v);
        test::Judged jt = test::judge_triangle(r, v);
        in += jt.verdict == test::Verdict::In;
        ambiguous += jt.verdict == test::Verdict::Ambiguous;
        if (jt.verdict != test::Verdict::In || jt.t >= last - jt.t_tol) continue;
        bool listed = false;
        for (int j = 0; j < kept; ++j) listed = listed || h[j].id == id;
        if (!listed) why << "triangle " << id << " clearly in at t = " << jt.t << " is missing; ";
    }
    if (count != std::numeric_limits<std::uint32_t>::max()) {
        if (count < in || count > in + ambiguous) why << "count " << count << " outside [" << in << ", " << in + ambiguous << "]; ";
        if (std::uint32_t(kept) != std::min<std::uint32_t>(count, std::uint32_t(k))) why << "kept " << kept << " of count " << count;
    }
    return why.str();
}

/// Walk versus brute force (bit for bit, with and without counts), K = 1 versus closest, a short
/// list versus a long one's head, and the oracle on the long lists. Returns the rays with more
/// hits than the list keeps.
std::size_t check_all(const Scene& scene, const std::vector<RayRecord>& rays, bool oracle, int k = 8)
{
    Renderer renderer(Device::open(), scene);
    RayQuery walk(renderer), brute(renderer, RayQueryOptions{std::size_t(1) << 20, true});
    Lists a = all_hits(walk, rays, k, true), b = all_hits(brute, rays, k, true), pruned = all_hits(walk, rays, k, false);
    require_same(a, b);
    require_same(a, pruned);
    REQUIRE(a.counts == b.counts);
    std::vector<HitRecord> closest(rays.size());
    RayQueryStats cs = walk.closest({rays.data(), rays.size()}, closest.data());
    Lists one = all_hits(walk, rays, 1, false), three = all_hits(walk, rays, 3, true);
    CHECK(a.stats.invalid == cs.invalid);
    REQUIRE(three.counts == a.counts);
    std::size_t bad = 0, many = 0;
    std::ostringstream failures;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        INFO("ray " << i);
        REQUIRE(same_hit(one.hits[i], closest[i]));
        for (int j = 0; j < 3; ++j) REQUIRE(same_hit(three.hits[3 * i + std::size_t(j)], a.hits[k * i + std::size_t(j)]));
        many += a.counts[i] > std::uint32_t(k);
        if (!ray_is_valid(rays[i])) {
            REQUIRE(a.counts[i] == 0);
            REQUIRE(a.hits[k * i].id == background_id);
            continue;
        }
        if (!oracle) continue;
        std::string why = judge_list(rays[i], scene, &a.hits[k * i], k, a.counts[i]);
        if (!why.empty() && bad++ < 5) failures << "ray " << i << ": " << why << "\n";
    }
    INFO(failures.str());
    CHECK(bad == 0);
    return many;
}

} // namespace

TEST_CASE("all hits through the BVH equal brute force and the oracle on a sphere, a soup and a stack", "[device][ray_query_all]")
{
    Scene sphere = scene_of(make_uv_sphere(2000));
    check_all(sphere, rays_around(sphere, 1200, 3), true);
    Scene soup = scene_of(make_soup(3000, 5));
    check_all(soup, rays_around(soup, 900, 4), true, 4);
    // 12 grids of 32 triangles stacked 0.1 apart (heights within 0.03), rays through the stack: more hits than the list keeps
    MeshData stack;
    stack.name = "stack";
    for (int layer = 0; layer < 12; ++layer) {
        MeshData g = make_grid(32, std::uint64_t(layer + 1));
        auto base = std::uint32_t(stack.positions.size() / 3);
        for (std::size_t i = 0; i < g.positions.size(); i += 3)
            stack.positions.insert(stack.positions.end(), {g.positions[i], 0.1f * g.positions[i + 1] + 0.1f * float(layer), g.positions[i + 2]});
        for (std::uint32_t i : g.indices) stack.indices.push_back(base + i);
    }
    Scene stacked = scene_of(stack);
    CHECK(check_all(stacked, rays_around(stacked, 600, 8), true) > 20);
}

TEST_CASE("all hits on the bunny equal brute force and the oracle", "[device][ray_query_all]")
{
    Scene bunny = load_scene({CLVIS_SOURCE_DIR "/scenes/stanford-bunny.obj"});
    check_all(bunny, rays_around(bunny, 400, 6), true);
}

TEST_CASE("a ray through a shared edge or vertex meets every triangle there, in id order", "[device][ray_query_all]")
{
    // a fan of 6 triangles about the origin in the plane z = 0, and a second fan at z = -2
    MeshData m;
    m.name = "fans";
    for (float z : {0.0f, -2.0f}) {
        auto base = std::uint32_t(m.positions.size() / 3);
        m.positions.insert(m.positions.end(), {0, 0, z});
        float ring[6][2] = {{2, 0}, {1, 2}, {-1, 2}, {-2, 0}, {-1, -2}, {1, -2}};
        for (auto& p : ring) m.positions.insert(m.positions.end(), {p[0], p[1], z});
        for (std::uint32_t j = 0; j < 6; ++j) m.indices.insert(m.indices.end(), {base, base + 1 + j, base + 1 + (j + 1) % 6});
    }
    Scene s = scene_of(m);
    Renderer renderer(Device::open(), s);
    RayQuery q(renderer);
    // through the shared vertex (the fan centre): all 6 triangles of each fan; through the edge
    // from the centre to (-2, 0): its two triangles of each fan
    std::vector<RayRecord> rays = {ray(0, 0, 5, 0, 0, -1), ray(-1, 0, 5, 0, 0, -1), ray(-1, 0, 5, 0, 0, -1, 0, 6)};
    const int k = 16;
    Lists a = all_hits(q, rays, k, true);
    REQUIRE(a.counts == std::vector<std::uint32_t>{12, 4, 2});
    for (int j = 0; j < 12; ++j) {
        CHECK(a.hits[std::size_t(j)].id == std::uint32_t(j));
        CHECK(a.hits[std::size_t(j)].t == (j < 6 ? 5.0f : 7.0f));
    }
    std::uint32_t edge[4] = {2, 3, 8, 9};
    for (int j = 0; j < 4; ++j) CHECK(a.hits[k + std::size_t(j)].id == edge[j]);
    CHECK(a.hits[k + 4].id == background_id);
    CHECK(a.hits[2 * k + 1].id == 3u);
    CHECK(a.hits[2 * k + 2].id == background_id);
    // the half-open count sees one crossing per fan
    std::vector<std::uint32_t> crossings(rays.size());
    q.count({rays.data(), rays.size()}, crossings.data());
    CHECK(crossings == std::vector<std::uint32_t>{2, 2, 1});
}

TEST_CASE("rays through the vertices of a closed sphere meet it at least twice", "[device][ray_query_all]")
{
    MeshData sphere = make_uv_sphere(800);
    Scene s = scene_of(sphere);
    Renderer renderer(Device::open(), s);
    RayQuery q(renderer);
    Bounds b = s.bounds();
    Vec3 c = (b.lo + b.hi) * 0.5;
    std::vector<RayRecord> rays;
    float v[9];
    for (std::uint32_t id = 0; id < s.triangle_count(); id += 3) {
        s.triangle(id, v);
        for (int corner = 0; corner < 3; ++corner) {
            // from outside through a vertex (or an edge midpoint) and on through the sphere
            float t[3];
            for (int a = 0; a < 3; ++a)
                t[a] = corner == 2 ? 0.5f * (v[a] + v[3 + a]) : v[3 * corner + a];
            float o[3] = {float(c.x + 3 * (t[0] - c.x)), float(c.y + 3 * (t[1] - c.y)) + 0.01f, float(c.z + 3 * (t[2] - c.z))};
            rays.push_back(ray(o[0], o[1], o[2], t[0] - o[0], t[1] - o[1], t[2] - o[2]));
        }
    }
    // along -z through the vertices of the upper half (no silhouette vertex: no grazing ray)
    std::size_t through = rays.size();
    for (std::size_t i = 0; i < sphere.vertex_count(); ++i) {
        const float* p = &sphere.positions[3 * i];
        if (p[2] > 0.3f) rays.push_back(ray(p[0], p[1], 4.0f, 0, 0, -1));
    }
    REQUIRE(rays.size() > through + 20);
    Lists a = all_hits(q, rays, 8, true);
    std::size_t many = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        INFO("ray " << i);
        REQUIRE(a.counts[i] >= 2); // watertight: no ray slips through an edge or a vertex
        many += a.counts[i] > 2;
    }
    CHECK(many > (rays.size() - through) / 2); // exactly through a vertex: every triangle around it
    check_all(s, rays, true);
}

TEST_CASE("all hits of a scene with instances equal its expansion's", "[device][ray_query_all]")
{
    MeshData sphere = make_uv_sphere(600);
    Scene inst, flat;
    std::size_t p = inst.add_prototype(sphere);
    Mat4 shifts[3];
    for (int j = 0; j < 3; ++j) {
        shifts[j](0, 3) = 0.7 * j;
        shifts[j](1, 3) = 0.1 * j;
        shifts[j](0, 0) = 1.0 + 0.2 * j;
        inst.add_instance(p, shifts[j]);
        flat.add_mesh(sphere, shifts[j]);
    }
    std::vector<RayRecord> rays = rays_around(flat, 600, 9);
    Renderer ri(Device::open(), inst), rf(Device::open(), flat);
    RayQuery qi(ri), qf(rf);
    for (bool counts : {false, true}) {
        Lists a = all_hits(qi, rays, 6, counts), b = all_hits(qf, rays, 6, counts);
        require_same(a, b);
        REQUIRE(a.counts == b.counts);
    }
    check_all(flat, rays, false);
}

TEST_CASE("all hits refuse a bad max_hits; split batches, SoA and device rays answer as one batch",
          "[device][ray_query_all]")
{
    Scene s = scene_of(make_uv_sphere(400));
    Renderer renderer(Device::open(), s);
    RayQuery q(renderer), small(renderer, RayQueryOptions{100, false});
    std::vector<RayRecord> rays = rays_around(s, 500, 11);
    std::vector<HitRecord> hits(rays.size() * 64);
    CHECK_THROWS_AS(q.all({rays.data(), rays.size()}, 0, hits.data()), Error);
    CHECK_THROWS_AS(q.all({rays.data(), rays.size()}, 65, hits.data()), Error);
    CHECK_THROWS_AS(q.all({rays.data(), rays.size()}, 4, nullptr), Error);
    Lists a = all_hits(q, rays, 64, true), b = all_hits(small, rays, 64, true);
    CHECK(b.stats.batches > 1); // 100 hit records per batch: one ray per batch at K = 64
    require_same(a, b);
    CHECK(a.counts == b.counts);
    Lists c = all_hits(q, rays, 5, true), d = all_hits(small, rays, 5, true);
    require_same(c, d);
    // rays as SoA planes on the host, and in the caller's cl_mem (SoA, a stride past the count)
    std::size_t stride = rays.size() + 3;
    std::vector<float> planes(8 * stride, 0.0f);
    for (std::size_t i = 0; i < rays.size(); ++i)
        for (std::size_t f = 0; f < 8; ++f) planes[f * stride + i] = (&rays[i].ox)[f];
    const float* p = planes.data();
    RaySoA soa{p, p + stride, p + 2 * stride, p + 3 * stride, p + 4 * stride, p + 5 * stride, p + 6 * stride, p + 7 * stride};
    Lists e;
    e.hits.resize(rays.size() * 5);
    e.counts.resize(rays.size());
    small.all({soa, rays.size()}, 5, e.hits.data(), e.counts.data());
    require_same(c, e);
    CHECK(c.counts == e.counts);
    cl_int err = 0;
    cl_mem in = clCreateBuffer(renderer.device().context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, planes.size() * 4,
                               planes.data(), &err);
    REQUIRE(err == CL_SUCCESS);
    Lists f;
    f.hits.resize(rays.size() * 5);
    small.all(DeviceRays{in, RayLayout::SoA, rays.size(), stride}, 5, f.hits.data());
    clReleaseMemObject(in);
    require_same(c, f);
}
