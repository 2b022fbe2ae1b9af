// Named corner attributes, object ids and camera-space normals resolved on the device
// (kernels/resolve_corners.cl, kernels/resolve.cl): uv with seams, RGBA colours and a custom
// one-component property on plain meshes and instances, judged by the CornerReferee in double on
// both paths; object ids against Scene::mesh_of; camera-space normals against the world normals
// rotated in double; NaN where a mesh lacks the attribute; unknown names and several samples per
// pixel refused by name.
#include "catch.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>

#include <cmath>
#include <set>
#include <string>
#include <vector>

using namespace clvis;

namespace {

/// Corner attributes set by hand: "uv" with a seam at every other triangle (one vertex, two
/// values), "color" RGBA and "temperature" (large magnitudes: the tolerance is relative).
void add_attributes(MeshData& m, bool temperature = true)
{
    m.attributes.clear();
    CornerAttribute uv{"uv", 2, {}}, color{"color", 4, {}}, temp{"temperature", 1, {}};
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const float* p = &m.positions[3 * std::size_t(m.indices[3 * t + k])];
            uv.values.push_back(std::fmod(std::fabs(p[0]) * 3.0f + float(t % 2) * 0.5f, 1.0f));
            uv.values.push_back(p[1]);
            for (int c = 0; c < 3; ++c) color.values.push_back(0.5f + 0.4f * std::sin(3.0f * p[c] + float(c)));
            color.values.push_back(float(t % 7) / 7);
            temp.values.push_back(300.0f + 50.0f * p[2] + float(t % 11));
        }
    m.attributes.push_back(uv);
    m.attributes.push_back(color);
    if (temperature) m.attributes.push_back(temp);
}

using test::placed;

MeshData spot()
{
    MeshData m = load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj");
    m.attributes.clear();
    return m;
}

/// Plain meshes: spot with every attribute, a quad behind it with none, a smaller spot without
/// "temperature".
Scene plain_scene()
{
    Scene s;
    MeshData a = spot(), quad;
    add_attributes(a);
    quad.name = "quad";
    quad.positions = {-1, -1, -0.8f, 1, -1, -0.8f, 1, 1.2f, -0.8f, -1, 1.2f, -0.8f};
    quad.indices = {0, 1, 2, 0, 2, 3};
    MeshData b = spot();
    add_attributes(b, false);
    s.add_mesh(a);
    s.add_mesh(quad);
    s.add_mesh(b, placed(0.4, {0.9, -0.4, 0.3}, 0.5));
    return s;
}

/// Items: a plain quad (none), instances of spot (every attribute), a plain spot (no
/// temperature), more instances.
Scene instanced_scene()
{
    Scene s;
    MeshData quad, proto = spot(), plain = spot();
    quad.name = "quad";
    quad.positions = {-1.7f, -1.3f, -1, 1.7f, -1.3f, -1, 1.7f, 1.6f, -1, -1.7f, 1.6f, -1};
    quad.indices = {0, 1, 2, 0, 2, 3};
    add_attributes(proto);
    add_attributes(plain, false);
    s.add_mesh(quad);
    std::size_t p = s.add_prototype(proto);
    s.add_instance(p, placed(0.3, {-1.2, 0.3, 0}, 0.7));
    s.add_instance(p, placed(1.4, {1.1, 0.5, 0.2}, 0.6));
    s.add_mesh(plain, placed(-0.5, {0, -0.9, 0.4}, 0.5));
    s.add_instance(p, placed(2.2, {0.2, 1.2, -0.5}, 0.5));
    return s;
}

