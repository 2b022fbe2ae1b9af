// clvis.RayQuery: a Renderer's RayQuery as a Python object, made once (kernels built, the BVH
// shared with the renderer's ray path, built there at most once) and reused over many calls.
// Rays come in as the device reads them, without a copy: (N, 8) float32 records (AoS, or a (N,)
// array of clvis.ray_dtype) or (8, N) float32 planes (SoA). Results go into arrays the caller
// owns (out=) or into new ones: closest hits as a (N,) clvis.hit_dtype array (AoS) or as four
// (N,) arrays t, id, u, v (SoA). Ambient occlusion and shadow rays are generated on the device
// from a rendered Visibility. The device works with the GIL released and the renderer locked.
#include "arrays.hpp"

#include <nanobind/stl/array.h>
#include <nanobind/stl/string.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace clvis::python {

namespace {

struct PyRayQuery {
    nb::object owner;        ///< the Python Renderer, kept alive while the query lives
    PyRenderer* renderer;    ///< its C++ side (nanobind never moves it)
    std::unique_ptr<RayQuery> query;
    RayQueryStats stats;     ///< of the last call
};

nb::object numpy() { return nb::module_::import_("numpy"); }

/// A figure for a repr: 4 significant digits ("8.612", "0.0003", "1.2e+04").
std::string number(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

/// clvis.ray_dtype or clvis.hit_dtype (python/clvis/__init__.py defines them, so that their stubs
/// are plain Python), looked up once and kept to the module's end.
PyObject* package_dtype(const char* name)
{
    static PyObject* rays = nullptr;
    static PyObject* hits = nullptr;
    PyObject*& kept = std::string(name) == "ray_dtype" ? rays : hits;
    if (!kept) kept = nb::object(nb::module_::import_("clvis").attr(name)).release().ptr();
    return kept;
}

/// Whether `obj` is a NumPy array of the structured dtype `dtype`. Only a NumPy array's dtype is
/// compared: another object's (an Open3D tensor's, a library's own dtype class) may refuse == with
/// a NumPy dtype or answer NotImplemented.
bool has_dtype(nb::handle obj, PyObject* dtype)
{
    if (!PyObject_IsInstance(obj.ptr(), numpy().attr("ndarray").ptr())) return false;
    return PyObject_RichCompareBool(obj.attr("dtype").ptr(), dtype, Py_EQ) == 1;
}

/// `obj` as NumPy sees it (np.asarray: a NumPy array is returned as it is, no copy), or
/// Error(InvalidArgument) naming `what` when NumPy cannot convert it.
nb::object as_array(nb::handle obj, const std::string& what)
{
    try {
        return numpy().attr("asarray")(obj);
    } catch (const nb::python_error& e) {
        throw Error(Error::Kind::InvalidArgument, what + ": not an array NumPy can convert (" +
                                                      nb::cast<std::string>(nb::str(nb::handle(Py_TYPE(obj.ptr())))) +
                                                      "): " + e.what());
    }
}

/// The rays of one call: `held` keeps the array the device reads.
RayInput rays_of(nb::handle rays, const std::string& layout, const std::string& what, HostArray<float>& held)
{
    const bool soa = parse_choice<bool>(layout, (what + ": layout").c_str(), {{"aos", false}, {"soa", true}});
    const std::string name = what + ": rays";
    if (!soa) {
        nb::object records = as_array(rays, name);
        if (has_dtype(records, package_dtype("ray_dtype")))
            records = records.attr("view")("float32").attr("reshape")(-1, 8);
        held = as_host_array<float>(records, {name.c_str(), "(N, 8)", 2, 8, false}, "float32");
        return RayInput(reinterpret_cast<const RayRecord*>(held.data()), held.shape(0));
    }
    held = as_host_array<float>(rays, {name.c_str(), "(8, N)", 2, 0, false}, "float32");
    if (held.shape(0) != 8)
        throw Error(Error::Kind::InvalidArgument,
                    name + ": expected an array of shape (8, N) (layout 'soa'), got " + std::to_string(held.shape(0)) + " rows");
    const float* p = held.data();
    const std::size_t n = held.shape(1);
    return RayInput(RaySoA{p, p + n, p + 2 * n, p + 3 * n, p + 4 * n, p + 5 * n, p + 6 * n, p + 7 * n}, n);
}

/// A new writable (N,) array of `dtype` (a name or a dtype object).
nb::object empty(std::size_t n, nb::handle dtype) { return numpy().attr("empty")(n, dtype); }

/// Runs `f` on the query, the GIL released and the renderer locked, and keeps its stats.
template <class F>
void run(PyRayQuery& q, F&& f)
{
    q.stats = unlocked(q.renderer->lock, [&] { return f(*q.query); });
}

/// The caller's AoS hits: a writable C-contiguous (N,) array of clvis.hit_dtype.
HitRecord* hit_records(nb::handle out, std::size_t n)
{
    void* data = has_dtype(out, package_dtype("hit_dtype")) ? writable_data(out, 0, sizeof(HitRecord), {n}) : nullptr;
    if (!data) bad_output(out, "RayQuery.closest: out", "clvis.hit_dtype", "(" + std::to_string(n) + ",)");
    return static_cast<HitRecord*>(data);
}

nb::object closest(PyRayQuery& q, nb::handle rays, const std::string& layout, nb::handle out)
{
    HostArray<float> held;
    const RayInput in = rays_of(rays, layout, "RayQuery.closest", held);
    const std::size_t n = in.count;
    if (nb::isinstance<nb::tuple>(out) || nb::isinstance<nb::list>(out)) {
        if (nb::len(out) != 4)
            throw Error(Error::Kind::InvalidArgument, "RayQuery.closest: out: expected a hit_dtype array or (t, id, u, v), got " +
                                                          std::to_string(nb::len(out)) + " items");
        const HitSoA hits{output_array<float>(out[0], "RayQuery.closest: out t", "float32", {n}),
                          output_array<std::uint32_t>(out[1], "RayQuery.closest: out id", "uint32", {n}),
                          output_array<float>(out[2], "RayQuery.closest: out u", "float32", {n}),
                          output_array<float>(out[3], "RayQuery.closest: out v", "float32", {n})};
        run(q, [&](RayQuery& query) { return n ? query.closest(in, hits) : RayQueryStats{}; });
        return nb::borrow(out);
    }
    nb::object result = out.is_none() ? empty(n, nb::handle(package_dtype("hit_dtype"))) : nb::borrow(out);
    HitRecord* hits = hit_records(result, n);
    run(q, [&](RayQuery& query) { return n ? query.closest(in, hits) : RayQueryStats{}; });
    return result;
}

/// occluded and count: one T per ray into `out` (or a new array).
template <class T, class Answer>
nb::object per_ray(PyRayQuery& q, nb::handle rays, const std::string& layout, nb::handle out, const char* what,
                   const char* dtype, Answer answer)
{
    HostArray<float> held;
    const RayInput in = rays_of(rays, layout, what, held);
    nb::object result = out.is_none() ? empty(in.count, nb::str(dtype)) : nb::borrow(out);
    T* values = output_array<T>(result, std::string(what) + ": out", dtype, {in.count});
    run(q, [&](RayQuery& query) { return in.count ? answer(query, in, values) : RayQueryStats{}; });
    return result;
}

/// All hits: a new (N, max_hits) clvis.hit_dtype array, and with `counts` a new (N,) uint32 array
/// of each ray's number of hits (the pair as a tuple).
nb::object all_hits(PyRayQuery& q, nb::handle rays, int max_hits, const std::string& layout, bool counts)
{
    if (max_hits < 1 || max_hits > ray_query_max_hits)
        throw Error(Error::Kind::InvalidArgument, "RayQuery.all: max_hits must lie in [1, " +
                                                      std::to_string(ray_query_max_hits) + "], got " + std::to_string(max_hits));
    HostArray<float> held;
    const RayInput in = rays_of(rays, layout, "RayQuery.all", held);
    const std::size_t n = in.count, k = std::size_t(max_hits);
    nb::object hits = numpy().attr("empty")(nb::make_tuple(n, k), nb::handle(package_dtype("hit_dtype")));
    auto* records = static_cast<HitRecord*>(writable_data(hits, 0, sizeof(HitRecord), {n, k}));
    nb::object per_ray = counts ? empty(n, nb::str("uint32")) : nb::none();
    std::uint32_t* c = counts ? output_array<std::uint32_t>(per_ray, "RayQuery.all: counts", "uint32", {n}) : nullptr;
    run(q, [&](RayQuery& query) { return n ? query.all(in, max_hits, records, c) : RayQueryStats{}; });
    if (!counts) return hits;
    return nb::make_tuple(hits, per_ray);
}

/// Per-pixel values into `out` (or a new (H, W) float32 array): one copy of H x W floats.
nb::object pixel_values(PyRayQuery& q, const PixelRays& values, nb::handle out, const char* what)
{
    q.stats = values.stats;
    const std::size_t h = std::size_t(values.height), w = std::size_t(values.width);
    nb::object result = out.is_none() ? numpy().attr("empty")(nb::make_tuple(h, w), "float32") : nb::borrow(out);
    float* data = output_array<float>(result, std::string(what) + ": out", "float32", {h, w});
    std::memcpy(data, values.value.data(), values.value.size() * sizeof(float));
    return result;
}

nb::object ambient_occlusion(PyRayQuery& q, const PyVisibility& vis, int rays, double distance, std::uint64_t seed,
                             nb::handle out)
{
    const VisibilityBuffer& buffer = device_buffer(vis, "RayQuery.ambient_occlusion");
    const AoOptions options{rays, float(distance), seed};
    const PixelRays ao = unlocked(q.renderer->lock, [&] { return q.query->ambient_occlusion(buffer, *vis.camera, options); });
    return pixel_values(q, ao, out, "RayQuery.ambient_occlusion");
}

nb::object shadows(PyRayQuery& q, const PyVisibility& vis, std::array<double, 3> light, nb::handle out)
{
    const VisibilityBuffer& buffer = device_buffer(vis, "RayQuery.shadows");
    const PixelRays lit = unlocked(q.renderer->lock, [&] { return q.query->shadows(buffer, *vis.camera, to_vec3(light)); });
    return pixel_values(q, lit, out, "RayQuery.shadows");
}

nb::object ambient_occlusion_rays(PyRayQuery& q, const PyVisibility& vis, int rays, double distance, std::uint64_t seed)
{
    const VisibilityBuffer& buffer = device_buffer(vis, "RayQuery.ambient_occlusion_rays");
    const AoOptions options{rays, float(distance), seed};
    auto records = std::make_shared<std::vector<RayRecord>>(
        unlocked(q.renderer->lock, [&] { return q.query->ambient_occlusion_rays(buffer, *vis.camera, options); }));
    const auto* data = reinterpret_cast<const float*>(records->data());
    return nb::cast(numpy_view(data, {records->size(), 8}, keep_alive(records)));
}

void bind_stats(nb::module_& m)
{
    nb::class_<RayQueryStats>(m, "RayQueryStats", "What one ray query call did (RayQuery.stats).")
        .def_ro("rays", &RayQueryStats::rays, "Rays answered.")
        .def_ro("invalid", &RayQueryStats::invalid,
                "Of which invalid (NaN or infinite component, zero direction, tmin < 0 or > tmax): answered as misses.")
        .def_ro("batches", &RayQueryStats::batches, "Kernel launches the rays were split into.")
        .def_ro("device_ms", &RayQueryStats::device_ms, "Kernel time summed over batches.")
        .def_ro("wall_ms", &RayQueryStats::wall_ms, "Host wall time of the call, transfers included.")
        .def("__repr__", [](const RayQueryStats& s) {
            return "<clvis.RayQueryStats rays=" + std::to_string(s.rays) + " invalid=" + std::to_string(s.invalid) +
                   " batches=" + std::to_string(s.batches) + " device_ms=" + number(s.device_ms) +
                   " wall_ms=" + number(s.wall_ms) + ">";
        });
    // BvhStats is bound with the Renderer (render.cpp); its repr, listing every field, is added here.
    nb::handle bvh = nb::type<BvhStats>();
    nb::setattr(bvh, "__repr__", nb::cpp_function([](const BvhStats& s) {
        auto count = [](std::uint64_t n) { return std::to_string(n); };
        return "<clvis.BvhStats build_ms=" + number(s.build_ms) + " upload_ms=" + number(s.upload_ms) +
               " nodes=" + count(s.nodes) + " leaves=" + count(s.leaves) + " depth=" + std::to_string(s.depth) +
               " sah_cost=" + number(s.sah_cost) + " refitted=" + (s.refitted ? "True" : "False") +
               " instances=" + count(s.instances) + " top_build_ms=" + number(s.top_build_ms) +
               " prototype_builds=" + count(s.prototype_builds) + " device_bytes=" + count(s.device_bytes) + ">";
    }, nb::is_method(), nb::name("__repr__"), nb::scope(bvh)));
}

const char* rays_doc =
    "`rays`: with layout='aos' (the default) an (N, 8) float32 array of records ox, oy, oz, tmin,\n"
    "dx, dy, dz, tmax (or an (N,) array of clvis.ray_dtype); with layout='soa' an (8, N) float32\n"
    "array, one row per field. float32 C-ordered input is read in place; other dtypes are converted\n"
    "once. Invalid rays are answered as misses and counted in stats.invalid.";

const char* query_doc =
    "Ray queries through a Renderer's scene and BVH, made once and reused: the kernels are built\n"
    "and the BVH shared with the renderer's ray path (built there once, refitted by\n"
    "Renderer.update), never rebuilt per call. Results go into new arrays or into the caller's\n"
    "(out=), which are returned. `batch_rays` bounds the rays per kernel launch (device memory);\n"
    "`brute` tests every triangle instead of walking the BVH; `lanes` (1..8) walks that many rays per\n"
    "work-item interleaved, so that their memory misses overlap (pays for incoherent rays through a\n"
    "large tree on a CPU device; the same answers at any value). The query keeps its Renderer alive;\n"
    "calls lock the renderer and release the GIL.\n\n"
    "Example:\n"
    "    query = clvis.RayQuery(renderer)\n"
    "    rays = np.zeros((n, 8), np.float32)   # ox, oy, oz, tmin, dx, dy, dz, tmax\n"
    "    hits = np.empty(n, clvis.hit_dtype)\n"
    "    for frame in frames:\n"
    "        fill(rays, frame)\n"
    "        query.closest(rays, out=hits)     # hits['t'], hits['id'], hits['u'], hits['v']";

} // namespace

void bind_ray_query(nb::module_& m)
{
    bind_stats(m);
    static const std::string closest_doc =
        std::string("The nearest hit of each ray in [tmin, tmax]: t, id (background_id for a miss, with t = inf\n"
                    "and u = v = 0) and barycentrics u, v (P = (1-u-v) v0 + u v1 + v v2). Returns `out`: a\n"
                    "writable (N,) array of clvis.hit_dtype (AoS, the default, new when out is None) or a tuple\n"
                    "(t, id, u, v) of (N,) float32, uint32, float32, float32 arrays (SoA).\n") + rays_doc;
    static const std::string any_doc =
        std::string("1 where a ray hits anything in [tmin, tmax], else 0: `out`, a (N,) uint8 array.\n") + rays_doc;
    static const std::string count_doc =
        std::string("Surface crossings of each ray in [tmin, tmax] (odd from inside a closed mesh): `out`, a (N,)\n"
                    "uint32 array.\n") + rays_doc;
    const auto sig = [](const char* name, const char* out) {
        return std::string("def ") + name + "(self, rays: numpy.typing.ArrayLike, layout: str = 'aos', *, out: " + out +
               " | None = None) -> " + out;
    };
    static const std::string closest_sig =
        sig("closest", "numpy.typing.NDArray[numpy.void] | tuple[numpy.typing.NDArray[numpy.float32], "
                       "numpy.typing.NDArray[numpy.uint32], numpy.typing.NDArray[numpy.float32], "
                       "numpy.typing.NDArray[numpy.float32]]");
    static const std::string any_sig = sig("occluded", "numpy.typing.NDArray[numpy.uint8]");
    static const std::string count_sig = sig("count", "numpy.typing.NDArray[numpy.uint32]");
    static const std::string all_doc =
        std::string("All hits of each ray: its `max_hits` (1 to 64) nearest hits in [tmin, tmax], edges inclusive as\n"
                    "closest (a ray through an edge shared by two triangles meets both), ordered by t then id, as a new\n"
                    "(N, max_hits) array of clvis.hit_dtype, the slots past a ray's last hit misses (id background_id,\n"
                    "t = inf, u = v = 0). With counts=True, (hits, counts): counts a (N,) uint32 array, the number of\n"
                    "all hits of each ray, edges inclusive (may exceed max_hits; not count()'s half-open crossings;\n"
                    "asking for it walks every box a ray meets).\n") + rays_doc;

    nb::class_<PyRayQuery>(m, "RayQuery", query_doc)
        .def(
            "__init__",
            [](PyRayQuery* self, nb::handle renderer, std::size_t batch_rays, bool brute, int lanes) {
                PyRenderer& r = nb::cast<PyRenderer&>(renderer);
                if (batch_rays == 0) throw Error(Error::Kind::InvalidArgument, "RayQuery: batch_rays must be positive");
                RayQueryOptions options;
                options.batch_rays = batch_rays;
                options.brute = brute;
                options.lanes = lanes; // checked by RayQuery: 0 (1) to 8
                auto query = unlocked(r.lock, [&] { return std::make_unique<RayQuery>(r.renderer, options); });
                new (self) PyRayQuery{nb::borrow(renderer), &r, std::move(query), {}};
            },
            nb::sig("def __init__(self, renderer: Renderer, *, batch_rays: int = 1048576, brute: bool = False, "
                    "lanes: int = 1) -> None"),
            nb::arg("renderer"), nb::kw_only(), nb::arg("batch_rays") = std::size_t(1) << 20, nb::arg("brute") = false,
            nb::arg("lanes") = 1)
        .def("closest", &closest, nb::sig(closest_sig.c_str()), nb::arg("rays"), nb::arg("layout") = "aos", nb::kw_only(),
             nb::arg("out") = nb::none(), closest_doc.c_str())
        .def(
            "occluded",
            [](PyRayQuery& q, nb::handle rays, const std::string& layout, nb::handle out) {
                return per_ray<std::uint8_t>(q, rays, layout, out, "RayQuery.occluded", "uint8",
                                             [](RayQuery& query, const RayInput& in, std::uint8_t* v) { return query.occluded(in, v); });
            },
            nb::sig(any_sig.c_str()), nb::arg("rays"), nb::arg("layout") = "aos", nb::kw_only(), nb::arg("out") = nb::none(),
            any_doc.c_str())
        .def(
            "count",
            [](PyRayQuery& q, nb::handle rays, const std::string& layout, nb::handle out) {
                return per_ray<std::uint32_t>(q, rays, layout, out, "RayQuery.count", "uint32",
                                              [](RayQuery& query, const RayInput& in, std::uint32_t* v) { return query.count(in, v); });
            },
            nb::sig(count_sig.c_str()), nb::arg("rays"), nb::arg("layout") = "aos", nb::kw_only(), nb::arg("out") = nb::none(),
            count_doc.c_str())
        .def("all", &all_hits,
             nb::sig("def all(self, rays: numpy.typing.ArrayLike, max_hits: int, layout: str = 'aos', *, counts: bool = False) "
                     "-> numpy.typing.NDArray[numpy.void] | tuple[numpy.typing.NDArray[numpy.void], "
                     "numpy.typing.NDArray[numpy.uint32]]"),
             nb::arg("rays"), nb::arg("max_hits"), nb::arg("layout") = "aos", nb::kw_only(), nb::arg("counts") = false,
             all_doc.c_str())
        .def("ambient_occlusion", &ambient_occlusion,
             nb::sig("def ambient_occlusion(self, visibility: Visibility, *, rays: int = 8, distance: float = 0.0, "
                     "seed: int = 1, out: numpy.typing.NDArray[numpy.float32] | None = None) -> numpy.typing.NDArray[numpy.float32]"),
             nb::arg("visibility"), nb::kw_only(), nb::arg("rays") = 8, nb::arg("distance") = 0.0, nb::arg("seed") = 1,
             nb::arg("out") = nb::none(),
             "Ambient occlusion of each pixel of `visibility` (rendered whole by this query's Renderer), its rays\n"
             "generated on the device: `rays` cosine-weighted rays per visible point, `distance` long (0: 10% of\n"
             "the scene's diagonal). (H, W) float32 unoccluded fraction in [0, 1], background 1, into `out`.")
        .def("ambient_occlusion_rays", &ambient_occlusion_rays, nb::arg("visibility"), nb::kw_only(), nb::arg("rays") = 8,
             nb::arg("distance") = 0.0, nb::arg("seed") = 1,
             "The rays of ambient_occlusion, as an (H * W * rays, 8) float32 array of records, pixels in\n"
             "row order (a background pixel's rays, which ambient_occlusion does not trace, have a zero\n"
             "direction: invalid, answered as misses).")
        .def("shadows", &shadows,
             nb::sig("def shadows(self, visibility: Visibility, light: tuple[float, float, float], *, "
                     "out: numpy.typing.NDArray[numpy.float32] | None = None) -> numpy.typing.NDArray[numpy.float32]"),
             nb::arg("visibility"), nb::arg("light"), nb::kw_only(), nb::arg("out") = nb::none(),
             "Whether each visible point of `visibility` sees the point light at `light` (world space), by shadow\n"
             "rays generated on the device: (H, W) float32, 1 lit, 0 shadowed, background 1, into `out`.")
        .def_prop_ro("stats", [](const PyRayQuery& q) { return q.stats; }, "RayQueryStats of the last call.")
        .def_prop_ro("renderer", [](const PyRayQuery& q) { return q.owner; }, "The Renderer it queries.")
        .def_prop_ro("batch_rays", [](const PyRayQuery& q) { return q.query->options().batch_rays; })
        .def_prop_ro("brute", [](const PyRayQuery& q) { return q.query->options().brute; })
        .def_prop_ro("lanes", [](const PyRayQuery& q) { return std::max(1, q.query->options().lanes); });
}

} // namespace clvis::python
