// Attributes resolved from visibility buffers (kernels/resolve.cl): barycentrics of both paths
// judged by the referee of CONVENTIONS.md "Barycentrics" under every camera kind, clipped
// triangles keeping the original's barycentrics, positions and normals against what the
// barycentrics name, the shared header against hand-computed values, and read-back into reused
// storage.
#include "catch.hpp"

#include "shared/resolve.h"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <string>
#include <vector>

using namespace clvis;

namespace {

constexpr double pi = 3.14159265358979323846;

Scene bundled(const char* name)
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + name + ".obj"));
    return s;
}

/// The camera kinds of the agreement suite: look-at, orthographic, intrinsics with an off-centre
/// principal point, and a pose matrix.
std::vector<std::pair<std::string, Camera>> camera_kinds(const Scene& s, int w, int h)
{
    Camera look = Camera::framing(s.bounds());
    Camera ortho = Camera::framing(s.bounds(), Projection::Orthographic);
    Camera intr = look;
    double f = h / (2 * std::tan(22.5 * pi / 180));
    intr.intrinsics = Intrinsics{f * 1.1, f * 0.95, w * 0.3, h * 0.7};
    Camera posed = Camera::from_pose(look.pose(), look);
    posed.eye = posed.eye * 0.8 + s.bounds().center() * 0.2; // closer, same frame
    posed.target = posed.eye + posed.frame().f;
    return {{"look-at", look}, {"ortho", ortho}, {"intrinsics", intr}, {"pose", posed}};
}

void check_barycentrics(Renderer& renderer, const Scene& s, const std::string& name, const Camera& cam, int w, int h)
{
    BarycentricReferee judge(s, cam, w, h);
    for (Path p : {Path::Raster, Path::Ray}) {
        VisibilityBuffer vis = renderer.render(cam, w, h, p);
        HostVisibility host = vis.read();
        AttributeRequest req;
        req.barycentrics = true;
        AttributeBuffers attrs = resolve(renderer, vis, cam, req);
        BaryReport rep = judge.check(host, attrs.read(Attribute::Barycentrics));
        std::string errors;
        for (const auto& e : rep.first_errors) errors += "\n  " + e;
        INFO(name << " " << to_string(p) << ": " << cam.to_flags() << errors);
        CHECK(rep.covered > std::size_t(w * h / 20));
        CHECK(rep.errors == 0);
        std::printf("bary %-24s %-6s %zu covered, max %.2e px, depth error %.2f of tolerance\n", name.c_str(),
                    to_string(p), rep.covered, rep.max_px_error, rep.max_depth_error_share);
    }
}

} // namespace

TEST_CASE("plane barycentrics of the shared header name the ray's point", "[attributes]")
{
    clvis_vec3 a{0, 0, -2}, b{2, 0, -2}, c{0, 4, -2}, o{0, 0, 0}, d{0.5f, 1, -1};
    float u, v, t;
    REQUIRE(clvis_plane_barycentrics(o, d, a, b, c, &u, &v, &t) == 1);
    CHECK(t == Approx(2)); // the plane z = -2, along d = (0.5, 1, -1)
    CHECK(u == Approx(0.5)); // P = (1, 2, -2) = 0.5 b + 0.5 c
    CHECK(v == Approx(0.5));
    // Outside the triangle: the plane's point all the same.
    clvis_vec3 d2{3, -1, -1};
    REQUIRE(clvis_plane_barycentrics(o, d2, a, b, c, &u, &v, &t) == 1);
    CHECK(u == Approx(3));
    CHECK(v == Approx(-0.5));
    // Parallel to the plane: none.
    clvis_vec3 d3{1, 0, 0};
    CHECK(clvis_plane_barycentrics(o, d3, a, b, c, &u, &v, &t) == 0);
    CHECK(u == 0);
    CHECK(v == 0);
}

TEST_CASE("barycentrics of both paths pass the referee under every camera kind", "[device][attributes]")
{
    Device device = Device::open();
    for (const char* name : {"stanford-bunny", "spot"}) {
        Scene s = bundled(name);
        Renderer renderer(device, s);
        const int w = 120, h = 90;
        for (const auto& [kind, cam] : camera_kinds(s, w, h))
            check_barycentrics(renderer, s, std::string(name) + " " + kind, cam, w, h);
    }
}

TEST_CASE("a triangle clipped by near keeps the original triangle's barycentrics", "[device][attributes]")
{
    // One large triangle through the eye's near plane and far beyond the frustum's sides: the
    // raster path clips it into pieces, the barycentrics stay those of the whole.
    Scene s;
    MeshData m;
    m.positions = {-40, -3, 5, 40, -3, 5, 0, 4, -60};
    m.indices = {0, 1, 2};
    s.add_mesh(std::move(m));
    Renderer renderer(Device::open(), s);
    Camera cam = Camera::perspective({0, 0, 0}, {0, -0.2, -1}, {0, 1, 0}, 60, 0.5, 100);
    check_barycentrics(renderer, s, "clipped", cam, 96, 64);
}

