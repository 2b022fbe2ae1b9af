// tinygltf's implementation for the fuzz targets only, so that libFuzzer sees (and the sanitizers
// check) its JSON, GLB and buffer parsing; the library links Debian's libtinygltf instead. Images
// are never decoded by clvis, so stb_image is left out (TINYGLTF_NO_STB_IMAGE and _WRITE are
// defined for the whole fuzz library in tests/fuzz/CMakeLists.txt).
#include <nlohmann/json.hpp>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_INCLUDE_JSON
#include <tiny_gltf.h>
