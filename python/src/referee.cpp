// The referee from Python: clvis.Referee(scene, camera, width, height) judges buffers from any
// source (both paths, other renderers' arrays, files) in double precision and returns its counts.
#include "arrays.hpp"

#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <tuple>

namespace clvis::python {

namespace {

struct PyReferee {
    Referee referee;
};

void check_pixel(const PyReferee& r, int x, int y)
{
    if (x < 0 || y < 0 || x >= r.referee.width() || y >= r.referee.height())
        throw Error(Error::Kind::InvalidArgument, "Referee: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                      ") outside the " + std::to_string(r.referee.width()) + "x" +
                                                      std::to_string(r.referee.height()) + " image");
}

void bind_verdicts(nb::module_& m)
{
    nb::class_<PixelVerdict>(m, "PixelVerdict", "The referee's verdict on one answer at one pixel.")
        .def_ro("x", &PixelVerdict::x)
        .def_ro("y", &PixelVerdict::y)
        .def_ro("id", &PixelVerdict::id, "The answer judged.")
        .def_prop_ro("error", [](const PixelVerdict& v) { return std::string(to_string(v.error)); },
                     "'none' (acceptable), 'coverage', 'hidden surface', 'missed', 'clipped', 'invalid id' or "
                     "'culled'.")
        .def_ro("source", &PixelVerdict::source, "compare(): 0 the first buffer, 1 the second, 2 both; else -1.")
        .def_ro("edge_distance", &PixelVerdict::edge_distance)
        .def_ro("depth", &PixelVerdict::depth)
        .def_ro("depth_excess", &PixelVerdict::depth_excess)
        .def_ro("nearest_id", &PixelVerdict::nearest_id)
        .def_ro("nearest_depth", &PixelVerdict::nearest_depth)
        .def_prop_ro("acceptable", &PixelVerdict::acceptable, "The id is acceptable (see depth_acceptable).")
        .def_ro("depth_judged", &PixelVerdict::depth_judged)
        .def_prop_ro("depth_error", [](const PixelVerdict& v) { return std::string(to_string(v.depth_error)); },
                     "'none', 'wrong depth' or 'no triangle' (an invalid id).")
        .def_ro("answer_depth", &PixelVerdict::answer_depth, "The buffer's depth.")
        .def_ro("depth_expected", &PixelVerdict::depth_expected, "The plane's exact depth along the ray (or NaN).")
        .def_ro("depth_lo", &PixelVerdict::depth_lo)
        .def_ro("depth_hi", &PixelVerdict::depth_hi)
        .def_prop_ro("depth_acceptable", &PixelVerdict::depth_acceptable)
        .def("describe", &PixelVerdict::describe)
        .def("__repr__", [](const PixelVerdict& v) { return "<clvis.PixelVerdict " + v.describe() + ">"; });
    nb::class_<CompareReport>(m, "CompareReport",
                              "Counts of a comparison: equal pixels, differing but both acceptable (explained), errors;\n"
                              "equal + explained + errors == pixels, and the same for the depth_ counts.")
        .def_ro("pixels", &CompareReport::pixels)
        .def_ro("judged", &CompareReport::judged)
        .def_ro("equal", &CompareReport::equal)
        .def_ro("explained", &CompareReport::explained)
        .def_ro("errors", &CompareReport::errors)
        .def_ro("errors_a", &CompareReport::errors_a)
        .def_ro("errors_b", &CompareReport::errors_b)
        .def_ro("depths_judged", &CompareReport::depths_judged)
        .def_ro("depth_equal", &CompareReport::depth_equal)
        .def_ro("depth_explained", &CompareReport::depth_explained)
        .def_ro("depth_errors", &CompareReport::depth_errors)
        .def_ro("depth_errors_a", &CompareReport::depth_errors_a)
        .def_ro("depth_errors_b", &CompareReport::depth_errors_b)
        .def_ro("first_errors", &CompareReport::first_errors, "Up to max_reported verdicts, in raster order.")
        .def("__repr__", [](const CompareReport& r) {
            return "<clvis.CompareReport pixels=" + std::to_string(r.pixels) + " equal=" + std::to_string(r.equal) +
                   " explained=" + std::to_string(r.explained) + " errors=" + std::to_string(r.errors) +
                   " depth_errors=" + std::to_string(r.depth_errors) + ">";
        });
}

const char* referee_doc =
    "The exact judge of CONVENTIONS.md for one scene (copied), camera and image size: whether an id\n"
    "is an acceptable answer at a pixel centre, and its depth the right one, in double precision from the\n"
    "scene's float32 vertices; cull ('none', 'back', 'front') as the buffers were rendered with.\n\n"
    "Example:\n    referee = clvis.Referee(scene, camera, 640, 360)\n"
    "    report = referee.compare(raster_vis, ray_vis)\n    assert report.errors == 0";

} // namespace

