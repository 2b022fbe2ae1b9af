// The host scene: ids as the concatenation of meshes, transforms on positions only, validation
// that names the mesh and the element, and the world-space arrays every consumer reads.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <cmath>

using namespace clvis;

namespace {

MeshData quad(const std::string& name, float z)
{
    MeshData m;
    m.name = name;
    m.positions = {0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

} // namespace

TEST_CASE("meshes are concatenated in order and ids follow", "[scene]")
{
    Scene s;
    CHECK(s.add_mesh(quad("a", 0)) == 0);
    CHECK(s.add_mesh(quad("b", 1)) == 1);
    CHECK(s.triangle_count() == 4);
    CHECK(s.vertex_count() == 8);
    CHECK(s.meshes()[1].first_triangle == 2);
    CHECK(s.mesh_of(0) == 0);
    CHECK(s.mesh_of(3) == 1);
    float t[9];
    s.triangle(2, t);
    CHECK(t[2] == 1.0f); // first triangle of mesh b
    CHECK(s.world_indices()[6] == 4);
    CHECK_THROWS_AS(s.triangle(4, t), Error);
}

TEST_CASE("an empty mesh keeps the ids of the meshes after it", "[scene]")
{
    Scene s;
    s.add_mesh(quad("a", 0));
    MeshData empty;
    empty.name = "empty";
    s.add_mesh(empty);
    s.add_mesh(quad("c", 2));
    CHECK(s.meshes()[2].first_triangle == 2);
    CHECK(s.mesh_of(2) == 2);
    CHECK(s.mesh_of(1) == 0);
}

TEST_CASE("a transform moves positions, row by row on column vectors", "[scene]")
{
    Scene s;
    Mat4 m; // translate by (10, 20, 30), scale x by 2
    m(0, 0) = 2;
    m(0, 3) = 10;
    m(1, 3) = 20;
    m(2, 3) = 30;
    s.add_mesh(quad("a", 0), m);
    const auto& p = s.world_positions();
    CHECK(p[3] == 12.0f); // vertex 1 = (1, 0, 0) -> (12, 20, 30)
    CHECK(p[4] == 20.0f);
    CHECK(p[5] == 30.0f);
    Bounds b = s.bounds();
    CHECK(b.lo.x == 10.0);
    CHECK(b.hi.x == 12.0);
    s.set_transform(0, Mat4::identity());
    CHECK(s.world_positions()[3] == 1.0f);
}

TEST_CASE("bad meshes are refused with the mesh and the element named", "[scene]")
{
    Scene s;
    MeshData bad = quad("broken", 0);
    bad.indices[4] = 9;
    CHECK_THROWS_WITH(s.add_mesh(bad), Catch::Contains("broken") && Catch::Contains("triangle 1") &&
                                           Catch::Contains("vertex 9"));
    bad = quad("nan", 0);
    bad.positions[7] = std::nanf("");
    CHECK_THROWS_WITH(s.add_mesh(bad), Catch::Contains("nan") && Catch::Contains("vertex 2"));
    bad = quad("inf", 0);
    bad.positions[0] = INFINITY;
    CHECK_THROWS_WITH(s.add_mesh(bad), Catch::Contains("non-finite"));
    bad = quad("ragged", 0);
    bad.indices.pop_back();
    CHECK_THROWS_WITH(s.add_mesh(bad), Catch::Contains("3 per triangle"));
    Mat4 projective;
    projective(3, 2) = 1;
    CHECK_THROWS_WITH(s.add_mesh(quad("p", 0), projective), Catch::Contains("last row"));
    Mat4 overflow;
    overflow(0, 0) = 1e39; // finite in double, overflows float32 once applied
    s.add_mesh(quad("big", 0), overflow);
    CHECK_THROWS_WITH(s.world_positions(), Catch::Contains("big") && Catch::Contains("overflows"));
    CHECK(s.triangle_count() == 2); // the refused meshes left nothing behind
}

TEST_CASE("new positions keep the vertex count and move the world positions", "[scene]")
{
    Scene s;
    s.add_mesh(quad("a", 0));
    std::vector<float> moved = quad("a", 5).positions;
    s.set_positions(0, moved.data(), 4);
    CHECK(s.world_positions()[2] == 5.0f);
    CHECK_THROWS_AS(s.set_positions(0, moved.data(), 3), Error);
    CHECK_THROWS_AS(s.set_positions(1, moved.data(), 4), Error);
}

TEST_CASE("more triangles than 32-bit ids allow are refused before anything is copied", "[scene]")
{
    Scene s;
    float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::uint32_t idx[3] = {0, 1, 2};
    // The count alone decides: the arrays are never read.
    try {
        s.add_mesh(p, 3, idx, std::size_t(1) << 32, Mat4::identity(), "huge");
        FAIL("accepted 2^32 triangles");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Limit);
        CHECK(std::string(e.what()).find("32-bit ids") != std::string::npos);
        CHECK(std::string(e.what()).find("4294967296") != std::string::npos);
    }
    CHECK(s.triangle_count() == 0);
}
