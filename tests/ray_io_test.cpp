// Files of rays and hits: .npy round trips (rays, structured hits, flags, counts) and raw
// records, headers as NumPy writes them, and malformed files refused with the file named.
#include "catch.hpp"

#include <clvis/error.hpp>
#include <clvis/ray_io.hpp>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

using namespace clvis;

namespace {

std::string temp_path(const std::string& name) { return std::string(CLVIS_BINARY_DIR) + "/ray_io_test_" + name; }

void write_bytes(const std::string& path, const std::string& bytes)
{
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

/// An .npy file with `header` as its dict (padded like NumPy) and `data_bytes` zero bytes.
std::string npy_bytes(const std::string& header, std::size_t data_bytes, char major = 1)
{
    std::string h = header;
    std::size_t len_size = major == 1 ? 2 : 4;
    while ((6 + 2 + len_size + h.size() + 1) % 64) h += ' ';
    h += '\n';
    std::string out = std::string("\x93NUMPY", 6) + major + '\0';
    for (std::size_t k = 0; k < len_size; ++k) out += char((h.size() >> (8 * k)) & 0xFF);
    return out + h + std::string(data_bytes, '\0');
}

std::string error_of(const std::string& path)
{
    try {
        read_rays(path);
    } catch (const Error& e) {
        CHECK(e.kind() == Error::Kind::Io);
        return e.what();
    }
    return "no error";
}

} // namespace

TEST_CASE("rays and hits survive a round trip through .npy and raw records")
{
    std::vector<RayRecord> rays;
    for (int i = 0; i < 5; ++i)
        rays.push_back(RayRecord{float(i), 1.5f, -2, 0, 0, 0, 1, i == 4 ? std::numeric_limits<float>::infinity() : 10});
    for (const char* name : {"rays.npy", "rays.bin"}) {
        write_rays(temp_path(name), rays);
        std::vector<RayRecord> back = read_rays(temp_path(name));
        REQUIRE(back.size() == rays.size());
        CHECK(std::memcmp(back.data(), rays.data(), rays.size() * sizeof(RayRecord)) == 0);
    }
    std::vector<HitRecord> hits = {{1.25f, 7, 0.25f, 0.5f}, {std::numeric_limits<float>::infinity(), 0xFFFFFFFFu, 0, 0}};
    write_hits(temp_path("hits.npy"), hits);
    std::vector<HitRecord> hb = read_hits(temp_path("hits.npy"));
    REQUIRE(hb.size() == 2);
    CHECK(std::memcmp(hb.data(), hits.data(), sizeof(HitRecord) * 2) == 0);
    NpyArray a = read_npy(temp_path("hits.npy"));
    CHECK(a.descr == "[('t', '<f4'), ('id', '<u4'), ('u', '<f4'), ('v', '<f4')]");
    CHECK(a.shape == std::vector<std::size_t>{2});
    write_flags(temp_path("flags.npy"), {1, 0, 1});
    a = read_npy(temp_path("flags.npy"));
    CHECK(a.descr == "|u1");
    CHECK(a.data == std::vector<char>{1, 0, 1});
    write_counts(temp_path("counts.npy"), {3, 0});
    a = read_npy(temp_path("counts.npy"));
    CHECK(a.descr == "<u4");
    CHECK(a.shape == std::vector<std::size_t>{2});
    CHECK(a.data.size() == 8);
}

TEST_CASE("an .npy header is NumPy's dict padded to 64 bytes")
{
    write_rays(temp_path("header.npy"), std::vector<RayRecord>(3));
    std::ifstream in(temp_path("header.npy"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(bytes.size() == 128 + 3 * 32); // 10 + 60 header bytes + newline, padded as NumPy pads
    CHECK(bytes.substr(0, 8) == std::string("\x93NUMPY\x01\x00", 8));
    CHECK(bytes.substr(10, 118).find("{'descr': '<f4', 'fortran_order': False, 'shape': (3, 8), }") == 0);
    CHECK(bytes[127] == '\n');
}

TEST_CASE("malformed .npy files are refused naming the file and the fault")
{
    std::string p = temp_path("bad.npy");
    write_bytes(p, "not numpy at all");
    CHECK(error_of(p).find("magic") != std::string::npos);
    CHECK(error_of(p).find(p) == 0);
    struct Bad {
        const char* header;
        std::size_t data_bytes;
        char major;
        const char* says;
    };
    const std::string ok = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), }";
    const Bad bad[] = {
        {"{'descr': '<f8', 'fortran_order': False, 'shape': (2, 8), }", 128, 1, "dtype '<f8'"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2, 7), }", 56, 1, "shape (2, 7)"},
        {"{'descr': '<f4', 'fortran_order': True, 'shape': (2, 8), }", 64, 1, "Fortran"},
        {ok.c_str(), 60, 1, "data bytes"},
        {"{'descr': '<f4', 'shape': (2, 8), }", 64, 1, "needs descr, fortran_order and shape"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2, x), }", 64, 1, "non-integer"},
        {"{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), 'extra': 1}", 64, 1, "unknown key 'extra'"},
        {ok.c_str(), 64, 4, "version 4"},
    };
    for (const Bad& b : bad) {
        INFO(b.header << " and " << b.data_bytes << " data bytes, version " << int(b.major));
        write_bytes(p, npy_bytes(b.header, b.data_bytes, b.major));
        CHECK(error_of(p).find(b.says) != std::string::npos);
    }
    write_bytes(p, npy_bytes("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 8), }", 64, 2));
    CHECK(read_rays(p).size() == 2); // version 2: a 4-byte header length
    write_bytes(p, std::string("\x93NUMPY\x01\x00\xff\x00{", 11));
    CHECK(error_of(p).find("truncated") != std::string::npos);
    std::string raw = temp_path("bad.bin");
    write_bytes(raw, std::string(33, '\0'));
    CHECK(error_of(raw).find("not a whole number of 32-byte records") != std::string::npos);
    CHECK(error_of(temp_path("missing.npy")).find("cannot open") != std::string::npos);
}

TEST_CASE("all hits are written as an (N, K) structured .npy or as raw records in order")
{
    std::vector<HitRecord> hits;
    for (std::uint32_t i = 0; i < 6; ++i) hits.push_back(HitRecord{float(i) * 0.5f, i, 0.25f, 0.125f});
    std::string npy = temp_path("all.npy"), raw = temp_path("all.bin");
    write_hit_lists(npy, hits, 3);
    write_hit_lists(raw, hits, 3);
    NpyArray a = read_npy(npy);
    CHECK(a.shape == std::vector<std::size_t>{2, 3});
    CHECK(a.descr.find("('id', '<u4')") != std::string::npos);
    REQUIRE(a.data.size() == hits.size() * sizeof(HitRecord));
    CHECK(std::memcmp(a.data.data(), hits.data(), a.data.size()) == 0);
    std::vector<HitRecord> back = read_hits(raw);
    REQUIRE(back.size() == hits.size());
    CHECK(std::memcmp(back.data(), hits.data(), back.size() * sizeof(HitRecord)) == 0);
    CHECK_THROWS_AS(write_hit_lists(temp_path("bad.npy"), hits, 4), Error);
    std::remove(npy.c_str());
    std::remove(raw.c_str());
}
