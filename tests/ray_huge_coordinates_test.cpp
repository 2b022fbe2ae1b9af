// Huge finite coordinates on the watertight ray test (issue 34): triangles with vertices anywhere in
// float32's range beside an ordinary mesh, judged by the referee on the ray path's two mappings and
// the brute path, and the ray queries judged by their oracle, with brute force and the BVH equal.
#include "catch.hpp"
#include "ray_oracle.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>
#include <clvis/ray_query.hpp>

#include <cmath>
#include <cstring>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace clvis;

namespace {

/// The referee's verdict on one buffer: unacceptable ids and depths, with the first few described.
std::string judged(const Referee& ref, const HostVisibility& v, std::size_t* errors)
{
    CompareOptions o;
    o.max_reported = 4;
    CompareReport r = ref.check(v, o);
    *errors = r.errors + r.depth_errors;
    std::ostringstream s;
    s << r.errors << " errors, " << r.depth_errors << " depth errors";
    for (const PixelVerdict& p : r.first_errors) s << "\n  " << p.describe();
    return s.str();
}

/// Both ray mappings (and the brute path when `brute`) on `scene` seen by `cam`, each judged by the
/// referee.
void check_paths(const Scene& scene, const Camera& cam, int w, int h, const std::string& what, bool brute)
{
    Device device = Device::open();
    Referee ref(scene, cam, w, h);
    for (RayMapping mapping : {RayMapping::Packet, RayMapping::Single}) {
        RenderOptions o;
        o.ray_mapping = mapping;
        Renderer r(device, scene, o);
        for (Path p : {Path::Ray, Path::Brute}) {
            if (p == Path::Brute && (!brute || mapping == RayMapping::Single)) continue;
            std::size_t errors = 0;
            std::string verdict = judged(ref, r.render(cam, w, h, p).read(), &errors);
            INFO(what << ", " << to_string(p) << " path, " << to_string(mapping) << " mapping: " << verdict);
            CHECK(errors == 0);
        }
    }
}

/// Primary rays at pixel centres as ray records, limited to [near, far].
std::vector<RayRecord> primary_rays(const Camera& cam, int w, int h)
{
    std::vector<RayRecord> rays;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Ray r = cam.primary_ray(x + 0.5, y + 0.5, w, h);
            rays.push_back({float(r.origin.x), float(r.origin.y), float(r.origin.z), float(cam.near),
                            float(r.direction.x), float(r.direction.y), float(r.direction.z), float(cam.far)});
        }
    return rays;
}

/// The ray queries (closest, any, count) with the camera's primary rays: occlusion is whether a
/// closest hit exists, every closest hit (id and t as depth) is acceptable to the referee at its
/// pixel, and (when `brute`) the BVH's answers equal brute force's bit for bit.
void check_queries(const Scene& scene, const Camera& cam, int w, int h, const std::string& what, bool brute)
{
    Renderer renderer(Device::open(), scene);
    RayQuery bvh(renderer), all(renderer, RayQueryOptions{std::size_t(1) << 20, true});
    std::vector<RayRecord> rays = primary_rays(cam, w, h);
    std::size_t n = rays.size();
    std::vector<HitRecord> hb(n), hf(n);
    std::vector<std::uint8_t> ob(n), of(n);
    std::vector<std::uint32_t> cb(n), cf(n);
    bvh.closest({rays.data(), n}, hb.data());
    bvh.occluded({rays.data(), n}, ob.data());
    bvh.count({rays.data(), n}, cb.data());
    if (brute) {
        all.closest({rays.data(), n}, hf.data());
        all.occluded({rays.data(), n}, of.data());
        all.count({rays.data(), n}, cf.data());
    } else {
        hf = hb;
        of = ob;
        cf = cb;
    }
    Referee ref(scene, cam, w, h);
    std::size_t differ = 0, bad = 0, hits = 0;
    std::string first;
    for (std::size_t i = 0; i < n; ++i) {
        differ += std::memcmp(&hb[i], &hf[i], sizeof(HitRecord)) != 0 || ob[i] != of[i] || cb[i] != cf[i];
        differ += ob[i] != (hb[i].id != background_id);
        hits += hb[i].id != background_id;
        SampleAnswer answer;
        answer.id = hb[i].id;
        answer.has_depth = true;
        answer.depth = hb[i].t;
        PixelVerdict v = ref.judge(int(i % std::size_t(w)), int(i / std::size_t(w)), answer);
        if (!v.acceptable() || !v.depth_acceptable()) {
            if (!bad) first = v.describe();
            ++bad;
        }
    }
    INFO(what << ", ray queries: " << differ << " differ from brute force, " << bad << " of " << n
              << " closest hits unacceptable (" << hits << " hits)" << (bad ? ", first: " + first : std::string()));
    CHECK(differ == 0);
    CHECK(bad == 0);
}

