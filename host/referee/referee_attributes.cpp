// The referee of resolved attributes (include/clvis/referee_attributes.hpp): barycentrics judged
// by where the point they name projects and by its view depth, in double precision.
#include <clvis/error.hpp>
#include <clvis/referee_attributes.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

namespace clvis {

std::string BaryVerdict::describe(int x, int y) const
{
    char buf[200];
    std::snprintf(buf, sizeof buf, "pixel (%d, %d): P %.3g px from the sample, depth off by %.3g (allowed %.3g)", x, y,
                  px_error, depth_error, depth_allowed);
    return buf;
}

BarycentricReferee::BarycentricReferee(const Scene& scene, const Camera& camera, int width, int height)
    : camera_(camera), width_(width), height_(height), scene_(scene)
{
    camera.validate();
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "BarycentricReferee: image size must be positive");
}

void BarycentricReferee::vertices(std::uint32_t id, Vec3 out[3]) const
{
    float w[9];
    scene_.triangle(id, w); // the item's own vertices through its transform: nothing expanded
    for (int k = 0; k < 3; ++k) out[k] = {w[3 * k], w[3 * k + 1], w[3 * k + 2]};
}

double BarycentricReferee::plane_depth(std::uint32_t id, double sx, double sy) const
{
    Vec3 p[3];
    vertices(id, p);
    Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    Ray ray = camera_.primary_ray(sx, sy, width_, height_);
    double den = dot(n, ray.direction);
    return den == 0 ? std::numeric_limits<double>::infinity() : dot(n, p[0] - ray.origin) / den;
}

BaryVerdict BarycentricReferee::judge_at(double sx, double sy, std::uint32_t id, double u, double v,
                                         double depth) const
{
    BaryVerdict b;
    if (id == background_id) {
        b.ok = u == 0 && v == 0;
        b.px_error = b.ok ? 0 : std::numeric_limits<double>::infinity();
        return b;
    }
    if (id >= scene_.triangle_count()) {
        b.ok = false;
        b.px_error = std::numeric_limits<double>::infinity();
        return b;
    }
    Vec3 p[3];
    vertices(id, p);
    Vec3 at = p[0] * (1 - u - v) + p[1] * u + p[2] * v;
    Vec3 r = camera_.to_raster(at, width_, height_);
    b.px_error = std::hypot(r.x - sx, r.y - sy);
    // The depth gradient: 1 / d is affine in raster space under perspective, d itself under an
    // orthographic camera, so differences over one pixel give it exactly.
    double d0 = plane_depth(id, sx, sy), dx = plane_depth(id, sx + 1, sy), dy = plane_depth(id, sx, sy + 1);
    double grad = camera_.projection == Projection::Perspective
                      ? d0 * d0 * std::hypot(1 / dx - 1 / d0, 1 / dy - 1 / d0)
                      : std::hypot(dx - d0, dy - d0);
    b.depth_allowed = depth_tolerance_rel * r.z + grad * depth_tolerance_px;
    b.depth_error = std::fabs(r.z - depth);
    b.ok = std::isfinite(b.px_error) && b.px_error <= bary_px_tolerance && !(b.depth_error > b.depth_allowed);
    return b;
}

BaryVerdict BarycentricReferee::judge(int x, int y, std::uint32_t id, double u, double v, double depth) const
{
    return judge_at(x + 0.5, y + 0.5, id, u, v, depth);
}

BaryReport BarycentricReferee::check(const HostVisibility& vis, const std::vector<float>& uv) const
{
    if (vis.samples != 1)
        throw Error(Error::Kind::InvalidArgument, "BarycentricReferee::check: barycentrics are judged at one sample "
                                                  "per pixel, the buffer holds " + std::to_string(vis.samples));
    if (vis.width != width_ || vis.height != height_ || uv.size() != vis.ids.size() * 2)
        throw Error(Error::Kind::InvalidArgument, "BarycentricReferee::check: sizes differ from the referee's");
    BaryReport rep;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            std::size_t i = std::size_t(y) * width_ + x;
            BaryVerdict b = judge(x, y, vis.ids[i], uv[2 * i], uv[2 * i + 1], vis.depth[i]);
            ++rep.pixels;
            if (vis.ids[i] != background_id) {
                ++rep.covered;
                rep.max_px_error = std::fmax(rep.max_px_error, b.px_error);
                if (b.depth_allowed > 0)
                    rep.max_depth_error_share = std::fmax(rep.max_depth_error_share, b.depth_error / b.depth_allowed);
            }
            if (!b.ok) {
                ++rep.errors;
                if (rep.first_errors.size() < 10) rep.first_errors.push_back(b.describe(x, y));
            }
        }
    return rep;
}

} // namespace clvis
