// Parts of `clvis render --json` (render_report.hpp).
#include "render_report.hpp"

namespace clvis::cli {

nlohmann::json stages_json(const FrameTiming& t)
{
    if (!t.stages_measured) return nullptr;
    nlohmann::json s = nlohmann::json::object();
    for (const auto& st : t.stages) s[st.name] = st.ms;
    return s;
}

namespace {

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

} // namespace

void add_raster_mapping_json(nlohmann::json& j, Renderer* renderer, const std::string& asked)
{
    put_mapping(j, "raster_mapping", asked, renderer ? &renderer->raster_mapping() : nullptr, "square",
                &RasterMappingChoice::square_ms, "pixel", &RasterMappingChoice::pixel_ms);
}

void add_ray_mapping_json(nlohmann::json& j, Renderer* renderer, const std::string& asked)
{
    put_mapping(j, "ray_mapping", asked, renderer ? &renderer->ray_mapping() : nullptr, "packet",
                &RayMappingChoice::packet_ms, "single", &RayMappingChoice::single_ms);
}

} // namespace clvis::cli
