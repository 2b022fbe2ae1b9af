#!/usr/bin/python3
"""Plots of a `clvis bench` run: reads DIR/bench.json, writes PNGs beside it.

  time_vs_triangles.png   median frame time per renderer over the procedural sphere sweep
                          (log-log, bars from the 25th to the 75th percentile; grid and soup
                          meshes as separate markers)
  time_vs_resolution.png  median frame time per renderer over image sizes (the bunny, framing)
  crossover.png           raster / ray frame time over triangle count: where the paths cross
  build_vs_triangles.png  clvis BVH build against Embree's build over triangle count

Run with Debian's interpreter, which has matplotlib: /usr/bin/python3 bench/plot.py bench.json OUT_DIR
"""
import math
import os
import sys

from bench_json import run_of
from plot_common import RENDERER_STYLE, plt, read_run, save

# (name in bench.json, label, colour, line style): clvis solid, the references dashed or dotted.
RENDERERS = [(name,) + RENDERER_STYLE[name] + (style,)
             for name, style in (("raster", "-"), ("ray", "-"), ("brute", "-"), ("llvmpipe", "--"),
                                 ("embree-intersect1", "--"), ("embree-intersect16", ":"))]


def frame_stats(point, renderer):
    run = run_of(point, renderer)
    if run is None:
        return None
    f = run["frame_ms"]
    return f["median"], f["p25"], f["p75"]


def in_sweep(point, sweep):
    return sweep in point.get("sweeps", [])


def family(point):
    return point["mesh"].split("-")[0]


def plot_series(ax, points, x_of, renderers=RENDERERS):
    plotted = False
    for name, label, colour, style in renderers:
        xs, ys, lo, hi = [], [], [], []
        for p in sorted(points, key=x_of):
            s = frame_stats(p, name)
            if s is None:
                continue
            xs.append(x_of(p))
            ys.append(s[0])
            lo.append(s[0] - s[1])
            hi.append(s[2] - s[0])
        if xs:
            ax.errorbar(xs, ys, yerr=[lo, hi], label=label, color=colour, linestyle=style, marker="o",
                        markersize=4, capsize=2)
            plotted = True
    return plotted


def subtitle(data):
    device = data.get("device", {}).get("name", "no device")
    refs = data.get("references", {})
    return "clvis %s on %s; %s; %s" % (data.get("clvis_version", "?"), device, refs.get("embree", "?"),
                                       refs.get("gl", "?").split(";")[0])


def finish(fig, ax, data, title, path):
    ax.set_title(title + "\n" + subtitle(data), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, path)


def time_vs_triangles(data, out):
    points = [p for p in data["points"] if in_sweep(p, "triangles")]
    spheres = [p for p in points if family(p) == "sphere"]
    if not spheres:
        return
    fig, ax = plt.subplots(figsize=(8, 5.5))
    plot_series(ax, spheres, lambda p: p["triangles"])
    # Grid and soup: the renderer's colour, one marker per mesh family, one legend entry per family.
    markers = {"grid": "s", "soup": "^"}
    for fam, marker in markers.items():
        others = [p for p in points if family(p) == fam]
        shown = False
        for name, _, colour, _ in RENDERERS:
            xs = [p["triangles"] for p in others if frame_stats(p, name)]
            ys = [frame_stats(p, name)[0] for p in others if frame_stats(p, name)]
            if xs:
                ax.scatter(xs, ys, color=colour, marker=marker, s=30, alpha=0.8)
                shown = True
        if shown:
            ax.scatter([], [], color="black", marker=marker, s=30, label="%s mesh (renderer's colour)" % fam)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles (UV sphere; squares: grid, triangles: soup)")
    ax.set_ylabel("frame time, median (ms)")
    w, h = spheres[0]["width"], spheres[0]["height"]
    finish(fig, ax, data, "Frame time vs triangle count, %dx%d, framing camera" % (w, h),
           os.path.join(out, "time_vs_triangles.png"))


