// clvis render's named attributes, object ids and normal space (CONVENTIONS.md "Vertex
// attributes", "Object ids"): --attributes FILE.exr (every attribute the scene has, channels
// NAME.x ..), --objects FILE (one uint32 channel "object"), --normals-space world|camera. Resolved
// with the other attributes in one call, only when asked.
#pragma once

#include <clvis/clvis.hpp>

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace clvis::cli {

struct CornerOutputs {
    std::string attributes;             ///< --attributes FILE (.exr)
    std::string objects;                ///< --objects FILE (.tif, .tiff, .exr)
    std::string normals_space = "world"; ///< --normals-space
    std::vector<AttributeInfo> scene;   ///< the scene's attributes, once it is loaded

    void add_to(CLI::App& cmd);
    /// Refuses (naming the flag) --objects with several samples per pixel or with --devices or
    /// --distribute; --attributes is refused there as every float output is.
    void check(int samples, bool spread) const;
    /// Reads the scene's attributes; refuses --attributes for a scene without any, naming it.
    void loaded(const Scene& scene);
    /// Adds what the flags ask to `request`.
    void request(AttributeRequest& request) const;
    /// Writes --attributes and --objects of `resolved` under the names `file_name` gives.
    void write(const AttributeBuffers& resolved, int width, int height,
               const std::function<std::string(const std::string&)>& file_name) const;
};

} // namespace clvis::cli
