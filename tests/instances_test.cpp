// Instances (CONVENTIONS.md, "Instances"): a prototype stored once and placed by transforms, from
// the C++ API and the scene file. Ids and world positions are those of the expanded scene, so both
// paths render an instanced scene bit-identical to its expansion, before and after a move.
#include "catch.hpp"
#include "test_files.hpp"

#include <clvis/clvis.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace clvis;

namespace {

Mat4 placed(double angle, Vec3 offset, double scale)
{
    Mat4 m;
    m(0, 0) = scale * std::cos(angle);
    m(0, 2) = scale * std::sin(angle);
    m(2, 0) = -scale * std::sin(angle);
    m(2, 2) = scale * std::cos(angle);
    m(1, 1) = scale;
    m(0, 3) = offset.x;
    m(1, 3) = offset.y;
    m(2, 3) = offset.z;
    return m;
}

MeshData quad(float z)
{
    MeshData m;
    m.name = "quad";
    m.positions = {-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

const std::vector<Mat4>& placements()
{
    static const std::vector<Mat4> p = {placed(0.3, {-0.6, 0, 0}, 0.7), placed(2.1, {0.5, 0.1, -0.3}, 0.9),
                                        placed(-1.2, {0.1, -0.4, 0.4}, 0.5)};
    return p;
}

/// quad, spot as instance 0, quad, spot as instances 1 and 2: instanced, or written out.
Scene spots(bool instanced)
{
    MeshData spot = load_mesh(CLVIS_SOURCE_DIR "/scenes/spot.obj");
    Scene s;
    s.add_mesh(quad(-2));
    std::size_t p = instanced ? s.add_prototype(spot) : 0;
    auto place = [&](const Mat4& t) { instanced ? s.add_instance(p, t) : s.add_mesh(spot, t); };
    place(placements()[0]);
    s.add_mesh(quad(-2.5f), placed(0.2, {0, 0, 0}, 1.5));
    place(placements()[1]);
    place(placements()[2]);
    return s;
}

bool same_bits(const HostVisibility& a, const HostVisibility& b)
{
    return a.ids == b.ids && a.depth.size() == b.depth.size() &&
           std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0;
}

std::string write_file(const std::string& name, const std::string& text)
{
    return test::write_temp_file("clvis-instances-test", name, text);
}

std::string matrix_json(const Mat4& m)
{
    std::string s = "[";
    for (int i = 0; i < 16; ++i) {
        char number[32];
        std::snprintf(number, sizeof number, "%.17g", m.m[std::size_t(i)]);
        s += (i ? "," : "") + std::string(number);
    }
    return s + "]";
}

} // namespace

TEST_CASE("an instanced scene has the ids and world positions of its expansion", "[instances]")
{
    Scene a = spots(true), b = spots(false);
    REQUIRE(a.prototypes().size() == 1);
    REQUIRE(a.meshes().size() == b.meshes().size());
    CHECK(a.triangle_count() == b.triangle_count());
    CHECK(a.vertex_count() == b.vertex_count());
    for (std::size_t i = 0; i < a.meshes().size(); ++i) {
        CHECK(a.meshes()[i].first_triangle == b.meshes()[i].first_triangle);
        CHECK(a.data_of(i).triangle_count() == b.data_of(i).triangle_count());
    }
    // The prototype is stored once: the instances hold no triangles of their own.
    CHECK(a.meshes()[1].prototype == 0);
    CHECK(a.meshes()[1].data.positions.empty());
    CHECK(&a.data_of(3) == &a.prototypes()[0]);
    CHECK(a.meshes()[0].prototype == Scene::no_prototype);
    CHECK(a.world_positions() == b.world_positions());
    CHECK(a.world_indices() == b.world_indices());
    std::uint32_t last = std::uint32_t(a.triangle_count() - 1);
    CHECK(a.mesh_of(last) == 4);
    float ta[9], tb[9];
    a.triangle(last, ta);
    b.triangle(last, tb);
    CHECK(std::memcmp(ta, tb, sizeof ta) == 0);
}

TEST_CASE("instances refuse a missing prototype, a bad transform and set_positions", "[instances]")
{
    Scene s;
    CHECK_THROWS_AS(s.add_instance(0, Mat4::identity()), Error);
    std::size_t p = s.add_prototype(quad(0));
    CHECK(s.empty()); // a prototype alone has no ids
    Mat4 bad;
    bad(3, 0) = 1;
    CHECK_THROWS_AS(s.add_instance(p, bad), Error);
    std::size_t i = s.add_instance(p, Mat4::identity());
    CHECK(s.triangle_count() == 2);
    std::vector<float> moved = quad(1).positions;
    CHECK_THROWS_AS(s.set_positions(i, moved.data(), 4), Error);
    MeshData broken = quad(0);
    broken.indices[2] = 9;
    CHECK_THROWS_AS(s.add_prototype(broken), Error);
    // A move changes the world positions as it would for the written-out mesh.
    Scene e;
    e.add_mesh(quad(0));
    s.set_transform(i, placements()[1]);
    e.set_transform(0, placements()[1]);
    CHECK(s.world_positions() == e.world_positions());
}

TEST_CASE("an instanced scene renders bit-identical to its expansion on both paths", "[device][instances]")
{
    Device device = Device::open();
    Scene a = spots(true), b = spots(false);
    Renderer ra(device, a), rb(device, b);
    Camera cam = Camera::framing(b.bounds());
    for (Path path : {Path::Raster, Path::Ray}) {
        INFO(to_string(path));
        HostVisibility va = ra.render(cam, 160, 120, path).read(), vb = rb.render(cam, 160, 120, path).read();
        CHECK(same_bits(va, vb));
        std::size_t spot_pixels = 0;
        for (std::uint32_t id : va.ids) spot_pixels += id != background_id && b.mesh_of(id) % 2 == 1;
        CHECK(spot_pixels > 500); // the instances are in view, not hidden behind the quads
    }
    // Moving one instance moves it as moving the written-out copy does, without a new renderer.
    HostVisibility before = ra.render(cam, 160, 120, Path::Ray).read();
    a.set_transform(3, placements()[0]);
    b.set_transform(3, placements()[0]);
    ra.update(a);
    rb.update(b);
    for (Path path : {Path::Raster, Path::Ray}) {
        INFO(to_string(path) << " after a move");
        HostVisibility va = ra.render(cam, 160, 120, path).read();
        CHECK(same_bits(va, rb.render(cam, 160, 120, path).read()));
        CHECK_FALSE(same_bits(va, before)); // the instance did move
    }
}

TEST_CASE("a scene file's instances are items at the mesh's place, in the order given", "[io][instances]")
{
    std::string tri = write_file("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto& p = placements();
    std::string path = write_file("instances.json", "{\"meshes\": [{\"file\": \"tri.obj\"}, {\"file\": \"tri.obj\", "
                                                    "\"instances\": [" + matrix_json(p[0]) + "," + matrix_json(p[1]) +
                                                    "]}, {\"file\": \"tri.obj\", \"transform\": " + matrix_json(p[2]) +
                                                    "}]}");
    Scene s = load_scene_file(path).scene;
    REQUIRE(s.meshes().size() == 4);
    CHECK(s.prototypes().size() == 1);
    CHECK(s.meshes()[1].prototype == 0);
    CHECK(s.meshes()[2].prototype == 0);
    CHECK(s.meshes()[3].prototype == Scene::no_prototype);
    Scene e;
    MeshData m = load_mesh(tri);
    e.add_mesh(m);
    for (const Mat4& t : p) e.add_mesh(m, t);
    CHECK(s.world_positions() == e.world_positions());
    CHECK(s.world_indices() == e.world_indices());
    struct Bad {
        std::string mesh, message;
    } bad[] = {
        {"{\"file\": \"tri.obj\", \"instances\": []}", "meshes[0].instances: expected a non-empty array"},
        {"{\"file\": \"tri.obj\", \"instances\": [" + matrix_json(p[0]) + "], \"transform\": " + matrix_json(p[0]) + "}",
         "meshes[0]: give either transform or instances"},
        {"{\"file\": \"tri.obj\", \"instances\": [" + matrix_json(p[0]) + ", [1, 2]]}",
         "meshes[0].instances[1]: expected 16 numbers"},
    };
    for (const Bad& b : bad) {
        INFO(b.mesh);
        try {
            load_scene_file(write_file("bad.json", "{\"meshes\": [" + b.mesh + "]}"));
            FAIL("a bad instances entry loaded");
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find(b.message) != std::string::npos);
        }
    }
}
