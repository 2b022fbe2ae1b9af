// clvis render --flow: the flow from each view of a views file to the next (CONVENTIONS.md "Motion
// between views (flow)"), named and checked in the run's output plan before anything is rendered
// and written as OpenEXR (flow.x, flow.y, flow.valid, flow.occluded) after the batch.
#pragma once

#include "output_plan.hpp"

#include <clvis/batch.hpp>
#include <clvis/views_file.hpp>

#include <functional>
#include <string>
#include <vector>

namespace clvis::cli {

/// Refuses (Error(InvalidArgument) naming --flow) a pattern without "{view}" or a run without a
/// views file of at least two views, and adds the views - 1 files to `plan`. Nothing when
/// `pattern` is empty.
void plan_flow(OutputPlan& plan, const std::string& pattern, int views, bool have_views_file);

/// The name of the flow file from view `view` to the next: "{view}" is `view`, padded like every
/// other output of a views file of `views` views.
std::string flow_file_name(const std::string& pattern, int view, int views);

/// Computes and writes the flow from each view of `batch` to the next, each under the name `name_of`
/// gives for flow_file_name's; `items` are the views' item transforms (may be empty).
void write_flow(Renderer& renderer, const VisibilityBatch& batch, const std::vector<Camera>& cameras,
                const std::vector<ItemTransforms>& items, const std::string& pattern,
                const std::function<std::string(const std::string&)>& name_of);

} // namespace clvis::cli
