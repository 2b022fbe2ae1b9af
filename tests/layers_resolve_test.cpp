// Depth layers downstream (issue 36: barycentrics, attributes and object ids per layer): a layer
// taken out of a layered buffer (VisibilityBuffer::layer) holds that layer's keys bit for bit, and
// everything that reads a one-layer buffer reads it: resolve's barycentrics, judged by the
// BarycentricReferee against the layer's own depths, and object ids, which must name the item of
// each layer's triangle, on both paths.
#include "catch.hpp"
#include "test_meshes.hpp"

#include <clvis/attributes.hpp>
#include <clvis/clvis.hpp>
#include <clvis/procedural.hpp>
#include <clvis/referee_attributes.hpp>

#include <vector>

using namespace clvis;

TEST_CASE("depth layers: each layer taken out resolves barycentrics and object ids", "[device][layers]")
{
    // Two spheres, one behind the other, and an instance: up to four surfaces per pixel, and
    // layers that belong to different items.
    Scene s;
    s.add_mesh(make_uv_sphere(600));
    Mat4 behind = Mat4::identity();
    behind(0, 3) = 0.4;
    behind(2, 3) = -1.5;
    s.add_mesh(make_uv_sphere(600), behind);
    std::size_t proto = s.add_prototype(make_uv_sphere(300));
    Mat4 small = Mat4::identity();
    small(0, 0) = small(1, 1) = small(2, 2) = 0.5;
    small(1, 3) = 0.3;
    small(2, 3) = 0.8;
    s.add_instance(proto, small);
    Camera cam = Camera::perspective({0.2, 0.3, 4}, {0, 0, -0.5}, {0, 1, 0}, 45, 0.5, 20);
    const int w = 96, h = 72, layers = 4;
    BarycentricReferee judge(s, cam, w, h);
    for (Path path : {Path::Raster, Path::Ray}) {
        RenderOptions o;
        o.layers = layers;
        Renderer r(Device::open(), s, o);
        VisibilityBuffer vis = r.render(cam, w, h, path);
        HostVisibility all = vis.read(); // the layers of a sample adjacent
        std::size_t deep = 0;
        for (int k = 0; k < layers; ++k) {
            INFO(to_string(path) << " path, layer " << k);
            VisibilityBuffer one = vis.layer(k);
            REQUIRE(one.layers() == 1);
            HostVisibility l = one.read();
            std::size_t differ = 0;
            for (std::size_t i = 0; i < l.ids.size(); ++i)
                differ += l.ids[i] != all.ids[i * layers + std::size_t(k)] ||
                          l.depth[i] != all.depth[i * layers + std::size_t(k)];
            CHECK(differ == 0);
            AttributeRequest q;
            q.barycentrics = true;
            q.object = true;
            AttributeBuffers a = resolve(r, one, cam, q);
            BaryReport report = judge.check(l, a.read(Attribute::Barycentrics));
            CHECK(report.errors == 0);
            std::vector<std::uint32_t> objects;
            a.read_objects(objects);
            std::size_t wrong = 0;
            for (std::size_t i = 0; i < l.ids.size(); ++i) {
                std::uint32_t expect = l.ids[i] == background_id ? background_id : std::uint32_t(s.mesh_of(l.ids[i]));
                wrong += objects[i] != expect;
                deep += k > 0 && l.ids[i] != background_id;
            }
            CHECK(wrong == 0);
        }
        CHECK(deep > 1000); // the layers behind the first hold surfaces
    }
    RenderOptions o;
    o.layers = 2;
    Renderer r(Device::open(), s, o);
    VisibilityBuffer vis = r.render(cam, w, h, Path::Raster);
    CHECK_THROWS_WITH(vis.layer(2), Catch::Contains("layer 2 of a buffer of 2"));
    CHECK_THROWS_WITH(VisibilityBuffer().layer(0), Catch::Contains("empty"));
}
