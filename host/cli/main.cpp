// The clvis tool: one executable, one file per subcommand. Errors print one line naming what was
// wrong and exit non-zero; nothing here catches what it cannot explain.
#include "commands.hpp"

#include <clvis/clvis.hpp>

#include <iostream>

int main(int argc, char** argv)
{
    CLI::App app{"clvis: the visibility problem solved twice on OpenCL, by rasterization and by ray "
                 "casting, with a referee that proves both see the same thing.\n\n"
                 "Example: clvis render scenes/stanford-bunny.obj --path raster --image bunny.png"};
    app.set_version_flag("--version", "clvis " + clvis::version());
    app.require_subcommand(1);
    app.fallthrough();
    clvis::cli::add_devices_command(app);
    clvis::cli::add_info_command(app);
    clvis::cli::add_render_command(app);
    clvis::cli::add_compare_command(app);
    clvis::cli::add_rays_command(app);
    clvis::cli::add_bench_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const clvis::Error& e) {
        std::cerr << "clvis: " << e.what() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "clvis: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
