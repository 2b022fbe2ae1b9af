// The flow referee (include/clvis/referee_flow.hpp): each sample of view A recomputed in double
// from the float32 corners of its triangle at each view (placed as the renderer places them,
// scene/instance_transform.hpp), A's primary ray meeting the triangle's plane, and B's camera; the
// flow buffer's answers judged against it with bands around each threshold.
#include "scene/instance_transform.hpp"

#include <clvis/error.hpp>
#include <clvis/referee_flow.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace clvis {

namespace {

/// The float32 world corners of triangle `id` with `items`' transforms replacing the scene's.
void corners(const Scene& scene, std::uint32_t id, const ItemTransforms& items, Vec3 out[3])
{
    std::size_t item = scene.mesh_of(id);
    const MeshData& data = scene.data_of(item);
    std::size_t local = id - scene.meshes()[item].first_triangle;
    auto it = items.find(item);
    const Mat4& t = it != items.end() ? it->second : scene.meshes()[item].transform;
    for (std::size_t k = 0; k < 3; ++k) {
        float w[3];
        detail::transform_positions(t, &data.positions[std::size_t(data.indices[local * 3 + k]) * 3], 1, w);
        out[k] = {w[0], w[1], w[2]};
    }
}

/// (u, v) where `ray` meets the plane of (a, b, c); false where it is parallel or the triangle flat.
bool plane_barycentrics(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c, double& u, double& v)
{
    Vec3 e1 = b - a, e2 = c - a, s = ray.origin - a, d = ray.direction;
    Vec3 p = cross(d, e2);
    double det = dot(e1, p);
    if (det == 0 || !std::isfinite(det)) return false;
    Vec3 q = cross(s, e1);
    u = dot(s, p) / det;
    v = dot(d, q) / det;
    return true;
}

bool near_value(double x, double at, double band) { return std::fabs(x - at) <= band; }

} // namespace

