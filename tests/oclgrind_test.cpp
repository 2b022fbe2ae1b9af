// Every kernel of both paths on Oclgrind's simulated device, which reports out-of-bounds
// accesses, data races, uninitialised reads and barrier divergence, on small scenes that exercise
// every branch (the raster path's growth-and-rerun of its triangle list, tile sizes and BVH leaf
// sizes other than the defaults included); and the buffers must equal PoCL's bit for bit. Run by its own CTest entry
// ("oclgrind"), which registers Oclgrind beside PoCL and fails on any report.
#include "catch.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>

#include "raster/raster_pipeline.hpp"
#include "render/renderer_probe.hpp"

#include <cmath>
#include <cstring>
#include <limits>

using namespace clvis;

namespace {

using test::triangle;

using test::Case;

/// `mesh` as a plain mesh, then as a prototype with three instances (one mirrored).
Scene plain_and_instanced(const MeshData& mesh)
{
    Scene s;
    s.add_mesh(mesh);
    std::size_t p = s.add_prototype(mesh);
    for (double k : {0.5, -0.7, 0.9}) {
        Mat4 t;
        t(0, 0) = k;
        t(1, 1) = std::fabs(k);
        t(2, 2) = 0.8;
        t(0, 3) = 0.2 * k;
        s.add_instance(p, t);
    }
    return s;
}

std::vector<Case> cases()
{
    std::vector<Case> out;
    Camera front = Camera::perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60, 0.5, 20);
    {
        Case c{"sphere, framing camera", {}, {}, 41, 29};
        c.scene.add_mesh(make_uv_sphere(240));
        c.camera = Camera::framing(c.scene.bounds());
        out.push_back(std::move(c));
    }
    {
        Case c{"sphere, orthographic", {}, {}, 33, 33};
        c.scene.add_mesh(make_uv_sphere(240));
        c.camera = Camera::framing(c.scene.bounds(), Projection::Orthographic);
        out.push_back(std::move(c));
    }
    {
        Case c{"sphere, intrinsics off-centre", {}, {}, 40, 30};
        c.scene.add_mesh(make_uv_sphere(240));
        c.camera = Camera::framing(c.scene.bounds());
        c.camera.intrinsics = Intrinsics{40, 36, 12.5, 20};
        out.push_back(std::move(c));
    }
    {
        // Near and far clipping, behind the eye, a triangle far larger than the screen, a
        // degenerate one, coincident ones (tie to the lower id).
        Case c{"clipping and ties", {}, front, 48, 32};
        c.scene.add_mesh(triangle(-1, -1, -0.2f, 1, -1, -3, 0, 1, -3));       // crosses near
        c.scene.add_mesh(triangle(-1, -1, 2, 1, -1, 2, 0, 1, 2));             // behind the eye
        c.scene.add_mesh(triangle(-1e3f, -1e3f, -15, 1e3f, -1e3f, -30, 0, 1e3f, -25)); // huge, crosses far
        c.scene.add_mesh(triangle(0, 0, -4, 0, 0, -4, 0, 0, -4));             // degenerate
        c.scene.add_mesh(triangle(-0.5f, -0.5f, -5, 0.5f, -0.5f, -5, 0, 0.5f, -5));
        c.scene.add_mesh(triangle(-0.5f, -0.5f, -5, 0.5f, -0.5f, -5, 0, 0.5f, -5)); // coincident
        out.push_back(std::move(c));
    }
    {
        // Many small triangles in one tile, the rest of the screen empty.
        Case c{"crowded tile", {}, front, 64, 64};
        MeshData soup = make_soup(400, 5);
        Mat4 m; // squeeze the unit cube into a small patch in front of the camera
        m(0, 0) = 0.2;
        m(1, 1) = 0.2;
        m(0, 3) = -0.1;
        m(1, 3) = -0.1;
        m(2, 3) = -4;
        c.scene.add_mesh(soup, m);
        out.push_back(std::move(c));
    }
    return out;
}

