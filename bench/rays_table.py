#!/usr/bin/python3
"""The ray queries' table of issue 37 from one or more `clvis bench --rays` runs (passes):
clvis's closest and any queries against Embree's rtcIntersect1 / rtcOccluded1 (the target, at
most 1.0) and the 16-wide packets, workload by workload, with the spread over every timed call
of every pass.

  /usr/bin/python3 bench/rays_table.py OUT.md RUN1/bench-rays.json [RUN2/bench-rays.json ...]
      [--command TEXT] [--note TEXT]

Times are medians (min-max) of the timed calls of all passes, in ms. A ratio is clvis's median
over the reference's; its spread runs from clvis's fastest call over the reference's slowest to
clvis's slowest over the reference's fastest. '!' marks a spread wholly above the target, '~'
one that crosses it.
"""
import argparse
import datetime
import json
import statistics
import sys

PAIRS = [("closest", "clvis-closest", "embree-intersect1", "embree-intersect16"),
         ("any", "clvis-any", "embree-occluded1", "embree-occluded16")]
TARGET = 1.0


def samples(runs, workload, renderer):
    """Every timed call of `renderer` on `workload` over the passes (ms); [] where it failed."""
    out = []
    for run in runs:
        for w in run["workloads"]:
            if w["name"] != workload:
                continue
            for r in w["runs"]:
                if r["renderer"] == renderer and not r.get("error"):
                    out.extend(r["ms"])
    return out


def ratio(a, b):
    """(median ratio, lo, hi, mark) of clvis samples a over reference samples b."""
    m = statistics.median(a) / statistics.median(b)
    lo, hi = min(a) / max(b), max(a) / min(b)
    mark = "!" if lo > TARGET else "~" if hi > TARGET else ""
    return m, lo, hi, mark


def times(s):
    return "%.1f (%.1f-%.1f)" % (statistics.median(s), min(s), max(s))


def table(runs):
    rows = ["| workload | triangles | rays | query | clvis ms | Embree x1 ms | clvis / x1 | Embree x16 ms "
            "| clvis / x16 | target (x1 <= 1.0) |",
            "|---|---:|---:|---|---:|---:|---:|---:|---:|---|"]
    met = total = 0
    for w in runs[0]["workloads"]:
        for query, mine, single, packet in PAIRS:
            a, b, c = (samples(runs, w["name"], r) for r in (mine, single, packet))
            if not a or not b:
                rows.append("| %s | %d | %d | %s | %s | %s | - | - | - | not measured |" % (
                    w["name"], w["triangles"], w["rays"], query, times(a) if a else "fail", times(b) if b else "fail"))
                continue
            m, lo, hi, mark = ratio(a, b)
            total += 1
            met += m <= TARGET
            x16 = ratio(a, c) if c else None
            verdict = "met" if m <= TARGET else "missed by %.2fx" % m
            rows.append("| %s | %d | %d | %s | %s | %s | %.2f (%.2f-%.2f)%s | %s | %s | %s |" % (
                w["name"], w["triangles"], w["rays"], query, times(a), times(b), m, lo, hi, mark,
                times(c) if c else "-", "%.2f (%.2f-%.2f)" % x16[:3] if x16 else "-", verdict))
    return rows, met, total


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    p.add_argument("runs", nargs="+")
    p.add_argument("--command", default="", help="how the runs were made (printed above the table)")
    p.add_argument("--note", default="", help="a paragraph under the provenance")
    args = p.parse_args(argv)
    runs = [json.load(open(f)) for f in args.runs]
    rows, met, total = table(runs)
    first = runs[0]
    head = ["# Ray queries against Embree (`clvis bench --rays`)", ""]
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    head.append("Made by %s (%s; %d pass(es), %s timed calls each; `bench/rays_table.py`)." % (
        args.command or "`clvis bench --rays`", when, len(runs), first.get("repeats", "?")))
    head.append("Device `%s`; Embree on %s threads; %s s for the first pass." % (
        first.get("device", "?"), first.get("threads", "?"), "%.0f" % first["total_s"] if "total_s" in first else "?"))
    if args.note:
        head += ["", args.note]
    head += ["", "Times are medians (min-max) of every timed call of every pass, in ms; a ratio's spread runs from "
             "clvis's fastest call over the reference's slowest to its slowest over the reference's fastest "
             "('!' wholly above the target of 1.0, '~' across it).", ""]
    foot = ["", "Issue 37's target, at most 1.0x rtcIntersect1 / rtcOccluded1: met at %d of %d points." % (met, total)]
    with open(args.out, "w") as f:
        f.write("\n".join(head + rows + foot) + "\n")
    print("rays_table.py: %d points from %d run(s) into %s" % (total, len(runs), args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
