// Conversions between NumPy (or anything numpy.asarray takes) and clvis's plain types: shapes
// checked with errors naming the argument, one conversion where a dtype or a layout differs, and
// NumPy arrays over C++ storage without copies.
#pragma once

#include "bindings.hpp"

#include <array>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <tuple>
#include <utility>

namespace clvis::python {

/// What an argument must be: `ndim` dimensions, the last one `cols` long (0: any), of integers
/// (converted to uint32, each checked to fit) or of numbers (converted to float32/float64).
struct ArraySpec {
    const char* what;  ///< e.g. "Scene.add_mesh: positions"
    const char* shape; ///< e.g. "(V, 3)"
    int ndim;
    long cols;
    bool integer;
};

/// str(obj), as Python writes it (a dtype, a shape).
std::string text_of(nb::handle obj);

/// `obj` as a C-contiguous NumPy array of `dtype` ("float32", "uint32", "float64"): the array
/// itself when it already is one, else one converted copy. Throws Error(InvalidArgument).
nb::object as_numpy(nb::handle obj, const ArraySpec& spec, const char* dtype);

template <class T>
using HostArray = nb::ndarray<const T, nb::c_contig, nb::device::cpu>;

template <class T>
HostArray<T> as_host_array(nb::handle obj, const ArraySpec& spec, const char* dtype)
{
    // The common case first, without a call into NumPy: already of this dtype, C order, the shape.
    HostArray<T> direct;
    if (nb::try_cast(obj, direct, false) && int(direct.ndim()) == spec.ndim &&
        (spec.cols == 0 || long(direct.shape(direct.ndim() - 1)) == spec.cols))
        return direct;
    return nb::cast<HostArray<T>>(as_numpy(obj, spec, dtype), false);
}

template <class T>
using OutArray = nb::ndarray<T, nb::c_contig, nb::device::cpu>;

/// Explains why `obj` is no writable C-contiguous array of `dtype` and `shape` (throws).
[[noreturn]] void bad_output(nb::handle obj, const std::string& what, const std::string& dtype,
                             const std::string& shape);

/// The buffer-protocol format character of T.
template <class T> constexpr char format_of();
template <> constexpr char format_of<std::uint8_t>() { return 'B'; }
template <> constexpr char format_of<std::uint32_t>() { return 'I'; }
template <> constexpr char format_of<float>() { return 'f'; }

/// The data of `obj` when it is a writable C-contiguous array of items of `itemsize` bytes in
/// `format` (a buffer-protocol character; 0: any, the caller checks the dtype) and exactly
/// `shape`, else null.
/// Through the buffer protocol, the pointer stays valid while the caller's array lives.
void* writable_data(nb::handle obj, char format, std::size_t itemsize, std::initializer_list<std::size_t> shape);

/// The caller's output array `obj` (`what` names it in errors): writable, C-contiguous, of
/// `dtype` ("uint32", "float32", "uint8") and exactly `shape`; written in place, never converted.
template <class T>
T* output_array(nb::handle obj, const std::string& what, const char* dtype, std::initializer_list<std::size_t> shape)
{
    if (void* data = writable_data(obj, format_of<T>(), sizeof(T), shape)) return static_cast<T*>(data);
    std::size_t k = 0;
    std::string text = "(";
    for (const std::size_t n : shape)
        text += std::to_string(n) + (++k == 1 && shape.size() == 1 ? ",)" : k == shape.size() ? ")" : ", ");
    bad_output(obj, what, dtype, text);
}

/// A capsule that keeps a shared object alive for as long as an array refers to it.
template <class P>
nb::capsule keep_alive(std::shared_ptr<P> owner)
{
    return nb::capsule(new std::shared_ptr<P>(std::move(owner)),
                       [](void* p) noexcept { delete static_cast<std::shared_ptr<P>*>(p); });
}

/// A read-only NumPy array over `data` (no copy), kept valid by `owner`.
template <class T>
nb::ndarray<nb::numpy, const T> numpy_view(const T* data, std::initializer_list<std::size_t> shape,
                                           nb::handle owner)
{
    return nb::ndarray<nb::numpy, const T>(data, shape, owner);
}

/// A read-only NumPy array that takes over `values` (no copy), `shape` giving its size.
template <class T>
nb::object owned_array(std::vector<T>&& values, std::initializer_list<std::size_t> shape)
{
    auto owner = std::make_shared<std::vector<T>>(std::move(values));
    return nb::cast(numpy_view(owner->data(), shape, keep_alive(owner)));
}

Vec3 to_vec3(const std::array<double, 3>& v);
/// A point or a vector as a Python tuple of 3 floats.
std::tuple<double, double, double> from_vec3(Vec3 v);
/// A (4, 4) array-like, row by row, applied to column vectors (p' = M p).
Mat4 to_mat4(nb::handle obj, const char* what);
nb::ndarray<nb::numpy, double> from_mat4(const Mat4& m);

/// The value of `choices` named `name`; Error(InvalidArgument) listing them otherwise.
template <class E>
E parse_choice(const std::string& name, const char* what,
               std::initializer_list<std::pair<const char*, E>> choices)
{
    std::string listed;
    for (const auto& [key, value] : choices) {
        if (name == key) return value;
        listed += (listed.empty() ? "" : ", ") + std::string(key);
    }
    throw Error(Error::Kind::InvalidArgument,
                std::string(what) + ": expected one of " + listed + ", got '" + name + "'");
}

} // namespace clvis::python
