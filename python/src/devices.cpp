// OpenCL devices from Python: clvis.devices() lists them, clvis.Device(spec) opens one. A Device
// is a shared handle (copies share the context), so renderers and results keep theirs alive.
#include "bindings.hpp"

#include <nanobind/stl/string.h>
#include <nanobind/stl/variant.h>
#include <nanobind/stl/vector.h>

#include <variant>

namespace clvis::python {

namespace {

std::string describe(const DeviceInfo& d)
{
    return "<clvis.DeviceInfo " + std::to_string(d.index) + ": " + d.name + " (" + d.platform + ", " +
           to_string(d.type) + ")>";
}

void bind_device_info(nb::module_& m)
{
    nb::class_<DeviceInfo>(m, "DeviceInfo", "What OpenCL says about one device (clvis.devices()).")
        .def_ro("index", &DeviceInfo::index, "Position in clvis.devices(): a spec for clvis.Device.")
        .def_ro("platform", &DeviceInfo::platform)
        .def_ro("name", &DeviceInfo::name)
        .def_ro("vendor", &DeviceInfo::vendor)
        .def_ro("version", &DeviceInfo::version, "CL_DEVICE_VERSION")
        .def_ro("driver_version", &DeviceInfo::driver_version)
        .def_ro("opencl_c_version", &DeviceInfo::opencl_c_version)
        .def_prop_ro("type", [](const DeviceInfo& d) { return std::string(to_string(d.type)); },
                     "'cpu', 'gpu', 'accelerator' or 'other'.")
        .def_ro("compute_units", &DeviceInfo::compute_units)
        .def_ro("global_memory", &DeviceInfo::global_memory, "Bytes.")
        .def_ro("max_allocation", &DeviceInfo::max_allocation, "Bytes, the largest single buffer.")
        .def_ro("local_memory", &DeviceInfo::local_memory, "Bytes per work-group.")
        .def_ro("max_work_group_size", &DeviceInfo::max_work_group_size)
        .def_ro("int64_atomics", &DeviceInfo::int64_atomics, "64-bit atomics: the raster path needs them.")
        .def_ro("fp64", &DeviceInfo::fp64)
        .def_ro("correctly_rounded_divide_sqrt", &DeviceInfo::correctly_rounded_divide_sqrt)
        .def("__repr__", &describe);
}

} // namespace

void bind_devices(nb::module_& m)
{
    bind_device_info(m);
    m.def(
        "devices",
        [] {
            nb::gil_scoped_release nogil;
            return list_devices();
        },
        "Every device of every OpenCL platform, as a list of DeviceInfo.\n\n"
        "Raises DeviceError (saying how to install PoCL) when no platform is installed.\n\n"
        "Example:\n    for d in clvis.devices():\n        print(d.index, d.name, d.type)");

    nb::class_<Device>(m, "Device",
                       "An OpenCL device, opened by spec; copies and the renderers made on it share its context.\n\n"
                       "Example:\n    device = clvis.Device('cpu')")
        .def(
            "__init__",
            [](Device* self, std::variant<std::monostate, int, std::string> spec) {
                std::string text;
                if (auto* i = std::get_if<int>(&spec)) text = std::to_string(*i);
                if (auto* s = std::get_if<std::string>(&spec)) text = *s;
                nb::gil_scoped_release nogil;
                new (self) Device(Device::open(text));
            },
            nb::arg("spec") = nb::none(),
            "Opens a device: an index into clvis.devices(), 'cpu', 'gpu', 'accelerator', or a\n"
            "case-insensitive part of the device or platform name. None reads the environment\n"
            "variable CLVIS_DEVICE, and with that unset takes the first GPU, else the first CPU.\n"
            "Raises DeviceError naming the spec when nothing matches.")
        .def_prop_ro("info", &Device::info, "The DeviceInfo of this device.")
        .def_prop_ro("name", [](const Device& d) { return d.info().name; })
        .def("__repr__", [](const Device& d) { return "<clvis.Device " + d.info().name + ">"; });
}

} // namespace clvis::python
