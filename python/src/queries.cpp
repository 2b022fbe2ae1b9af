// Ray queries from Python as Renderer methods: cast_rays (closest hit), occluded (any hit) and
// count_intersections (surface crossings) over (N, 3) origins and directions with one interval
// [tmin, tmax], or over (N, 8) ray records; and ambient occlusion of a rendered Visibility. The
// device works with the GIL released; results are NumPy arrays that own their storage.
#include "arrays.hpp"

#include <nanobind/stl/string.h>

#include <cmath>
#include <limits>

namespace clvis::python {

namespace {

/// The rays of one call: the caller's (N, 8) float32 records used in place, or records built
/// from (N, 3) origins and directions.
struct Rays {
    HostArray<float> held;
    std::vector<RayRecord> built;
    const RayRecord* data = nullptr;
    std::size_t count = 0;
};

Rays ray_input(nb::handle origins, nb::handle directions, double tmin, double tmax, const std::string& what)
{
    Rays r;
    if (directions.is_none()) {
        const std::string name = what + ": rays";
        r.held = as_host_array<float>(origins, {name.c_str(), "(N, 8)", 2, 8, false}, "float32");
        r.data = reinterpret_cast<const RayRecord*>(r.held.data());
        r.count = r.held.shape(0);
        return r;
    }
    const std::string on = what + ": origins", dn = what + ": directions";
    const auto o = as_host_array<float>(origins, {on.c_str(), "(N, 3)", 2, 3, false}, "float32");
    const auto d = as_host_array<float>(directions, {dn.c_str(), "(N, 3)", 2, 3, false}, "float32");
    if (o.shape(0) != d.shape(0))
        throw Error(Error::Kind::InvalidArgument, what + ": origins has " + std::to_string(o.shape(0)) +
                                                      " rays, directions " + std::to_string(d.shape(0)));
    r.count = o.shape(0);
    r.built.resize(r.count);
    const float lo = float(tmin), hi = float(tmax);
    for (std::size_t i = 0; i < r.count; ++i) {
        const float* a = o.data() + 3 * i;
        const float* b = d.data() + 3 * i;
        r.built[i] = RayRecord{a[0], a[1], a[2], lo, b[0], b[1], b[2], hi};
    }
    r.data = r.built.data();
    return r;
}

/// Runs `f` on the renderer's RayQuery (made on first use), the GIL released and the renderer
/// locked; no call for no rays.
template <class F>
RayQueryStats query(PyRenderer& r, const Rays& rays, F&& f)
{
    if (rays.count == 0) return {};
    return unlocked(r.lock, [&] {
        if (!r.query) r.query = std::make_unique<RayQuery>(r.renderer);
        return f(*r.query, RayInput(rays.data, rays.count));
    });
}

nb::dict cast_rays(PyRenderer& r, nb::handle origins, nb::handle directions, double tmin, double tmax)
{
    const Rays rays = ray_input(origins, directions, tmin, tmax, "cast_rays");
    const std::size_t n = rays.count;
    std::vector<float> t(n), u(n), v(n);
    std::vector<std::uint32_t> id(n);
    const RayQueryStats s = query(r, rays, [&](RayQuery& q, const RayInput& in) {
        return q.closest(in, HitSoA{t.data(), id.data(), u.data(), v.data()});
    });
    nb::dict out;
    out["t"] = owned_array(std::move(t), {n});
    out["id"] = owned_array(std::move(id), {n});
    out["u"] = owned_array(std::move(u), {n});
    out["v"] = owned_array(std::move(v), {n});
    out["invalid"] = s.invalid;
    return out;
}

/// One value of type T per ray, as `answer` gives them, under `key` with the invalid count.
template <class T, class Answer>
nb::dict per_ray(PyRenderer& r, const Rays& rays, const char* key, Answer answer)
{
    std::vector<T> values(rays.count);
    const RayQueryStats s =
        query(r, rays, [&](RayQuery& q, const RayInput& in) { return answer(q, in, values.data()); });
    nb::dict out;
    out[key] = owned_array(std::move(values), {rays.count});
    out["invalid"] = s.invalid;
    return out;
}

nb::dict occluded(PyRenderer& r, nb::handle origins, nb::handle directions, double tmin, double tmax)
{
    return per_ray<std::uint8_t>(r, ray_input(origins, directions, tmin, tmax, "occluded"), "occluded",
                                 [](RayQuery& q, const RayInput& in, std::uint8_t* out) { return q.occluded(in, out); });
}

nb::dict count_intersections(PyRenderer& r, nb::handle origins, nb::handle directions, double tmin, double tmax)
{
    return per_ray<std::uint32_t>(r, ray_input(origins, directions, tmin, tmax, "count_intersections"), "count",
                                  [](RayQuery& q, const RayInput& in, std::uint32_t* out) { return q.count(in, out); });
}

nb::object ambient_occlusion(PyRenderer& r, const PyVisibility& vis, int rays, double distance, std::uint64_t seed)
{
    const VisibilityBuffer& buffer = device_buffer(vis, "ambient_occlusion");
    const AoOptions options{rays, float(distance), seed};
    PixelRays ao = unlocked(r.lock, [&] {
        if (!r.query) r.query = std::make_unique<RayQuery>(r.renderer);
        return r.query->ambient_occlusion(buffer, *vis.camera, options);
    });
    return owned_array(std::move(ao.value), {std::size_t(ao.height), std::size_t(ao.width)});
}

const char* rays_doc =
    "Rays are `origins` and `directions`, (N, 3) float32 (other dtypes converted once), all over\n"
    "[tmin, tmax] (t in units of the direction's length), or `origins` alone as (N, 8) float32\n"
    "records ox, oy, oz, tmin, dx, dy, dz, tmax (used in place). Invalid rays (NaN, zero direction,\n"
    "tmin < 0 or > tmax) are answered as misses and counted in 'invalid'. The GIL is released.\n";

} // namespace

void bind_ray_queries(nb::class_<PyRenderer>& r)
{
    const double inf = std::numeric_limits<double>::infinity();
    const auto rays_sig = [](const char* name, const char* result) {
        return std::string("def ") + name +
               "(self, origins: numpy.typing.ArrayLike, directions: numpy.typing.ArrayLike | None = None, "
               "tmin: float = 0.0, tmax: float = float('inf')) -> " + result;
    };
    static const std::string closest_sig = rays_sig("cast_rays", "dict[str, typing.Any]");
    static const std::string any_sig = rays_sig("occluded", "dict[str, typing.Any]");
    static const std::string count_sig = rays_sig("count_intersections", "dict[str, typing.Any]");
    static const std::string closest_doc = std::string(
        "The nearest hit of each ray: {'t', 'id', 'u', 'v'} as (N,) arrays (float32, uint32 with\n"
        "background_id for a miss, float32 barycentrics: P = (1-u-v) v0 + u v1 + v v2; a miss has\n"
        "t = inf, u = v = 0) and 'invalid', the count of invalid rays.\n") + rays_doc +
        "\nExample:\n    hits = renderer.cast_rays(origins, directions)\n    hit = hits['id'] != clvis.background_id";
    static const std::string any_doc = std::string(
        "Whether each ray hits anything in [tmin, tmax]: {'occluded': (N,) uint8, 'invalid': int}.\n") + rays_doc;
    static const std::string count_doc = std::string(
        "Surface crossings of each ray in [tmin, tmax] ({'count': (N,) uint32, 'invalid': int}); from\n"
        "inside a closed mesh the count is odd.\n") + rays_doc;
    r.def("cast_rays", &cast_rays, nb::sig(closest_sig.c_str()), nb::arg("origins"), nb::arg("directions") = nb::none(),
          nb::arg("tmin") = 0.0, nb::arg("tmax") = inf, closest_doc.c_str())
        .def("occluded", &occluded, nb::sig(any_sig.c_str()), nb::arg("origins"), nb::arg("directions") = nb::none(),
             nb::arg("tmin") = 0.0, nb::arg("tmax") = inf, any_doc.c_str())
        .def("count_intersections", &count_intersections, nb::sig(count_sig.c_str()), nb::arg("origins"),
             nb::arg("directions") = nb::none(), nb::arg("tmin") = 0.0, nb::arg("tmax") = inf, count_doc.c_str())
        .def("ambient_occlusion", &ambient_occlusion, nb::arg("visibility"), nb::kw_only(), nb::arg("rays") = 8,
             nb::arg("distance") = 0.0, nb::arg("seed") = 1,
             "Ambient occlusion of each pixel of `visibility` (rendered by this Renderer): `rays` cosine-weighted\n"
             "rays per visible point, `distance` long (0: 10% of the scene's diagonal). (H, W) float32, the\n"
             "unoccluded fraction in [0, 1], background pixels 1.");
}

} // namespace clvis::python
