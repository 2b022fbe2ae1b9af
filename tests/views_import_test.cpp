// Cameras from other tools as views (CONVENTIONS.md "Cameras from other tools"): NeRF's
// transforms.json (fl_x and camera_angle_x forms, per-frame intrinsics), COLMAP text models
// (PINHOLE, SIMPLE_PINHOLE) and glTF camera nodes (perspective, orthographic, under a transformed
// parent), each the same camera, bit for bit, as the clvis views file that spells the documented
// meaning out, and rendering the same keys; the refusals name the file and the line or field.
#include "catch.hpp"
#include "test_files.hpp"
#include "test_meshes.hpp"

#include <clvis/clvis.hpp>
#include <clvis/views_file.hpp>

#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace clvis;

namespace {

const char* folder = "clvis-views-import-test";
constexpr double pi = 3.14159265358979323846;

std::string num(double v)
{
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string write(const std::string& name, const std::string& text) { return test::write_temp_file(folder, name, text); }

/// The 16 numbers of `m` row by row, as a flat JSON list or as 4 rows (NeRF's transform_matrix).
std::string flat(const Mat4& m)
{
    std::string s = "[";
    for (int i = 0; i < 16; ++i) s += (i ? ", " : "") + num(m.m[std::size_t(i)]);
    return s + "]";
}
std::string rows(const Mat4& m)
{
    std::string s = "[";
    for (int r = 0; r < 4; ++r) {
        s += r ? ", [" : "[";
        for (int c = 0; c < 4; ++c) s += (c ? ", " : "") + num(m(r, c));
        s += "]";
    }
    return s + "]";
}
std::string vec(Vec3 v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; }
/// glTF's column-major "matrix".
std::string column_major(const Mat4& m)
{
    std::string s = "[";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) s += (c || r ? ", " : "") + num(m(r, c));
    return s + "]";
}

bool same_camera(const Camera& a, const Camera& b)
{
    auto same = [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; };
    auto same3 = [&](Vec3 x, Vec3 y) { return same(x.x, y.x) && same(x.y, y.y) && same(x.z, y.z); };
    bool k = a.intrinsics.has_value() == b.intrinsics.has_value();
    if (k && a.intrinsics)
        k = same(a.intrinsics->fx, b.intrinsics->fx) && same(a.intrinsics->fy, b.intrinsics->fy) &&
            same(a.intrinsics->cx, b.intrinsics->cx) && same(a.intrinsics->cy, b.intrinsics->cy);
    return k && same3(a.eye, b.eye) && same3(a.target, b.target) && same3(a.up, b.up) &&
           a.projection == b.projection && same(a.fov_y, b.fov_y) && same(a.ortho_height, b.ortho_height) &&
           same(a.near, b.near) && same(a.far, b.far);
}

/// The bunny and a device, once for the file.
struct Bunny {
    Scene scene = test::scene_file("stanford-bunny.obj");
    Device device = Device::open();
    Renderer renderer{device, scene};
};
Bunny& bunny()
{
    static Bunny b;
    return b;
}

/// Both files hold the same cameras bit for bit, and each view renders the same keys (ray path),
/// covering some of the bunny.
void check_same(const ViewsFile& imported, const ViewsFile& expected)
{
    REQUIRE(imported.width == expected.width);
    REQUIRE(imported.height == expected.height);
    REQUIRE(imported.views.size() == expected.views.size());
    for (std::size_t v = 0; v < imported.views.size(); ++v) {
        INFO("view " << v << ": " << imported.views[v].to_flags() << " / " << expected.views[v].to_flags());
        CHECK(same_camera(imported.views[v], expected.views[v]));
        HostVisibility a = bunny().renderer.render(imported.views[v], imported.width, imported.height, Path::Ray).read();
        HostVisibility b = bunny().renderer.render(expected.views[v], expected.width, expected.height, Path::Ray).read();
        CHECK(test::differing_bits(a, b) == 0);
        CHECK(test::covered(a) > 50);
    }
    // and views_file_text writes them back as a clvis views file that reads as the same bits
    ViewsFile back = load_views_file(write("back.json", views_file_text(imported)));
    REQUIRE(back.views.size() == imported.views.size());
    for (std::size_t v = 0; v < back.views.size(); ++v) CHECK(same_camera(back.views[v], imported.views[v]));
}

/// The message of the error that loading `path` throws (it starts with the path), "" if none.
std::string load_error(const std::string& path, std::optional<int> w = std::nullopt, std::optional<int> h = std::nullopt)
{
    try {
        load_views_file(path, w, h);
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find(path) == 0);
        return e.what();
    }
    return "";
}

