// clvis render: meshes in, a camera, one or both paths, buffers and images out, with the timings
// of CONVENTIONS.md's --json. With --path all both paths run and the referee compares them.
#include "commands.hpp"
#include "options.hpp"
#include "output_plan.hpp"
#include "render_ao.hpp"
#include "render_flow.hpp"
#include "render_corners.hpp"
#include "render_report.hpp"
#include "render_spread.hpp"

#include "bench_stats.hpp"

#include <clvis/clvis.hpp>
#include <clvis/views_file.hpp>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <iostream>
#include <tuple>

namespace clvis::cli {

namespace {

struct RenderArgs {
    SceneInput scene;
    CameraOptions camera;
    DeviceOptions device;
    std::string path = "raster"; ///< raster, ray, brute or all
    RenderOptions options;       ///< --tile, --cull, --samples, the mappings, --leaf-size, --coverage
    std::string ids, depth, image;
    ShadeMode shade = ShadeMode::Lambert;
    std::string bary, normals, position; ///< attributes resolved from the buffer (EXR)
    std::string visible;                 ///< the visible set: ids, one per line, ascending
    std::string views;                   ///< a views file: many cameras, one batch
    std::string flow;                    ///< --flow: the flow from each view to the next
    std::vector<ItemTransforms> items;   ///< the views file's item transforms, per view
    Scene* moving = nullptr;             ///< the loaded scene (moved between views with items)
    int ao = 0; ///< rays per pixel of the ambient-occlusion image; 0: a shaded image
    int repeat = 0;
    bool json = false, quiet = false;
    bool timings = false; ///< --timings: what the first frame costs, phase by phase
    int width = 0, height = 0; ///< the image size, once resolved
    SpreadArgs spread; ///< --devices, --distribute: several devices or MPI ranks
    CornerOutputs corners; ///< --attributes, --objects, --normals-space
};

#if !CLVIS_WITH_IMAGE_IO
[[noreturn]] void no_image_io(const std::string& flag)
{
    throw Error(Error::Kind::InvalidArgument, flag + ": this clvis was built without OpenImageIO (CLVIS_WITH_IMAGE_IO=OFF)");
}
#endif

/// Each output flag of render, its file ("" when not given) and its kind.
std::vector<std::tuple<std::string, std::string, OutputKind>> output_flags(const RenderArgs& a)
{
    return {{"--ids", a.ids, OutputKind::Ids},           {"--depth", a.depth, OutputKind::Depth},
            {"--image", a.image, OutputKind::Image},     {"--bary", a.bary, OutputKind::Floats},
            {"--normals", a.normals, OutputKind::Floats}, {"--position", a.position, OutputKind::Floats},
            {"--visible", a.visible, OutputKind::Text},  {"--attributes", a.corners.attributes, OutputKind::Floats},
            {"--objects", a.corners.objects, OutputKind::Ids}};
}

/// The file a flag's name gives for one path (suffixed when several paths write) and one view.
std::string output_name(const std::string& file, Path path, bool several, int view, int last)
{
    return view_file_name(several ? with_suffix(file, to_string(path)) : file, view, last);
}

/// Names every file of the run in `plan` (each checked there): every flag's file for each of
/// `paths` and each of `views` views, plus the --device-map of --devices.
void plan_outputs(OutputPlan& plan, const RenderArgs& a, const std::vector<Path>& paths, int views)
{
    const auto flags = output_flags(a);
    for (const auto& [flag, file, kind] : flags)
        OutputPlan::need_view_key(flag, file, views, "--views FILE holds " + std::to_string(views) + " views");
    for (Path p : paths)
        for (int v = 0; v < views; ++v)
            for (const auto& [flag, file, kind] : flags)
                if (!file.empty()) plan.add(flag, output_name(file, p, paths.size() > 1, v, views - 1), kind);
    if (!a.spread.device_map.empty()) plan.add("--device-map", a.spread.device_map, OutputKind::Image);
}

/// --bary, --normals, --position: resolved on the device only when asked, then written as EXR.
/// With depth layers each layer is taken out (VisibilityBuffer::layer) and resolved on its own,
/// every file holding each layer's channels as L{k}.<channel> (layer_channels).
void write_attributes(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera, const RenderArgs& a,
                      const std::function<std::string(const std::string&)>& file_name)
{
    AttributeRequest request;
    request.barycentrics = !a.bary.empty();
    request.smooth_normal = !a.normals.empty();
    request.position = !a.position.empty();
    a.corners.request(request);
    if (!request.any()) return;
#if CLVIS_WITH_IMAGE_IO
    std::vector<AttributeBuffers> layers;
    for (int k = 0; k < vis.layers(); ++k)
        layers.push_back(resolve(renderer, vis.layers() == 1 ? vis : vis.layer(k), camera, request));
    std::vector<std::vector<float>> pixels(layers.size());
    const struct {
        const std::string& file;
        Attribute attribute;
        std::vector<std::string> channels;
    } outputs[] = {{a.bary, Attribute::Barycentrics, {"u", "v"}},
                   {a.normals, Attribute::SmoothNormal, {"x", "y", "z"}},
                   {a.position, Attribute::Position, {"x", "y", "z"}}};
    for (const auto& o : outputs) {
        if (o.file.empty()) continue;
        for (std::size_t k = 0; k < layers.size(); ++k) layers[k].read(o.attribute, pixels[k]);
        write_float_channels(file_name(o.file), vis.width(), vis.height(), layer_channels(o.channels, vis.layers()),
                             interleave_layers(pixels, o.channels.size()));
    }
    a.corners.write(layers, vis.width(), vis.height(), file_name);
#else
    (void)renderer, (void)vis, (void)camera, (void)file_name;
    a.corners.write({}, 0, 0, file_name);
    no_image_io(!a.bary.empty() ? "--bary" : !a.normals.empty() ? "--normals" : "--position");
#endif
}

/// --visible: the visible set, compacted on the device, one id per line in ascending order.
void write_visible(Renderer& renderer, const VisibilityBuffer& vis, const std::string& file, std::uint32_t triangles)
{
    if (file.empty()) return;
    VisibleSet set(renderer.device(), triangles);
    set.mark(vis);
    std::vector<std::uint32_t> ids = set.read_ids();
    std::FILE* f = std::fopen(file.c_str(), "w");
    if (!f) throw Error(Error::Kind::Io, file + ": cannot open for writing");
    for (std::uint32_t id : ids) std::fprintf(f, "%u\n", id);
    if (std::fclose(f) != 0) throw Error(Error::Kind::Io, file + ": write failed");
}

using NameFn = std::function<std::string(const std::string&)>;

/// Every file one visibility buffer gives: ids, depth, image, attributes and the visible set,
/// each written under the temporary name `name_of` gives for the flag's file. `host` receives
/// the buffer read back when ids or depth are written (or when `need_host`).
void write_outputs(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera, const RenderArgs& a,
                   const NameFn& name_of, std::uint32_t triangles, HostVisibility& host, bool need_host)
{
    if (need_host || !a.ids.empty() || !a.depth.empty()) vis.read(host);
    write_attributes(renderer, vis, camera, a, name_of);
    write_visible(renderer, vis, a.visible.empty() ? a.visible : name_of(a.visible), triangles);
#if CLVIS_WITH_IMAGE_IO
    if (!a.ids.empty()) write_ids(name_of(a.ids), host);
    if (!a.depth.empty()) write_depth(name_of(a.depth), host);
    if (!a.image.empty()) {
        ShadeOptions so;
        so.mode = a.shade;
        write_image(name_of(a.image),
                    a.ao > 0 ? ao_image(renderer, vis, camera, a.ao, a.quiet) : shade(renderer, vis, camera, so));
    }
#else
    if (!a.ids.empty()) no_image_io("--ids");
    if (!a.depth.empty()) no_image_io("--depth");
    if (!a.image.empty()) no_image_io("--image");
#endif
}

/// Renders one camera (or, with `views`, every view as one batch) `repeat` times after a warm-up.
PathResult run_path(Renderer& renderer, const std::vector<Camera>& cameras, const RenderArgs& a, int width,
                    int height, Path path, bool several, bool need_host, std::uint32_t triangles,
                    const OutputPlan& plan)
{
    PathResult r;
    r.path = path;
    auto t_prepare = std::chrono::steady_clock::now();
    renderer.prepare(path);
    r.prepare_ms = bench::ms_since(t_prepare);
    if (path == Path::Ray) {
        r.bvh = renderer.bvh_stats();
        r.build_ms = r.bvh.build_ms;
    }
    bool batch = !a.views.empty();
    VisibilityBatch views;
    VisibilityBuffer vis;
    if (batch) views = VisibilityBatch(renderer.device(), int(cameras.size()), width, height);
    else vis = VisibilityBuffer(renderer.device(), width, height, a.options.samples, a.options.layers);
    auto frame = [&] {
        if (batch) render_views(renderer, *a.moving, cameras, a.items, path, views);
        else renderer.render(cameras[0], path, vis);
    };
    if (a.repeat > 0 || a.timings) { // warm-up: first launches compile
        auto t_first = std::chrono::steady_clock::now();
        frame(); // render() returns once the queue has finished
        r.first_frame_ms = bench::ms_since(t_first);
    }
    double best = 1e300;
    for (int i = 0; i < std::max(a.repeat, 1); ++i) {
        frame();
        const FrameTiming& t = renderer.last_frame();
        r.samples.push_back(t.frame_ms);
        if (t.frame_ms < best) {
            best = t.frame_ms;
            r.fastest = t;
        }
    }
    if (!batch) {
        write_outputs(renderer, vis, cameras[0], a,
                      [&](const std::string& f) { return plan.temporary(output_name(f, path, several, 0, 0)); },
                      triangles, r.vis, need_host);
        return r;
    }
    HostVisibility host;
    int last = views.views() - 1;
    for (int v = 0; v <= last; ++v)
        write_outputs(renderer, views.view(v), cameras[std::size_t(v)], a,
                      [&](const std::string& f) { return plan.temporary(output_name(f, path, several, v, last)); },
                      triangles, host, false);
    write_flow(renderer, views, cameras, a.items, a.flow,
               [&](const std::string& f) { return plan.temporary(f); });
    return r;
}

/// Refuses, before any file is read, what the flags cannot do together (Error(InvalidArgument)
/// naming the flag), and returns the paths that run.
/// The spread modes' request with what the flags say; the caller adds the scene and cameras.
SpreadRequest spread_request(const RenderArgs& a)
{
    SpreadRequest request;
    request.spread = a.spread;
    request.path = a.path;
    request.views = a.views;
    request.image = a.image;
    request.device_spec = a.device.spec;
    return request;
}

std::vector<Path> check_flags(const RenderArgs& a)
{
    auto refuse = [](const std::string& why) { throw Error(Error::Kind::InvalidArgument, why); };
    const int ranks = mpi_world_size_from_environment();
#if CLVIS_WITH_MPI
    const std::string options = "give --distribute frames, screen or scene, or run one process";
#else
    const std::string options = "this clvis was built without MPI (no --distribute): run one process";
#endif
    if (ranks > 1 && a.spread.distribute.empty())
        refuse("--distribute: clvis render runs as " + std::to_string(ranks) +
               " MPI processes (mpirun) without it, which would all write the same files; " + options);
    if (a.ao > 0 && a.image.empty()) refuse("--ao: needs --image FILE to write");
    if (a.options.samples != 1 && (a.ao > 0 || a.spread.any() || !a.views.empty()))
        refuse("--samples: --ao, --views, --devices, --distribute draw 1 per pixel");
    if (a.options.samples != 1)
        for (const auto& [flag, file, kind] : output_flags(a))
            if (!file.empty() && kind == OutputKind::Floats)
                refuse(flag + ": attributes are resolved at one sample per pixel; --samples " +
                       std::to_string(a.options.samples) + " is for --ids, --depth, --image and --visible");
    a.corners.check(a.options.samples, a.spread.any());
    if (a.options.layers != 1) { // depth layers: the buffers of one camera on one device
        std::string k = "--layers " + std::to_string(a.options.layers);
        if (a.options.samples != 1) refuse(k + ": depth layers take one sample per pixel (--samples 1)");
        if (!a.views.empty() || (!a.spread.distribute.empty() && a.spread.distribute != "scene"))
            refuse(k + ": --views and --distribute frames|screen draw one layer; render one camera (on one or more "
                       "--devices, or --distribute scene)");
        if (a.ao > 0) refuse(k + ": --ao shades one layer; render the image without --layers");
        if (!a.visible.empty())
            refuse("--visible: lists the triangles seen, the nearest of each pixel; with " + k +
                   " the --ids file holds every layer's ids (channels L0.id ..)");
    }
    if (a.path == "all" && !a.views.empty()) refuse("--views: renders one path (--path raster, ray or brute), not all");
    if (a.spread.any() && !a.flow.empty()) refuse("--flow: for one device in one process");
    if (a.spread.any()) {
        for (const auto& [flag, file, kind] : output_flags(a))
            if (!file.empty() && kind != OutputKind::Ids && kind != OutputKind::Depth && flag != "--image")
                refuse(flag + ": for one device in one process; --devices and --distribute write --ids and --depth");
        return {check_spread(spread_request(a))};
    }
    if (a.path == "all") return {Path::Raster, Path::Ray};
    return {path_from_string(a.path)};
}

void render_command(RenderArgs a)
{
    return_large_blocks();
    std::vector<Path> paths = check_flags(a);
    std::vector<Camera> cameras;
    ViewsFile vf;
    if (!a.views.empty()) {
        vf = load_views_file(a.views, a.camera.width, a.camera.height); // sizes for glTF, NeRF without w, h
        cameras = vf.views;
    }
    // --distribute: every rank checks every name here; render_dist.cpp plans its own views' files.
    OutputPlan plan;
    plan_outputs(plan, a, paths, std::max(int(cameras.size()), 1));
    plan_flow(plan, a.flow, int(cameras.size()), !a.views.empty());
    double load_ms = 0;
    SceneFile file = a.scene.load(&load_ms);
    View view = resolve_view(a.camera, file, a.scene.scene_file());
    if (!a.views.empty()) {
        view.width = vf.width;
        view.height = vf.height;
    }
    a.width = view.width;
    a.height = view.height;
    const Camera camera = cameras.empty() ? view.camera : cameras[0];
    if (cameras.empty()) cameras.push_back(camera);
    if (file.scene.empty()) throw Error(Error::Kind::InvalidArgument, "the scene holds no triangles");
    check_view_items(vf, file.scene); // a views file's "items": each names an item of the scene
    if (vf.moves() && a.spread.any())
        throw Error(Error::Kind::InvalidArgument, a.views + ": views that move items render on one device in one process");
    a.items = vf.items;
    a.moving = &file.scene;
    a.corners.loaded(file.scene);
    if (a.spread.any()) {
        SpreadRequest request = spread_request(a);
        request.file = &file;
        request.load_ms = load_ms;
        request.cameras = cameras;
        request.width = a.width;
        request.height = a.height;
        request.options = a.options;
        request.ids = a.ids;
        request.depth = a.depth;
        request.repeat = a.repeat;
        request.json = a.json;
        request.quiet = a.quiet;
        request.plan = &plan;
        return render_spread(request);
    }
    bool several = paths.size() > 1;

    auto t_open = std::chrono::steady_clock::now();
    Device device = a.device.open();
    const double open_ms = bench::ms_since(t_open);
    auto say = [&](const std::string& line) {
        if (!a.quiet) std::cerr << line << "\n";
    };
    say("clvis: " + std::to_string(file.scene.triangle_count()) + " triangles from " +
        std::to_string(a.scene.files.size()) + " file(s) in " + std::to_string(int(load_ms + 0.5)) + " ms; device " +
        device.info().name);
    if (a.views.empty() && view.framed) say("clvis: framing camera: " + camera.to_flags());
    // One path needs nothing more of our scene (only --path all's referee does, and views that
    // move items): the Renderer takes it over, so the mesh is held once, never copied (issue 37).
    const std::size_t triangle_count = file.scene.triangle_count();
    const bool keep_scene = several || vf.moves();
    auto t_renderer = std::chrono::steady_clock::now();
    Renderer renderer = keep_scene ? Renderer(device, file.scene, a.options)
                                   : Renderer(device, std::move(file.scene), a.options);
    const double renderer_ms = bench::ms_since(t_renderer);

    std::vector<PathResult> results;
    for (Path p : paths) {
        results.push_back(run_path(renderer, cameras, a, a.width, a.height, p, several, several,
                                   std::uint32_t(triangle_count), plan));
        say(path_line(results.back()));
    }
    if (a.timings) say(first_frame_line(open_ms, renderer_ms, results));
    CompareReport verdict;
    if (several) {
        Referee referee(file.scene, camera, a.width, a.height, a.options);
        if (a.options.layers > 1) { // depth layers: each judged against its own earlier layers
            std::vector<CompareReport> per_layer = referee.compare_layers(results[0].vis, results[1].vis);
            verdict = sum_layers(per_layer, CompareOptions{}.max_reported);
            for (const std::string& line : compare_lines(verdict)) say(line);
            for (const std::string& line : layer_lines(per_layer)) say("clvis: " + line);
        } else {
            verdict = referee.compare(results[0].vis, results[1].vis);
            for (const std::string& line : compare_lines(verdict)) say(line);
        }
    }
    for (const std::string& f : plan.commit()) say("clvis: wrote " + f);
    if (a.json) {
        RenderJson run;
        run.triangles = triangle_count;
        run.width = a.width;
        run.height = a.height;
        run.options = a.options;
        run.load_ms = load_ms;
        run.warm_up = a.repeat > 0 || a.timings;
        run.camera = camera.to_flags();
        run.compare = several ? &verdict : nullptr;
        if (a.timings) {
            run.open_ms = open_ms;
            run.renderer_ms = renderer_ms;
        }
        std::cout << render_json(run, renderer, results).dump(2) << "\n";
    }
    if (several && (verdict.errors > 0 || verdict.depth_errors > 0)) {
        std::cerr << "clvis: the referee rejected ids or depths of a path (see above)\n";
        throw CLI::RuntimeError(exit_rejected); // main returns the status
    }
}

/// A CLI11 check by one of the library's own (`check` throws Error naming the value), so that a
/// bad value is refused while the flags are parsed, naming the flag, before any file is read.
CLI::Validator library_check(std::function<void(int)> check, const std::string& what)
{
    return CLI::Validator(
        [check](std::string& text) {
            int value = 0;
            try {
                std::size_t used = 0;
                value = std::stoi(text, &used);
                if (used != text.size()) return std::string(); // not a number: CLI11's conversion says so
            } catch (const std::exception&) {
                return std::string();
            }
            try {
                check(value);
            } catch (const Error& e) {
                return std::string(e.what());
            }
            return std::string();
        },
        what);
}

} // namespace

void add_render_command(CLI::App& app)
{
    auto args = std::make_shared<RenderArgs>();
    auto* cmd = app.add_subcommand(
        "render", "Render meshes by rasterization, by ray casting, or both, and write the visibility buffers.\n"
                  "Example: clvis render scenes/stanford-bunny.obj --path all --image bunny.png --ids ids.tif");
    args->scene.add_to(*cmd);
    args->camera.add_to(*cmd);
    args->device.add_to(*cmd);
    std::vector<std::string> paths = option_names<Path>();
    paths.push_back("all");
    cmd->add_option("--path", args->path, "raster, ray, brute, or all (raster and ray, compared by the referee)")
        ->check(CLI::IsMember(paths));
    cmd->add_option("--ids", args->ids, "write the id buffer (.tif, .tiff, .exr; uint32, background 0xFFFFFFFF)");
    cmd->add_option("--depth", args->depth, "write the view-depth buffer (.exr; float, background +inf)");
    cmd->add_option("--bary", args->bary, "write barycentrics u, v of the visible triangles (.exr; background 0, 0)");
    cmd->add_option("--normals", args->normals,
                    "write unit normals x, y, z (.exr; smooth where the mesh has normals; background NaN)");
    cmd->add_option("--position", args->position, "write world positions x, y, z (.exr; background NaN)");
    args->corners.add_to(*cmd);
    cmd->add_option("--views", args->views,
                    "render every camera of a views file in one batch: clvis's JSON, NeRF's transforms.json, a COLMAP "
                    "text model's folder, or a glTF file's camera nodes (--width, --height where the file gives no "
                    "size); {view} in output names is the view");
    cmd->add_option("--flow", args->flow,
                    "with --views: write the flow from each view to the next (.exr: flow.x, flow.y, flow.valid, "
                    "flow.occluded); the name must contain {view}, the first view of each pair");
    cmd->add_option("--visible", args->visible, "write the visible triangle ids, one per line, ascending");
    cmd->add_option("--image", args->image, "write a shaded colour image (.png, .exr, .tif, .jpg, ...)");
    add_choice(*cmd, "--shade", args->shade, "colour image: lambert, depth or ids");
    cmd->add_option("--ao", args->ao, "with --image: an ambient-occlusion image of N rays per pixel (seeded)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("--repeat", args->repeat, "render N timed frames after one untimed warm-up")
        ->check(CLI::Range(0, 1000000));
    cmd->add_option("--samples", args->options.samples,
                    "samples per pixel: 1, 2, 4, 8 or 16 at the standard positions (CONVENTIONS.md); the id and "
                    "depth files get channels id0.. and Z0.., the image is their mean")
        ->check(library_check([](int n) { samples_log2(n); }, "1, 2, 4, 8 or 16"));
    cmd->add_option("--layers", args->options.layers,
                    "depth layers: the K nearest triangles of every pixel (1 to 8; CONVENTIONS.md 'Depth layers'); "
                    "the id and depth files get channels L0.id .. and L0.Z .. (TIFF: ids in layer order), --bary, "
                    "--normals, --position, --attributes and --objects every layer's as L0.<channel> ..")
        ->check(library_check([](int n) { check_layers(n); }, "1 to 8"));
    RenderOptions& o = args->options;
    cmd->add_option("--tile", o.tile_size, "raster tile size in pixels (power of two; 0: default)")
        ->check(library_check(
            [](int n) {
                if (n != 0 && (n < 4 || n > 256 || (n & (n - 1))))
                    throw Error(Error::Kind::InvalidArgument, "must be a power of two in [4, 256] (or 0 for the "
                                                              "default), got " + std::to_string(n));
            },
            "a power of two in [4, 256], or 0"));
    add_choice(*cmd, "--cull", o.cull, "face culling: none, back or front");
    add_choice(*cmd, "--raster-atomics", o.raster_atomics,
               "raster depth test: on (64-bit atomics), off (tile ownership, no atomics) or auto (on where "
               "the device has 64-bit atomics, but off for frames of few triangles on PoCL's CPU device); the same keys either way");
    add_choice(*cmd, "--raster-mapping", o.raster_mapping,
               "raster fine stage: square (CPUs), pixel (GPUs) or auto (measured per device, cached); same keys");
    add_choice(*cmd, "--ray-mapping", o.ray_mapping,
               "ray path: packet (a work-item per 4x4 rays, CPUs), single (a work-item per ray, GPUs) or auto "
               "(measured per device, cached); same keys");
    cmd->add_option("--leaf-size", o.bvh.max_leaf_size, "BVH: triangles per leaf at most")->check(CLI::Range(1, 64));
    args->spread.add_to(*cmd);
    add_choice(*cmd, "--coverage", o.coverage,
               "ray and brute paths: watertight (the ray test, default) or raster-rule (the raster path's "
               "predicate: buffers bit-identical to raster's)");
    cmd->add_flag("--json", args->json, "print one JSON object with the timings on standard output");
    cmd->add_flag("--timings", args->timings,
                  "what a one-off render pays before its first frame: device open, renderer (upload), prepare "
                  "(program build; BVH for ray) and the first frame against the next (with --json: first_frame)");
    cmd->add_flag("--quiet,-q", args->quiet, "say nothing on standard error");
    add_verbose_flag(*cmd);
    cmd->callback([args] { render_command(*args); });
}

} // namespace clvis::cli
