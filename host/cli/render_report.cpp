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

void add_raster_mapping_json(nlohmann::json& j, Renderer* renderer, const std::string& asked)
{
    if (!renderer) {
        j["raster_mapping"] = asked;
        return;
    }
    const RasterMappingChoice& m = renderer->raster_mapping();
    j["raster_mapping"] = to_string(m.mapping);
    j["raster_mapping_source"] = m.source;
    if (m.square_ms >= 0 && m.pixel_ms >= 0) j["raster_mapping_ms"] = {{"square", m.square_ms}, {"pixel", m.pixel_ms}};
}

} // namespace clvis::cli
