// clvis::Error as Python exceptions: clvis.Error (a RuntimeError) and one subclass per kind,
// also derived from the built-in that Python code catches for it (ValueError, OSError). The
// message is the C++ one, unchanged.
#include "bindings.hpp"

#include <nanobind/stl/string.h>

#include <array>

namespace clvis::python {

namespace {

struct KindClass {
    Error::Kind kind;
    const char* name;
    PyObject* builtin; ///< a second base, or null
    const char* doc;
};

const std::array<KindClass, 5> kind_classes{{
    {Error::Kind::InvalidArgument, "InvalidArgumentError", PyExc_ValueError,
     "A value given by the caller is out of its domain (the message names it)."},
    {Error::Kind::Io, "IoError", PyExc_OSError,
     "A file could not be read, parsed or written (the message names the file and line)."},
    {Error::Kind::Device, "DeviceError", nullptr,
     "No OpenCL platform or device, or an OpenCL call failed (the message names the call)."},
    {Error::Kind::Build, "BuildError", nullptr, "A kernel program failed to build (the message carries the log)."},
    {Error::Kind::Limit, "LimitError", nullptr,
     "A request exceeds what the device or the 32-bit id format can hold."},
}};

/// The classes, indexed by kind; owned by the module (one reference each, kept to its end).
std::array<PyObject*, 5> classes{};

nb::object make_class(nb::handle module, const char* name, nb::tuple bases, const char* doc, const char* kind)
{
    nb::dict ns;
    ns["__module__"] = module.attr("__name__"); // as the bound classes: stubgen then writes them
    ns["__doc__"] = doc;
    ns["kind"] = kind;
    return nb::borrow(reinterpret_cast<PyObject*>(&PyType_Type))(name, bases, ns);
}

} // namespace

void bind_errors(nb::module_& m)
{
    nb::object base = make_class(
        m, "Error", nb::make_tuple(nb::handle(PyExc_RuntimeError)),
        "Every failure of clvis: a clvis.Error of the subclass named by its kind, with the library's message.\n\n"
        "Example:\n    try:\n        clvis.load_mesh('missing.obj')\n    except clvis.IoError as e:\n"
        "        print(e.kind, e)",
        "");
    m.attr("Error") = base;
    for (const KindClass& k : kind_classes) {
        nb::tuple bases = k.builtin ? nb::make_tuple(base, nb::handle(k.builtin)) : nb::make_tuple(base);
        nb::object cls = make_class(m, k.name, bases, k.doc, to_string(k.kind));
        m.attr(k.name) = cls;
        classes[static_cast<std::size_t>(k.kind)] = cls.release().ptr();
    }
    m.def(
        "_raise_error",
        [](const std::string& kind, const std::string& message) {
            for (const KindClass& k : kind_classes)
                if (kind == to_string(k.kind)) throw Error(k.kind, message);
            throw Error(Error::Kind::InvalidArgument, "_raise_error: no error kind '" + kind + "'");
        },
        nb::arg("kind"), nb::arg("message"), "Throws a clvis::Error of `kind` from C++: tests the translation.");
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const Error& e) {
            PyErr_SetString(classes[static_cast<std::size_t>(e.kind())], e.what());
        }
    });
}

} // namespace clvis::python