/// Cameras around the bunny (its centre about (-0.017, 0.11, 0), radius about 0.1).
Camera around(int k)
{
    Vec3 c{-0.017, 0.11, 0};
    Vec3 eyes[3] = {{0.05, 0.2, 0.3}, {-0.3, 0.15, -0.1}, {0.2, 0.05, -0.25}};
    return test::look(c + eyes[k], c, 40, 0.01, 10);
}

/// COLMAP's world-to-camera of a clvis camera: R's rows r, -u, f (OpenCV's axes), t = -R eye, and
/// R's unit quaternion (w, x, y, z).
void colmap_of(const Camera& cam, double q[4], double t[3])
{
    CameraFrame fr = cam.frame();
    Vec3 rows3[3] = {fr.r, fr.u * -1.0, fr.f};
    double R[3][3];
    for (int i = 0; i < 3; ++i) {
        R[i][0] = rows3[i].x;
        R[i][1] = rows3[i].y;
        R[i][2] = rows3[i].z;
        t[i] = -(R[i][0] * cam.eye.x + R[i][1] * cam.eye.y + R[i][2] * cam.eye.z);
    }
    double tr = R[0][0] + R[1][1] + R[2][2];
    if (tr > 0) {
        double s = 2 * std::sqrt(tr + 1);
        q[0] = s / 4;
        q[1] = (R[2][1] - R[1][2]) / s;
        q[2] = (R[0][2] - R[2][0]) / s;
        q[3] = (R[1][0] - R[0][1]) / s;
    } else {
        int i = R[1][1] > R[0][0] ? (R[2][2] > R[1][1] ? 2 : 1) : (R[2][2] > R[0][0] ? 2 : 0);
        int j = (i + 1) % 3, k = (i + 2) % 3;
        double s = 2 * std::sqrt(1 + R[i][i] - R[j][j] - R[k][k]);
        q[1 + i] = s / 4;
        q[0] = (R[k][j] - R[j][k]) / s;
        q[1 + j] = (R[j][i] + R[i][j]) / s;
        q[1 + k] = (R[k][i] + R[i][k]) / s;
    }
}

/// The clvis pose of COLMAP's image (qw, qx, qy, qz, t) as CONVENTIONS.md spells it: the unit
/// quaternion's rotation R (COLMAP's formula), the camera-to-world [R^T | -R^T t], its axes
/// (x, -y, -z) flipped into clvis's (columns R's rows 0, -1, -2).
Mat4 pose_of_colmap(const double q_in[4], const double t[3])
{
    double n = std::sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] + q_in[3] * q_in[3]);
    double w = q_in[0] / n, x = q_in[1] / n, y = q_in[2] / n, z = q_in[3] / n;
    double R[3][3] = {{1 - 2 * y * y - 2 * z * z, 2 * x * y - 2 * w * z, 2 * z * x + 2 * w * y},
                      {2 * x * y + 2 * w * z, 1 - 2 * x * x - 2 * z * z, 2 * y * z - 2 * w * x},
                      {2 * z * x - 2 * w * y, 2 * y * z + 2 * w * x, 1 - 2 * x * x - 2 * y * y}};
    Mat4 p;
    for (int i = 0; i < 3; ++i) {
        p(i, 0) = R[0][i] + 0.0; // zeros +0
        p(i, 1) = -R[1][i] + 0.0;
        p(i, 2) = -R[2][i] + 0.0;
        p(i, 3) = -(R[0][i] * t[0] + R[1][i] * t[1] + R[2][i] * t[2]) + 0.0;
    }
    return p;
}

