#!/usr/bin/python3
"""Rewrites the performance table of README.md from a `clvis bench` run: everything between the
lines <!-- bench-table:begin --> and <!-- bench-table:end --> is replaced by how the run was made
(command, date, device, machine and its load, references, frame rule) and one row per point.

  /usr/bin/python3 bench/readme_table.py docs/bench/bench.json README.md [--note TEXT]

scripts/bench_table.sh runs the sweep and then this. Ratios are clvis / reference of medians in
the same run; the range after each is its spread (the medians' 95 % intervals and every pass);
'!' marks a spread wholly above its target, '~' one that crosses it.
"""
import json
import sys

from bench_json import run_of

BEGIN = "<!-- bench-table:begin -->"
END = "<!-- bench-table:end -->"


def ms(point, renderer):
    run = run_of(point, renderer)
    return "%.2f" % run["frame_ms"]["median"] if run else "fail"


def build(point, renderer):
    run = run_of(point, renderer)
    return "%.1f" % run["build_ms"]["median"] if run and "build_ms" in run else "-"


def ratio(point, key):
    spread = point.get("ratio_spread", {}).get(key)
    if not spread:
        return "-"
    mark = {"missed": "!", "crosses": "~"}.get(spread.get("verdict"), "")
    return "%.2f (%.2f-%.2f)%s" % (point["ratios"][key], spread["lo"], spread["hi"], mark)


def verdict(point, a, b):
    for c in point["comparisons"]:
        if c["a"] == a and c["b"] == b:
            return "n/a" if "error" in c else "%de/%dx" % (c["errors"], c["explained"])
    return "-"


def load_text(load):
    return "unknown" if load is None else "%.2f %.2f %.2f" % tuple(load)


def provenance(data, note):
    machine = data.get("machine", {})
    frames = data["parameters"]["frames"]
    if frames["exact"]:
        rule = "exactly %d timed frames per renderer and point" % frames["exact"]
    else:
        rule = ("timed frames until each median's 95 %% interval is within %.0f %% of it (%d to %d frames, "
                "a %.1f s budget)" % (100 * frames["median_ci_rel"], frames["min"], frames["max"],
                                      frames["budget_ms"] / 1000))
    targets = data["parameters"]["targets"]
    lines = [
        "Made by `%s` (then `bench/readme_table.py`; `scripts/bench_table.sh` does both) on %s:" % (
            data["command"], data["date"]),
        "%s cores of %s, clvis %s on %s, %s, %s (%d reference threads)." % (
            machine.get("cores", "?"), machine.get("cpu_model", "?"), data["clvis_version"],
            data["device"].get("name", "no device"), data["references"]["embree"],
            data["references"]["gl"].split(";")[0], data["references"]["threads"]),
        "Load (1, 5, 15 minutes) %s before, %s after; %d pass(es) of the sweep, %.0f s in all." % (
            load_text(machine.get("load_before")), load_text(machine.get("load_after")),
            data["parameters"]["passes"], data["total_s"]),
        "At each point every renderer is warmed up, then all are timed in interleaved rounds (one frame "
        "each per round); %s." % rule,
        "Median frame times in ms; ratios clvis / reference with their spread; targets raster / llvmpipe "
        "<= %.2f, ray / Embree rtcIntersect16 <= %.2f, BVH build / Embree build <= %.2f ('!' missed by the "
        "whole spread, '~' crossed by it). Referee verdicts: unacceptable pixels (e) / explained "
        "mismatches (x)." % (targets["raster_over_llvmpipe"], targets["ray_over_embree_intersect16"],
                             targets["bvh_build_over_embree_build"]),
    ]
    if note:
        lines.append("")
        lines.append("**%s**" % note)
    return lines


def table(data):
    rows = ["| mesh | camera | size | triangles | raster | llvmpipe | raster / llvmpipe | ray | Embree x16 | "
            "ray / x16 | Embree x1 | ray / x1 | BVH build | Embree build | build / Embree | raster vs ray | "
            "raster vs llvmpipe |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for p in data["points"]:
        rows.append("| " + " | ".join([
            p["mesh"], p["camera"], "%dx%d" % (p["width"], p["height"]), "{:,}".format(p["triangles"]),
            ms(p, "raster"), ms(p, "llvmpipe"), ratio(p, "raster_over_llvmpipe"),
            ms(p, "ray"), ms(p, "embree-intersect16"), ratio(p, "ray_over_embree_intersect16"),
            ms(p, "embree-intersect1"), ratio(p, "ray_over_embree_intersect1"),
            build(p, "ray"), build(p, "embree-intersect1"), ratio(p, "bvh_build_over_embree_build"),
            verdict(p, "raster", "ray"), verdict(p, "raster", "llvmpipe")]) + " |")
    return rows


def main(argv):
    args = argv[1:]
    note = ""
    if "--note" in args:
        k = args.index("--note")
        if k + 1 >= len(args):
            sys.stderr.write("readme_table.py: --note needs a text\n")
            return 2
        note = args[k + 1]
        del args[k:k + 2]
    if len(args) != 2:
        sys.stderr.write(__doc__)
        return 2
    with open(args[0]) as f:
        data = json.load(f)
    with open(args[1]) as f:
        text = f.read()
    if text.count(BEGIN) != 1 or text.count(END) != 1 or text.index(BEGIN) > text.index(END):
        sys.stderr.write("readme_table.py: %s needs one %s line before one %s line\n" % (args[1], BEGIN, END))
        return 1
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    body = "\n".join(provenance(data, note) + [""] + table(data))
    with open(args[1], "w") as f:
        f.write(head + BEGIN + "\n" + body + "\n" + END + tail)
    print("readme_table.py: %d points from %s into %s" % (len(data["points"]), args[0], args[1]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
