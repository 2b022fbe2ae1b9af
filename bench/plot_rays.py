#!/usr/bin/python3
"""Plot of a `clvis bench --rays` run: reads DIR/bench-rays.json, writes rays_mrays.png beside it:
Mrays/s per workload (ambient occlusion rays of the bunny and of a 1M sphere, random rays through
a 1M soup) for clvis's closest-hit and any-hit queries and Embree's rtcIntersect / rtcOccluded,
single rays and 16-wide packets.

Run with Debian's interpreter, which has matplotlib:
  /usr/bin/python3 bench/plot_rays.py bench-rays.json OUT_DIR
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend is chosen first)

RENDERERS = [
    # (name in bench-rays.json, label, colour, hatch)
    ("clvis-closest", "clvis closest", "tab:orange", ""),
    ("embree-intersect1", "Embree rtcIntersect1", "tab:red", ""),
    ("embree-intersect16", "Embree rtcIntersect16", "tab:red", "//"),
    ("clvis-any", "clvis any", "tab:blue", ""),
    ("embree-occluded1", "Embree rtcOccluded1", "tab:purple", ""),
    ("embree-occluded16", "Embree rtcOccluded16", "tab:purple", "//"),
]


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 2
    with open(argv[1]) as f:
        data = json.load(f)
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
    fig.tight_layout()
    path = os.path.join(argv[2], "rays_mrays.png")
    fig.savefig(path, dpi=110)
    print("wrote", path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
