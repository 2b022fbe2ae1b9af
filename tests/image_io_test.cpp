// Image files through OpenImageIO: ids never pass through float, depth keeps +inf, row 0 on top,
// and bad files are named.
#include "catch.hpp"

#include <clvis/clvis.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>
#include <limits>

using namespace clvis;

namespace {

std::string temp_path(const std::string& name)
{
    auto dir = std::filesystem::temp_directory_path() / "clvis-image-test";
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

HostVisibility sample_buffer()
{
    HostVisibility v;
    v.width = 5;
    v.height = 3;
    // Values that float32 cannot hold exactly (2^24 + 1, 2^32 - 2) and the background.
    v.ids = {0, 1, 16777217u, 0xFFFFFFFEu, background_id, 7, 8, 9, 10, 11, 4000000001u, 13, 14, 15, 16};
    v.depth.assign(15, 0.0f);
    for (int i = 0; i < 15; ++i) v.depth[i] = 0.5f + i * 1e-3f;
    v.depth[4] = std::numeric_limits<float>::infinity();
    return v;
}

} // namespace

TEST_CASE("id buffers round-trip exactly through TIFF and EXR, ids near 2^32 included", "[image]")
{
    HostVisibility v = sample_buffer();
    for (const char* ext : {"tif", "tiff", "exr"}) {
        std::string path = temp_path(std::string("ids.") + ext);
        write_ids(path, v);
        HostVisibility back = read_ids(path);
        CHECK(back.width == 5);
        CHECK(back.height == 3);
        CHECK(back.ids == v.ids);
        // The file holds one UINT32 channel named "id".
        auto in = OIIO::ImageInput::open(path);
        REQUIRE(in);
        CHECK(in->spec().format == OIIO::TypeDesc::UINT32);
        CHECK(in->spec().nchannels == 1);
        // TIFF has no channel names (OpenImageIO reads its one channel as "Y"); EXR keeps "id".
        if (std::string(ext) == "exr") CHECK(in->spec().channelnames[0] == "id");
    }
}

TEST_CASE("depth buffers round-trip through EXR with +inf for the background", "[image]")
{
    HostVisibility v = sample_buffer();
    std::string path = temp_path("depth.exr");
    write_depth(path, v);
    HostVisibility back;
    read_depth(path, back);
    CHECK(back.depth == v.depth);
    auto in = OIIO::ImageInput::open(path);
    REQUIRE(in);
    CHECK(in->spec().channelnames[0] == "Z");
    CHECK(in->spec().format == OIIO::TypeDesc::FLOAT);
}

TEST_CASE("buffers of 2 to 16 samples round-trip with channels id0.. and Z0..", "[image][samples]")
{
    for (int n : {2, 4, 16}) {
        HostVisibility v;
        v.width = 3;
        v.height = 2;
        v.samples = n;
        for (int i = 0; i < 6 * n; ++i) {
            v.ids.push_back(i % 5 == 4 ? background_id : 4000000000u + std::uint32_t(i));
            v.depth.push_back(i % 5 == 4 ? std::numeric_limits<float>::infinity() : 1.0f + float(i) / 64);
        }
        for (const char* ext : {"exr", "tif"}) {
            INFO(n << " samples, ." << ext);
            std::string path = temp_path("samples." + std::string(ext));
            write_ids(path, v);
            HostVisibility back = read_ids(path);
            CHECK(back.samples == n);
            CHECK(back.ids == v.ids); // sample k of a pixel back in its place (EXR sorts names: id10 < id2)
            auto in = OIIO::ImageInput::open(path);
            REQUIRE(in);
            CHECK(in->spec().nchannels == n);
            if (std::string(ext) == "exr") {
                std::vector<std::string> names = in->spec().channelnames;
                std::sort(names.begin(), names.end());
                std::vector<std::string> expected;
                for (int k = 0; k < n; ++k) expected.push_back("id" + std::to_string(k));
                std::sort(expected.begin(), expected.end());
                CHECK(names == expected);
            }
        }
        std::string zpath = temp_path("samples-z.exr");
        write_depth(zpath, v);
        HostVisibility ids = read_ids(temp_path("samples.exr"));
        read_depth(zpath, ids);
        CHECK(ids.depth == v.depth);
        HostVisibility one = sample_buffer(); // 5x3, one sample: its depth file does not fit these ids
        write_depth(zpath, one);
        CHECK_THROWS_WITH(read_depth(zpath, ids), Catch::Contains("sample"));
    }
    HostVisibility three = sample_buffer();
    three.samples = 3;
    CHECK_THROWS_AS(write_ids(temp_path("three.exr"), three), Error);
}

TEST_CASE("row 0 of a written file is the top row", "[image]")
{
    Image img;
    img.width = 2;
    img.height = 2;
    img.rgba = {255, 0, 0, 255, 255, 0, 0, 255, 0, 0, 255, 255, 0, 0, 255, 255}; // red on top
    std::string path = temp_path("rows.png");
    write_image(path, img);
    auto in = OIIO::ImageInput::open(path);
    REQUIRE(in);
    std::vector<unsigned char> px(16);
    REQUIRE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, px.data()));
    CHECK(int(px[0]) == 255); // first scanline read is red: the top
    CHECK(int(px[2]) == 0);
    CHECK(int(px[8]) == 0);
    CHECK(int(px[10]) == 255);
}