TEST_CASE("positions and normals are what the barycentrics name, background NaN", "[device][attributes]")
{
    Device device = Device::open();
    Scene s;
    s.add_mesh(make_uv_sphere(2000));
    Renderer renderer(device, s);
    Camera cam = Camera::framing(s.bounds());
    const int w = 80, h = 60;
    AttributeRequest all;
    all.barycentrics = all.position = all.normal = all.smooth_normal = true;
    AttributeBuffers attrs;
    for (Path p : {Path::Raster, Path::Ray}) {
        VisibilityBuffer vis = renderer.render(cam, w, h, p);
        HostVisibility host = vis.read();
        resolve(renderer, vis, cam, all, attrs);
        std::vector<float> uv = attrs.read(Attribute::Barycentrics), pos = attrs.read(Attribute::Position);
        std::vector<float> n = attrs.read(Attribute::Normal), sn = attrs.read(Attribute::SmoothNormal);
        const bool has_normals = !s.meshes()[0].data.normals.empty();
        std::size_t covered = 0;
        for (std::size_t i = 0; i < host.ids.size(); ++i) {
            INFO(to_string(p) << " pixel " << i);
            if (host.ids[i] == background_id) {
                CHECK((uv[2 * i] == 0 && uv[2 * i + 1] == 0));
                CHECK((std::isnan(pos[3 * i]) && std::isnan(n[3 * i + 1]) && std::isnan(sn[3 * i + 2])));
                continue;
            }
            ++covered;
            float v[9];
            s.triangle(host.ids[i], v);
            Vec3 a{v[0], v[1], v[2]}, b{v[3], v[4], v[5]}, c{v[6], v[7], v[8]};
            double bu = uv[2 * i], bv = uv[2 * i + 1];
            Vec3 at = a * (1 - bu - bv) + b * bu + c * bv;
            CHECK(length(at - Vec3{pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]}) < 1e-6);
            Vec3 g = normalize(cross(b - a, c - a));
            CHECK(length(g - Vec3{n[3 * i], n[3 * i + 1], n[3 * i + 2]}) < 1e-6);
            Vec3 smooth{sn[3 * i], sn[3 * i + 1], sn[3 * i + 2]};
            CHECK(std::fabs(length(smooth) - 1) < 1e-6);
            // The sphere's vertex normals are radial: the smooth normal points away from its centre.
            if (has_normals) CHECK(dot(smooth, normalize(at - s.bounds().center())) > 0.99);
            else CHECK(length(smooth - g) < 1e-6);
        }
        CHECK(covered > std::size_t(w * h / 8));
    }
    // Asking for less releases the rest; nothing asked, nothing made.
    AttributeRequest only;
    only.position = true;
    VisibilityBuffer vis = renderer.render(cam, w, h, Path::Ray);
    resolve(renderer, vis, cam, only, attrs);
    CHECK(attrs.has(Attribute::Position));
    CHECK_FALSE(attrs.has(Attribute::Barycentrics));
    CHECK_THROWS_AS(attrs.buffer(Attribute::Normal), Error);
    resolve(renderer, vis, cam, AttributeRequest{}, attrs);
    CHECK_FALSE(attrs.has(Attribute::Position));
}

TEST_CASE("reads into reused storage equal the allocating read", "[device][renderer]")
{
    Scene s = bundled("spot");
    Renderer renderer(Device::open(), s);
    Camera cam = Camera::framing(s.bounds());
    VisibilityBuffer vis = renderer.render(cam, 64, 48, Path::Raster);
    HostVisibility fresh = vis.read();
    HostVisibility reused;
    reused.ids.reserve(64 * 48);
    reused.depth.reserve(64 * 48);
    const std::uint32_t* before = reused.ids.data();
    vis.read(reused);
    CHECK(reused.ids.data() == before); // no new allocation
    CHECK(reused.ids == fresh.ids);
    CHECK(std::memcmp(reused.depth.data(), fresh.depth.data(), fresh.depth.size() * 4) == 0);
    std::vector<std::uint32_t> ids;
    vis.read_ids(ids);
    CHECK(ids == fresh.ids);
    std::vector<float> depth(64 * 48);
    vis.read(nullptr, depth.data());
    CHECK(std::memcmp(depth.data(), fresh.depth.data(), depth.size() * 4) == 0);
    std::vector<std::uint64_t> keys;
    vis.read_keys(keys);
    HostVisibility split = split_keys(keys.data(), 64, 48);
    CHECK(split.ids == fresh.ids);
}

TEST_CASE("the visible set lists the ids of the buffer, one view or accumulated", "[device][attributes]")
{
    Scene s = bundled("spot");
    Device device = Device::open();
    Renderer renderer(device, s);
    Camera front = Camera::framing(s.bounds());
    Camera back = front;
    back.eye = s.bounds().center() * 2.0 - front.eye; // the other side
    VisibleSet set(device, std::uint32_t(s.triangle_count()));
    std::vector<std::uint32_t> expected;
    for (const Camera& cam : {front, back})
        for (Path p : {Path::Raster, Path::Ray}) {
            VisibilityBuffer vis = renderer.render(cam, 96, 72, p);
            std::vector<std::uint32_t> ids = vis.read_ids();
            for (std::uint32_t id : ids)
                if (id != background_id) expected.push_back(id);
            set.mark(vis);
        }
    std::sort(expected.begin(), expected.end());
    expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
    REQUIRE(expected.size() > 100);
    std::vector<std::uint32_t> got = set.read_ids();
    CHECK(got == expected);
    std::vector<std::uint8_t> mask;
    set.read_mask(mask);
    REQUIRE(mask.size() == s.triangle_count());
    std::size_t marked = 0;
    for (std::uint32_t id = 0; id < mask.size(); ++id) {
        marked += mask[id];
        if (mask[id]) CHECK(std::binary_search(expected.begin(), expected.end(), id));
    }
    CHECK(marked == expected.size());
    set.clear();
    CHECK(set.read_ids().empty());
    // One view alone: a subset of the accumulated set.
    set.mark(renderer.render(front, 96, 72, Path::Ray));
    std::vector<std::uint32_t> one = set.read_ids();
    CHECK(!one.empty());
    CHECK(one.size() < expected.size());
    CHECK(std::includes(expected.begin(), expected.end(), one.begin(), one.end()));
}