void check_scene(const Scene& s, const std::string& what)
{
    Renderer renderer(Device::open(), s);
    const int w = 160, h = 120;
    Camera cam = Camera::framing(s.bounds());
    Camera ortho = Camera::framing(s.bounds(), Projection::Orthographic);
    const std::vector<std::string> names = {"uv", "color", "temperature"};
    AttributeRequest req;
    req.named = names;
    req.object = true;
    AttributeBuffers attrs;
    for (const Camera& c : {cam, ortho}) {
        CornerReferee judge(s, c, w, h);
        for (Path p : {Path::Raster, Path::Ray}) {
            VisibilityBuffer vis = renderer.render(c, w, h, p);
            HostVisibility host = vis.read();
            resolve(renderer, vis, c, req, attrs); // buffers reused from the second round on
            CHECK(attrs.names() == names);
            for (const std::string& name : names) {
                std::vector<float> values;
                attrs.read(name, values);
                CornerReport rep = judge.check(host, name, values);
                std::string errors;
                for (const auto& e : rep.first_errors) errors += "\n  " + e;
                INFO(what << " " << to_string(p) << " " << name << errors);
                CHECK(rep.covered > std::size_t(w * h / 40));
                CHECK(rep.covered < rep.pixels); // NaN pixels judged too
                CHECK(rep.errors == 0);
                std::printf("attr %-10s %-6s %-11s %zu covered, max %.2f of the tolerance\n", what.c_str(),
                            to_string(p), name.c_str(), rep.covered, rep.max_error_share);
                // The referee can fail: one covered value off by 1e-4 of the largest, one NaN answered.
                const std::size_t c = std::size_t(attrs.components(name));
                std::size_t i = 0;
                while (host.ids[i] == background_id || std::isnan(values[i * c])) ++i;
                values[i * c] += 1e-4f * std::fmax(1.0f, std::fabs(values[i * c]));
                std::size_t j = 0;
                while (host.ids[j] != background_id) ++j;
                values[j * c] = 0;
                CHECK(judge.check(host, name, values).errors == 2);
            }
            std::vector<std::uint32_t> objects;
            attrs.read_objects(objects);
            std::vector<std::string> first;
            std::size_t wrong = judge.check_objects(host, objects, &first);
            INFO(what << " objects " << (first.empty() ? "" : first[0]));
            CHECK(wrong == 0);
            std::set<std::uint32_t> seen(objects.begin(), objects.end());
            CHECK(seen.count(background_id) == 1);
            CHECK(seen.size() >= 4); // the background and several items
        }
    }
}

} // namespace

TEST_CASE("named attributes and object ids of plain meshes pass the referee on both paths",
          "[device][attributes_resolve]")
{
    check_scene(plain_scene(), "plain");
}

TEST_CASE("instances read their prototype's corners and get their own object ids",
          "[device][attributes_resolve]")
{
    check_scene(instanced_scene(), "instanced");
}

TEST_CASE("a mesh without the attribute and the background give NaN", "[device][attributes_resolve]")
{
    Scene s = plain_scene();
    Renderer renderer(Device::open(), s);
    Camera cam = Camera::framing(s.bounds());
    VisibilityBuffer vis = renderer.render(cam, 64, 48, Path::Raster);
    HostVisibility host = vis.read();
    AttributeRequest req;
    req.named = {"temperature"};
    AttributeBuffers attrs = resolve(renderer, vis, cam, req);
    std::vector<float> t;
    attrs.read("temperature", t);
    CHECK(!attrs.has_objects());
    CHECK(attrs.components("temperature") == 1);
    std::size_t nan = 0, finite = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        std::uint32_t id = host.ids[i];
        bool has = id != background_id && s.mesh_of(id) == 0; // only mesh 0 has it
        if (has) CHECK(std::isfinite(t[i]));
        else CHECK(std::isnan(t[i]));
        (has ? finite : nan) += 1;
    }
    CHECK(finite > 0);
    CHECK(nan > 0);
}

TEST_CASE("unknown names and several samples per pixel are refused by name", "[device][attributes_resolve]")
{
    Scene s = plain_scene();
    Renderer renderer(Device::open(), s);
    Camera cam = Camera::framing(s.bounds());
    VisibilityBuffer vis = renderer.render(cam, 32, 24, Path::Raster);
    AttributeRequest req;
    req.named = {"uv", "albedo"};
    CHECK_THROWS_WITH(resolve(renderer, vis, cam, req),
                      Catch::Contains("'albedo'") && Catch::Contains("uv, color, temperature"));
    Scene bare;
    MeshData quad;
    quad.positions = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
    quad.indices = {0, 1, 2};
    bare.add_mesh(quad);
    CHECK(scene_attributes(bare).empty());
    RenderOptions four;
    four.samples = 4;
    Renderer r4(Device::open(), s, four);
    VisibilityBuffer v4 = r4.render(cam, 32, 24, Path::Raster);
    AttributeRequest obj;
    obj.object = true;
    CHECK_THROWS_WITH(resolve(r4, v4, cam, obj), Catch::Contains("one sample per pixel"));
    CHECK_THROWS_WITH(normal_space_from_string("eye"), Catch::Contains("'eye'"));
}

