// The clvis tool: one executable, one file per subcommand. Every error prints one line starting
// "clvis:" that names what was wrong (the flag, the file, the value), and exits with
// exit_usage; a referee that rejects answers exits with exit_rejected (commands.hpp).
#include "commands.hpp"

#include <clvis/clvis.hpp>

#include <iostream>

namespace clvis::cli {

int report_parse_error(const CLI::App& app, const CLI::ParseError& error)
{
    if (error.get_exit_code() == 0) return app.exit(error); // --help, --version
    std::string message = error.what();
    std::cerr << "clvis: " << message << (message.empty() || message.back() != '\n' ? "\n" : "");
    return exit_usage;
}

} // namespace clvis::cli

int main(int argc, char** argv)
{
    using namespace clvis::cli;
    CLI::App app{"clvis: the visibility problem solved twice on OpenCL, by rasterization and by ray "
                 "casting, with a referee that proves both see the same thing.\n\n"
                 "Exit status: 0 done, 1 the referee rejected answers, 2 bad flags, files or devices.\n"
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
    } catch (const CLI::RuntimeError& e) {
        return e.get_exit_code(); // a subcommand's status, its result already reported
    } catch (const CLI::ParseError& e) {
        return report_parse_error(app, e);
    } catch (const std::exception& e) {
        std::cerr << "clvis: " << e.what() << "\n";
        return exit_usage;
    }
    return exit_ok;
}
