// The referee with render options and depths, against hand-computed answers: culled triangles are
// no candidates (mirroring transforms included), depths are judged against the exact view depth
// within CONVENTIONS.md's tolerance, the background's depth must be +inf, and compare() and check()
// judge every pixel by default with counts that add up, for ids and for depths.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <array>
#include <cmath>
#include <limits>

using namespace clvis;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

Scene scene_of(std::vector<float> positions, const Mat4& transform = Mat4::identity())
{
    Scene s;
    MeshData m;
    m.name = "hand-made";
    m.positions = std::move(positions);
    for (std::uint32_t i = 0; i < m.positions.size() / 3; ++i) m.indices.push_back(i);
    s.add_mesh(m, transform);
    return s;
}

// One world unit per pixel, raster (x, H - y), view depth 10 - z (as in referee_test.cpp).
Camera pixel_ortho(int w, int h, double far = 100)
{
    return Camera::orthographic({w / 2.0, h / 2.0, 10}, {w / 2.0, h / 2.0, 0}, {0, 1, 0}, h, 1, far);
}

// Two triangles covering an 8x8 ortho view at z = 0 and z = -1 (depths 10 and 11): id 0
// counter-clockwise seen from the camera (front), id 1 the same wound the other way (back).
std::vector<float> front_over_back()
{
    return {-10, -10, 0, 30, -10, 0, -10, 30, 0, //
            -10, -10, -1, -10, 30, -1, 30, -10, -1};
}

SampleAnswer answer(std::uint32_t id, float depth)
{
    SampleAnswer a;
    a.id = id;
    a.has_depth = true;
    a.depth = depth;
    return a;
}

/// (judged, equal, explained, errors, errors_a, errors_b), then the same six for depths (with
/// depth_equal + depth_explained + depth_errors for judged).
std::array<std::size_t, 12> counts(const CompareReport& r)
{
    return {r.judged,       r.equal,          r.explained,       r.errors,
            r.errors_a,     r.errors_b,       r.depth_equal + r.depth_explained + r.depth_errors,
            r.depth_equal,  r.depth_explained, r.depth_errors,   r.depth_errors_a,
            r.depth_errors_b};
}

using Counts = std::array<std::size_t, 12>;

void check_adds_up(const CompareReport& r)
{
    CHECK(r.equal + r.explained + r.errors == r.pixels);
    if (r.depths_judged) CHECK(r.depth_equal + r.depth_explained + r.depth_errors == r.pixels);
}

} // namespace

TEST_CASE("a culled triangle is no candidate, and answering it is an error", "[referee]")
{
    Scene s = scene_of(front_over_back());
    for (Projection proj : {Projection::Orthographic, Projection::Perspective}) {
        Camera cam = proj == Projection::Orthographic
                         ? pixel_ortho(8, 8)
                         : Camera::perspective({4, 4, 10}, {4, 4, 0}, {0, 1, 0}, 40, 1, 100);
        INFO(cam.to_flags());
        RenderOptions none, back, front;
        back.cull = Cull::Back;
        front.cull = Cull::Front;
        CHECK(Referee(s, cam, 8, 8, none).reference(3, 3) == 0);
        CHECK(Referee(s, cam, 8, 8, back).reference(3, 3) == 0);
        Referee rf(s, cam, 8, 8, front);
        CHECK(rf.reference(3, 3) == 1); // the front face is culled: the back one shows
        CHECK(rf.classify(0, 3, 3).culled);
        CHECK(rf.classify(0, 3, 3).cls == SampleClass::Out);
        CHECK(rf.judge(3, 3, 0).error == AnswerError::Culled);
        CHECK_THAT(rf.judge(3, 3, 0).describe(), Catch::Contains("culled"));
        CHECK(Referee(s, cam, 8, 8, none).judge(3, 3, 1).error == AnswerError::HiddenSurface);
        Referee rb(s, cam, 8, 8, back);
        CHECK(rb.judge(3, 3, 1).error == AnswerError::Culled); // hidden too, but culled first
        CHECK(rb.classify(1, 3, 3).culled);
        CHECK_FALSE(rb.classify(0, 3, 3).culled);
    }
}

TEST_CASE("a mirroring transform turns front faces into back faces for the referee", "[referee]")
{
    // Mirror x about x = 4 (determinant -1): the image is the same, each winding reversed.
    Mat4 mirror;
    mirror(0, 0) = -1;
    mirror(0, 3) = 8;
    Scene s = scene_of(front_over_back(), mirror);
    RenderOptions back;
    back.cull = Cull::Back;
    Referee ref(s, pixel_ortho(8, 8), 8, 8, back);
    CHECK(ref.reference(3, 3) == 1); // id 0 now faces away and is culled; id 1 faces the camera
    CHECK(ref.judge(3, 3, 0).error == AnswerError::Culled);
    CHECK(ref.judge(3, 3, 1).acceptable());
}