TEST_CASE("wrong files and formats are named in the error", "[image]")
{
    HostVisibility v = sample_buffer();
    CHECK_THROWS_WITH(write_ids(temp_path("ids.png"), v), Catch::Contains("ids.png"));
    CHECK_THROWS_WITH(write_depth(temp_path("depth.tif"), v), Catch::Contains(".exr"));
    CHECK_THROWS_WITH(read_ids(temp_path("missing.tif")), Catch::Contains("missing.tif"));
    // A colour PNG is not an id buffer.
    Image img;
    img.width = img.height = 1;
    img.rgba = {1, 2, 3, 255};
    write_image(temp_path("colour.png"), img);
    try {
        read_ids(temp_path("colour.png"));
        FAIL("read a colour PNG as ids");
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Io);
        CHECK(std::string(e.what()).find("colour.png") != std::string::npos);
    }
    // A float image is not an id buffer either: ids must never pass through float.
    write_depth(temp_path("float.exr"), v);
    CHECK_THROWS_WITH(read_ids(temp_path("float.exr")), Catch::Contains("32-bit unsigned"));
}

TEST_CASE("depth layers are written as channels L0.id .. and L0.Z .. and read back by name", "[image][layers]")
{
    HostVisibility v;
    v.width = 4;
    v.height = 2;
    v.layers = 3; // the layers of a pixel adjacent, nearest first
    for (std::uint32_t i = 0; i < 24; ++i) {
        v.ids.push_back(i % 3 == 2 ? background_id : 4000000000u + i);
        v.depth.push_back(i % 3 == 2 ? std::numeric_limits<float>::infinity() : 0.25f + float(i) * 1e-3f);
    }
    std::string ids = temp_path("layers.exr"), depth = temp_path("layers-z.exr");
    write_ids(ids, v);
    write_depth(depth, v);
    auto in = OIIO::ImageInput::open(ids);
    REQUIRE(in);
    CHECK(in->spec().nchannels == 3);
    CHECK(in->spec().channelnames == std::vector<std::string>{"L0.id", "L1.id", "L2.id"});
    in->close();
    HostVisibility back = read_ids(ids);
    read_depth(depth, back);
    CHECK(back.layers == 3);
    CHECK(back.samples == 1);
    CHECK(back.ids == v.ids);
    CHECK(back.depth == v.depth);
    CHECK(back.layer(1).id(2, 1) == v.id(2, 1, 0, 1));
    // TIFF keeps no names: the ids in layer order, read back as channels
    std::string tif = temp_path("layers.tif");
    write_ids(tif, v);
    auto t = OIIO::ImageInput::open(tif);
    REQUIRE(t);
    CHECK(t->spec().nchannels == 3);
    std::vector<std::uint32_t> raw(24);
    t->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT32, raw.data());
    CHECK(raw == v.ids);
}
