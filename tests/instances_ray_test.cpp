// Instances on the ray path (CONVENTIONS.md "Instances", host/ray/bvh_instances.cpp): one tree per
// prototype and a top level over the instances, yet every path draws the bits of the expansion
// (rotations, scales, mirrors, exact ties between coincident instances, instances behind the
// eye); a move rebuilds the top level only; each instance costs a few dozen device bytes.
#include "catch.hpp"
#include "render/renderer_probe.hpp"
#include "scene/instance_transform.hpp"
#include "test_files.hpp"

#include <clvis/clvis.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace clvis;

namespace {

Mat4 placed(double yaw, double pitch, Vec3 offset, Vec3 scale)
{
    double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(pitch), sp = std::sin(pitch);
    // rotation about y, then about x, times a diagonal scale (a negative entry mirrors)
    double r[3][3] = {{cy, 0, sy}, {sp * sy, cp, -sp * cy}, {-cp * sy, sp, cp * cy}};
    Mat4 m;
    double s[3] = {scale.x, scale.y, scale.z}, t[3] = {offset.x, offset.y, offset.z};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) m(i, j) = r[i][j] * s[j];
        m(i, 3) = t[i];
    }
    return m;
}

/// Plain quads and spot instances interleaved: rotated, scaled, mirrored (two of them), two
/// coincident (exact ties: the lower id must win), one reaching behind the camera at the origin.
Scene spots(bool instanced)
{
    MeshData spot = load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj");
    MeshData quad;
    quad.name = "quad";
    quad.positions = {-3, -3, 0, 3, -3, 0, 3, 3, 0, -3, 3, 0};
    quad.indices = {0, 1, 2, 0, 2, 3};
    Scene s;
    std::size_t p = instanced ? s.add_prototype(spot) : 0;
    auto place = [&](const Mat4& t) { instanced ? s.add_instance(p, t) : s.add_mesh(spot, t); };
    s.add_mesh(quad, placed(0, 0, {0, 0, -6}, {2, 2, 2}));
    place(placed(0.3, 0.1, {-0.9, 0, -3}, {0.8, 0.8, 0.8}));
    place(placed(2.1, -0.4, {0.8, 0.2, -3.5}, {-1.1, 0.9, 1.0})); // mirrored
    s.add_mesh(quad, placed(0.5, 0.2, {0, -1.5, -4}, {0.4, 0.4, 0.4}));
    place(placed(-1.2, 0.0, {0.1, -0.6, -2.5}, {0.5, 0.5, -0.5}));   // mirrored
    place(placed(-1.2, 0.0, {0.1, -0.6, -2.5}, {0.5, 0.5, -0.5}));   // coincident with the one before
    place(placed(0.7, 0.3, {0.6, 0.7, -0.2}, {1.3, 1.3, 1.3}));      // reaches behind the eye
    return s;
}

bool same_bits(const HostVisibility& a, const HostVisibility& b)
{
    return a.ids == b.ids && a.depth.size() == b.depth.size() &&
           std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0;
}

Camera eye_at_origin() { return Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 70, 0.05, 50); }

} // namespace

TEST_CASE("an instance's world box holds its float32 vertices", "[instances]")
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1, 1);
    for (int trial = 0; trial < 200; ++trial) {
        Mat4 t = placed(u(rng) * 3, u(rng) * 3, {u(rng) * 1e3, u(rng), u(rng) * 1e-3},
                        {u(rng) * 4, u(rng) * 1e-2, u(rng) * 1e2});
        auto m = detail::instance_matrix(t);
        float lo[3] = {u(rng), u(rng) * 100, u(rng) * 1e-4f}, hi[3];
        for (int a = 0; a < 3; ++a) hi[a] = lo[a] + std::fabs(u(rng)) * (a + 1);
        float wlo[3], whi[3];
        clvis_instance_box(m.data(), lo, hi, wlo, whi);
        for (int corner = 0; corner < 64; ++corner) {
            float p[3];
            for (int a = 0; a < 3; ++a) {
                float f = corner < 8 ? float((corner >> a) & 1) : (u(rng) + 1) / 2;
                p[a] = f == 1 ? hi[a] : lo[a] + f * (hi[a] - lo[a]);
            }
            clvis_vec3 w = clvis_instance_point(m.data(), p[0], p[1], p[2]);
            INFO("trial " << trial << " corner " << corner);
            CHECK((w.x >= wlo[0] && w.x <= whi[0] && w.y >= wlo[1] && w.y <= whi[1] && w.z >= wlo[2] && w.z <= whi[2]));
        }
    }
    float empty_lo[3] = {1, 1, 1}, empty_hi[3] = {0, 0, 0}, wlo[3], whi[3];
    auto m = detail::instance_matrix(placed(0.4, 0.2, {1, 2, 3}, {2, 2, 2}));
    clvis_instance_box(m.data(), empty_lo, empty_hi, wlo, whi);
    CHECK(wlo[0] > whi[0]); // an empty box stays empty
}

