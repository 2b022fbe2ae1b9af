// What every path shares for a frame: the float32 camera for the kernels, the clear of the
// visibility buffer, and the stage timings from profiling events.
#include "frame/frame.hpp"

#include "runtime/cl_runtime.hpp"
#include "scene/instance_transform.hpp"
#include "scene/scene_probe.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <cmath>

namespace clvis::detail {

void item_world_positions(const Scene& scene, std::size_t item, float* out)
{
    const MeshData& data = scene.data_of(item);
    transform_positions(scene.meshes()[item].transform, data.positions.data(), data.vertex_count(), out);
    for (std::size_t i = 0; i < data.positions.size(); ++i)
        if (!std::isfinite(out[i]))
            throw Error(Error::Kind::InvalidArgument, "mesh '" + data.name + "': a transformed vertex overflows float32");
}

WorldMesh world_mesh(const Scene& scene)
{
    WorldMesh w;
    const auto& items = scene.meshes();
    if (items.size() == 1 && items[0].transform.is_identity()) { // the mesh's own bits: nothing to copy
        w.positions = scene.data_of(0).positions.data();
        w.indices = scene.data_of(0).indices.data();
        return w;
    }
    w.own_positions.resize(scene.vertex_count() * 3);
    if (items.size() != 1) w.own_indices.resize(scene.triangle_count() * 3);
    bool instances = false;
    std::size_t v = 0, t = 0;
    for (std::size_t k = 0; k < items.size(); ++k) {
        const MeshData& data = scene.data_of(k);
        item_world_positions(scene, k, &w.own_positions[v * 3]);
        if (items.size() != 1)
            for (std::uint32_t index : data.indices) w.own_indices[t++] = index + std::uint32_t(v);
        v += data.vertex_count();
        instances |= items[k].prototype != Scene::no_prototype;
    }
    if (instances) expansion_vertices_built += scene.vertex_count(); // as Scene::world_positions() counts it
    w.positions = w.own_positions.data();
    w.indices = items.size() == 1 ? scene.data_of(0).indices.data() : w.own_indices.data();
    return w;
}

clvis_camera_gpu make_gpu_camera(const Camera& camera, int width, int height)
{
    CameraFrame fr = camera.frame();
    Intrinsics k = camera.raster_map(width, height);
    clvis_camera_gpu g{};
    g.eye_x = float(camera.eye.x); g.eye_y = float(camera.eye.y); g.eye_z = float(camera.eye.z);
    g.near_d = float(camera.near);
    g.far_d = float(camera.far);
    g.r_x = float(fr.r.x); g.r_y = float(fr.r.y); g.r_z = float(fr.r.z);
    g.u_x = float(fr.u.x); g.u_y = float(fr.u.y); g.u_z = float(fr.u.z);
    g.f_x = float(fr.f.x); g.f_y = float(fr.f.y); g.f_z = float(fr.f.z);
    g.fx = float(k.fx);
    g.fy = float(k.fy);
    g.cx = float(k.cx);
    g.cy = float(k.cy);
    g.width = width;
    g.height = height;
    g.ortho = camera.projection == Projection::Orthographic ? 1 : 0;
    return g;
}

static_assert(sizeof(clvis_camera_gpu) == 96, "layout shared with kernels/shared/camera.h");

void DeviceScene::set_args(cl::Kernel& kernel, cl_uint first) const
{
    kernel.setArg(first, positions);
    kernel.setArg(first + 1, indices);
    kernel.setArg(first + 2, normals);
    kernel.setArg(first + 3, cl_int(has_normals));
    kernel.setArg(first + 4, cl_uint(triangle_count));
}


void StageRecorder::add(const std::string& stage, const cl::Event& event) { events_.emplace_back(stage, event); }

std::optional<std::vector<StageTiming>> StageRecorder::collect_sum()
{
    std::vector<StageTiming> out;
    for (auto& [name, event] : events_) {
        double ms = 0;
        try {
            ms = double(event.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                        event.getProfilingInfo<CL_PROFILING_COMMAND_START>()) * 1e-6;
        } catch (const cl::Error&) {
            events_.clear(); // a wrapped queue made without profiling: stage times are absent
            return std::nullopt;
        }
        auto it = std::find_if(out.begin(), out.end(), [&](const StageTiming& s) { return s.name == name; });
        if (it == out.end()) out.push_back({name, ms});
        else it->ms += ms;
    }
    events_.clear();
    return out;
}

std::optional<std::vector<StageTiming>> StageRecorder::collect()
{
    // A stage's time is the span of each run of its consecutive events (first start to last end),
    // summed over its runs: a frame drawn in one pass has one run per stage, as it always had,
    // and a frame that draws a stage again (chunks of items, a sample drawn again after its list
    // grew) never counts the other stages between its runs, so the stages sum to at most the frame.
    std::vector<std::string> order;
    std::vector<double> ms;
    std::size_t run_stage = 0;
    cl_ulong run_start = 0, run_end = 0;
    bool in_run = false;
    auto close_run = [&] {
        if (in_run) ms[run_stage] += double(run_end - run_start) * 1e-6;
        in_run = false;
    };
    for (auto& [name, event] : events_) {
        cl_ulong start = 0, end = 0;
        try {
            start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
            end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        } catch (const cl::Error&) {
            // A wrapped queue made without profiling: stage times are absent.
            events_.clear();
            return std::nullopt;
        }
        std::size_t stage = std::size_t(std::find(order.begin(), order.end(), name) - order.begin());
        if (stage == order.size()) {
            order.push_back(name);
            ms.push_back(0.0);
        }
        if (in_run && stage == run_stage) {
            run_start = std::min(run_start, start);
            run_end = std::max(run_end, end);
            continue;
        }
        close_run();
        in_run = true;
        run_stage = stage;
        run_start = start;
        run_end = end;
    }
    close_run();
    events_.clear();
    std::vector<StageTiming> out;
    for (std::size_t i = 0; i < order.size(); ++i) out.push_back({order[i], ms[i]});
    return out;
}

} // namespace clvis::detail