void check_pose_near(const Camera& got, const Camera& want)
{
    Mat4 a = got.pose(), b = want.pose();
    for (int i = 0; i < 12; ++i) CHECK(std::fabs(a.m[std::size_t(i)] - b.m[std::size_t(i)]) < 1e-12);
}

} // namespace

TEST_CASE("NeRF transforms.json: fl_x and camera_angle_x, per-frame intrinsics, as the views file", "[views_import][device]")
{
    const char* k = "\"fl_x\": 100.5, \"fl_y\": 98.25, \"cx\": 47.3, \"cy\": 35.1";
    std::string nerf = std::string("{\"w\": 96, \"h\": 72, ") + k + ", \"k1\": 0, \"p1\": 0, \"aabb_scale\": 4, \"frames\": [" +
                       "{\"file_path\": \"a.png\", \"transform_matrix\": " + rows(around(0).pose()) + "}, " +
                       "{\"file_path\": \"b.png\", \"fl_x\": 120, \"fl_y\": 121, \"transform_matrix\": " +
                       rows(around(1).pose()) + "}]}";
    std::string same = "{\"width\": 96, \"height\": 72, \"views\": [{\"pose\": " + flat(around(0).pose()) +
                       ", \"intrinsics\": [100.5, 98.25, 47.3, 35.1]}, {\"pose\": " + flat(around(1).pose()) +
                       ", \"intrinsics\": [120, 121, 47.3, 35.1]}]}";
    ViewsFile f = load_views_file(write("transforms.json", nerf));
    CHECK(f.format == ViewsFormat::Nerf);
    check_same(f, load_views_file(write("nerf-same.json", same)));
    check_pose_near(f.views[0], around(0));
    CHECK(load_views_file(write("transforms.json", nerf), 5, 5).width == 96); // the file's size wins

    // camera_angle_x: fx = fy = w / 2 / tan(angle / 2), the principal point at the centre; the size
    // from the caller when the file has none
    std::string angle = "{\"camera_angle_x\": 0.6911112070083618, \"frames\": [{\"transform_matrix\": " +
                        rows(around(2).pose()) + "}]}";
    std::string path = write("angle.json", angle);
    CHECK(load_error(path).find("w: missing: the image width") != std::string::npos);
    CHECK(load_error(path, 96).find("h: missing: the image height") != std::string::npos);
    double fx = 0.5 * 96 / std::tan(0.5 * 0.6911112070083618);
    std::string same2 = "{\"width\": 96, \"height\": 72, \"views\": [{\"pose\": " + flat(around(2).pose()) +
                        ", \"intrinsics\": [" + num(fx) + ", " + num(fx) + ", 48, 36]}]}";
    check_same(load_views_file(path, 96, 72), load_views_file(write("angle-same.json", same2)));
}

