// A colour image in host memory: what shading produces and image files store.
#pragma once

#include <cstdint>
#include <vector>

namespace clvis {

/// An RGBA image of 8-bit channels, row 0 on top.
struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba; ///< 4 bytes per pixel
};

} // namespace clvis