TEST_CASE("near a culled triangle's edge it stays ambiguous, well inside it is out", "[referee]")
{
    // A back face whose edge x = 3.5 runs through the centres of column 3.
    Scene s = scene_of({3.5f, -10, 0, -10, 0, 0, 3.5f, 30, 0});
    RenderOptions back;
    back.cull = Cull::Back;
    Referee ref(s, pixel_ortho(8, 8), 8, 8, back);
    CHECK(ref.classify(0, 3, 3).cls == SampleClass::Ambiguous);
    CHECK(ref.classify(0, 2, 3).cls == SampleClass::Out);
    CHECK(ref.judge(3, 3, 0).acceptable());
    CHECK(ref.judge(3, 3, background_id).acceptable());
}

TEST_CASE("depths are judged within 1e-5 d plus the gradient over 1/65536 px", "[referee]")
{
    // The plane z = -10 x: view depth 10 + 10 x, 10 per pixel across. At pixel (2, 3), x = 2.5:
    // d = 35, tolerance 35e-5 + 10 / 65536 = 5.03e-4 (the gradient's share 1.5e-4).
    Scene s = scene_of({0, -10, 0, 8, -10, -80, 0, 30, 0});
    Referee ref(s, pixel_ortho(8, 8), 8, 8);
    PixelVerdict ok = ref.judge(2, 3, answer(0, 35.00045f));
    CHECK(ok.acceptable());
    CHECK(ok.depth_judged);
    CHECK(ok.depth_acceptable());
    CHECK(ok.depth_expected == Approx(35).epsilon(1e-12));
    CHECK(ok.depth_hi - 35 == Approx(35e-5 + 10.0 / 65536).epsilon(1e-6));
    PixelVerdict far = ref.judge(2, 3, answer(0, 35.00055f));
    CHECK(far.acceptable()); // the id is right ...
    CHECK(far.depth_error == DepthError::Wrong); // ... its depth is not
    CHECK_THAT(far.describe(), Catch::Contains("wrong depth") && Catch::Contains("exact 35"));
    CHECK(ref.judge(2, 3, answer(0, 34.99945f)).depth_error == DepthError::Wrong);
    CHECK(ref.judge(2, 3, answer(0, std::nanf(""))).depth_error == DepthError::Wrong);
    CHECK(ref.judge(2, 3, answer(0, inf)).depth_error == DepthError::Wrong);
    // A buffer of one pixel, that sample: CompareOptions::depth_px widens the gradient's share,
    // only when asked, and only up to 1 px.
    Referee one(s, Camera::orthographic({2.5, 4.5, 10}, {2.5, 4.5, 0}, {0, 1, 0}, 1, 1, 100), 1, 1);
    HostVisibility v;
    v.width = v.height = 1;
    v.ids = {0};
    v.depth = {35.00055f};
    CHECK(one.check(v).depth_errors == 1);
    CompareOptions wide;
    wide.depth_px = 1e-3; // 35e-5 + 10 * 1e-3
    CHECK(one.check(v, wide).depth_errors == 0);
    v.depth = {35.0105f};
    CHECK(one.check(v, wide).depth_errors == 1);
    for (double bad : {0.0, 1e-6, 1.0, std::nan("")}) {
        wide.depth_px = bad;
        CHECK_THROWS_AS(one.check(v, wide), Error);
    }
    // Without a depth nothing is judged.
    CHECK_FALSE(ref.judge(2, 3, 0).depth_judged);
    CHECK(ref.judge(2, 3, 0).depth_acceptable());
}

TEST_CASE("the background's depth is +inf, and an invalid id has no depth to judge", "[referee]")
{
    Scene s = scene_of({0, 0, 0, 2, 0, 0, 0, 2, 0}); // covers pixel (0, 7) only
    Referee ref(s, pixel_ortho(8, 8), 8, 8);
    CHECK(ref.judge(5, 2, answer(background_id, inf)).depth_acceptable());
    PixelVerdict finite = ref.judge(5, 2, answer(background_id, 1e30f));
    CHECK(finite.acceptable());
    CHECK(finite.depth_error == DepthError::Wrong);
    CHECK_THAT(finite.describe(), Catch::Contains("+inf"));
    PixelVerdict invalid = ref.judge(5, 2, answer(9, 10));
    CHECK(invalid.error == AnswerError::InvalidId);
    CHECK(invalid.depth_error == DepthError::NoTriangle);
}

