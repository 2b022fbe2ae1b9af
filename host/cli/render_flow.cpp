// clvis render --flow (render_flow.hpp): the views - 1 flow files of a views file.
#include "render_flow.hpp"

#include <clvis/clvis.hpp>
#if CLVIS_WITH_IMAGE_IO
#include <clvis/image_io.hpp>
#endif

namespace clvis::cli {

std::string flow_file_name(const std::string& pattern, int view, int views)
{
    return view_file_name(pattern, view, views - 1);
}

void plan_flow(OutputPlan& plan, const std::string& pattern, int views, bool have_views_file)
{
    if (pattern.empty()) return;
    auto refuse = [](const std::string& why) { throw Error(Error::Kind::InvalidArgument, "--flow: " + why); };
    if (!have_views_file) refuse("needs --views FILE (the flow goes from each view to the next)");
    if (views < 2) refuse("the views file holds " + std::to_string(views) + " view; the flow needs at least two");
    if (pattern.find("{view}") == std::string::npos)
        refuse("'" + pattern + "' must contain {view}: the flow from view k to view k + 1 is written as file k");
    for (int v = 0; v + 1 < views; ++v) plan.add("--flow", flow_file_name(pattern, v, views), OutputKind::Floats);
}

void write_flow(Renderer& renderer, const VisibilityBatch& batch, const std::vector<Camera>& cameras,
                const std::vector<ItemTransforms>& items, const std::string& pattern,
                const std::function<std::string(const std::string&)>& name_of)
{
    if (pattern.empty()) return;
#if CLVIS_WITH_IMAGE_IO
    static const ItemTransforms none;
    auto items_of = [&](int v) -> const ItemTransforms& {
        return std::size_t(v) < items.size() ? items[std::size_t(v)] : none;
    };
    FlowBuffer buffer;
    std::vector<float> pixels;
    for (int v = 0; v + 1 < batch.views(); ++v) {
        flow(renderer, batch.view(v), cameras[std::size_t(v)], batch.view(v + 1), cameras[std::size_t(v) + 1], buffer,
             items_of(v), items_of(v + 1));
        buffer.read(pixels);
        write_float_channels(name_of(flow_file_name(pattern, v, batch.views())), batch.width(), batch.height(),
                             {"flow.x", "flow.y", "flow.valid", "flow.occluded"}, pixels);
    }
#else
    (void)renderer, (void)batch, (void)cameras, (void)items, (void)name_of;
    throw Error(Error::Kind::InvalidArgument, "--flow: this clvis was built without OpenImageIO (CLVIS_WITH_IMAGE_IO=OFF)");
#endif
}

} // namespace clvis::cli
