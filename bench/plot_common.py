"""What the plots of `clvis bench` share (plot.py, plot_rays.py): matplotlib without a display,
reading a run's JSON from the command line, and writing a figure.

Import it from a script in this folder (Python puts the script's folder first on sys.path).
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401  (the backend is chosen first; scripts use plt)

# Every renderer of bench.json and bench-rays.json: its label and colour (a clvis path and the
# reference it is held against share a colour).
RENDERER_STYLE = {
    "raster": ("clvis raster", "tab:blue"),
    "ray": ("clvis ray", "tab:orange"),
    "brute": ("clvis brute", "tab:gray"),
    "llvmpipe": ("llvmpipe (Mesa)", "tab:blue"),
    "embree-intersect1": ("Embree rtcIntersect1", "tab:orange"),
    "embree-intersect16": ("Embree rtcIntersect16", "tab:red"),
    "clvis-closest": ("clvis closest", "tab:orange"),
    "clvis-any": ("clvis any", "tab:blue"),
    "embree-occluded1": ("Embree rtcOccluded1", "tab:purple"),
    "embree-occluded16": ("Embree rtcOccluded16", "tab:purple"),
}


def read_run(argv, usage):
    """(data, out_dir) from argv = [script, RUN.json, OUT_DIR], out_dir created; None (after
    printing `usage` to standard error) when the arguments are wrong."""
    if len(argv) != 3:
        sys.stderr.write(usage.rstrip("\n") + "\n")
        return None
    with open(argv[1]) as f:
        data = json.load(f)
    os.makedirs(argv[2], exist_ok=True)
    return data, argv[2]


def save(fig, path, dpi=120):
    """Writes `fig` to `path`, closes it and says so."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    print("wrote " + path)