TEST_CASE("camera-space normals are the world normals in the camera's axes", "[device][attributes_resolve]")
{
    Scene s = instanced_scene();
    Renderer renderer(Device::open(), s);
    const int w = 96, h = 72;
    Camera cam = Camera::framing(s.bounds());
    cam.eye = cam.eye + Vec3{0.3, -0.2, 0.1};
    CameraFrame fr = cam.frame();
    for (Path p : {Path::Raster, Path::Ray}) {
        VisibilityBuffer vis = renderer.render(cam, w, h, p);
        AttributeRequest world;
        world.normal = world.smooth_normal = true;
        AttributeRequest camera = world;
        camera.normal_space = NormalSpace::Camera;
        AttributeBuffers a = resolve(renderer, vis, cam, world), b = resolve(renderer, vis, cam, camera);
        for (Attribute which : {Attribute::Normal, Attribute::SmoothNormal}) {
            std::vector<float> n = a.read(which), c = b.read(which);
            std::size_t covered = 0;
            double worst = 0;
            for (std::size_t i = 0; i < n.size(); i += 3) {
                Vec3 v{n[i], n[i + 1], n[i + 2]};
                if (std::isnan(v.x)) {
                    CHECK(std::isnan(c[i]));
                    continue;
                }
                ++covered;
                Vec3 want{dot(v, fr.r), dot(v, fr.u), -dot(v, fr.f)};
                double off = std::fmax(std::fabs(want.x - c[i]), std::fabs(want.y - c[i + 1]));
                worst = std::fmax(worst, std::fmax(off, std::fabs(want.z - c[i + 2])));
            }
            INFO(to_string(p) << " " << to_string(which) << " worst " << worst);
            CHECK(covered > std::size_t(w * h / 10));
            CHECK(worst < 1e-6);
        }
    }
}

TEST_CASE("attributes of triangles a pixel or two across meet the tolerance", "[device][attributes_resolve]")
{
    // The bunny's triangles at 640x360 cover a pixel or two: float32 barycentrics (resolve's, from
    // the float32 ray) would leave little margin there; the exact ones the kernel computes leave plenty.
    MeshData bunny = load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/stanford-bunny.obj");
    bunny.attributes.clear();
    CornerAttribute uv{"uv", 2, {}};
    for (std::uint32_t i : bunny.indices)
        uv.values.insert(uv.values.end(), {bunny.positions[3 * i] * 10, bunny.positions[3 * i + 1] * 10});
    bunny.attributes.push_back(uv);
    Scene s;
    s.add_mesh(bunny);
    Renderer renderer(Device::open(), s);
    const int w = 640, h = 360;
    Camera cam = Camera::framing(s.bounds());
    CornerReferee judge(s, cam, w, h);
    AttributeRequest req;
    req.named = {"uv"};
    for (Path p : {Path::Raster, Path::Ray}) {
        VisibilityBuffer vis = renderer.render(cam, w, h, p);
        std::vector<float> values;
        resolve(renderer, vis, cam, req).read("uv", values);
        CornerReport rep = judge.check(vis.read(), "uv", values);
        INFO(to_string(p) << (rep.first_errors.empty() ? "" : " " + rep.first_errors[0]));
        CHECK(rep.covered > std::size_t(w * h / 20));
        CHECK(rep.errors == 0);
        CHECK(rep.max_error_share < 0.1);
        std::printf("attr bunny %-6s uv %zu covered, max %.3f of the tolerance\n", to_string(p), rep.covered,
                    rep.max_error_share);
    }
}
