// The untimed host logic of the multi-view workload (bench_views.hpp).
#include "bench_views.hpp"

#include <clvis/error.hpp>
#include <clvis/math.hpp>

#include <cmath>
#include <filesystem>

namespace clvis::bench {

namespace {

/// `v` turned by `angle` radians about the unit axis `k` (Rodrigues).
Vec3 rotate(Vec3 v, Vec3 k, double angle)
{
    double c = std::cos(angle), s = std::sin(angle);
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

} // namespace

std::vector<Camera> orbit_cameras(const Bounds& bounds, int views)
{
    if (views < 1) throw Error(Error::Kind::InvalidArgument, "--views: the view count must be >= 1 (got " +
                                                           std::to_string(views) + ")");
    Camera framing = Camera::framing(bounds);
    Vec3 c = bounds.center(), d = framing.eye - c, axis = normalize(framing.up);
    std::vector<Camera> out;
    out.reserve(std::size_t(views));
    for (int i = 0; i < views; ++i) {
        Camera cam = framing;
        if (i > 0) cam.eye = c + rotate(d, axis, 2 * 3.14159265358979323846 * i / views);
        out.push_back(cam);
    }
    return out;
}

double views_per_second(double ms, int views) { return ms > 0 ? views * 1000.0 / ms : 0; }

std::string bundled_mesh(const std::string& file)
{
    namespace fs = std::filesystem;
    fs::path here = fs::path("scenes") / file;
    std::error_code ec;
    if (fs::is_regular_file(here, ec)) return here.string();
#ifdef CLVIS_BENCH_SOURCE_DIR
    return (fs::path(CLVIS_BENCH_SOURCE_DIR) / "scenes" / file).string();
#else
    return here.string();
#endif
}

} // namespace clvis::bench
