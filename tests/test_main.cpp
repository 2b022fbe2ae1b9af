// The test runner's entry point, for Catch2 2.x and 3.x alike (catch.hpp picks the headers; 2.x
// compiles its runner into this file, 3.x's is in the library linked).
#define CATCH_CONFIG_RUNNER
#include "catch.hpp"

#include <cstdlib>

int main(int argc, char** argv)
{
    // What clvis keeps between runs (tuned choices such as RasterMapping::Auto's, program
    // binaries) goes to the build tree, never to the user's cache folder; or to
    // CLVIS_TEST_CACHE_DIR where a run names one (scripts/gpu-check.sh: its output folder).
    const char* wanted = std::getenv("CLVIS_TEST_CACHE_DIR");
    setenv("CLVIS_CACHE_DIR", wanted && *wanted ? wanted : CLVIS_BINARY_DIR "/tests/cache", 1);
    return Catch::Session().run(argc, argv);
}
