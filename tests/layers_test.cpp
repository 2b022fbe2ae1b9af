// Depth layers (RenderOptions::layers, CONVENTIONS.md "Depth layers"): every sample keeps its K
// nearest distinct triangles. Checked here, at K = 2, 4 and 8 on small images: layer 0 equals the
// one-layer buffer bit for bit on every path; the raster path's atomic cascade equals tile
// ownership and its square mapping its pixel mapping; in raster-rule coverage the ray and brute
// paths give the raster path's layers bit for bit, and in watertight coverage the BVH walk gives
// the brute path's; every layer is sorted and distinct and the referee accepts every layer; an
// instanced scene renders as its expansion; unsupported combinations are refused by name.
#include "catch.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>
#include <clvis/multi_device.hpp>
#include <clvis/procedural.hpp>
#include <clvis/referee.hpp>

#include <limits>
#include <string>
#include <utility>
#include <vector>

using namespace clvis;

namespace {

Device& device()
{
    static Device d = Device::open();
    return d;
}

std::vector<std::uint64_t> keys_of(const Scene& s, const Camera& c, int w, int h, RenderOptions o, Path path)
{
    Renderer r(device(), s, o);
    return r.render(c, w, h, path).read_keys();
}

RenderOptions with_layers(int layers, Coverage coverage = Coverage::Watertight)
{
    RenderOptions o;
    o.layers = layers;
    o.coverage = coverage;
    return o;
}

/// Each sample's K keys (layer-major buffer of `plane` keys per layer) sorted ascending, distinct
/// but for the background, background only after the last triangle.
void check_sorted(const std::vector<std::uint64_t>& keys, int layers)
{
    std::size_t plane = keys.size() / std::size_t(layers), bad = 0;
    for (std::size_t i = 0; i < plane; ++i)
        for (int k = 1; k < layers; ++k) {
            std::uint64_t a = keys[std::size_t(k - 1) * plane + i], b = keys[std::size_t(k) * plane + i];
            bad += !(a < b || (a == background_key && b == background_key));
        }
    CHECK(bad == 0);
}

/// Samples whose layer k holds a triangle.
std::size_t held(const std::vector<std::uint64_t>& keys, int layers, int k)
{
    std::size_t plane = keys.size() / std::size_t(layers), n = 0;
    for (std::size_t i = 0; i < plane; ++i) n += keys[std::size_t(k) * plane + i] != background_key;
    return n;
}

/// The referee accepts every layer of the buffer (ids and depths), at edges as CONVENTIONS says.
void check_referee(const Scene& s, const Camera& c, int w, int h, const std::vector<std::uint64_t>& keys, int layers)
{
    Referee referee(s, c, w, h);
    HostVisibility v = split_keys(keys.data(), w, h, 1, layers);
    std::vector<CompareReport> reports = referee.check_layers(v);
    REQUIRE(reports.size() == std::size_t(layers));
    for (int k = 0; k < layers; ++k) {
        INFO("layer " << k << (reports[k].first_errors.empty() ? std::string() : ": " + reports[k].first_errors[0].describe()));
        CHECK(reports[k].errors == 0);
        CHECK(reports[k].depth_errors == 0);
    }
}

/// Everything the paths must agree on for one scene and camera at K layers.
/// The ray mappings that run layers here: not the packet where the device caps a work-item's
/// loops (llvmpipe; RayMapping::Auto then picks the single mapping, source "layers").
std::vector<RayMapping> layer_mappings(const Scene& s)
{
    Renderer r(device(), s, with_layers(2));
    if (r.ray_mapping().source == "layers") return {RayMapping::Single};
    return {RayMapping::Packet, RayMapping::Single};
}

void check_all(const Scene& s, const Camera& c, int w, int h, int layers, std::size_t min_layer1)
{
    INFO("layers " << layers << " " << w << "x" << h << " " << c.to_flags());
    std::vector<std::uint64_t> one = keys_of(s, c, w, h, with_layers(1), Path::Raster);
    RenderOptions o = with_layers(layers);
    // raster: the atomic cascade and tile ownership, the square and pixel mappings (tile ownership
    // alone where the device has no 64-bit atomics: Rusticl on llvmpipe)
    o.raster_atomics = device().info().int64_atomics ? RasterAtomics::On : RasterAtomics::Off;
    o.raster_mapping = RasterMapping::Square;
    std::vector<std::uint64_t> raster = keys_of(s, c, w, h, o, Path::Raster);
    REQUIRE(raster.size() == one.size() * std::size_t(layers));
    CHECK(std::vector<std::uint64_t>(raster.begin(), raster.begin() + std::ptrdiff_t(one.size())) == one);
    check_sorted(raster, layers);
    CHECK(held(raster, layers, 1) >= min_layer1);
    o.raster_mapping = RasterMapping::Pixel;
    CHECK(keys_of(s, c, w, h, o, Path::Raster) == raster);
    o.raster_atomics = RasterAtomics::Off;
    CHECK(keys_of(s, c, w, h, o, Path::Raster) == raster);
    o.raster_mapping = RasterMapping::Square;
    CHECK(keys_of(s, c, w, h, o, Path::Raster) == raster);
    // ray and brute in raster-rule coverage: the raster path's layers bit for bit
    RenderOptions rule = with_layers(layers, Coverage::RasterRule);
    std::vector<RayMapping> mappings = layer_mappings(s);
    for (RayMapping mapping : mappings) {
        rule.ray_mapping = mapping;
        CHECK(keys_of(s, c, w, h, rule, Path::Ray) == raster);
    }
    CHECK(keys_of(s, c, w, h, rule, Path::Brute) == raster);
    // watertight: the walk's layers are the brute path's, layer 0 the one-layer ray buffer's
    std::vector<std::uint64_t> ray = keys_of(s, c, w, h, o, Path::Brute);
    for (RayMapping mapping : mappings) {
        o.ray_mapping = mapping;
        CHECK(keys_of(s, c, w, h, o, Path::Ray) == ray);
    }
    std::vector<std::uint64_t> ray_one = keys_of(s, c, w, h, with_layers(1), Path::Ray);
    CHECK(std::vector<std::uint64_t>(ray.begin(), ray.begin() + std::ptrdiff_t(ray_one.size())) == ray_one);
    check_sorted(ray, layers);
    check_referee(s, c, w, h, raster, layers);
    check_referee(s, c, w, h, ray, layers);
}

Scene sphere_scene()
{
    Scene s;
    s.add_mesh(make_uv_sphere(400));
    return s;
}

/// Two coplanar quads overlapping in z = 0 (equal depths: the lower id first), a third
/// triangle cutting through both, and a soup behind.
Scene coplanar_scene()
{
    Scene s;
    MeshData a;
    a.positions = {-1, -1, 0, 0.5f, -1, 0, 0.5f, 0.5f, 0, -1, 0.5f, 0};
    a.indices = {0, 1, 2, 0, 2, 3};
    MeshData b = a;
    for (std::size_t i = 0; i < b.positions.size(); i += 3) {
        b.positions[i] += 0.5f;
        b.positions[i + 1] += 0.5f;
    }
    s.add_mesh(a);
    s.add_mesh(b);
    s.add_mesh(test::triangle(-1.2f, -0.2f, -0.8f, 1.2f, -0.1f, 0.8f, 0.1f, 1.1f, 0.1f));
    MeshData soup = make_soup(200, 3);
    s.add_mesh(soup, Mat4::identity());
    return s;
}

} // namespace