def time_vs_resolution(data, out):
    points = [p for p in data["points"] if in_sweep(p, "resolution")]
    if not points:
        return
    fig, ax = plt.subplots(figsize=(8, 5.5))
    plot_series(ax, points, lambda p: p["width"] * p["height"] / 1e6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    sizes = sorted({(p["width"], p["height"]) for p in points}, key=lambda s: s[0] * s[1])
    ax.set_xticks([w * h / 1e6 for w, h in sizes])
    ax.set_xticklabels(["%dx%d\n%.2f MP" % (w, h, w * h / 1e6) for w, h in sizes], fontsize=7)
    ax.minorticks_off()
    ax.set_xlabel("image size")
    ax.set_ylabel("frame time, median (ms)")
    finish(fig, ax, data, "Frame time vs resolution, %s (%d triangles), framing camera"
           % (points[0]["mesh"], points[0]["triangles"]), os.path.join(out, "time_vs_resolution.png"))


def crossover(data, out):
    points = sorted([p for p in data["points"] if in_sweep(p, "triangles") and family(p) == "sphere"],
                    key=lambda p: p["triangles"])
    xs, ratios = [], []
    for p in points:
        r, y = frame_stats(p, "raster"), frame_stats(p, "ray")
        if r and y and y[0] > 0:
            xs.append(p["triangles"])
            ratios.append(r[0] / y[0])
    if not xs:
        return
    fig, ax = plt.subplots(figsize=(8, 5.5))
    ax.plot(xs, ratios, marker="o", color="tab:purple", label="clvis raster / clvis ray (median frame)")
    ax.axhline(1.0, color="black", linewidth=0.8, linestyle="--", label="equal time")
    # The crossover: where the ratio passes 1, interpolated in log-log between neighbours.
    for (x0, r0), (x1, r1) in zip(zip(xs, ratios), zip(xs[1:], ratios[1:])):
        if (r0 - 1) * (r1 - 1) < 0:
            t = math.log(r0) / (math.log(r0) - math.log(r1))
            xc = math.exp(math.log(x0) + t * (math.log(x1) - math.log(x0)))
            ax.axvline(xc, color="tab:green", linestyle=":", label="crossover near %d triangles" % round(xc))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles (UV sphere)")
    ax.set_ylabel("raster time / ray time (below 1: raster faster)")
    finish(fig, ax, data, "Raster vs ray crossover, %dx%d" % (points[0]["width"], points[0]["height"]),
           os.path.join(out, "crossover.png"))


def build_vs_triangles(data, out):
    points = sorted([p for p in data["points"] if in_sweep(p, "triangles") and family(p) == "sphere"],
                    key=lambda p: p["triangles"])
    series = {"ray": ("clvis BVH build", "tab:orange", "-"),
              "embree-intersect1": ("Embree build (robust, high quality)", "tab:red", "--")}
    fig, ax = plt.subplots(figsize=(8, 5.5))
    plotted = False
    for name, (label, colour, style) in series.items():
        xs, ys = [], []
        for p in points:
            run = run_of(p, name)
            if run and "build_ms" in run:
                xs.append(p["triangles"])
                ys.append(run["build_ms"]["median"])
        if xs:
            ax.plot(xs, ys, marker="o", color=colour, linestyle=style, label=label)
            plotted = True
    if not plotted:
        plt.close(fig)
        return
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles (UV sphere)")
    ax.set_ylabel("build time, median (ms)")
    finish(fig, ax, data, "BVH build vs triangle count", os.path.join(out, "build_vs_triangles.png"))


def main(argv):
    run = read_run(argv, "usage: plot.py bench.json OUT_DIR")
    if run is None:
        return 2
    data, out = run
    time_vs_triangles(data, out)
    time_vs_resolution(data, out)
    crossover(data, out)
    build_vs_triangles(data, out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