/// More triangles listed for binning than the raster path's first list holds
/// (detail::raster_first_tri_capacity): one-row triangles 12 px wide (too wide for setup's
/// small-triangle path) in a 48x16 image, so the first frame overflows the list, grows it and runs
/// setup again. Their boxes overlap in every tile.
Case overflowing_list()
{
    const int w = 48, h = 16, n = int(clvis::detail::raster_first_tri_capacity) + 104;
    Case c{"overflowing triangle list", {}, Camera::orthographic({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, h, 0.5, 100), w, h};
    MeshData m;
    for (int i = 0; i < n; ++i) {
        float x = float((i * 37) % (w - 12)) - w / 2.0f, y = h / 2.0f - float(i % h) - 0.2f;
        float d = 1.0f + float((i * 53) % 97) * 0.5f;
        m.positions.insert(m.positions.end(), {x, y, -d, x + 12.0f, y - 0.3f, -d, x + 3.0f, y - 0.6f, -d});
        for (std::uint32_t k = 0; k < 3; ++k) m.indices.push_back(3 * std::uint32_t(i) + k);
    }
    c.scene.add_mesh(m);
    return c;
}

/// Renders `path` on a fresh Oclgrind device and on PoCL with `options` (and, for a scene with
/// instances, `chunk` triangles per chunk of the raster path when not 0); the keys must match.
void check_on_grind(const Device& pocl, const Case& c, Path path, const RenderOptions& options = {},
                    std::size_t chunk = 0)
{
    Device grind = Device::open("oclgrind");
    Renderer on_grind(grind, c.scene, options);
    Renderer on_pocl(pocl, c.scene, options);
    if (chunk) {
        clvis::detail::set_raster_chunk(on_grind, chunk);
        clvis::detail::set_raster_chunk(on_pocl, chunk);
    }
    auto a = on_grind.render(c.camera, c.width, c.height, path).read_keys();
    auto b = on_pocl.render(c.camera, c.width, c.height, path).read_keys();
    std::size_t differ = 0, covered = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        differ += a[i] != b[i];
        covered += (b[i] & 0xFFFFFFFFu) != background_id;
    }
    CHECK(differ == 0);
    CHECK(covered > 0);
}

} // namespace

// Each case opens Oclgrind afresh: Oclgrind 21.10 reports reads of kernel-written buffers as
// uninitialised once an earlier context's buffers on the same device have been released.
TEST_CASE("every kernel runs clean on Oclgrind and matches PoCL bit for bit", "[.oclgrind]")
{
    Device pocl = Device::open("portable computing language");
    REQUIRE(Device::open("oclgrind").info().name.find("Oclgrind") != std::string::npos);
    for (Case& c : cases()) {
        for (Path path : {Path::Raster, Path::Ray, Path::Brute}) {
            INFO(c.name << ", " << to_string(path) << " path");
            check_on_grind(pocl, c, path);
        }
    }
    // Shading reads the visibility buffer and the scene: it runs clean too.
    Case c = std::move(cases().front());
    Renderer r(Device::open("oclgrind"), c.scene);
    auto vis = r.render(c.camera, c.width, c.height, Path::Raster);
    for (ShadeMode mode : {ShadeMode::Lambert, ShadeMode::Depth, ShadeMode::Ids}) {
        ShadeOptions o;
        o.mode = mode;
        CHECK(shade(r, vis, c.camera, o).rgba.size() == std::size_t(c.width) * c.height * 4);
    }
    // So do the attributes and the visible set, which read nothing else.
    AttributeRequest all;
    all.barycentrics = all.position = all.normal = all.smooth_normal = true;
    AttributeBuffers attrs = resolve(r, vis, c.camera, all);
    CHECK(attrs.read(Attribute::SmoothNormal).size() == std::size_t(c.width) * c.height * 3);
    VisibleSet set(r.device(), std::uint32_t(c.scene.triangle_count()));
    set.mark(vis);
    set.mark(vis);
    CHECK(!set.read_ids().empty());
}

/// Answers of the three queries for `rays` (through the BVH, or brute force), each work-item
/// walking `lanes` rays interleaved.
std::vector<std::uint32_t> query_all(Renderer& r, const std::vector<RayRecord>& rays, bool brute, int lanes = 1)
{
    RayQueryOptions options{64, brute};
    options.lanes = lanes;
    RayQuery q(r, options);
    std::vector<HitRecord> hits(rays.size());
    std::vector<std::uint8_t> flags(rays.size());
    std::vector<std::uint32_t> counts(rays.size()), out;
    q.closest({rays.data(), rays.size()}, hits.data());
    q.occluded({rays.data(), rays.size()}, flags.data());
    q.count({rays.data(), rays.size()}, counts.data());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        std::uint32_t t;
        std::memcpy(&t, &hits[i].t, 4);
        out.insert(out.end(), {t, hits[i].id, flags[i], counts[i]});
    }
    return out;
}

