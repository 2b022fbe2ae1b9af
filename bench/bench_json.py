"""Reading a `clvis bench` run's bench.json, for plot.py and readme_table.py (no matplotlib)."""


def run_of(point, renderer):
    """The run of `renderer` at `point` that has frame times, or None (missing or failed)."""
    for run in point["runs"]:
        if run["renderer"] == renderer and "frame_ms" in run:
            return run
    return None
