// Files of rays and of their answers (CONVENTIONS.md "Ray queries"): NumPy's .npy (rays an
// (N, 8) float32 array; closest hits a structured array of fields t, id, u, v; occlusion flags
// uint8; hit counts uint32) or, for any other extension, the raw little-endian records. Also the
// small, strict .npy reader and writer underneath. Host only: no OpenCL here.
#pragma once

#include <clvis/rays.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clvis {

/// An .npy array as read: its dtype as written in the header (a string such as "<f4", or the
/// text of a structured dtype's list), C order, shape and raw little-endian bytes.
struct NpyArray {
    std::string descr;
    std::vector<std::size_t> shape;
    std::vector<char> data;
};

/// Reads an .npy file (format versions 1, 2 and 3). Throws Error(Io) naming the file and what is
/// wrong: bad magic, a header that is not the dict NumPy writes, Fortran order, a data size that
/// does not match the shape.
NpyArray read_npy(const std::string& path);
/// Writes an .npy file (version 1.0, header padded to 64 bytes). `descr` is written as given: a
/// quoted string such as "'<f4'" or a list such as "[('t', '<f4'), ...]".
void write_npy(const std::string& path, const std::string& descr, const std::vector<std::size_t>& shape,
               const void* data, std::size_t bytes);

/// The rays of a file: .npy of dtype '<f4' and shape (N, 8), or raw 32-byte records.
std::vector<RayRecord> read_rays(const std::string& path);
/// Writes rays as `read_rays` reads them (by the file's extension).
void write_rays(const std::string& path, const std::vector<RayRecord>& rays);
/// Writes closest hits (.npy: fields t '<f4', id '<u4', u '<f4', v '<f4'; else 16-byte records).
void write_hits(const std::string& path, const std::vector<HitRecord>& hits);
/// Writes all hits, `per_ray` records per ray (.npy: a structured (N, per_ray) array of the same
/// fields; else the records in order).
void write_hit_lists(const std::string& path, const std::vector<HitRecord>& hits, std::size_t per_ray);
/// Reads closest hits as write_hits writes them.
std::vector<HitRecord> read_hits(const std::string& path);
/// Writes one uint8 (occlusion) or uint32 (count) per ray.
void write_flags(const std::string& path, const std::vector<std::uint8_t>& flags);
void write_counts(const std::string& path, const std::vector<std::uint32_t>& counts);

} // namespace clvis