FlowReport judge_flow(const Scene& scene, const HostVisibility& a, const Camera& camera_a, const HostVisibility& b,
                      const Camera& camera_b, const std::vector<float>& flow, const ItemTransforms& items_a,
                      const ItemTransforms& items_b, const FlowTolerance& tol)
{
    auto refuse = [](const std::string& why) { throw Error(Error::Kind::InvalidArgument, "judge_flow: " + why); };
    if (a.width != b.width || a.height != b.height) refuse("views of different sizes");
    if (a.samples != 1 || b.samples != 1) refuse("one sample per pixel is expected");
    const int w = a.width, h = a.height;
    if (flow.size() != std::size_t(w) * std::size_t(h) * 4) refuse("the flow holds " + std::to_string(flow.size()) + " floats, not 4 per pixel");
    for (const ItemTransforms* items : {&items_a, &items_b})
        for (const auto& entry : *items)
            if (entry.first >= scene.meshes().size()) refuse("no item " + std::to_string(entry.first));
    FlowReport report;
    auto error = [&](std::size_t& count, int x, int y, const std::string& what) {
        ++count;
        if (report.first_error.empty())
            report.first_error = "sample (" + std::to_string(x) + ", " + std::to_string(y) + "): " + what;
    };
    const double rel = 1e-4; // CONVENTIONS.md: occluded when B's depth is nearer by more than 1e-4 of P_B's
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            ++report.samples;
            const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
            const float* got = &flow[p * 4];
            const bool got_valid = got[2] == 1.0f, got_occluded = got[3] == 1.0f;
            const bool got_nan = std::isnan(got[0]) && std::isnan(got[1]);
            if ((got[2] != 0.0f && got[2] != 1.0f) || (got[3] != 0.0f && got[3] != 1.0f)) {
                error(report.valid_errors, x, y, "masks are neither 0 nor 1");
                continue;
            }
            const std::uint32_t id = a.ids[p];
            bool sure = false, maybe = false; // valid beyond doubt / possibly valid
            Vec3 raster{0, 0, 0};
            if (id != background_id) {
                if (id >= scene.triangle_count()) refuse("id " + std::to_string(id) + " is not in the scene");
                ++report.foreground;
                Vec3 ca[3], cb[3];
                corners(scene, id, items_a, ca);
                corners(scene, id, items_b, cb);
                double u = 0, v = 0;
                if (plane_barycentrics(camera_a.primary_ray(x + 0.5, y + 0.5, w, h), ca[0], ca[1], ca[2], u, v)) {
                    Vec3 pb = cb[0] * (1 - u - v) + cb[1] * u + cb[2] * v;
                    Vec3 q = camera_b.to_camera(pb);
                    const double depth = -q.z;
                    const double nb = tol.threshold_relative * camera_b.near, fb = tol.threshold_relative * camera_b.far;
                    bool depth_in = depth >= camera_b.near && depth <= camera_b.far;
                    bool depth_edge = near_value(depth, camera_b.near, nb) || near_value(depth, camera_b.far, fb);
                    if (depth > 0 && (depth_in || depth_edge)) {
                        raster = camera_b.camera_to_raster(q, w, h);
                        const double e = tol.flow_px;
                        bool inside = raster.x >= 0 && raster.x < w && raster.y >= 0 && raster.y < h;
                        bool edge = near_value(raster.x, 0, e) || near_value(raster.x, w, e) ||
                                    near_value(raster.y, 0, e) || near_value(raster.y, h, e);
                        sure = depth_in && inside && !depth_edge && !edge;
                        maybe = sure || ((depth_in || depth_edge) && (inside || edge));
                        raster.z = depth;
                    }
                }
            }
            if (maybe && !sure) ++report.ambiguous;
            if (got_valid && !maybe) {
                error(report.valid_errors, x, y, "valid where the referee finds the sample invalid");
                continue;
            }
            if (!got_valid && sure) {
                error(report.valid_errors, x, y, "invalid where the referee finds it valid");
                continue;
            }
            if (!got_valid) {
                if (!got_nan || got_occluded) error(report.flow_errors, x, y, "an invalid sample needs NaN flow and masks 0");
                continue;
            }
            // Valid on both sides: the flow, then occlusion against B's depth at the pixel (or,
            // within flow_px of a pixel's edge, either pixel).
            if (sure) ++report.valid;
            const double fx = raster.x - (x + 0.5), fy = raster.y - (y + 0.5);
            const double ox = std::fabs(got[0] - fx), oy = std::fabs(got[1] - fy);
            const double off = std::max(ox, oy);
            if (!(ox <= tol.flow_px && oy <= tol.flow_px)) { // NaN fails too
                std::ostringstream s;
                s << "flow (" << got[0] << ", " << got[1] << ") where the referee finds (" << fx << ", " << fy << ")";
                error(report.flow_errors, x, y, s.str());
                continue;
            }
            report.max_flow_error = std::max(report.max_flow_error, off);
            const double depth = raster.z, threshold = depth * (1 - rel), band = tol.occluded_band * depth;
            bool can_occlude = false, can_see = false, doubt = false;
            for (double dx : {-tol.flow_px, tol.flow_px})
                for (double dy : {-tol.flow_px, tol.flow_px}) {
                    int ix = std::clamp(int(std::floor(raster.x + dx)), 0, w - 1);
                    int iy = std::clamp(int(std::floor(raster.y + dy)), 0, h - 1);
                    double seen = b.depth_at(ix, iy);
                    if (near_value(seen, threshold, band)) {
                        can_occlude = can_see = doubt = true;
                    } else if (seen < threshold) {
                        can_occlude = true;
                    } else {
                        can_see = true;
                    }
                }
            if (can_occlude && can_see) doubt = true;
            if (doubt && sure) ++report.ambiguous;
            if (can_occlude && !can_see && sure) ++report.occluded;
            if ((got_occluded && !can_occlude) || (!got_occluded && !can_see))
                error(report.occluded_errors, x, y,
                      got_occluded ? "occluded where B sees the point" : "not occluded where B sees nearer");
        }
    return report;
}

} // namespace clvis
