#!/usr/bin/env bash
# Peak resident memory per triangle of `clvis render` (issue 37): for make_uv_sphere meshes of
# about 1M and 4M triangles (scripts/make_sphere.py, as PLY), each path's peak resident set
# (/usr/bin/time's "Maximum resident set size") minus the same command's on a 64-triangle sphere
# (the process's baseline: libraries, OpenCL runtime, the keys of the image), divided by the
# triangles. On PoCL the device's buffers are host memory, so they count.
#
#   scripts/memory_check.sh [CLVIS] [TRIANGLES...]     (default: build/clvis 1048576 4194304)
#
# Environment: WORK (scratch folder, default a temporary one), PATHS (default "ray raster"),
# WIDTH/HEIGHT (default 1920x1080), RUNS (runs per case, the smallest peak counts; default 2:
# the first run of a new program writes its binary to clvis's cache), CLVIS_DEVICE (default cpu).
# Prints one line per mesh and path: triangles, path, peak KiB, baseline KiB, bytes per triangle.
# LIMIT_RAY / LIMIT_RASTER (bytes per triangle): exit status 1 where a path's peak is above its
# limit (tests/CMakeLists.txt's memory_per_triangle; issue 37's targets are 100 and 60).
# The mappings are pinned (--ray-mapping packet, --raster-mapping square) so that no tuning run
# (a sphere of its own) lands in either measurement.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
clvis="${1:-$here/../build/clvis}"
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1048576 4194304)
paths=(${PATHS:-ray raster})
width="${WIDTH:-1920}" height="${HEIGHT:-1080}" runs="${RUNS:-2}"
export CLVIS_DEVICE="${CLVIS_DEVICE:-cpu}"
time_bin=/usr/bin/time
[ -x "$time_bin" ] || { echo "memory_check: needs GNU time at $time_bin" >&2; exit 2; }
py=python3
for p in python3 /usr/bin/python3; do command -v "$p" >/dev/null && { py=$p; break; }; done
work="${WORK:-}"
if [ -z "$work" ]; then
    work="$(mktemp -d)"
    trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"

# peak MESH PATH: the smallest peak resident set in KiB over $runs runs.
peak() {
    local best=""
    for ((r = 0; r < runs; ++r)); do
        "$time_bin" -f %M -o "$work/rss" "$clvis" render "$1" --path "$2" --width "$width" --height "$height" \
            --ray-mapping packet --raster-mapping square -q >/dev/null
        local kib
        kib="$(tail -n 1 "$work/rss")"
        if [ -z "$best" ] || [ "$kib" -lt "$best" ]; then best=$kib; fi
    done
    echo "$best"
}

"$py" "$here/make_sphere.py" 64 "$work/sphere-64.ply" >/dev/null
declare -A base
failed=0
for p in "${paths[@]}"; do base[$p]="$(peak "$work/sphere-64.ply" "$p")"; done
printf '%-10s %-7s %12s %12s %10s\n' triangles path peak_KiB base_KiB B/tri
for n in "${sizes[@]}"; do
    mesh="$work/sphere-$n.ply"
    [ -s "$mesh" ] || "$py" "$here/make_sphere.py" "$n" "$mesh" >/dev/null
    tris="$(sed -n 's/^element face \([0-9]*\).*/\1/p' "$mesh" | head -n 1)"
    for p in "${paths[@]}"; do
        kib="$(peak "$mesh" "$p")"
        per="$(awk -v k="$kib" -v b="${base[$p]}" -v t="$tris" 'BEGIN { printf "%.1f", (k - b) * 1024 / t }')"
        printf '%-10s %-7s %12s %12s %10s\n' "$tris" "$p" "$kib" "${base[$p]}" "$per"
        limit_var="LIMIT_$(echo "$p" | tr a-z A-Z)"
        limit="${!limit_var:-}"
        if [ -n "$limit" ] && awk -v x="$per" -v l="$limit" 'BEGIN { exit !(x > l) }'; then
            echo "memory_check: the $p path held $per bytes per triangle of $tris at its peak, more than $limit" >&2
            failed=1
        fi
    done
done
exit "$failed"
