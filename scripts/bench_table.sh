#!/bin/sh
# Regenerates the README's performance table in one command: runs `clvis bench` (the full sweep
# by default) into docs/bench (bench.json, bench.csv, plots), then rewrites the table between the
# bench-table markers of README.md with how the run was made (command, machine, load), and writes
# bounds.md beside the run: where each point's time goes (stages, misses, builds).
#   scripts/bench_table.sh                      # the full sweep, as the README's table is made
#   scripts/bench_table.sh --repeat 3           # three passes: the spread across them as well
#   BENCH_OUT=/tmp/b scripts/bench_table.sh --quick   # a short check that leaves docs/bench alone
#   BENCH_NOTE="machine loaded by builds" scripts/bench_table.sh   # a line under the provenance
# CLVIS names the tool (default build/clvis); further arguments go to `clvis bench`.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
clvis=${CLVIS:-$root/build/clvis}
out=${BENCH_OUT:-docs/bench}
[ -x "$clvis" ] || { echo "bench_table.sh: $clvis not found: build the clvis target first" >&2; exit 1; }
cd "$root"
"$clvis" bench --out "$out" "$@"
/usr/bin/python3 bench/readme_table.py "$out/bench.json" README.md --note "${BENCH_NOTE:-}"
/usr/bin/python3 bench/bounds_table.py "$out/bench.json" "$out/bounds.md"
