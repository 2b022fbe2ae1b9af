// The referee without the expansion (issue 34): it keeps set up only the triangles whose bounds
// hold a sample position of the image (any sample count), exactly those, and sets any other up
// again from the scene's items when a judgement asks for it, bit for bit the triangle the set-up
// from the expansion's world positions gives; verdicts on an instanced scene equal those on the
// same scene written out as plain meshes.
#include "catch.hpp"
#include "referee/referee_impl.hpp"

#include <clvis/clvis.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace clvis;
using detail::Triangle;

namespace {

Mat4 placed(Vec3 offset, double scale, bool mirrored = false)
{
    Mat4 m;
    m(0, 0) = scale * 0.8;
    m(0, 2) = scale * 0.6;
    m(2, 0) = -scale * 0.6;
    m(2, 2) = scale * 0.8;
    m(1, 1) = mirrored ? -scale : scale;
    m(0, 3) = offset.x;
    m(1, 3) = offset.y;
    m(2, 3) = offset.z;
    return m;
}

/// A plain quad, an empty mesh, a transformed plain sphere, then instances of a sphere: a grid of
/// 120 far away (a small fraction of a pixel each), a few near, one across the near plane, one
/// behind the eye, one beside the view, one beyond far, a mirrored one. Instanced, or the same
/// items written out as plain meshes.
Scene many_spheres(bool instanced)
{
    MeshData sphere = make_uv_sphere(200);
    sphere.name = "sphere";
    MeshData quad;
    quad.name = "quad";
    quad.positions = {-20, -20, -45, 20, -20, -45, 20, 20, -45, -20, 20, -45};
    quad.indices = {0, 1, 2, 0, 2, 3};
    MeshData empty;
    empty.name = "empty";
    Scene s;
    s.add_mesh(quad);
    s.add_mesh(empty);
    s.add_mesh(sphere, placed({2.5, -1, -9}, 1.5));
    std::size_t p = instanced ? s.add_prototype(sphere) : 0;
    auto add = [&](const Mat4& t) { instanced ? s.add_instance(p, t) : s.add_mesh(sphere, t); };
    for (int i = 0; i < 120; ++i) add(placed({(i % 12) * 1.3 - 7.0, (i / 12) * 1.1 - 5.0, -30.0 - i % 5}, 0.05));
    add(placed({-1, 0.5, -4}, 1));
    add(placed({0.6, -0.4, -0.8}, 0.5));  // across near
    add(placed({0, 0, 3}, 1));            // behind the eye
    add(placed({-40, 0, -5}, 1));         // beside the view
    add(placed({0, 0, -80}, 1));          // beyond far
    add(placed({1, 1.5, -6}, 0.8, true)); // mirrored
    s.add_mesh(empty);
    return s;
}

/// Whether a sample position of a width x height image, of any sample count, lies in t's bounds:
/// what for_candidates' test can let through, sample by sample.
bool holds_a_sample(const Triangle& t, int width, int height)
{
    if (t.n == 0) return false;
    auto axis = [](double lo, double hi, int size, int log2n, int k, int a) {
        double first = std::fmax(0.0, std::floor(lo) - 1), last = std::fmin(size - 1.0, std::ceil(hi) + 1);
        for (double i = first; i <= last; ++i) {
            double s = detail::sample_position(int(i), log2n, k, a);
            if (s >= lo && s <= hi) return true;
        }
        return false;
    };
    for (int log2n = 0; log2n <= CLVIS_MAX_SAMPLES_LOG2; ++log2n)
        for (int k = 0; k < 1 << log2n; ++k)
            if (axis(t.lo_x, t.hi_x, width, log2n, k, 0) && axis(t.lo_y, t.hi_y, height, log2n, k, 1)) return true;
    return false;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_triangle(const Triangle& a, const Triangle& b)
{
    auto linear = [](const detail::Linear& p, const detail::Linear& q) {
        return same_bits(p.a, q.a) && same_bits(p.b, q.b) && same_bits(p.c, q.c);
    };
    bool same = linear(a.det, b.det) && linear(a.num, b.num) && a.flat == b.flat && a.culled == b.culled &&
                a.n == b.n && same_bits(a.lo_x, b.lo_x) && same_bits(a.lo_y, b.lo_y) && same_bits(a.hi_x, b.hi_x) &&
                same_bits(a.hi_y, b.hi_y);
    for (int k = 0; k < 3; ++k) same = same && linear(a.edge[k], b.edge[k]);
    for (int k = 0; k < a.n && same; ++k)
        same = same_bits(a.px[k], b.px[k]) && same_bits(a.py[k], b.py[k]) && same_bits(a.pd[k], b.pd[k]);
    return same;
}

} // namespace

TEST_CASE("the referee keeps set up exactly the triangles a sample can meet, and sets up any other on demand",
          "[referee][instances]")
{
    Scene scene = many_spheres(true);
    const int width = 64, height = 48;
    struct Case {
        const char* name;
        Camera camera;
        Cull cull;
    };
    Camera persp = Camera::perspective({0.3, 0.2, 0}, {0, 0, -10}, {0, 1, 0}, 60, 0.7, 50);
    Camera ortho = Camera::orthographic({0.3, 0.2, 5}, {0, 0, -10}, {0, 1, 0}, 14, 0.7, 50);
    for (const Case& c : {Case{"perspective", persp, Cull::None}, Case{"orthographic", ortho, Cull::None},
                          Case{"perspective, back faces culled", persp, Cull::Back}}) {
        INFO(c.name);
        Referee::Impl impl;
        impl.camera = c.camera;
        impl.width = width;
        impl.height = height;
        impl.cull = c.cull;
        impl.setup(scene);
        REQUIRE(impl.triangle_count == scene.triangle_count());
        REQUIRE(impl.kept.size() == impl.kept_ids.size());
        CHECK(std::is_sorted(impl.kept_ids.begin(), impl.kept_ids.end()));
        CHECK(std::adjacent_find(impl.kept_ids.begin(), impl.kept_ids.end()) == impl.kept_ids.end());

        // Each triangle as the set-up from the expansion gives it (the world positions the paths
        // upload for a plain scene), against the referee's, kept or set up again.
        const std::vector<float>& world = scene.world_positions();
        const std::vector<std::uint32_t>& index = scene.world_indices();
        std::size_t wrong = 0, missing = 0, extra = 0, candidates = 0;
        for (std::uint32_t id = 0; id < scene.triangle_count(); ++id) {
            Vec3 w[3], cam[3];
            for (int k = 0; k < 3; ++k) {
                std::size_t v = index[3 * std::size_t(id) + std::size_t(k)];
                w[k] = {world[3 * v], world[3 * v + 1], world[3 * v + 2]};
                cam[k] = c.camera.to_camera(w[k]);
            }
            Triangle expected;
            impl.setup_triangle(expected, w, cam);
            Triangle scratch;
            if (!same_triangle(impl.triangle(id, scratch), expected)) ++wrong;
            bool kept = std::binary_search(impl.kept_ids.begin(), impl.kept_ids.end(), id);
            bool candidate = holds_a_sample(expected, width, height);
            candidates += candidate;
            missing += candidate && !kept;
            extra += kept && !candidate;
        }
        CHECK(wrong == 0);
        CHECK(missing == 0);
        CHECK(extra == 0);
        // The far grid is most of the scene and holds few samples: the referee keeps what the
        // image can show, not the scene.
        CHECK(candidates == impl.kept.size());
        CHECK(impl.kept.size() * 3 < scene.triangle_count());
    }
}

TEST_CASE("the referee judges an instanced scene as the same scene of plain meshes", "[referee][instances]")
{
    Scene instanced = many_spheres(true), plain = many_spheres(false);
    REQUIRE(instanced.triangle_count() == plain.triangle_count());
    const int width = 40, height = 30;
    Camera camera = Camera::perspective({0.3, 0.2, 0}, {0, 0, -10}, {0, 1, 0}, 60, 0.7, 50);
    Referee a(instanced, camera, width, height), b(plain, camera, width, height);
    // Every triangle as the answer at a few pixels (most kept nowhere near them: set up on demand),
    // and each pixel's reference, as a buffer checked by both.
    std::size_t differ = 0;
    for (std::uint32_t id = 0; id < instanced.triangle_count(); id += 3)
        for (auto [x, y] : {std::pair{0, 0}, std::pair{17, 11}, std::pair{39, 29}}) {
            SampleAnswer answer;
            answer.id = id;
            answer.has_depth = true;
            answer.depth = 5.0f;
            differ += a.judge(x, y, answer).describe() != b.judge(x, y, answer).describe();
            differ += a.classify(id, x, y).depth != b.classify(id, x, y).depth &&
                      !(std::isnan(a.classify(id, x, y).depth) && std::isnan(b.classify(id, x, y).depth));
        }
    CHECK(differ == 0);
    HostVisibility v;
    v.width = width;
    v.height = height;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            v.ids.push_back((x + y) % 5 == 0 ? std::uint32_t(x * 977 + y) : a.reference(x, y)); // some wrong
    CompareReport ra = a.check(v), rb = b.check(v);
    CHECK(ra.errors > 0);
    CHECK(ra.errors == rb.errors);
    CHECK(ra.equal == rb.equal);
    CHECK(ra.explained == rb.explained);
    REQUIRE(ra.first_errors.size() == rb.first_errors.size());
    for (std::size_t i = 0; i < ra.first_errors.size(); ++i)
        CHECK(ra.first_errors[i].describe() == rb.first_errors[i].describe());
}

TEST_CASE("the referee refuses the first item with a transformed vertex that overflows float32", "[referee][instances]")
{
    MeshData sphere = make_uv_sphere(50);
    sphere.name = "sphere";
    Scene s;
    std::size_t p = s.add_prototype(sphere);
    for (int i = 0; i < 3; ++i) s.add_instance(p, placed({0, 0, -5.0 * (i + 1)}, 1));
    MeshData big = sphere;
    big.name = "huge";
    s.add_mesh(big, placed({2e38, 0, -5}, 2e38)); // x up to 4e38: beyond float32
    s.add_instance(p, placed({2e38, 0, -5}, 2e38));
    Camera camera = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.5, 50);
    CHECK_THROWS_WITH(Referee(s, camera, 16, 12),
                      Catch::Contains("mesh 'huge': a transformed vertex overflows float32"));
}
