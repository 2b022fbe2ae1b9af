// clvis render --devices / --distribute (render_spread.hpp): the flags, what each refuses, and the
// hand-over to render_multi.cpp or (built with MPI) render_dist.cpp.
#include "render_spread.hpp"
#include "render_multi.hpp"
#if CLVIS_WITH_MPI
#include "render_dist.hpp"
#endif

namespace clvis::cli {

void SpreadArgs::add_to(CLI::App& cmd)
{
#if CLVIS_WITH_MPI
    cmd.add_option("--distribute", distribute,
                   "under mpirun: frames (--views split by rank), screen (rows per rank, gathered) or scene "
                   "(triangles per rank, keys reduced by min)")
        ->check(CLI::IsMember({"frames", "screen", "scene"}));
#endif
    cmd.add_option("--devices", devices, "several devices, one frame: SPEC,SPEC,... (as --device), tiles shared out");
    cmd.add_option("--screen-tile", screen_tile, "with --devices: the screen tiles' edge in pixels")
        ->check(CLI::Range(1, 4096));
    cmd.add_option("--device-map", device_map, "with --devices: an image of which device drew each tile (.png, ...)");
}

Path check_spread(const SpreadRequest& r)
{
    const SpreadArgs& s = r.spread;
    auto refuse = [](const std::string& why) { throw Error(Error::Kind::InvalidArgument, why); };
    if (!s.device_map.empty() && s.devices.empty()) refuse("--device-map: needs --devices SPEC,SPEC,...");
    if (r.path == "all" || !r.image.empty())
        refuse(std::string(s.devices.empty() ? "--distribute" : "--devices") +
               " renders one path (raster, ray or brute) into --ids/--depth; --path all and --image are for one "
               "device in one process");
    Path path = path_from_string(r.path);
    if (!s.devices.empty()) {
        if (!r.views.empty() || !s.distribute.empty() || !r.device_spec.empty())
            refuse("--devices renders one camera; --views, --distribute and --device are not for it");
        return path;
    }
    if ((s.distribute == "frames") != !r.views.empty())
        refuse("--distribute frames splits the views of --views FILE; screen and scene share one camera's frame");
    return path;
}

void render_spread(const SpreadRequest& r)
{
    Path path = check_spread(r);
    if (!r.spread.devices.empty()) return render_multi_device(r, path);
#if CLVIS_WITH_MPI
    render_distributed(r, path);
#endif
}

} // namespace clvis::cli
