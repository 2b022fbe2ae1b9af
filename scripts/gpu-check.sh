#!/usr/bin/env bash
# The GPU check of issue #21 in one command, for a machine with an NVIDIA GPU (the lent H100/H200:
# Ubuntu 24.04, PoCL 5 and NVIDIA's OpenCL installed, no OpenImageIO, Embree, Mesa or network):
#   1. registers NVIDIA's OpenCL driver beside the installed ICDs (it ships unregistered there);
#   2. builds clvis without the image layer and the reference renderers (what that machine lacks);
#   3. runs the device suite (the mapping tests among it), the agreement suite, the raster-rule and
#      tile-ownership checks and both ray mappings (packet, single) on each device found: NVIDIA's
#      GPU, then PoCL's CPU device (all cores);
#   4. runs `clvis bench --quick` on each, clvis against itself only (no reference renderer there),
#      and 1080p renders of both paths, of both raster mappings (Auto's choice in devices-tuned.txt)
#      and of both ray mappings.
# Writes everything under $OUT (default gpu-check-out/): clinfo, test logs, bench.json / .csv per
# device, and summary.txt (one line per step with its exit status and seconds). Exits non-zero
# when any step failed; every step runs regardless, so one run reports everything.
#
#   bash scripts/gpu-check.sh            # everything (about 10 minutes on an H100 + 16 cores)
#   GPU_CHECK_QUICK=1 bash scripts/gpu-check.sh   # device suite and bench only
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
out=${OUT:-gpu-check-out}
mkdir -p "$out"
summary=$out/summary.txt
export CLVIS_CACHE_DIR="$(cd "$out" && pwd)/cache" # Auto's measurements come back with the rest
: >"$summary"
failed=0
jobs=$(nproc)

step() { # step NAME LOG COMMAND...: runs COMMAND, its output to LOG, a line in the summary
    local name=$1 log=$2 t0 rc
    shift 2
    t0=$(date +%s)
    "$@" >"$log" 2>&1
    rc=$?
    printf '%-48s rc=%-3d %5ds  %s\n' "$name" "$rc" "$(( $(date +%s) - t0 ))" "$log" | tee -a "$summary"
    [ "$rc" -eq 0 ] || failed=1
    return 0
}

# 1. NVIDIA's OpenCL beside what is registered (NOTES.md: the driver is installed, not registered).
vendors=$(mktemp -d)
cp /etc/OpenCL/vendors/*.icd "$vendors"/ 2>/dev/null || true
for lib in /usr/lib/x86_64-linux-gnu/libnvidia-opencl.so.1 /usr/lib/libnvidia-opencl.so.1 \
           /usr/lib64/libnvidia-opencl.so.1; do
    if [ -e "$lib" ]; then echo "$lib" >"$vendors/nvidia.icd"; break; fi
done
export OCL_ICD_VENDORS=$vendors
{ command -v clinfo >/dev/null && clinfo; } >"$out/clinfo.txt" 2>&1 || true
{ command -v nvidia-smi >/dev/null && nvidia-smi; } >"$out/nvidia-smi.txt" 2>&1 || true

# 2. Build: the core, the tool and the tests; no OpenImageIO, no reference renderers, no Python.
build=${GPU_CHECK_BUILD:-build-gpu}
step "configure" "$out/configure.log" cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release \
    -DCLVIS_WITH_IMAGE_IO=OFF -DCLVIS_BUILD_BENCH_REFERENCES=OFF -DCLVIS_BUILD_PYTHON=OFF
step "build" "$out/build.log" cmake --build "$build" -j "$jobs"
if [ ! -x "$build/tests/clvis_tests" ]; then
    echo "clvis_tests did not build: see $out/build.log" | tee -a "$summary"
    exit 1
fi

# 3. and 4. per device: the names are matched against platform and device names (Device::open).
"$build/clvis" devices >"$out/devices.txt" 2>&1 || true
devices=()
grep -qi nvidia "$out/devices.txt" && devices+=("NVIDIA")
grep -qi "portable computing language\|pocl" "$out/devices.txt" && devices+=("portable computing language")
if [ ${#devices[@]} -eq 0 ]; then
    echo "no OpenCL device found: see $out/devices.txt and $out/clinfo.txt" | tee -a "$summary"
    exit 1
fi
for dev in "${devices[@]}"; do
    tag=$(echo "$dev" | tr ' A-Z' '_a-z')
    export CLVIS_DEVICE=$dev
    step "device suite on $dev" "$out/device-$tag.log" \
        "$build/tests/clvis_tests" "[device]~[slow]~[.]" --durations yes
    if [ -z "${GPU_CHECK_QUICK:-}" ]; then
        step "agreement suite (slow cases) on $dev" "$out/agree-slow-$tag.log" \
            "$build/tests/clvis_tests" "[agree][slow]" --durations yes
        step "raster rule, tile ownership, regions on $dev" "$out/modes-$tag.log" \
            "$build/tests/clvis_tests" "[rule],[raster_atomics],[region]" --durations yes
        step "ray mappings (packet, single) on $dev" "$out/ray-mapping-$tag.log" \
            "$build/tests/clvis_tests" "the single mapping*" --durations yes
        step "float-only exact fallback on $dev" "$out/exact-float-$tag.log" env CLVIS_EXACT_FLOAT=1 \
            "$build/tests/clvis_tests" "a plane face-on*,triangles seen edge-on*,rays aimed exactly at shared edges*,the single mapping gives the packet mapping's keys where the exact fallback runs"
    fi
    step "clvis bench --quick on $dev" "$out/bench-$tag.log" \
        "$build/clvis" bench --quick --no-plot --device "$dev" --out "$out/bench-$tag"
    for run in raster ray:packet ray:single; do
        path=${run%%:*} mapping=()
        [ "$path" = "$run" ] || mapping=(--ray-mapping "${run#*:}")
        step "clvis render bunny 1920x1080 $run on $dev" "$out/render-${run/:/-}-$tag.log" \
            "$build/clvis" render scenes/stanford-bunny.obj --path "$path" "${mapping[@]}" --width 1920 \
            --height 1080 --repeat 20 --timings --json --device "$dev"
    done
    # The raster fine stage's two mappings at 1080p, against Auto's choice in the render above.
    for mapping in square pixel; do
        step "clvis render bunny 1920x1080 raster $mapping on $dev" "$out/render-raster-$mapping-$tag.log" \
            "$build/clvis" render scenes/stanford-bunny.obj --raster-mapping "$mapping" --width 1920 --height 1080 \
            --repeat 20 --json --device "$dev"
    done
done
unset CLVIS_DEVICE
# RasterMapping::Auto's measured choices per device (kept in $out/cache, listed by clvis devices).
"$build/clvis" devices >"$out/devices-tuned.txt" 2>&1 || true
echo "summary: $summary" >&2
exit "$failed"
