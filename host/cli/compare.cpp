// clvis compare: two id buffers (from either path, or from an outside renderer), optionally their
// depth buffers, the meshes and the camera (and cull option) they were rendered with; the referee
// judges every pixel (or only where they differ) and the exit status says whether any answer is
// wrong: 0 none, 1 some, 2 unusable input.
#include "commands.hpp"
#include "options.hpp"
#include "render_report.hpp"

#include <clvis/clvis.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <tuple>
#include <utility>

namespace clvis::cli {

namespace {

/// Exit statuses of clvis compare (those of every subcommand, commands.hpp).
constexpr int exit_agree = exit_ok;      ///< no unacceptable answer
constexpr int exit_errors = exit_rejected; ///< the referee rejected at least one answer
constexpr int exit_unusable = exit_usage;  ///< bad flags, unreadable files, sizes that do not match

struct CompareArgs {
    std::string first, second;
    SceneInput scene;
    CameraOptions camera;
    std::string depths; ///< "A.exr,B.exr"
    Cull cull = Cull::None;
    bool all = false;
    bool differing_only = false;
    bool json = false;
    std::size_t max_reported = 20;
};

const char* description =
    "Judge two id buffers (and with --depths their depth buffers) with the referee of CONVENTIONS.md, "
    "every pixel of both: counts of equal pixels, of explained mismatches (both answers acceptable) "
    "and of errors, which add up to the pixels (the same for depths), and the first errors one per "
    "line. Give the meshes (or scene file), camera flags and --cull the buffers were rendered with; --width/--height "
    "default to the buffers' size. Exit status 0: no error, 1: errors, 2: unusable input.\n"
    "Example: clvis compare raster.tif ray.tif scenes/spot.obj --eye 0,1,3 --target 0,0,0 --fov 40";

void add_options(CLI::App& app, CompareArgs& a)
{
    app.add_option("first", a.first, "first id buffer (.tif, .tiff, .exr)")->required();
    app.add_option("second", a.second, "second id buffer")->required();
    a.scene.add_to(app);
    a.camera.add_to(app);
    app.add_option("--depths", a.depths, "A.exr,B.exr: the two depth buffers, judged too");
    add_choice(app, "--cull", a.cull, "the face culling the buffers were rendered with: none, back or front");
    app.add_flag("--differing-only", a.differing_only,
                 "judge only the pixels where the buffers differ (the others count as equal unjudged)");
    app.add_flag("--all", a.all, "judge every pixel of both buffers (the default)");
    app.add_flag("--json", a.json, "print one JSON object on standard output");
    app.add_option("--max-errors", a.max_reported, "errors listed at most (default 20)");
}

[[noreturn]] void unusable(const std::string& message)
{
    throw Error(Error::Kind::InvalidArgument, message);
}

/// Reads both buffers, loads the scene and resolves the camera; throws Error on unusable input.
struct Inputs {
    HostVisibility a, b;
    SceneFile file;
    Camera camera;
    bool framed = false;
};

/// An id buffer file, and its depth file when `depth` is not empty, through the image layer.
HostVisibility read_buffer(const std::string& path, const std::string& depth)
{
#if CLVIS_WITH_IMAGE_IO
    HostVisibility v = read_ids(path);
    if (!depth.empty()) read_depth(depth, v);
    return v;
#else
    (void)depth;
    unusable(path + ": this clvis was built without OpenImageIO (CLVIS_WITH_IMAGE_IO=OFF) and reads no id buffers");
#endif
}

/// The two files of --depths A,B (empty when not given).
std::pair<std::string, std::string> depth_files(const std::string& flag)
{
    if (flag.empty()) return {};
    std::size_t comma = flag.find(',');
    if (comma == std::string::npos || comma == 0 || comma + 1 == flag.size() ||
        flag.find(',', comma + 1) != std::string::npos)
        unusable("--depths: expected two files A.exr,B.exr, got '" + flag + "'");
    return {flag.substr(0, comma), flag.substr(comma + 1)};
}

Inputs read_inputs(const CompareArgs& args)
{
    Inputs in;
    auto [depth_a, depth_b] = depth_files(args.depths);
    in.a = read_buffer(args.first, depth_a);
    in.b = read_buffer(args.second, depth_b);
    if (in.a.width != in.b.width || in.a.height != in.b.height)
        unusable("the buffers differ in size: " + args.first + " is " + std::to_string(in.a.width) + "x" +
                 std::to_string(in.a.height) + ", " + args.second + " " + std::to_string(in.b.width) + "x" +
                 std::to_string(in.b.height));
    in.file = args.scene.load();
    View view = resolve_view(args.camera, in.file, args.scene.scene_file(), std::pair{in.a.width, in.a.height});
    in.camera = view.camera;
    in.framed = view.framed;
    return in;
}

nlohmann::json verdict_json(const PixelVerdict& v)
{
    nlohmann::json j = {{"x", v.x},         {"y", v.y},
                        {"id", v.id},       {"error", to_string(v.error)},
                        {"buffer", v.source == 0 ? "first" : v.source == 1 ? "second" : "both"},
                        {"nearest_id", v.nearest_id}, {"describe", v.describe()}};
    if (v.samples > 1) j["sample"] = v.sample;
    if (v.id != background_id && v.error != AnswerError::InvalidId && std::isfinite(v.depth)) j["depth"] = v.depth;
    if (v.nearest_id != background_id) j["nearest_depth"] = v.nearest_depth;
    if (v.error == AnswerError::Coverage) j["edge_distance"] = v.edge_distance;
    if (v.error == AnswerError::HiddenSurface) j["depth_excess"] = v.depth_excess;
    if (v.depth_judged) {
        j["depth_error"] = to_string(v.depth_error);
        j["answer_depth"] = std::isfinite(v.answer_depth) ? nlohmann::json(v.answer_depth) : nlohmann::json(nullptr);
        if (std::isfinite(v.depth_lo) && std::isfinite(v.depth_hi)) j["depth_range"] = {v.depth_lo, v.depth_hi};
    }
    return j;
}

/// One line (or JSON object) per depth layer: each layer's counts.
nlohmann::json layer_json(const CompareReport& r, int layer)
{
    nlohmann::json j = {{"layer", layer}, {"equal", r.equal}, {"explained", r.explained}, {"errors", r.errors}};
    if (r.depths_judged)
        j["depths"] = {{"equal", r.depth_equal}, {"explained", r.depth_explained}, {"errors", r.depth_errors}};
    return j;
}

int run_compare(const CompareArgs& args)
{
    Inputs in;
    CompareReport r;
    std::vector<CompareReport> per_layer; // depth layers: a report per layer, r their sum
    try {
        in = read_inputs(args);
        if (args.all && args.differing_only) unusable("--all and --differing-only exclude each other");
        RenderOptions render;
        render.cull = args.cull;
        Referee referee(in.file.scene, in.camera, in.a.width, in.a.height, render);
        CompareOptions options;
        options.differing_only = args.differing_only;
        options.max_reported = args.max_reported;
        if (in.a.layers > 1 || in.b.layers > 1) {
            per_layer = referee.compare_layers(in.a, in.b, options);
            r = sum_layers(per_layer, args.max_reported);
        } else {
            r = referee.compare(in.a, in.b, options);
        }
    } catch (const Error& e) {
        std::cerr << "clvis: compare: " << e.what() << "\n";
        return exit_unusable;
    }
    if (in.framed && !args.json) std::cerr << "clvis: framing camera: " << in.camera.to_flags() << "\n";

    if (args.json) {
        nlohmann::json j = {{"first", args.first},
                            {"second", args.second},
                            {"width", in.a.width},
                            {"height", in.a.height},
                            {"samples", in.a.samples},
                            {"triangles", in.file.scene.triangle_count()},
                            {"camera", in.camera.to_flags()},
                            {"cull", to_string(args.cull)},
                            {"differing_only", args.differing_only},
                            {"pixels", r.pixels},
                            {"judged", r.judged},
                            {"equal", r.equal},
                            {"explained", r.explained},
                            {"errors", r.errors},
                            {"errors_first", r.errors_a},
                            {"errors_second", r.errors_b},
                            {"first_errors", nlohmann::json::array()}};
        if (r.depths_judged)
            j["depths"] = {{"equal", r.depth_equal},         {"explained", r.depth_explained},
                           {"errors", r.depth_errors},       {"errors_first", r.depth_errors_a},
                           {"errors_second", r.depth_errors_b}};
        for (const PixelVerdict& v : r.first_errors) j["first_errors"].push_back(verdict_json(v));
        if (!per_layer.empty()) {
            j["layers"] = nlohmann::json::array();
            for (std::size_t k = 0; k < per_layer.size(); ++k) j["layers"].push_back(layer_json(per_layer[k], int(k)));
        }
        std::cout << j.dump(2) << "\n";
    } else {
        std::printf("%s vs %s: %zu pixels, %zu judged%s: %zu equal, %zu explained, %zu errors (first %zu, second "
                    "%zu)\n",
                    args.first.c_str(), args.second.c_str(), r.pixels, r.judged,
                    args.differing_only ? " (where they differ)" : "", r.equal, r.explained, r.errors, r.errors_a,
                    r.errors_b);
        if (r.depths_judged)
            std::printf("depths: %zu equal, %zu explained, %zu errors (first %zu, second %zu)\n", r.depth_equal,
                        r.depth_explained, r.depth_errors, r.depth_errors_a, r.depth_errors_b);
        for (const std::string& line : layer_lines(per_layer)) std::printf("%s\n", line.c_str());
        for (const PixelVerdict& v : r.first_errors) std::printf("  %s\n", v.describe().c_str());
        if (r.first_errors.size() == args.max_reported && (r.errors > 0 || r.depth_errors > 0))
            std::printf("  ... (--max-errors N lists more)\n");
    }
    return r.errors > 0 || r.depth_errors > 0 ? exit_errors : exit_agree;
}

/// Parses the subcommand's own arguments (as given, in order) and runs it: CLI11's own exit
/// codes for syntax errors are not compare's 2, so compare parses its flags itself.
int compare_main(const std::vector<std::string>& given)
{
    CLI::App app{description, "clvis compare"};
    CompareArgs args;
    add_options(app, args);
    std::vector<std::string> reversed(given.rbegin(), given.rend()); // CLI11 pops from the back
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError& e) {
        return report_parse_error(app, e); // the help (status 0), or the error naming the flag
    }
    return run_compare(args);
}

} // namespace

void add_compare_command(CLI::App& app)
{
    auto* cmd = app.add_subcommand("compare", description);
    // Everything after "compare" (help included) goes to compare's own parser, which maps every
    // kind of bad input to exit status 2.
    cmd->prefix_command();
    cmd->fallthrough(false);
    cmd->set_help_flag();
    cmd->callback([cmd] {
        int code = compare_main(cmd->remaining());
        if (code != exit_agree) throw CLI::RuntimeError(code); // main returns the code, silently
    });
}

} // namespace clvis::cli
