// Conversions between NumPy and clvis's plain types (see arrays.hpp).
#include "arrays.hpp"

#include <nanobind/stl/string.h>

namespace clvis::python {

namespace {

[[noreturn]] void bad(const ArraySpec& spec, const std::string& why)
{
    throw Error(Error::Kind::InvalidArgument, std::string(spec.what) + ": " + why);
}

void check_shape(nb::handle a, const ArraySpec& spec)
{
    const auto ndim = nb::cast<int>(a.attr("ndim"));
    bool ok = ndim == spec.ndim;
    if (ok && spec.cols > 0) ok = nb::cast<long>(a.attr("shape")[ndim - 1]) == spec.cols;
    if (!ok) bad(spec, std::string("expected an array of shape ") + spec.shape + ", got shape " + text_of(a.attr("shape")));
}

/// Integers converted to uint32 must fit: a negative or too large index is an error, not a wrap.
void check_integers(nb::handle a, const ArraySpec& spec, const std::string& kind)
{
    if (kind != "u" && kind != "i")
        bad(spec, "expected integers, got dtype " + text_of(a.attr("dtype")));
    if (nb::cast<std::size_t>(a.attr("size")) == 0) return;
    const auto lo = nb::cast<long long>(a.attr("min")());
    const auto hi = nb::cast<unsigned long long>(a.attr("max")());
    if (lo < 0) bad(spec, "negative value " + std::to_string(lo));
    if (hi > 0xFFFFFFFFull) bad(spec, "value " + std::to_string(hi) + " does not fit 32 bits");
}

} // namespace

std::string text_of(nb::handle obj) { return nb::cast<std::string>(nb::str(obj)); }

nb::object as_numpy(nb::handle obj, const ArraySpec& spec, const char* dtype)
{
    nb::module_ np = nb::module_::import_("numpy");
    nb::object a;
    try {
        a = np.attr("asarray")(obj);
    } catch (const nb::python_error& e) {
        bad(spec, std::string("not an array: ") + e.what());
    }
    check_shape(a, spec);
    const auto kind = nb::cast<std::string>(a.attr("dtype").attr("kind"));
    if (spec.integer) {
        if (text_of(a.attr("dtype")) != dtype) check_integers(a, spec, kind);
    } else if (kind != "f" && kind != "i" && kind != "u") {
        bad(spec, "expected numbers, got dtype " + text_of(a.attr("dtype")));
    }
    return np.attr("ascontiguousarray")(a, nb::arg("dtype") = dtype);
}

void* writable_data(nb::handle obj, char format, std::size_t itemsize, std::initializer_list<std::size_t> shape)
{
    if (!PyObject_CheckBuffer(obj.ptr())) return nullptr;
    Py_buffer view;
    if (PyObject_GetBuffer(obj.ptr(), &view, PyBUF_WRITABLE | PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) != 0) {
        PyErr_Clear();
        return nullptr;
    }
    const char* f = view.format ? view.format : "B";
    if (*f == '@' || *f == '=' || *f == '<') ++f;
    bool ok = (format == 0 || (f[0] == format && f[1] == 0)) && std::size_t(view.itemsize) == itemsize &&
              std::size_t(view.ndim) == shape.size();
    int k = 0;
    for (const std::size_t n : shape) ok = ok && std::size_t(view.shape[k++]) == n;
    void* data = ok ? view.buf : nullptr;
    PyBuffer_Release(&view);
    return data;
}

void bad_output(nb::handle obj, const std::string& what, const std::string& dtype, const std::string& shape)
{
    std::string got = "got " + text_of(obj.type().attr("__name__"));
    if (nb::hasattr(obj, "dtype") && nb::hasattr(obj, "shape")) {
        got = "got dtype " + text_of(obj.attr("dtype")) + ", shape " + text_of(obj.attr("shape"));
        if (nb::hasattr(obj, "flags")) {
            if (!nb::cast<bool>(obj.attr("flags").attr("c_contiguous"))) got += ", not C-contiguous";
            if (!nb::cast<bool>(obj.attr("flags").attr("writeable"))) got += ", read-only";
        }
    }
    throw Error(Error::Kind::InvalidArgument,
                what + ": expected a writable C-contiguous " + dtype + " array of shape " + shape + ", " + got);
}

Vec3 to_vec3(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

std::tuple<double, double, double> from_vec3(Vec3 v) { return {v.x, v.y, v.z}; }

Mat4 to_mat4(nb::handle obj, const char* what)
{
    const ArraySpec spec{what, "(4, 4)", 2, 4, false};
    auto a = as_host_array<double>(obj, spec, "float64");
    if (a.shape(0) != 4) bad(spec, "expected an array of shape (4, 4), got " + std::to_string(a.shape(0)) + " rows");
    Mat4 m;
    for (int i = 0; i < 16; ++i) m.m[i] = a.data()[i];
    return m;
}

nb::ndarray<nb::numpy, double> from_mat4(const Mat4& m)
{
    auto* copy = new double[16];
    for (int i = 0; i < 16; ++i) copy[i] = m.m[i];
    nb::capsule owner(copy, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    return nb::ndarray<nb::numpy, double>(copy, {4, 4}, owner);
}

} // namespace clvis::python