TEST_CASE("depth layers: a closed sphere from outside and inside", "[device][layers][rusticl]")
{
    Scene s = sphere_scene();
    Camera outside = test::look({0.4, 0.5, 3.0}, {0, 0, 0}, 45, 0.1, 10);
    Camera inside = test::look({0.1, 0.2, 0.3}, {0.5, 0.1, -1}, 70, 0.01, 10);
    check_all(s, outside, 61, 47, 2, 1000);
    check_all(s, outside, 45, 33, 8, 500);
    check_all(s, inside, 53, 40, 4, 0);
    // From outside every sample of the sphere's inside has its two sides (front and back).
    std::vector<std::uint64_t> k2 = keys_of(s, outside, 61, 47, with_layers(4), Path::Raster);
    CHECK(held(k2, 4, 2) == 0);
    // From inside one side only.
    std::vector<std::uint64_t> in = keys_of(s, inside, 53, 40, with_layers(2), Path::Raster);
    CHECK(held(in, 2, 0) == std::size_t(53 * 40));
    CHECK(held(in, 2, 1) == 0); // the top-left rule gives a sample on a shared edge to one triangle
}

TEST_CASE("depth layers: the bunny", "[device][layers]")
{
    Scene bunny = test::scene_file("stanford-bunny.obj");
    Camera c = test::look({-0.02, 0.11, 0.25}, {-0.02, 0.1, 0}, 45, 0.01, 10);
    check_all(bunny, c, 64, 48, 4, 500);
}

