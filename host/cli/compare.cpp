// clvis compare: two id buffers (from either path, or from an outside renderer), the meshes and
// the camera they were rendered with; the referee judges where they differ (or every pixel) and
// the exit status says whether any answer is wrong: 0 none, 1 some, 2 unusable input.
#include "commands.hpp"
#include "options.hpp"

#include <clvis/clvis.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <tuple>

namespace clvis::cli {

namespace {

/// Exit statuses of clvis compare.
constexpr int exit_agree = 0;    ///< no unacceptable answer
constexpr int exit_errors = 1;   ///< the referee rejected at least one answer
constexpr int exit_unusable = 2; ///< bad flags, unreadable files, sizes that do not match

struct CompareArgs {
    std::string first, second;
    SceneInput scene;
    CameraOptions camera;
    bool all = false;
    bool json = false;
    std::size_t max_reported = 20;
};

const char* description =
    "Judge two id buffers with the referee of CONVENTIONS.md: counts of equal pixels, of explained "
    "mismatches (both answers acceptable) and of errors, and the first errors one per line. Give the "
    "meshes and camera flags the buffers were rendered with; --width/--height default to the "
    "buffers' size. Exit status 0: no error, 1: errors, 2: unusable input.\n"
    "Example: clvis compare raster.tif ray.tif scenes/spot.obj --eye 0,1,3 --target 0,0,0 --fov 40";

void add_options(CLI::App& app, CompareArgs& a)
{
    app.add_option("first", a.first, "first id buffer (.tif, .tiff, .exr)")->required();
    app.add_option("second", a.second, "second id buffer")->required();
    a.scene.add_to(app);
    a.camera.add_to(app);
    app.add_flag("--all", a.all, "judge every pixel of both buffers, not only where they differ");
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

/// An id buffer file, through the image layer.
HostVisibility read_buffer(const std::string& path)
{
#if CLVIS_WITH_IMAGE_IO
    return read_ids(path);
#else
    unusable(path + ": this clvis was built without OpenImageIO (CLVIS_WITH_IMAGE_IO=OFF) and reads no id buffers");
#endif
}

Inputs read_inputs(const CLI::App& app, const CompareArgs& args)
{
    Inputs in;
    in.a = read_buffer(args.first);
    in.b = read_buffer(args.second);
    if (in.a.width != in.b.width || in.a.height != in.b.height)
        unusable("the buffers differ in size: " + args.first + " is " + std::to_string(in.a.width) + "x" +
                 std::to_string(in.a.height) + ", " + args.second + " " + std::to_string(in.b.width) + "x" +
                 std::to_string(in.b.height));
    CameraOptions cam = args.camera;
    for (auto [flag, given, size] : {std::tuple{"--width", cam.width, in.a.width}, {"--height", cam.height, in.a.height}})
        if (app.count(flag) > 0 && given != size)
            unusable(std::string(flag) + ": " + std::to_string(given) + " does not match the buffers (" +
                     std::to_string(in.a.width) + "x" + std::to_string(in.a.height) + ")");
    cam.width = in.a.width;
    cam.height = in.a.height;
    in.file = args.scene.load();
    in.camera = cam.resolve(in.file.scene, in.file.camera);
    in.framed = cam.framed(in.file.camera);
    return in;
}

nlohmann::json verdict_json(const PixelVerdict& v)
{
    nlohmann::json j = {{"x", v.x},         {"y", v.y},
                        {"id", v.id},       {"error", to_string(v.error)},
                        {"buffer", v.source == 0 ? "first" : v.source == 1 ? "second" : "both"},
                        {"nearest_id", v.nearest_id}, {"describe", v.describe()}};
    if (v.id != background_id && v.error != AnswerError::InvalidId && std::isfinite(v.depth)) j["depth"] = v.depth;
    if (v.nearest_id != background_id) j["nearest_depth"] = v.nearest_depth;
    if (v.error == AnswerError::Coverage) j["edge_distance"] = v.edge_distance;
    if (v.error == AnswerError::HiddenSurface) j["depth_excess"] = v.depth_excess;
    return j;
}

int run_compare(const CLI::App& app, const CompareArgs& args)
{
    Inputs in;
    CompareReport r;
    try {
        in = read_inputs(app, args);
        Referee referee(in.file.scene, in.camera, in.a.width, in.a.height);
        CompareOptions options;
        options.all = args.all;
        options.max_reported = args.max_reported;
        r = referee.compare(in.a, in.b, options);
    } catch (const Error& e) {
        std::cerr << "clvis compare: " << e.what() << "\n";
        return exit_unusable;
    }
    if (in.framed && !args.json) std::cerr << "clvis: framing camera: " << in.camera.to_flags() << "\n";

    if (args.json) {
        nlohmann::json j = {{"first", args.first},
                            {"second", args.second},
                            {"width", in.a.width},
                            {"height", in.a.height},
                            {"triangles", in.file.scene.triangle_count()},
                            {"camera", in.camera.to_flags()},
                            {"all", args.all},
                            {"pixels", r.pixels},
                            {"equal", r.equal},
                            {"explained", r.explained},
                            {"errors", r.errors},
                            {"errors_first", r.errors_a},
                            {"errors_second", r.errors_b},
                            {"first_errors", nlohmann::json::array()}};
        for (const PixelVerdict& v : r.first_errors) j["first_errors"].push_back(verdict_json(v));
        std::cout << j.dump(2) << "\n";
    } else {
        std::printf("%s vs %s: %zu pixels%s, %zu equal, %zu explained, %zu errors (first %zu, second %zu)\n",
                    args.first.c_str(), args.second.c_str(), r.pixels,
                    args.all ? " (all judged)" : " (judged where they differ)", r.equal, r.explained, r.errors,
                    r.errors_a, r.errors_b);
        for (const PixelVerdict& v : r.first_errors) std::printf("  %s\n", v.describe().c_str());
        if (r.first_errors.size() < r.errors_a + r.errors_b)
            std::printf("  ... (%zu more; --max-errors N lists more)\n",
                        r.errors_a + r.errors_b - r.first_errors.size());
    }
    return r.errors > 0 ? exit_errors : exit_agree;
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
        int code = app.exit(e); // prints help (status 0) or the error naming the flag
        return code == 0 ? exit_agree : exit_unusable;
    }
    return run_compare(app, args);
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