TEST_CASE("an edge-on triangle's depth is judged by its visible part near the sample", "[referee]")
{
    // The triangle lies in the plane y = 4.5 (seen edge-on by the ortho camera), depths 10 to 14;
    // within EPS of pixel (3, 3), at x = 3.5, its depths run from 10 to 12.
    Scene s = scene_of({1, 4.5f, 0, 6, 4.5f, 0, 1, 4.5f, -4});
    Referee ref(s, pixel_ortho(8, 8), 8, 8);
    CHECK(ref.classify(0, 3, 3).cls == SampleClass::Ambiguous);
    PixelVerdict in_range = ref.judge(3, 3, answer(0, 11));
    CHECK(in_range.depth_acceptable());
    CHECK(std::isnan(in_range.depth_expected));
    CHECK(in_range.depth_lo == Approx(10).epsilon(1e-4));
    CHECK(in_range.depth_hi == Approx(12).epsilon(1e-3));
    CHECK(ref.judge(3, 3, answer(0, 12)).depth_acceptable());
    CHECK(ref.judge(3, 3, answer(0, 13)).depth_error == DepthError::Wrong);
    CHECK(ref.judge(3, 3, answer(0, 9.5f)).depth_error == DepthError::Wrong);
}

TEST_CASE("within EPS outside a steep triangle, its depths near the sample are accepted", "[referee]")
{
    // A plane steep in x (depth 10 + 1000 x) whose edge x = 3.5 - 2e-4 is vertical on screen:
    // pixel (3, 3)'s ray misses it by 2e-4 px, where its plane's depth (3510) differs from the
    // nearest visible one (3509.8) by more than the plane's own tolerance (0.05); the visible
    // part within EPS covers both.
    Scene s = scene_of({0, -10, 0, 3.4998f, -10, -3499.8f, 3.4998f, 30, -3499.8f});
    Referee ref(s, pixel_ortho(8, 8, 1e4), 8, 8);
    CHECK(ref.classify(0, 3, 3).cls == SampleClass::Ambiguous);
    CHECK(ref.judge(3, 3, answer(0, 3509.8f)).depth_acceptable());
    CHECK(ref.judge(3, 3, answer(0, 3510.0f)).depth_acceptable());
    CHECK(ref.judge(3, 3, answer(0, 3508.5f)).depth_error == DepthError::Wrong);
    CHECK(ref.judge(2, 3, answer(0, 2509.8f)).depth_error == DepthError::Wrong); // inside: the plane
}

TEST_CASE("compare judges every pixel by default, ids and depths, counts adding up", "[referee]")
{
    // Front over back as above, 8x8: every sample sees id 0 at depth 10.
    Scene s = scene_of(front_over_back());
    Referee ref(s, pixel_ortho(8, 8), 8, 8);
    HostVisibility a;
    a.width = a.height = 8;
    a.ids.assign(64, 0);
    a.depth.assign(64, 10);
    HostVisibility b = a;
    a.ids[9] = b.ids[9] = 1;           // (1, 1): the same wrong answer in both, ...
    a.depth[9] = b.depth[9] = 11;      // ... at its own (right) depth
    b.depth[20] = 10.00001f;          // (4, 2): a different but acceptable depth
    a.depth[30] = b.depth[30] = 10.5f; // (6, 3): the same wrong depth in both
    b.depth[40] = 9;                  // (0, 5): a wrong depth in b only

    CompareReport r = ref.compare(a, b);
    check_adds_up(r);
    CHECK(r.pixels == 64);
    REQUIRE(r.depths_judged);
    CHECK(counts(r) == Counts{64, 63, 0, 1, 1, 1, 64, 61, 1, 2, 1, 2});
    REQUIRE(r.first_errors.size() == 3);
    CHECK(r.first_errors[0].source == 2); // (1, 1), both
    CHECK(r.first_errors[0].error == AnswerError::HiddenSurface);
    CHECK(r.first_errors[1].x == 6);
    CHECK(r.first_errors[1].depth_error == DepthError::Wrong);
    CHECK(r.first_errors[2].source == 1);

    CompareOptions differing;
    differing.differing_only = true;
    CompareReport d = ref.compare(a, b, differing);
    check_adds_up(d);
    // Only (4, 2) and (0, 5) are judged: the same wrong answers pass unjudged.
    CHECK(counts(d) == Counts{2, 64, 0, 0, 0, 0, 64, 62, 1, 1, 0, 1});

    CompareReport c = ref.check(b);
    check_adds_up(c);
    CHECK(counts(c) == Counts{64, 63, 0, 1, 1, 0, 64, 61, 1, 2, 2, 0});

    HostVisibility ids_only = a;
    ids_only.depth.clear();
    CompareReport no_depths = ref.compare(ids_only, b);
    CHECK_FALSE(no_depths.depths_judged);
    CHECK(no_depths.depth_errors + no_depths.depth_equal == 0);
    check_adds_up(no_depths);
    HostVisibility short_depths = a;
    short_depths.depth.resize(10);
    CHECK_THROWS_AS(ref.compare(short_depths, b), Error);
}