TEST_CASE("instanced scenes trace bit-identical to their expansion on every path", "[device][instances]")
{
    Device device = Device::open();
    Scene a = spots(true), b = spots(false);
    Camera cam = eye_at_origin();
    for (Cull cull : {Cull::None, Cull::Back}) {
        for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
            RenderOptions o;
            o.cull = cull;
            o.coverage = coverage;
            Renderer ra(device, a, o), rb(device, b, o);
            for (Path path : {Path::Ray, Path::Brute, Path::Raster}) {
                if (path == Path::Brute && (cull != Cull::None || coverage != Coverage::Watertight)) continue;
                INFO(to_string(path) << " cull " << int(cull) << " " << to_string(coverage));
                HostVisibility va = ra.render(cam, 64, 48, path).read();
                CHECK(same_bits(va, rb.render(cam, 64, 48, path).read()));
                std::size_t covered = 0, tied_loser = 0;
                std::uint32_t loser = a.meshes()[5].first_triangle; // the second coincident instance
                for (std::uint32_t id : va.ids) {
                    covered += id != background_id;
                    tied_loser += id != background_id && id >= loser && id < loser + a.data_of(5).triangle_count();
                }
                CHECK(covered > 64 * 48 / 8);
                CHECK(tied_loser == 0); // every tie goes to the lower id: the first of the pair
            }
            CHECK(ra.bvh_stats().instances == 6); // five instances and the plain meshes
        }
    }
    RenderOptions o;
    for (RasterAtomics atomics : {RasterAtomics::Off, RasterAtomics::Auto}) {
        o.raster_atomics = atomics;
        Renderer ra(device, a, o), rb(device, b, o);
        INFO(to_string(atomics));
        CHECK(same_bits(ra.render(cam, 64, 48, Path::Raster).read(), rb.render(cam, 64, 48, Path::Raster).read()));
    }
}

TEST_CASE("ray queries on an instanced scene answer as on its expansion", "[device][instances]")
{
    Device device = Device::open();
    Scene a = spots(true), b = spots(false);
    Renderer ra(device, a), rb(device, b);
    RayQuery qa(ra), qb(rb);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<RayRecord> rays;
    for (int i = 0; i < 3000; ++i) rays.push_back({u(rng) * 0.3f, u(rng) * 0.3f, 0.5f, 0, u(rng), u(rng), -1, 100});
    std::vector<HitRecord> ha(rays.size()), hb(rays.size());
    qa.closest({rays.data(), rays.size()}, ha.data());
    qb.closest({rays.data(), rays.size()}, hb.data());
    CHECK(std::memcmp(ha.data(), hb.data(), ha.size() * sizeof(HitRecord)) == 0);
    // After a move the queries see the moved instance, as on the moved expansion.
    Mat4 moved = placed(1.0, 0.5, {0, 0, -2}, {1, 1, 1});
    a.set_transform(1, moved);
    b.set_transform(1, moved);
    ra.update(a);
    rb.update(b);
    std::vector<HitRecord> ma(rays.size()), mb(rays.size());
    qa.closest({rays.data(), rays.size()}, ma.data());
    qb.closest({rays.data(), rays.size()}, mb.data());
    CHECK(std::memcmp(ma.data(), mb.data(), ma.size() * sizeof(HitRecord)) == 0);
    CHECK(std::memcmp(ma.data(), ha.data(), ma.size() * sizeof(HitRecord)) != 0);
}