void bind_referee(nb::module_& m)
{
    bind_verdicts(m);
    nb::class_<PyReferee>(m, "Referee", referee_doc)
        .def(
            "__init__",
            [](PyReferee* self, PyScene& scene, const Camera& camera, int width, int height, const std::string& cull) {
                RenderOptions o;
                o.cull = cull_from_string(cull);
                unlocked(scene.lock, [&] {
                    new (self) PyReferee{Referee(scene.scene, camera, width, height, o)};
                });
            },
            nb::arg("scene"), nb::arg("camera"), nb::arg("width"), nb::arg("height"), nb::kw_only(),
            nb::arg("cull") = "none")
        .def_prop_ro("width", [](const PyReferee& r) { return r.referee.width(); })
        .def_prop_ro("height", [](const PyReferee& r) { return r.referee.height(); })
        .def(
            "compare",
            [](const PyReferee& r, const PyVisibility& a, const PyVisibility& b, bool differing_only,
               std::size_t max_reported) {
                HostVisibility scratch_a, scratch_b;
                const HostVisibility& ha = host_of(a, scratch_a);
                const HostVisibility& hb = host_of(b, scratch_b);
                nb::gil_scoped_release nogil;
                CompareOptions o;
                o.differing_only = differing_only;
                o.max_reported = max_reported;
                return r.referee.compare(ha, hb, o);
            },
            nb::arg("a"), nb::arg("b"), nb::kw_only(), nb::arg("differing_only") = false, nb::arg("max_reported") = 20,
            "Compares two buffers of this size pixel by pixel, judging every pixel of both, ids and depths\n"
            "(only where they differ with differing_only=True). Two correct buffers give errors == 0 and\n"
            "depth_errors == 0.")
        .def(
            "check",
            [](const PyReferee& r, const PyVisibility& a, std::size_t max_reported) {
                HostVisibility scratch;
                const HostVisibility& ha = host_of(a, scratch);
                nb::gil_scoped_release nogil;
                CompareOptions o;
                o.max_reported = max_reported;
                return r.referee.check(ha, o);
            },
            nb::arg("a"), nb::kw_only(), nb::arg("max_reported") = 20,
            "Judges every pixel of one buffer, ids and depths, against the reference answer.")
        .def(
            "judge",
            [](const PyReferee& r, int x, int y, std::uint32_t id) {
                check_pixel(r, x, y);
                return r.referee.judge(x, y, id);
            },
            nb::arg("x"), nb::arg("y"), nb::arg("id"), "The verdict on `id` as the answer at pixel (x, y).")
        .def(
            "reference",
            [](const PyReferee& r, int x, int y) {
                check_pixel(r, x, y);
                bool ambiguous = false;
                double depth = 0;
                const std::uint32_t id = r.referee.reference(x, y, &ambiguous, &depth);
                return std::make_tuple(id, ambiguous, depth);
            },
            nb::arg("x"), nb::arg("y"),
            "(id, ambiguous, depth): the nearest triangle robustly covering pixel (x, y)'s centre\n"
            "(background_id if none), whether another answer is acceptable too, and its depth.");
}

} // namespace clvis::python