TEST_CASE("NeRF transforms.json refusals name the file and the field", "[views_import]")
{
    std::string frame = "{\"transform_matrix\": " + rows(around(0).pose()) + "}";
    auto file = [&](const std::string& top, const std::string& frames) {
        return "{\"w\": 32, \"h\": 24, " + top + "\"frames\": [" + frames + "]}";
    };
    CHECK(load_error(write("k1.json", file("\"fl_x\": 30, \"k1\": 0.01, ", frame))).find("k1: 0.01: lens distortion") !=
          std::string::npos);
    CHECK(load_error(write("p2.json", file("\"fl_x\": 30, ", "{\"p2\": -0.5, \"transform_matrix\": " +
                                                                 rows(around(0).pose()) + "}")))
              .find("frames[0].p2") != std::string::npos);
    Mat4 scaled = around(0).pose();
    for (int i = 0; i < 3; ++i) scaled(i, 0) *= 2;
    CHECK(load_error(write("scaled.json", file("\"fl_x\": 30, ", frame + ", {\"transform_matrix\": " + rows(scaled) + "}")))
              .find("frames[1].transform_matrix: pose: the 3x3 part is not orthonormal") != std::string::npos);
    CHECK(load_error(write("nofocal.json", file("", frame))).find("frames[0]: no focal length") != std::string::npos);
    CHECK(load_error(write("fisheye.json", file("\"fl_x\": 30, \"camera_model\": \"OPENCV_FISHEYE\", ", frame)))
              .find("camera_model: 'OPENCV_FISHEYE' is not read") != std::string::npos);
    CHECK(load_error(write("sizes.json", file("\"fl_x\": 30, ", frame + ", {\"w\": 64, \"transform_matrix\": " +
                                                                    rows(around(1).pose()) + "}")))
              .find("frames[1]: is 64x24, frames[0] 32x24") != std::string::npos);
}
TEST_CASE("COLMAP text models: PINHOLE and SIMPLE_PINHOLE, as the views file", "[views_import][device]")
{
    auto dir = test::fresh_temp_dir("clvis-views-import-colmap");
    std::string images = "# Image list with two lines of data per image:\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, "
                         "CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
    std::string same = "{\"width\": 96, \"height\": 72, \"views\": [";
    // images listed 7, 2, 4: views in ascending IMAGE_ID (2, 4, 7 = cameras 1, 2, 0)
    int ids[3] = {7, 2, 4}, camera_of[3] = {1, 2, 1};
    std::string by_id[3];
    for (int i = 0; i < 3; ++i) {
        double q[4], t[3];
        colmap_of(around(i), q, t);
        images += std::to_string(ids[i]) + " " + num(q[0]) + " " + num(q[1]) + " " + num(q[2]) + " " + num(q[3]) +
                  " " + num(t[0]) + " " + num(t[1]) + " " + num(t[2]) + " " + std::to_string(camera_of[i]) +
                  " img" + std::to_string(i) + ".png\n" + (i == 1 ? "\n" : "12.5 3.25 -1 40.0 2.0 17\n");
        const char* k = camera_of[i] == 1 ? "[100.5, 98.25, 47.3, 35.1]" : "[80, 80, 48.5, 36.5]";
        by_id[ids[i] == 2 ? 0 : ids[i] == 4 ? 1 : 2] = "{\"pose\": " + flat(pose_of_colmap(q, t)) + ", \"intrinsics\": " + k + "}";
    }
    same += by_id[0] + ", " + by_id[1] + ", " + by_id[2] + "]}";
    test::write_temp_file("clvis-views-import-colmap", "cameras.txt",
                          "# Camera list with one line of data per camera:\n1 PINHOLE 96 72 100.5 98.25 47.3 35.1\n"
                          "2 SIMPLE_PINHOLE 96 72 80 48.5 36.5\n");
    test::write_temp_file("clvis-views-import-colmap", "images.txt", images);
    ViewsFile f = load_views_file(dir.string());
    CHECK(f.format == ViewsFormat::Colmap);
    check_same(f, load_views_file(write("colmap-same.json", same)));
    check_pose_near(f.views[0], around(1));
    check_pose_near(f.views[1], around(2));
    check_pose_near(f.views[2], around(0));
    // the folder, or either file in it
    CHECK(load_views_file((dir / "images.txt").string()).views.size() == 3);
}

TEST_CASE("COLMAP refusals: other models by name, mixed sizes, unknown cameras, with their lines", "[views_import]")
{
    auto model = [](const std::string& name, const std::string& cameras, const std::string& images) {
        auto dir = test::fresh_temp_dir("clvis-views-import-" + name);
        test::write_temp_file("clvis-views-import-" + name, "cameras.txt", cameras);
        test::write_temp_file("clvis-views-import-" + name, "images.txt", images);
        return dir.string();
    };
    const std::string image = "1 1 0 0 0 0 0 2 1 a.png\n\n";
    std::string e = load_error(model("opencv", "# c\n1 OPENCV 96 72 100 100 48 36 0.1 0 0 0\n", image));
    CHECK(e.find("cameras.txt:2: camera 1: model OPENCV is not read (clvis reads PINHOLE and SIMPLE_PINHOLE") !=
          std::string::npos);
    e = load_error(model("sizes", "1 PINHOLE 96 72 100 100 48 36\n2 PINHOLE 64 48 100 100 32 24\n", image));
    CHECK(e.find("cameras.txt:2: camera 2 is 64x48, the camera of line 1 96x72: views share one image size") !=
          std::string::npos);
    e = load_error(model("unknown", "1 PINHOLE 96 72 100 100 48 36\n", "# x\n\n3 1 0 0 0 0 0 2 9 a.png\n\n"));
    CHECK(e.find("images.txt:3: image 3: camera 9 is not in") != std::string::npos);
    e = load_error(model("params", "1 SIMPLE_PINHOLE 96 72 100 48\n", image));
    CHECK(e.find("SIMPLE_PINHOLE takes 3 parameters (f cx cy), got 2") != std::string::npos);
}

