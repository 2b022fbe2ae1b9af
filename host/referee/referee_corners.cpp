// The referee of named corner attributes and object ids (include/clvis/referee_attributes.hpp):
// each value recomputed in double from the exact barycentrics of the sample, independent of the
// kernels (kernels/resolve_corners.cl) that resolved it.
#include <clvis/error.hpp>
#include <clvis/referee_attributes.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace clvis {

CornerReferee::CornerReferee(const Scene& scene, const Camera& camera, int width, int height)
    : camera_(camera), width_(width), height_(height), scene_(scene)
{
    camera.validate();
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "CornerReferee: image size must be positive");
}

bool CornerReferee::expected(double sx, double sy, std::uint32_t id, const std::string& name, double* out,
                             double* allowed) const
{
    if (id >= scene_.triangle_count()) return false;
    std::size_t item = scene_.mesh_of(id);
    const MeshData& data = scene_.data_of(item);
    const CornerAttribute* attr = nullptr;
    for (const CornerAttribute& a : data.attributes)
        if (a.name == name) attr = &a;
    if (!attr) return false;
    float w[9];
    scene_.triangle(id, w);
    Vec3 p0{w[0], w[1], w[2]}, p1{w[3], w[4], w[5]}, p2{w[6], w[7], w[8]};
    // The exact barycentrics: the double-precision primary ray meeting the triangle's plane.
    Ray ray = camera_.primary_ray(sx, sy, width_, height_);
    Vec3 e1 = p1 - p0, e2 = p2 - p0, s = ray.origin - p0;
    Vec3 p = cross(ray.direction, e2), q = cross(s, e1);
    double det = dot(e1, p);
    double u = det == 0 ? 0 : dot(s, p) / det, v = det == 0 ? 0 : dot(ray.direction, q) / det;
    const int c = attr->components;
    const std::size_t local = id - scene_.meshes()[item].first_triangle;
    const float* corner = attr->values.data() + 3 * local * std::size_t(c);
    for (int j = 0; j < c; ++j) {
        double a0 = corner[j], a1 = corner[c + j], a2 = corner[2 * c + j];
        out[j] = (1 - u - v) * a0 + u * a1 + v * a2;
        allowed[j] = corner_tolerance_rel * std::max({std::fabs(a0), std::fabs(a1), std::fabs(a2)}) +
                     corner_tolerance_abs;
    }
    return true;
}

CornerReport CornerReferee::check(const HostVisibility& vis, const std::string& name,
                                  const std::vector<float>& values) const
{
    int c = 0;
    for (std::size_t item = 0; item < scene_.meshes().size() && c == 0; ++item)
        for (const CornerAttribute& a : scene_.data_of(item).attributes)
            if (a.name == name) c = a.components;
    if (c == 0)
        throw Error(Error::Kind::InvalidArgument, "CornerReferee::check: the scene has no attribute '" + name + "'");
    if (vis.samples != 1 || vis.width != width_ || vis.height != height_ || values.size() != vis.ids.size() * std::size_t(c))
        throw Error(Error::Kind::InvalidArgument, "CornerReferee::check: sizes differ from the referee's");
    CornerReport rep;
    double want[4], allowed[4];
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const std::size_t i = std::size_t(y) * width_ + x;
            const float* got = values.data() + i * std::size_t(c);
            ++rep.pixels;
            bool ok = true;
            double worst = 0;
            const bool has = expected(x + 0.5, y + 0.5, vis.ids[i], name, want, allowed);
            if (has) {
                ++rep.covered;
                for (int j = 0; j < c; ++j) {
                    if (std::isnan(want[j])) { // a corner without a value (a loader's NaN): NaN
                        ok &= std::isnan(got[j]);
                        continue;
                    }
                    double share = std::fabs(double(got[j]) - want[j]) / allowed[j];
                    if (!(share <= 1)) ok = false;
                    worst = std::isfinite(share) ? std::max(worst, share) : HUGE_VAL;
                }
                rep.max_error_share = std::max(rep.max_error_share, worst);
            } else {
                for (int j = 0; j < c; ++j) ok &= std::isnan(got[j]);
            }
            if (!ok) {
                ++rep.errors;
                if (rep.first_errors.size() < 10) {
                    char buf[200];
                    std::snprintf(buf, sizeof buf, "pixel (%d, %d) id %u: %s.x = %.9g, expected %.9g (error %.3g of "
                                  "the tolerance)", x, y, vis.ids[i], name.c_str(), double(got[0]),
                                  has ? want[0] : std::nan(""), worst);
                    rep.first_errors.push_back(buf);
                }
            }
        }
    return rep;
}

std::size_t CornerReferee::check_objects(const HostVisibility& vis, const std::vector<std::uint32_t>& objects,
                                         std::vector<std::string>* first) const
{
    if (objects.size() != vis.ids.size())
        throw Error(Error::Kind::InvalidArgument, "CornerReferee::check_objects: sizes differ");
    std::size_t errors = 0;
    for (std::size_t i = 0; i < objects.size(); ++i) {
        std::uint32_t id = vis.ids[i];
        std::uint32_t want = id < scene_.triangle_count() ? std::uint32_t(scene_.mesh_of(id)) : background_id;
        if (objects[i] == want) continue;
        ++errors;
        if (first && first->size() < 10)
            first->push_back("pixel " + std::to_string(i) + " id " + std::to_string(id) + ": object " +
                             std::to_string(objects[i]) + ", expected " + std::to_string(want));
    }
    return errors;
}

} // namespace clvis
