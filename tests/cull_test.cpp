// Face culling means the same on every path: the raster, ray and brute paths drop the same faces
// as the referee judging with the same options (a culled triangle is no candidate), under
// perspective and orthographic cameras, on a closed mesh, on a soup of overlapping triangles of
// both windings, and with mirroring transforms (negative determinant), which swap front and back.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <random>
#include <set>
#include <string>

using namespace clvis;

namespace {

const Path paths[] = {Path::Raster, Path::Ray, Path::Brute};
const Cull culls[] = {Cull::None, Cull::Back, Cull::Front};

const char* name(Cull c) { return c == Cull::Back ? "back" : c == Cull::Front ? "front" : "none"; }

/// x -> 2 c - x: a mirror (determinant -1) about the plane x = c.
Mat4 mirror_x(double c)
{
    Mat4 m;
    m(0, 0) = -1;
    m(0, 3) = 2 * c;
    return m;
}

/// Renders with every path under `cull` and judges each buffer, ids and depths, with a referee
/// given the same options: no errors. Returns the raster path's buffer.
HostVisibility judged(Device& device, const Scene& s, const Camera& cam, int w, int h, Cull cull)
{
    RenderOptions o;
    o.cull = cull;
    Renderer renderer(device, s, o);
    Referee ref(s, cam, w, h, o);
    HostVisibility first;
    for (Path p : paths) {
        HostVisibility v = renderer.render(cam, w, h, p).read();
        CompareReport r = ref.check(v);
        std::string errors;
        for (const PixelVerdict& e : r.first_errors) errors += "\n  " + e.describe();
        INFO(to_string(p) << " path, cull " << name(cull) << ", " << cam.to_flags() << ": " << r.errors
                          << " errors, " << r.depth_errors << " depth errors" << errors);
        CHECK(r.errors == 0);
        CHECK(r.depth_errors == 0);
        if (p == Path::Raster) first = v;
    }
    return first;
}

std::set<std::uint32_t> ids_of(const HostVisibility& v) { return {v.ids.begin(), v.ids.end()}; }

Scene soup(std::uint32_t seed, int count)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1, 1);
    MeshData m;
    m.name = "soup";
    for (int k = 0; k < 3 * count; ++k) {
        m.positions.insert(m.positions.end(), {2 * u(rng), 1.5f * u(rng), u(rng)});
        m.indices.push_back(std::uint32_t(k));
    }
    Scene s;
    s.add_mesh(m);
    return s;
}

} // namespace

TEST_CASE("every path culls what the referee culls, on a closed mesh and a soup", "[device][agree]")
{
    Device device = Device::open();
    Scene spot;
    spot.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"));
    Scene mixed = soup(7, 300);
    for (const Scene* s : {&spot, &mixed}) {
        for (Projection proj : {Projection::Perspective, Projection::Orthographic}) {
            Camera cam = Camera::framing(s->bounds(), proj);
            HostVisibility none = judged(device, *s, cam, 64, 48, Cull::None);
            HostVisibility back = judged(device, *s, cam, 64, 48, Cull::Back);
            HostVisibility front = judged(device, *s, cam, 64, 48, Cull::Front);
            // Culling changes the picture (front culling shows a closed mesh's inside), and a
            // referee that ignores it rejects it: the checks above can fail.
            CHECK(front.ids != none.ids);
            CHECK(Referee(*s, cam, 64, 48).check(front).errors > 0);
            if (s == &mixed) CHECK(back.ids != none.ids);
        }
    }
}

TEST_CASE("a mirroring transform turns front faces into back faces on every path", "[device][agree]")
{
    Device device = Device::open();
    // One triangle counter-clockwise seen from +z (front), in a mesh mirrored about x = 0.
    MeshData m;
    m.name = "ccw";
    m.positions = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
    m.indices = {0, 1, 2};
    Scene plain, mirrored;
    plain.add_mesh(m);
    mirrored.add_mesh(m, mirror_x(0));
    for (Camera cam : {Camera::perspective({0.1, 0.2, 4}, {0, 0, 0}, {0, 1, 0}, 45, 0.5, 10),
                       Camera::orthographic({0.1, 0.2, 4}, {0, 0, 0}, {0, 1, 0}, 3, 0.5, 10)}) {
        const std::set<std::uint32_t> drawn{0u, background_id}, empty{background_id};
        CHECK(ids_of(judged(device, plain, cam, 32, 24, Cull::Back)) == drawn);
        CHECK(ids_of(judged(device, plain, cam, 32, 24, Cull::Front)) == empty);
        CHECK(ids_of(judged(device, mirrored, cam, 32, 24, Cull::Back)) == empty);
        CHECK(ids_of(judged(device, mirrored, cam, 32, 24, Cull::Front)) == drawn);
        // Seen from behind, front and back swap again.
        Camera behind = cam;
        behind.eye = {0.1, 0.2, -4};
        CHECK(ids_of(judged(device, mirrored, behind, 32, 24, Cull::Back)) == drawn);
    }
    // A closed mesh beside its mirror image, every cull mode: the referee agrees with every path.
    Scene spot;
    MeshData mesh = load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj");
    spot.add_mesh(mesh);
    spot.add_mesh(mesh, mirror_x(spot.bounds().hi.x + 0.05));
    for (Cull c : culls) judged(device, spot, Camera::framing(spot.bounds()), 96, 48, c);
}