namespace {

/// spots() and three instances of a quad side by side far to the right: the first two share the
/// edge x = 103, the second and the third (mirrored) x = 109, all with the same float bits.
Scene spots_and_tiles(bool instanced)
{
    Scene s = spots(instanced);
    MeshData quad;
    quad.name = "tile";
    quad.positions = {-3, -3, 0, 3, -3, 0, 3, 3, 0, -3, 3, 0};
    quad.indices = {0, 1, 2, 0, 2, 3};
    std::size_t p = instanced ? s.add_prototype(quad) : 0;
    for (const Mat4& t : {placed(0, 0, {100, 0, -5}, {1, 1, 1}), placed(0, 0, {106, 0, -5}, {1, 1, 1}),
                          placed(0, 0, {112, 0, -5}, {-1, 1, 1})})
        instanced ? s.add_instance(p, t) : s.add_mesh(quad, t);
    return s;
}

/// Rays from the eye, from inside the spot instances (mirrored ones too), and straight down
/// through the tiles' shared edges (first 200) and their inner diagonals.
std::vector<RayRecord> probe_rays()
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<RayRecord> rays;
    for (int i = 0; i < 100; ++i) {
        float y = u(rng) * 2.9f;
        rays.push_back({103, y, 0, 0, 0, 0, -1, 100});
        rays.push_back({109, y, 0, 0, 0, 0, -1, 100});
    }
    for (int i = 0; i < 200; ++i) {
        float x = u(rng) * 2.9f;
        rays.push_back({100 + x, x, 0, 0, 0, 0, -1, 100});     // the diagonal of the first tile
        rays.push_back({112 - x, x, 0, 0, 0.1f, 0, -1, 100}); // near the mirrored one's, slanted
    }
    const float inside[4][3] = {{-0.9f, 0, -3}, {0.8f, 0.2f, -3.5f}, {0.1f, -0.6f, -2.5f}, {0.6f, 0.7f, -0.2f}};
    for (int i = 0; i < 2000; ++i) {
        const float* o = inside[i % 4];
        rays.push_back({o[0], o[1], o[2], i % 3 == 0 ? 0.05f : 0.0f, u(rng), u(rng), u(rng), i % 5 == 0 ? 0.4f : 100});
    }
    for (int i = 0; i < 2000; ++i) rays.push_back({u(rng) * 0.3f, u(rng) * 0.3f, 0.5f, 0, u(rng), u(rng), -1, 100});
    return rays;
}

/// Closest (records and SoA), any and count answers of `q` for `rays`, as bytes.
std::vector<unsigned char> answers(RayQuery& q, const std::vector<RayRecord>& rays)
{
    std::size_t n = rays.size();
    std::vector<HitRecord> hits(n);
    q.closest({rays.data(), n}, hits.data());
    std::vector<float> f[8];
    for (std::size_t i = 0; i < n; ++i) {
        const float* r = &rays[i].ox;
        for (int k = 0; k < 8; ++k) f[k].push_back(r[k]);
    }
    RaySoA soa{f[0].data(), f[1].data(), f[2].data(), f[3].data(), f[4].data(), f[5].data(), f[6].data(), f[7].data()};
    std::vector<float> t(n), hu(n), hv(n);
    std::vector<std::uint32_t> id(n), counts(n);
    q.closest({soa, n}, HitSoA{t.data(), id.data(), hu.data(), hv.data()});
    std::vector<std::uint8_t> flags(n);
    q.occluded({rays.data(), n}, flags.data());
    q.count({rays.data(), n}, counts.data());
    std::vector<unsigned char> out;
    auto add = [&](const void* p, std::size_t bytes) {
        out.insert(out.end(), static_cast<const unsigned char*>(p), static_cast<const unsigned char*>(p) + bytes);
    };
    add(hits.data(), n * sizeof(HitRecord));
    for (const auto* v : {&t, &hu, &hv}) add(v->data(), n * 4);
    add(id.data(), n * 4);
    add(flags.data(), n);
    add(counts.data(), n * 4);
    return out;
}

} // namespace

