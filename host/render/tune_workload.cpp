// The mapping tuners' workload (tune_workload.hpp).
#include "render/tune_workload.hpp"

#include "runtime/cl_runtime.hpp"
#include "runtime/embedded_kernels.hpp"
#include "runtime/tune_cache.hpp"

#include <clvis/error.hpp>
#include <clvis/procedural.hpp>
#include <clvis/renderer.hpp>
#include <clvis/version.hpp>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <mutex>

namespace clvis::detail {

namespace {

/// The tuning frame: large enough that the measured stage dominates (raster: triangles of tens of
/// pixels, binned rather than drawn at setup, two layers deep), short enough to cost well under a
/// second on a CPU device. Changing a workload changes its name.
struct TuneWorkload {
    const char* name;         ///< tune_workload_name()
    int width, height;        ///< the frame, pixels
    std::size_t sphere, grid; ///< triangles of the UV sphere and of the height field
};
/// CLVIS_TUNE_WORKLOAD=full (the default) or small: a sixteenth of the pixels and a twentieth of
/// the triangles, the same scene, camera and timing rule, for a simulator (Oclgrind ran the full
/// workload's candidates in about 19 minutes) or a test.
const TuneWorkload tune_workloads[] = {
    {"sphere6000+grid6000@640x480 min(3 frames, 500 ms) frame_ms v3", 640, 480, 6000, 6000},
    {"sphere300+grid300@160x120 min(3 frames, 500 ms) frame_ms v3", 160, 120, 300, 300},
};
const char* const tune_workload_variable = "CLVIS_TUNE_WORKLOAD";
constexpr int tune_frames = 3; ///< timed frames per candidate at most, after one untimed
/// Timed frames stop once they took this long (ms) in all, after the first: a slow mapping on a
/// slow device (the pixel mapping on llvmpipe, 2 s a frame) is not timed three times.
constexpr double tune_budget_ms = 500;

/// The workload CLVIS_TUNE_WORKLOAD names (read at each use); an Error (InvalidArgument) naming
/// the variable for any other value.
const TuneWorkload& tune_workload()
{
    const char* v = std::getenv(tune_workload_variable);
    if (!v || !*v || std::string(v) == "full") return tune_workloads[0];
    if (std::string(v) == "small") return tune_workloads[1];
    throw Error(Error::Kind::InvalidArgument,
                std::string(tune_workload_variable) + " must name one of full, small, got '" + v + "'");
}

Scene make_tuning_scene(const TuneWorkload& w)
{
    Scene s;
    s.add_mesh(make_grid(w.grid, 21));
    s.add_mesh(make_uv_sphere(w.sphere));
    return s;
}

/// The workload's scene, made once in the process when first asked for.
const Scene& tuning_scene(const TuneWorkload& w)
{
    if (&w == &tune_workloads[0]) {
        static const Scene full = make_tuning_scene(w);
        return full;
    }
    static const Scene small = make_tuning_scene(w);
    return small;
}

} // namespace

const char* tune_workload_name() { return tune_workload().name; }

TuneKey tune_device_key(const Device& device, std::initializer_list<const char*> names)
{
    // The hash of the kernels' sources (about 100 KB, hashed a byte at a time) is taken once per
    // build options and names in a process: every Renderer that prepares a tuned path asks.
    std::string options = DeviceAccess::of(device, "tune_device_key").build_options(""), which = options;
    for (const char* name : names) which += std::string("\n") + name;
    static std::mutex mutex;
    static std::map<std::string, std::string> hashes;
    std::lock_guard<std::mutex> lock(mutex);
    auto hash = hashes.find(which);
    if (hash == hashes.end()) {
        std::string text = version() + "\n" + options;
        for (const char* name : names) text += embedded_kernel(name);
        hash = hashes.emplace(which, stable_hash(text)).first;
    }
    const DeviceInfo& info = device.info();
    return {{"device", info.name}, {"platform", info.platform}, {"driver", info.driver_version}, {"kernels", hash->second}};
}

double measure_tune_frames(const Device& device, const RenderOptions& options, Path path)
{
    const TuneWorkload& w = tune_workload();
    Renderer renderer(device, tuning_scene(w), options);
    Camera camera = Camera::perspective({0.3, 1.4, 2.6}, {0, 0, 0}, {0, 1, 0}, 50, 0.1, 20);
    VisibilityBuffer target(device, w.width, w.height);
    renderer.render(camera, path, target); // untimed: the driver's first launch
    double best = -1, spent = 0;
    for (int frame = 0; frame < tune_frames && spent < tune_budget_ms; ++frame) {
        renderer.render(camera, path, target);
        double ms = renderer.last_frame().frame_ms;
        best = best < 0 ? ms : std::min(best, ms);
        spent += ms;
    }
    return best;
}

TunedMapping tune_mapping(const TuneRequest& request)
{
    TuneResult result = tune(request, TuneSettings::from_environment(request));
    TunedMapping m{result.choice, to_string(result.source)};
    for (const TuneTime& t : result.times)
        for (std::size_t i = 0; i < 2 && i < request.candidates.size(); ++i)
            if (t.candidate == request.candidates[i]) m.ms[i] = t.ms;
    return m;
}

} // namespace clvis::detail