TEST_CASE("depth layers: coplanar and intersecting triangles", "[device][layers]")
{
    Scene s = coplanar_scene();
    Camera c = test::look({0.3, 0.2, 3.0}, {0, 0, 0}, 50, 0.1, 10);
    check_all(s, c, 57, 43, 3, 300);
    // Where the quads overlap at equal depth (seen straight on: the depth is 3 everywhere on
    // them), the lower id comes first: mesh a's ids (0, 1) before mesh b's (2, 3).
    Camera straight = Camera::perspective({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 50, 0.1, 10);
    std::vector<std::uint64_t> keys = keys_of(s, straight, 57, 43, with_layers(2), Path::Raster);
    std::size_t plane = keys.size() / 2, tied = 0;
    for (std::size_t i = 0; i < plane; ++i) {
        std::uint64_t a = keys[i], b = keys[plane + i];
        if (b != background_key && (a >> 32) == (b >> 32)) {
            ++tied;
            CHECK(std::uint32_t(a) < std::uint32_t(b));
        }
    }
    CHECK(tied > 50);
}

TEST_CASE("depth layers: instances render as their expansion", "[device][layers]")
{
    MeshData sphere = make_uv_sphere(200);
    Scene inst, flat;
    inst.add_mesh(make_soup(100, 7));
    flat.add_mesh(make_soup(100, 7));
    std::size_t proto = inst.add_prototype(sphere);
    for (int k = 0; k < 3; ++k) {
        Mat4 t;
        t(0, 0) = t(1, 1) = t(2, 2) = 0.5;
        t(0, 3) = 0.3 * k - 0.3;
        t(2, 3) = -0.2 * k;
        inst.add_instance(proto, t);
        flat.add_mesh(sphere, t);
    }
    Camera c = test::look({0.2, 0.4, 3}, {0, 0, 0}, 45, 0.1, 10);
    for (Path path : {Path::Raster, Path::Ray}) {
        RenderOptions o = with_layers(4);
        CHECK(keys_of(inst, c, 50, 40, o, path) == keys_of(flat, c, 50, 40, o, path));
        o.coverage = Coverage::RasterRule;
        CHECK(keys_of(inst, c, 50, 40, o, path) == keys_of(flat, c, 50, 40, o, Path::Raster));
    }
}

TEST_CASE("depth layers: regions hold the whole render's layers", "[device][layers]")
{
    Scene s = sphere_scene();
    Camera c = test::look({0.4, 0.5, 3.0}, {0, 0, 0}, 45, 0.1, 10);
    for (Path path : {Path::Raster, Path::Ray}) {
        RenderOptions o = with_layers(3);
        std::vector<std::uint64_t> whole = keys_of(s, c, 40, 30, o, path);
        o.region = Region{7, 5, 21, 17};
        std::vector<std::uint64_t> part = keys_of(s, c, 40, 30, o, path);
        REQUIRE(part.size() == std::size_t(21 * 17 * 3));
        std::size_t wrong = 0;
        for (int k = 0; k < 3; ++k)
            for (int y = 0; y < 17; ++y)
                for (int x = 0; x < 21; ++x)
                    wrong += part[std::size_t(k) * 21 * 17 + std::size_t(y) * 21 + std::size_t(x)] !=
                             whole[std::size_t(k) * 40 * 30 + std::size_t(y + 5) * 40 + std::size_t(x + 7)];
        CHECK(wrong == 0);
    }
}

TEST_CASE("depth layers: reads give the layers of a sample adjacent", "[device][layers]")
{
    Scene s = sphere_scene();
    Camera c = test::look({0.4, 0.5, 3.0}, {0, 0, 0}, 45, 0.1, 10);
    Renderer r(device(), s, with_layers(2));
    VisibilityBuffer v = r.render(c, 20, 16, Path::Raster);
    CHECK(v.layers() == 2);
    CHECK(v.key_count() == std::size_t(20 * 16 * 2));
    std::vector<std::uint64_t> keys = v.read_keys();
    HostVisibility h = v.read();
    CHECK(h.layers == 2);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 20; ++x)
            for (int k = 0; k < 2; ++k) {
                std::uint64_t key = keys[std::size_t(k) * 320 + std::size_t(y) * 20 + std::size_t(x)];
                CHECK(h.id(x, y, 0, k) == std::uint32_t(key));
                CHECK(h.layer(k).id(x, y) == std::uint32_t(key));
            }
    CHECK_THROWS_AS(h.layer(2), Error);
}

TEST_CASE("depth layers: unsupported combinations are refused by name", "[device][layers]")
{
    Scene s = sphere_scene();
    auto refused = [&](RenderOptions o, const std::string& word) {
        try {
            Renderer r(device(), s, o);
            FAIL("not refused");
        } catch (const Error& e) {
            CHECK(std::string(e.what()).find(word) != std::string::npos);
        }
    };
    RenderOptions o = with_layers(0);
    refused(o, "layers");
    o.layers = 9;
    refused(o, "layers");
    o.layers = 2;
    o.samples = 4;
    refused(o, "samples");
    o.samples = 1;
    Renderer r(device(), s, o);
    VisibilityBatch batch(device(), 2, 8, 8); // one layer per view: not what the Renderer draws
    Camera c = test::look({0.4, 0.5, 3.0}, {0, 0, 0}, 45, 0.1, 10);
    try {
        render_views(r, {c, c}, Path::Raster, batch);
        FAIL("a batch of one layer was not refused");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("layer") != std::string::npos);
    }
}

