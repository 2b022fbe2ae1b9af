// What `clvis render` says of its frames (render_report.hpp): the lines on standard error and the
// --json object, with the raster and ray mappings that ran (RasterMapping::Auto and
// RayMapping::Auto resolved).
#include "render_report.hpp"

#include "bench_stats.hpp"

#include <algorithm>
#include <cstdio>

namespace clvis::cli {

std::string path_line(const PathResult& r)
{
    std::string line = std::string("clvis: ") + to_string(r.path) + ": ";
    char buf[128];
    if (r.first_frame_ms >= 0)
        std::snprintf(buf, sizeof buf, "frame %.2f ms min, %.2f ms median of %zu after a warm-up",
                      *std::min_element(r.samples.begin(), r.samples.end()), bench::median_of(r.samples), r.samples.size());
    else
        std::snprintf(buf, sizeof buf, "frame %.2f ms (first frame: includes the driver's first-launch "
                                       "compilation; --repeat N times warm frames)", r.samples[0]);
    line += buf;
    if (!r.fastest.stages_measured) line += "; stage times absent (queue without profiling)";
    for (const auto& st : r.fastest.stages) {
        std::snprintf(buf, sizeof buf, "; %s %.2f", st.name.c_str(), st.ms);
        line += buf;
    }
    if (r.path == Path::Ray) {
        std::snprintf(buf, sizeof buf, "; BVH %zu nodes built in %.1f ms", r.bvh.nodes, r.build_ms);
        line += buf;
    }
    return line;
}

std::string first_frame_line(double open_ms, double renderer_ms, const std::vector<PathResult>& results)
{
    char buf[200];
    std::snprintf(buf, sizeof buf, "clvis: first frame: device open %.1f ms, renderer (upload) %.1f ms", open_ms,
                  renderer_ms);
    std::string line = buf;
    for (const auto& r : results) {
        std::snprintf(buf, sizeof buf, "; %s: prepare (programs%s) %.1f ms, first frame %.1f ms, next %.2f ms",
                      to_string(r.path), r.path == Path::Ray ? ", BVH" : "", r.prepare_ms, r.first_frame_ms,
                      bench::median_of(r.samples));
        line += buf;
    }
    return line;
}

std::vector<std::string> compare_lines(const CompareReport& rep)
{
    char buf[320];
    std::snprintf(buf, sizeof buf, "clvis: raster vs ray: %zu pixels, %zu equal, %zu explained, %zu errors "
                                   "(raster %zu, ray %zu); depths %zu equal, %zu explained, %zu errors "
                                   "(raster %zu, ray %zu)",
                  rep.pixels, rep.equal, rep.explained, rep.errors, rep.errors_a, rep.errors_b, rep.depth_equal,
                  rep.depth_explained, rep.depth_errors, rep.depth_errors_a, rep.depth_errors_b);
    std::vector<std::string> lines{buf};
    for (const auto& e : rep.first_errors) lines.push_back("  " + e.describe());
    return lines;
}

/// Depth layers: every layer's report summed into one (first errors in layer order, up to `max`).
CompareReport sum_layers(const std::vector<CompareReport>& layers, std::size_t max)
{
    CompareReport t;
    for (const CompareReport& r : layers) {
        t.pixels += r.pixels;
        t.judged += r.judged;
        t.equal += r.equal;
        t.explained += r.explained;
        t.errors += r.errors;
        t.errors_a += r.errors_a;
        t.errors_b += r.errors_b;
        t.depths_judged = r.depths_judged;
        t.depth_equal += r.depth_equal;
        t.depth_explained += r.depth_explained;
        t.depth_errors += r.depth_errors;
        t.depth_errors_a += r.depth_errors_a;
        t.depth_errors_b += r.depth_errors_b;
        for (const PixelVerdict& v : r.first_errors)
            if (t.first_errors.size() < max) t.first_errors.push_back(v);
    }
    return t;
}

std::vector<std::string> layer_lines(const std::vector<CompareReport>& layers)
{
    std::vector<std::string> lines;
    char buf[256];
    for (std::size_t k = 0; k < layers.size(); ++k) {
        const CompareReport& l = layers[k];
        std::snprintf(buf, sizeof buf, "layer %zu: %zu equal, %zu explained, %zu errors", k, l.equal, l.explained,
                      l.errors);
        std::string line = buf;
        if (l.depths_judged) {
            std::snprintf(buf, sizeof buf, "; depths: %zu equal, %zu explained, %zu errors", l.depth_equal,
                          l.depth_explained, l.depth_errors);
            line += buf;
        }
        lines.push_back(line);
    }
    return lines;
}

namespace {

nlohmann::json stages_json(const FrameTiming& t)
{
    if (!t.stages_measured) return nullptr;
    nlohmann::json s = nlohmann::json::object();
    for (const auto& st : t.stages) s[st.name] = st.ms;
    return s;
}

nlohmann::json path_json(const PathResult& r)
{
    return nlohmann::json{{"path", to_string(r.path)},
                          {"frame_ms", {{"min", *std::min_element(r.samples.begin(), r.samples.end())},
                                        {"median", bench::median_of(r.samples)},
                                        {"samples", r.samples}}},
                          {"stages_ms", stages_json(r.fastest)},
                          {"build_ms", r.build_ms},
                          {"bvh_nodes", r.bvh.nodes}};
}

nlohmann::json compare_json(const CompareReport& rep)
{
    nlohmann::json depths = {{"equal", rep.depth_equal}, {"explained", rep.depth_explained}, {"errors", rep.depth_errors},
                             {"errors_raster", rep.depth_errors_a}, {"errors_ray", rep.depth_errors_b}};
    return {{"pixels", rep.pixels}, {"equal", rep.equal}, {"explained", rep.explained}, {"errors", rep.errors},
            {"errors_raster", rep.errors_a}, {"errors_ray", rep.errors_b}, {"depths", depths}};
}

nlohmann::json first_frame_json(double open_ms, double renderer_ms, const std::vector<PathResult>& results)
{
    nlohmann::json paths = nlohmann::json::array();
    for (const auto& r : results)
        paths.push_back({{"path", to_string(r.path)},
                         {"prepare_ms", r.prepare_ms},
                         {"first_frame_ms", r.first_frame_ms},
                         {"next_frame_ms", bench::median_of(r.samples)}});
    return {{"device_open_ms", open_ms}, {"renderer_ms", renderer_ms}, {"paths", paths}};
}

/// j[field] = the mapping of `m` (a RasterMappingChoice or RayMappingChoice) with
/// j[field + "_source"], and j[field + "_ms"] {first, second} when both candidates were measured;
/// without a choice (the path did not run), j[field] = `asked` alone.
template <class Choice>
void put_mapping(nlohmann::json& j, const std::string& field, const std::string& asked, const Choice* m,
                 const char* first, double Choice::*first_ms, const char* second, double Choice::*second_ms)
{
    if (!m) {
        j[field] = asked;
        return;
    }
    j[field] = to_string(m->mapping);
    j[field + "_source"] = m->source;
    if (m->*first_ms >= 0 && m->*second_ms >= 0) j[field + "_ms"] = {{first, m->*first_ms}, {second, m->*second_ms}};
}

bool ran(const std::vector<PathResult>& results, Path path)
{
    return std::any_of(results.begin(), results.end(), [path](const PathResult& r) { return r.path == path; });
}

} // namespace

nlohmann::json render_json(const RenderJson& run, Renderer& renderer, const std::vector<PathResult>& results)
{
    bool several = results.size() > 1;
    nlohmann::json j = several ? nlohmann::json{{"path", "all"}} : path_json(results[0]);
    j["triangles"] = run.triangles;
    j["width"] = run.width;
    j["height"] = run.height;
    const DeviceInfo& device = renderer.device().info();
    j["device"] = device.name;
    // The raster path's depth test as its frames drew (FrameTiming::raster_atomics: Auto picks
    // tile ownership for few triangles on PoCL's CPU device); without a raster frame, as Auto
    // would resolve it for a frame of many triangles (atomics where offered).
    RasterAtomics atomics = run.options.raster_atomics;
    for (const auto& r : results)
        if (r.path == Path::Raster && r.fastest.raster_atomics != RasterAtomics::Auto) atomics = r.fastest.raster_atomics;
    j["raster_atomics"] = atomics != RasterAtomics::Auto ? to_string(atomics) : device.int64_atomics ? "on" : "off";
    put_mapping(j, "raster_mapping", to_string(run.options.raster_mapping),
                ran(results, Path::Raster) ? &renderer.raster_mapping() : nullptr, "square",
                &RasterMappingChoice::square_ms, "pixel", &RasterMappingChoice::pixel_ms);
    put_mapping(j, "ray_mapping", to_string(run.options.ray_mapping),
                ran(results, Path::Ray) ? &renderer.ray_mapping() : nullptr, "packet", &RayMappingChoice::packet_ms,
                "single", &RayMappingChoice::single_ms);
    j["load_ms"] = run.load_ms;
    j["warm_up"] = run.warm_up;
    j["camera"] = run.camera;
    j["coverage"] = to_string(run.options.coverage);
    j["samples"] = run.options.samples;
    j["layers"] = run.options.layers; // depth layers (RenderOptions::layers)
    if (several) {
        j["build_ms"] = results[1].build_ms;
        j["results"] = nlohmann::json::array();
        for (const auto& r : results) j["results"].push_back(path_json(r));
    }
    if (run.compare) j["compare"] = compare_json(*run.compare);
    if (run.open_ms >= 0) j["first_frame"] = first_frame_json(run.open_ms, run.renderer_ms, results);
    return j;
}

} // namespace clvis::cli
