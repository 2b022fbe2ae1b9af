// libFuzzer target: parse_ply (host/scene/scene_ply.cpp) on arbitrary bytes. It must return a valid
// mesh or throw clvis::Error; anything else (a crash, a sanitizer report, another exception, a
// broken mesh) is a bug. Seeds: tests/fuzz/corpus/ply/.
#include "fuzz_check.hpp"
#include "scene/scene_parsers.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        clvis::fuzz::check_mesh(clvis::detail::parse_ply(bytes, "fuzz.ply"));
    } catch (const clvis::Error&) {
    }
    return 0;
}