TEST_CASE("queries walk the instances' two levels and equal the expansion's bits", "[device][instances]")
{
    Device device = Device::open();
    Scene a = spots_and_tiles(true), b = spots_and_tiles(false);
    Renderer ra(device, a), rb(device, b);
    RayQuery qa(ra), qb(rb);
    std::uint64_t bytes = ra.bvh_stats().device_bytes;
    std::vector<RayRecord> rays = probe_rays();
    std::vector<unsigned char> got = answers(qa, rays), want = answers(qb, rays);
    REQUIRE(got.size() == want.size());
    CHECK(std::memcmp(got.data(), want.data(), got.size()) == 0);
    std::size_t n = rays.size();
    std::vector<std::uint32_t> counts(n);
    std::memcpy(counts.data(), got.data() + got.size() - 4 * n, 4 * n);
    std::size_t several = 0, hit = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (i < 200) CHECK(counts[i] == 1); // a shared edge of two instances counts once
        several += counts[i] > 1;
        hit += counts[i] > 0;
    }
    CHECK(several > 100); // rays from inside a spot leave it, and some cross others
    CHECK(hit > n / 2);
    // No flat tree of the expansion: the BVH's device bytes are those of the two levels.
    CHECK(ra.bvh_stats().device_bytes == bytes);
    CHECK(bytes < 48 * a.triangle_count());
}

TEST_CASE("moving an instance rebuilds the top level, not its prototype's tree", "[device][instances]")
{
    Device device = Device::open();
    Scene a = spots(true), b = spots(false);
    Renderer ra(device, a), rb(device, b);
    Camera cam = eye_at_origin();
    ra.render(cam, 64, 48, Path::Ray);
    REQUIRE(ra.bvh_stats().prototype_builds == 1); // one prototype, built once for five instances
    for (int step = 1; step <= 3; ++step) {
        Mat4 t = placed(0.5 * step, 0.1 * step, {0.3 * step - 0.6, 0, -2.8}, {0.7, 0.7, 0.7});
        a.set_transform(4, t);
        b.set_transform(4, t);
        ra.update(a);
        rb.update(b);
        INFO("step " << step);
        CHECK(same_bits(ra.render(cam, 64, 48, Path::Ray).read(), rb.render(cam, 64, 48, Path::Ray).read()));
        CHECK(ra.bvh_stats().prototype_builds == 1);
        CHECK(ra.bvh_stats().top_build_ms >= 0);
    }
}

TEST_CASE("each instance adds a few dozen bytes of BVH on the device", "[device][instances]")
{
    Device device = Device::open();
    MeshData spot = load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj");
    auto bytes = [&](int instances) {
        Scene s;
        std::size_t p = s.add_prototype(spot);
        for (int i = 0; i < instances; ++i)
            s.add_instance(p, placed(0.1 * i, 0, {double(i % 20), double(i / 20), 0}, {0.5, 0.5, 0.5}));
        Renderer r(device, s);
        r.render(Camera::framing(s.bounds()), 16, 16, Path::Ray);
        return r.bvh_stats().device_bytes;
    };
    std::uint64_t few = bytes(4), many = bytes(404);
    double per_instance = double(many - few) / 400;
    INFO("bytes: " << few << " for 4 instances, " << many << " for 404");
    // a 56-byte instance and its share of the top level's nodes (one box per full leaf of four,
    // nearly full 4-wide nodes): 67 here
    CHECK(per_instance < 72);
    CHECK(few > 48 * spot.triangle_count()); // the prototype's tree, stored once
}

TEST_CASE("an update refuses a changed prototype and follows a moved instance", "[device][instances]")
{
    Device device = Device::open();
    Scene a = spots(true);
    Renderer r(device, a);
    Scene changed;
    MeshData other = a.prototypes()[0];
    other.positions[0] += 0.5f; // the same topology, another prototype
    std::size_t p = changed.add_prototype(other);
    for (std::size_t i = 0; i < a.meshes().size(); ++i) {
        const Scene::Mesh& m = a.meshes()[i];
        m.prototype == Scene::no_prototype ? changed.add_mesh(m.data, m.transform) : changed.add_instance(p, m.transform);
    }
    CHECK_THROWS_WITH(r.update(changed), Catch::Contains("mesh 1") && Catch::Contains("prototype"));
    Scene plain_moved = a;
    plain_moved.set_transform(0, placed(0.1, 0, {0, 0, -7}, {2, 2, 2}));
    CHECK_NOTHROW(r.update(plain_moved)); // a plain mesh moves too, the instances stay
}