/// A coordinate of magnitude log-uniform in [2^-126, FLT_MAX], either sign.
float any_magnitude(std::mt19937_64& rng)
{
    std::uniform_real_distribution<double> e(-126, 128), sign(0, 1);
    double m = std::fmin(std::exp2(e(rng)), 3.4028234e38);
    return float(sign(rng) < 0.5 ? -m : m);
}

} // namespace

TEST_CASE("triangles at +-3e38 beside the bunny: no pixel where they do not cover it", "[device][ray][huge]")
{
    // The report: a plane x = 0.1 beside the bunny, its corners at +-3e38 (the float test's hit
    // distance cancelled to garbage: tens of thousands of pixels missed or hit wrongly), and two
    // more such triangles.
    const float big = 3e38f;
    Camera cam = Camera::perspective({-0.02, 0.11, 0.3}, {-0.02, 0.11, 0}, {0, 1, 0}, 40, 0.01, 10);
    MeshData tris[] = {test::triangle(0.1f, -big, -big, 0.1f, big, -big, 0.1f, 0, big),
                       test::triangle(0.2f, 0.1f, -big, big, 0.1f, big, -big, 0.1f, big),
                       test::triangle(0.05f, big, -big, 0.05f, -big, -big, 0.06f, 0, big)};
    for (std::size_t k = 0; k < 3; ++k) {
        Scene s = test::scene_file("stanford-bunny.obj");
        s.add_mesh(tris[k]);
        std::string what = "bunny and huge triangle " + std::to_string(k);
        check_paths(s, cam, 320, 240, what, false); // brute force over the bunny: too slow
        if (k == 0) check_queries(s, cam, 320, 240, what, false);
    }
}

TEST_CASE("random triangles with coordinates over float32's whole range beside a mesh, judged by the referee",
          "[device][ray][huge]")
{
    // Cameras look along a world axis, up along another: their transform only permutes and
    // translates the axes, so the referee's double precision keeps each coordinate's own relative
    // precision (under a rotation, a coordinate of 1e-3 beside one of 1e30 is lost in double too,
    // and the referee itself is wrong where such a triangle's plane passes near the eye).
    const Vec3 axes[6] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
        std::mt19937_64 rng(seed);
        Scene s;
        s.add_mesh(make_uv_sphere(1200));
        MeshData m;
        for (std::uint32_t i = 0; i < 24; ++i) {
            for (int k = 0; k < 9; ++k) m.positions.push_back(any_magnitude(rng));
            m.indices.insert(m.indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
        }
        s.add_mesh(m);
        Vec3 axis = axes[seed - 1];
        Vec3 up = std::fabs(axis.y) > 0 ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
        Camera cam = Camera::perspective(axis * 3.0, {0, 0, 0}, up, 50, 0.05, 1e3);
        std::string what = "seed " + std::to_string(seed);
        check_paths(s, cam, 160, 120, what, true);
        check_queries(s, cam, 160, 120, what, true);
    }
}