TEST_CASE("depth layers: the referee rejects swapped, repeated and missing layers", "[device][layers]")
{
    Scene s = sphere_scene();
    Camera c = test::look({0.4, 0.5, 3.0}, {0, 0, 0}, 45, 0.1, 10);
    const int w = 30, h = 24;
    HostVisibility good = split_keys(keys_of(s, c, w, h, with_layers(2), Path::Raster).data(), w, h, 1, 2);
    Referee referee(s, c, w, h);
    std::vector<CompareReport> ok = referee.check_layers(good);
    CHECK(ok[0].errors + ok[1].errors == 0);
    // with one layer, check_layers is check()
    HostVisibility first = good.layer(0);
    first.depth.clear();
    CHECK(referee.check_layers(first)[0].equal == referee.check(first).equal);
    // a pixel of the sphere's middle holds its front and back side
    int x = w / 2, y = h / 2;
    std::size_t i0 = good.index(x, y, 0, 0), i1 = good.index(x, y, 0, 1);
    REQUIRE(good.ids[i1] != background_id);
    HostVisibility swapped = good, repeated = good, missing = good;
    std::swap(swapped.ids[i0], swapped.ids[i1]);
    std::swap(swapped.depth[i0], swapped.depth[i1]);
    repeated.ids[i1] = repeated.ids[i0];
    repeated.depth[i1] = repeated.depth[i0];
    missing.ids[i1] = background_id;
    missing.depth[i1] = std::numeric_limits<float>::infinity();
    std::vector<CompareReport> r = referee.check_layers(swapped);
    CHECK(r[0].errors == 1);
    REQUIRE(!r[0].first_errors.empty());
    CHECK(r[0].first_errors[0].error == AnswerError::HiddenSurface);
    r = referee.check_layers(repeated);
    CHECK(r[0].errors == 0);
    CHECK(r[1].errors == 1);
    REQUIRE(!r[1].first_errors.empty());
    CHECK(r[1].first_errors[0].error == AnswerError::Repeated);
    r = referee.check_layers(missing);
    CHECK(r[1].errors == 1);
    REQUIRE(!r[1].first_errors.empty());
    CHECK(r[1].first_errors[0].error == AnswerError::Missed);
    // compare_layers: the good buffer against the missing one, layer by layer
    r = referee.compare_layers(good, missing);
    CHECK(r[0].errors == 0);
    CHECK(r[1].errors == 1);
    CHECK(r[1].errors_b == 1);
}

TEST_CASE("depth layers: tiles on several devices hold every layer of one device's frame", "[device][layers]")
{
    Scene s = sphere_scene();
    Camera c = test::look({0.4, 0.5, 3.0}, {0, 0, 0}, 45, 0.1, 10);
    RenderOptions o = with_layers(3);
    MultiDeviceRenderer many({device(), device()}, s, o);
    for (Path path : {Path::Raster, Path::Ray}) {
        std::vector<std::uint64_t> want = keys_of(s, c, 40, 30, o, path);
        MultiDeviceOptions mo;
        mo.tile = 7;
        MultiDeviceFrame f = many.render(c, 40, 30, path, mo);
        CHECK(f.layers == 3);
        CHECK(f.keys == want);
    }
}

TEST_CASE("depth layers: each view of a batch holds the layers of the view rendered alone", "[device][layers]")
{
    Scene s = sphere_scene();
    std::vector<Camera> cams = {test::look({0.4, 0.5, 3.0}, {0, 0, 0}, 45, 0.1, 10),
                                test::look({-1.5, 0.3, 2.0}, {0, 0.1, 0}, 40, 0.1, 10),
                                test::look({0.1, 0.2, 0.3}, {0.5, 0.1, -1}, 70, 0.01, 10)};
    for (Path path : {Path::Raster, Path::Ray, Path::Brute})
        for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
            RenderOptions o = with_layers(4, coverage);
            Renderer r(device(), s, o);
            VisibilityBatch batch(device(), 3, 33, 21, 4);
            CHECK(batch.layers() == 4);
            render_views(r, cams, path, batch);
            for (int v = 0; v < 3; ++v) {
                INFO(to_string(path) << " " << to_string(coverage) << " view " << v);
                CHECK(batch.view(v).layers() == 4);
                CHECK(batch.view(v).read_keys() == keys_of(s, cams[std::size_t(v)], 33, 21, o, path));
            }
        }
}
