#!/usr/bin/python3
"""Plot of a `clvis bench --rays` run: reads DIR/bench-rays.json, writes rays_mrays.png beside it:
Mrays/s per workload (ambient occlusion rays of the bunny and of a 1M sphere, random rays through
a 1M soup) for clvis's closest-hit and any-hit queries and Embree's rtcIntersect / rtcOccluded,
single rays and 16-wide packets.

Run with Debian's interpreter, which has matplotlib:
  /usr/bin/python3 bench/plot_rays.py bench-rays.json OUT_DIR
"""
import os
import sys

from plot_common import RENDERER_STYLE, plt, read_run, save

# (name in bench-rays.json, label, colour, hatch): 16-wide packets hatched.
RENDERERS = [(name,) + RENDERER_STYLE[name] + ("//" if name.endswith("16") else "",)
             for name in ("clvis-closest", "embree-intersect1", "embree-intersect16", "clvis-any",
                          "embree-occluded1", "embree-occluded16")]


def main(argv):
    run = read_run(argv, __doc__)
    if run is None:
        return 2
    data, out = run
    workloads = data["workloads"]
    fig, ax = plt.subplots(figsize=(9, 4.5))
    width = 0.8 / len(RENDERERS)
    for k, (name, label, colour, hatch) in enumerate(RENDERERS):
        xs, ys = [], []
        for i, w in enumerate(workloads):
            for run in w["runs"]:
                if run["renderer"] == name and not run["error"]:
                    xs.append(i + (k - (len(RENDERERS) - 1) / 2) * width)
                    ys.append(run["mrays_per_s"])
        ax.bar(xs, ys, width, label=label, color=colour, hatch=hatch, edgecolor="black", linewidth=0.5)
    ax.set_xticks(range(len(workloads)))
    ax.set_xticklabels(["%s\n%d triangles, %d rays" % (w["name"], w["triangles"], w["rays"]) for w in workloads])
    ax.set_ylabel("Mrays/s (median of runs)")
    ax.set_title("Ray queries on %s; Embree on %d threads" % (data["device"], data["threads"]), fontsize=10)
    ax.legend(fontsize=8, ncol=2)
    ax.grid(axis="y", alpha=0.3)
    save(fig, os.path.join(out, "rays_mrays.png"), dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