#ifdef CLVIS_HAVE_TINYGLTF
TEST_CASE("glTF camera nodes: perspective, orthographic, under a transformed parent, as the views file", "[views_import][device]")
{
    // nodes[0]: a perspective camera posed by its own matrix; nodes[1] (not a camera) turns and
    // moves its child nodes[2], an orthographic camera moved 0.3 along its parent's z; nodes[3]:
    // a perspective camera without zfar, turned by a quaternion
    Mat4 parent;
    parent(0, 0) = 0.6; parent(0, 2) = 0.8; parent(2, 0) = -0.8; parent(2, 2) = 0.6;
    parent(0, 3) = -0.017; parent(1, 3) = 0.12;
    Mat4 child;
    child(2, 3) = 0.3;
    double half = 0.25, s = std::sin(half), c = std::cos(half); // 0.5 rad about y
    std::string rest =
        "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.7,\"znear\":0.01,\"zfar\":5,"
        "\"aspectRatio\":3}},{\"type\":\"orthographic\",\"orthographic\":{\"xmag\":9,\"ymag\":0.1,"
        "\"znear\":0.01,\"zfar\":2}},{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"znear\":0.02}}],"
        "\"nodes\":[{\"camera\":0,\"matrix\":" + column_major(around(0).pose()) + "},{\"matrix\":" +
        column_major(parent) + ",\"children\":[2]},{\"camera\":1,\"translation\":[0,0,0.3]},{\"camera\":2,"
        "\"translation\":[0.151,0.11,0.307],\"rotation\":[0," + num(s) + ",0," + num(c) + "]}],"
        "\"scenes\":[{\"nodes\":[0,1,3]}]";
    std::string gltf = "{\"asset\":{\"version\":\"2.0\"}," + rest + "}";
    std::string path = write("cameras.gltf", gltf);
    CHECK(load_error(path).find("glTF cameras give no image size: give --width") != std::string::npos);
    CHECK(load_error(path, 96).find("--height") != std::string::npos);
    ViewsFile f = load_views_file(path, 96, 72);
    CHECK(f.format == ViewsFormat::Gltf);
    REQUIRE(f.views.size() == 3);
    Mat4 world2 = (Mat4::identity() * parent) * child; // the walk's product along the path
    std::string same = "{\"width\": 96, \"height\": 72, \"views\": [{\"pose\": " +
                       flat(Mat4::identity() * around(0).pose()) + ", \"fov\": " + num(0.7 * 180 / pi) +
                       ", \"near\": 0.01, \"far\": 5}, {\"pose\": " + flat(world2) +
                       ", \"ortho\": 0.2, \"near\": 0.01, \"far\": 2}, {\"eye\": " + vec(f.views[2].eye) + ", \"target\": " +
                       vec(f.views[2].target) + ", \"up\": " + vec(f.views[2].up) + ", \"fov\": " +
                       num(0.5 * 180 / pi) + ", \"near\": 0.02, \"far\": 1000}]}"; // its frame checked below
    check_same(f, load_views_file(write("gltf-same.json", same)));
    // the quaternion's camera: at its translation, looking down its turned -z (0.5 rad about y)
    CHECK(std::fabs(f.views[2].eye.z - 0.307) < 1e-15);
    CameraFrame fr = f.views[2].frame();
    CHECK(std::fabs(fr.f.x + std::sin(0.5)) < 1e-12);
    CHECK(std::fabs(fr.f.z + std::cos(0.5)) < 1e-12);
    // the orthographic child: its parent's turn and move applied (eye = parent * (0, 0, 0.3))
    CHECK(std::fabs(f.views[1].eye.x - (-0.017 + 0.8 * 0.3)) < 1e-15);
    CHECK(std::fabs(f.views[1].eye.z - 0.6 * 0.3) < 1e-15);
    // also read by content: glTF's JSON under another extension, and a GLB (its JSON chunk alone)
    CHECK(load_views_file(write("cameras.json", gltf), 96, 72).format == ViewsFormat::Gltf);
    std::string chunk = gltf;
    while (chunk.size() % 4) chunk += ' ';
    std::string glb = "glTF";
    auto u32 = [&glb](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(std::uint32_t(12 + 8 + chunk.size()));
    u32(std::uint32_t(chunk.size()));
    u32(0x4E4F534A); // "JSON"
    ViewsFile binary = load_views_file(write("cameras.bin", glb + chunk), 96, 72);
    REQUIRE(binary.views.size() == 3);
    for (std::size_t v = 0; v < 3; ++v) CHECK(same_camera(binary.views[v], f.views[v]));
}

TEST_CASE("glTF cameras: zfar absent takes the framing far of the file's triangles; refusals", "[views_import]")
{
    // one triangle in a base64 buffer: positions (0,0,0) (1,0,0) (0,1,0)
    const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::string bin(reinterpret_cast<const char*>(xyz), sizeof xyz);
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string b64;
    for (std::size_t i = 0; i < bin.size(); i += 3) {
        std::uint32_t n = std::uint32_t(std::uint8_t(bin[i])) << 16 | std::uint32_t(std::uint8_t(bin[i + 1])) << 8 |
                          std::uint32_t(std::uint8_t(bin[i + 2]));
        for (int k = 3; k >= 0; --k) b64 += digits[n >> (6 * k) & 63];
    }
    auto file = [&](const std::string& nodes, const std::string& cameras) {
        return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/"
               "octet-stream;base64," + b64 + "\"}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
               "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"type\":\"VEC3\",\"count\":3,"
               "\"min\":[0,0,0],\"max\":[1,1,0]}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
               "\"cameras\":" + cameras + ",\"nodes\":[{\"mesh\":0}," + nodes + "],\"scenes\":[{\"nodes\":[0,1]}]}";
    };
    const std::string persp = "[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"znear\":0.05}}]";
    ViewsFile f = load_views_file(write("far.gltf", file("{\"camera\":0,\"translation\":[0.5,0.5,4]}", persp)), 32, 24);
    REQUIRE(f.views.size() == 1);
    Bounds b;
    b.add({0, 0, 0});
    b.add({1, 1, 0});
    double dist = length(b.center() - Vec3{0.5, 0.5, 4}), radius = length(b.extent()) / 2;
    CHECK(f.views[0].far == 1.1 * (dist + radius));
    CHECK(f.views[0].near == 0.05);
    CHECK(std::fabs(f.views[0].fov_y - 0.8 * 180 / pi) < 1e-12);

    std::string e = load_error(write("scaled.gltf", file("{\"camera\":0,\"scale\":[2,2,2]}", persp)), 32, 24);
    CHECK(e.find("nodes[1] (the world transform of cameras[0]): pose: the 3x3 part is not orthonormal") !=
          std::string::npos);
    e = load_error(write("ortho0.gltf", file("{\"camera\":0}", "[{\"type\":\"orthographic\",\"orthographic\":"
                                                                 "{\"xmag\":1,\"ymag\":1,\"znear\":0,\"zfar\":9}}]")),
                   32, 24);
    CHECK(e.find("cameras[0].orthographic.znear: 0: clvis needs a near view depth > 0") != std::string::npos);
    e = load_error(write("nocam.gltf", file("{\"mesh\":0}", persp)), 32, 24);
    CHECK(e.find("holds no camera node") != std::string::npos);
}
#endif
