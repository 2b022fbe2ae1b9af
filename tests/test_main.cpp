// The test runner's entry point, for Catch2 2.x and 3.x alike.
#if __has_include(<catch2/catch_session.hpp>)
#include <catch2/catch_session.hpp>
#else
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#endif

#include <cstdlib>

int main(int argc, char** argv)
{
    // What clvis keeps between runs (tuned choices such as RasterMapping::Auto's, program
    // binaries) goes to the build tree, never to the user's cache folder.
    setenv("CLVIS_CACHE_DIR", CLVIS_BINARY_DIR "/tests/cache", 1);
    return Catch::Session().run(argc, argv);
}