/// All hits of `rays` (3 a ray; with counts, then without) as words: t, id, u, v per hit, the counts.
std::vector<std::uint32_t> all_hits_words(Renderer& r, const std::vector<RayRecord>& rays, bool brute, int lanes = 1)
{
    RayQueryOptions options{64, brute};
    options.lanes = lanes;
    RayQuery q(r, options);
    std::vector<HitRecord> hits(rays.size() * 3), pruned(rays.size() * 3);
    std::vector<std::uint32_t> counts(rays.size()), out(hits.size() * 8);
    q.all({rays.data(), rays.size()}, 3, hits.data(), counts.data());
    q.all({rays.data(), rays.size()}, 3, pruned.data());
    std::memcpy(out.data(), hits.data(), hits.size() * sizeof(HitRecord));
    std::memcpy(out.data() + hits.size() * 4, pruned.data(), pruned.size() * sizeof(HitRecord));
    out.insert(out.end(), counts.begin(), counts.end());
    return out;
}

TEST_CASE("the ray query kernels run clean on Oclgrind and match PoCL", "[.oclgrind]")
{
    Scene scene;
    scene.add_mesh(make_uv_sphere(40));
    // The same sphere also as a prototype: three instances, one mirrored (CLVIS_INSTANCES).
    Scene instanced = plain_and_instanced(scene.data_of(0));
    std::vector<RayRecord> rays;
    for (int i = 0; i < 150; ++i) {
        float a = 0.37f * float(i), z = float(i % 7) - 3.0f;
        rays.push_back(RayRecord{1.5f * std::cos(a), 0.3f * z, 1.5f * std::sin(a), 0, -std::cos(a), 0.1f, -std::sin(a),
                                 i % 5 ? std::numeric_limits<float>::infinity() : 1.0f});
    }
    rays.push_back(RayRecord{0, 0, 0, 1, 0, 0, 0, 2});                                             // zero direction
    rays.push_back(RayRecord{std::nanf(""), 0, 0, 0, 1, 0, 0, 2});                                 // NaN
    rays.push_back(RayRecord{0, 0, 0, 0, 0, 1, 0, std::numeric_limits<float>::infinity()});         // from inside
    Device pocl = Device::open("portable computing language");
    for (const Scene* s : {&scene, &instanced}) {
        for (bool brute : {false, true}) {
            INFO((s == &scene ? "plain, " : "instanced, ") << (brute ? "brute force" : "BVH"));
            Renderer on_grind(Device::open("oclgrind"), *s), on_pocl(pocl, *s);
            const auto want = query_all(on_pocl, rays, brute);
            CHECK(query_all(on_grind, rays, brute) == want);
            // three rays walked interleaved per work-item (a run of 12 per work-item, 153 rays:
            // the last work-items' lanes run out at different steps)
            if (!brute) CHECK(query_all(on_grind, rays, false, 3) == want);
            const auto all_want = all_hits_words(on_pocl, rays, brute);
            CHECK(all_hits_words(on_grind, rays, brute, brute ? 1 : 3) == all_want);
        }
    }
}

// Oclgrind 21.10's uninitialised-value checker loses track of a buffer's bytes when a buffer is
// freed and another allocated in its place between two kernels: the generator's rays, made anew
// on every call, read as uninitialised in the second call (each call alone was clean). RayQuery
// now keeps its generated-ray buffers from call to call, and the case runs with every check on.
TEST_CASE("the ray generation kernels run clean on Oclgrind and match PoCL", "[.oclgrind]")
{
    Scene scene;
    scene.add_mesh(make_uv_sphere(40));
    Camera cam = Camera::framing(scene.bounds());
    AoOptions o;
    o.rays = 2;
    Device pocl = Device::open("portable computing language");
    Renderer on_grind(Device::open("oclgrind"), scene), on_pocl(pocl, scene);
    auto vis_grind = on_grind.render(cam, 9, 7, Path::Ray);
    auto vis_pocl = on_pocl.render(cam, 9, 7, Path::Ray);
    RayQuery q_grind(on_grind), q_pocl(on_pocl);
    auto ao_grind = q_grind.ambient_occlusion(vis_grind, cam, o), ao_pocl = q_pocl.ambient_occlusion(vis_pocl, cam, o);
    CHECK(ao_grind.value.size() == 63);
    CHECK(ao_grind.value == ao_pocl.value);
    auto shadow_grind = q_grind.shadows(vis_grind, cam, Vec3{0, 5, 0});
    auto shadow_pocl = q_pocl.shadows(vis_pocl, cam, Vec3{0, 5, 0});
    CHECK(shadow_grind.value.size() == 63);
    CHECK(shadow_grind.value == shadow_pocl.value);
}

TEST_CASE("the raster path's list growth and rerun run clean on Oclgrind", "[.oclgrind]")
{
    Device pocl = Device::open("portable computing language");
    Case c = overflowing_list();
    check_on_grind(pocl, c, Path::Raster);
}