TEST_CASE("the raster path draws instances in chunks with the expansion's keys", "[device][instances][raster]")
{
    Device device = Device::open();
    Scene a = spots_and_tiles(true), b = spots_and_tiles(false);
    Camera cam = eye_at_origin();
    for (RasterAtomics atomics : {RasterAtomics::Off, RasterAtomics::Auto}) {
        for (RasterMapping mapping : {RasterMapping::Square, RasterMapping::Pixel}) {
            for (int samples : {1, 4}) {
                RenderOptions o;
                o.raster_atomics = atomics;
                o.raster_mapping = mapping;
                o.samples = samples;
                o.cull = samples == 4 ? Cull::Back : Cull::None;
                Renderer rb(device, b, o);
                HostVisibility want = rb.render(cam, 64, 48, Path::Raster).read();
                o.region = Region{5, 7, 40, 30};
                HostVisibility want_region = Renderer(device, b, o).render(cam, 64, 48, Path::Raster).read();
                // one chunk; a chunk per item (an item larger than a chunk); several items a chunk
                for (std::size_t chunk : {std::size_t(1) << 21, std::size_t(1), std::size_t(6000)}) {
                    INFO(to_string(atomics) << " " << to_string(mapping) << " samples " << samples << " chunk " << chunk);
                    o.region = Region{};
                    Renderer ra(device, a, o);
                    detail::set_raster_chunk(ra, chunk);
                    CHECK(same_bits(ra.render(cam, 64, 48, Path::Raster).read(), want));
                    CHECK(same_bits(ra.render(cam, 64, 48, Path::Raster).read(), want)); // again, buffers kept
                    o.region = Region{5, 7, 40, 30};
                    Renderer rr(device, a, o);
                    detail::set_raster_chunk(rr, chunk);
                    CHECK(same_bits(rr.render(cam, 64, 48, Path::Raster).read(), want_region));
                    CHECK_FALSE(detail::expansion_uploaded(ra));
                }
            }
        }
    }
}

TEST_CASE("the raster path of an instanced scene never uploads the expansion", "[device][instances][raster]")
{
    Device device = Device::open();
    MeshData spot = load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj");
    Scene s, expanded;
    std::size_t p = s.add_prototype(spot);
    for (int i = 0; i < 300; ++i) {
        Mat4 t = placed(0.1 * i, 0, {double(i % 20), double(i / 20), 0}, {0.5, 0.5, 0.5});
        s.add_instance(p, t);
        expanded.add_mesh(spot, t);
    }
    Camera cam = Camera::framing(s.bounds());
    Renderer r(device, s), re(device, expanded);
    CHECK(detail::item_device_bytes(r) == 0); // nothing before the raster path draws
    HostVisibility got = r.render(cam, 96, 64, Path::Raster).read();
    CHECK_FALSE(detail::expansion_uploaded(r));
    std::uint64_t bytes = detail::item_device_bytes(r);
    INFO("device bytes " << bytes);
    CHECK(bytes <= 24 * spot.triangle_count() + 12 * spot.vertex_count() + 64 * 300 + 64); // mesh once, 64 B an item
    CHECK(bytes >= 12 * spot.triangle_count());
    CHECK(same_bits(got, re.render(cam, 96, 64, Path::Raster).read()));
    // A batch of views draws each as alone, still without the expansion.
    std::vector<Camera> views{cam, eye_at_origin()};
    VisibilityBatch batch(device, 2, 96, 64);
    render_views(r, views, Path::Raster, batch);
    for (int v = 0; v < 2; ++v)
        CHECK(batch.view(v).read_keys() == r.render(views[std::size_t(v)], 96, 64, Path::Raster).read_keys());
    CHECK_FALSE(detail::expansion_uploaded(r));
    // Moving an instance draws it moved, still without the expansion.
    Mat4 moved = placed(1.0, 0.5, {3, 3, 1}, {1, 1, 1});
    s.set_transform(7, moved);
    expanded.set_transform(7, moved);
    r.update(s);
    re.update(expanded);
    HostVisibility after = r.render(cam, 96, 64, Path::Raster).read();
    CHECK(same_bits(after, re.render(cam, 96, 64, Path::Raster).read()));
    CHECK_FALSE(same_bits(after, got));
    CHECK_FALSE(detail::expansion_uploaded(r));
    CHECK(detail::expansion_uploaded(re)); // a plain scene's raster path uploads it
}