TEST_CASE("small frames binned in one launch run clean on Oclgrind", "[.oclgrind]")
{
    // raster_bin_small (PoCL's CPU device's binning of small frames), forced on both devices:
    // its local counts and cursors between barriers, the overflowing list's growth and rerun too.
    struct SmallFrames {
        SmallFrames() { clvis::detail::set_raster_small_frames(1); }
        ~SmallFrames() { clvis::detail::set_raster_small_frames(-1); }
    } on;
    Device pocl = Device::open("portable computing language");
    Case c = std::move(cases().front());
    check_on_grind(pocl, c, Path::Raster);
    check_on_grind(pocl, overflowing_list(), Path::Raster);
}

TEST_CASE("tile and BVH leaf sizes other than the defaults run clean on Oclgrind", "[.oclgrind]")
{
    // The smallest tile with one-triangle leaves, the largest tile with the largest leaves.
    Device pocl = Device::open("portable computing language");
    for (auto [tile, leaf] : {std::pair{4, 1}, {256, 64}}) {
        RenderOptions o;
        o.tile_size = tile;
        o.bvh.max_leaf_size = leaf;
        o.bvh.sah_bins = leaf == 1 ? 2 : 64;
        Case c = std::move(cases().front());
        for (Path path : {Path::Raster, Path::Ray}) {
            INFO(c.name << ", tile " << tile << ", leaf " << leaf << ", " << to_string(path) << " path");
            check_on_grind(pocl, c, path, o);
        }
    }
}

TEST_CASE("the pixel mapping of the raster fine stage runs clean on Oclgrind", "[.oclgrind]")
{
    // Its batches in local memory between barriers, under both depth tests and a tile smaller
    // than its largest group (Oclgrind checks barriers, races and local memory); keys as PoCL's.
    Device pocl = Device::open("portable computing language");
    for (RasterAtomics mode : {RasterAtomics::Off, RasterAtomics::Auto}) {
        for (int tile : {0, 8}) {
            RenderOptions o;
            o.raster_mapping = RasterMapping::Pixel;
            o.raster_atomics = mode;
            o.tile_size = tile;
            Case c = std::move(cases().front());
            INFO(c.name << ", atomics " << to_string(mode) << ", tile " << tile);
            check_on_grind(pocl, c, Path::Raster, o);
        }
    }
}

namespace {

/// The first case's mesh as a prototype: a plain copy, then three instances (one mirrored).
Case first_case_instanced()
{
    Case c = std::move(cases().front());
    return Case{c.name + " instanced", plain_and_instanced(c.scene.data_of(0)), c.camera, c.width, c.height};
}

} // namespace

TEST_CASE("the two-level walk of instances runs clean on Oclgrind in both coverage modes", "[.oclgrind]")
{
    Device pocl = Device::open("portable computing language");
    Case inst = first_case_instanced();
    for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
        RenderOptions o;
        o.coverage = coverage;
        INFO(to_string(coverage));
        check_on_grind(pocl, inst, Path::Ray, o);
    }
}

TEST_CASE("ray_trace_single runs clean on Oclgrind in both coverage modes", "[.oclgrind]")
{
    // ray_trace_single.cl on a plain scene and on instances (the two-level walk), a group per tile
    // with the last row and column of groups partly outside the image; keys as PoCL's packets.
    Device pocl = Device::open("portable computing language");
    Case c = std::move(cases().front());
    Case inst{c.name + " instanced", plain_and_instanced(c.scene.data_of(0)), c.camera, c.width, c.height};
    for (const Case* k : {&c, &inst}) {
        for (Coverage coverage : {Coverage::Watertight, Coverage::RasterRule}) {
            RenderOptions single, packet;
            single.coverage = packet.coverage = coverage;
            single.ray_mapping = RayMapping::Single;
            INFO(k->name << ", " << to_string(coverage));
            Renderer on_grind(Device::open("oclgrind"), k->scene, single), on_pocl(pocl, k->scene, packet);
            CHECK(on_grind.render(k->camera, k->width, k->height, Path::Ray).read_keys() ==
                  on_pocl.render(k->camera, k->width, k->height, Path::Ray).read_keys());
        }
    }
}

TEST_CASE("the raster path's chunks of instances run clean on Oclgrind", "[.oclgrind]")
{
    // A chunk per item (the plain copy, then each instance) under both depth tests.
    Device pocl = Device::open("portable computing language");
    Case inst = first_case_instanced();
    for (RasterAtomics mode : {RasterAtomics::Off, RasterAtomics::Auto}) {
        INFO(to_string(mode));
        RenderOptions o;
        o.raster_atomics = mode;
        check_on_grind(pocl, inst, Path::Raster, o, 1);
    }
}
