#!/usr/bin/env bash
# The GPU check (issues #21, #38) in one command, for the lent NVIDIA machine (README of the device
# tool: Ubuntu 24.04, CMake, ninja, g++ 13, Python; NVIDIA's driver under a read-only
# /usr/local/nvidia; PoCL perhaps; no package registry). Run scripts/gpu-prereqs.sh here first
# and carry .gpu-deps: Catch2, CLI11, nlohmann-json, the OpenCL headers, loader and clinfo.
#   1. preflight: the prerequisites (image or .gpu-deps; "missing: ..." in the summary), the GPU
#      as nvidia-smi sees it, NVIDIA's OpenCL driver found and registered beside the image's ICDs;
#   2. builds the tool and the tests as two targets (no image layer, references, Python or MPI);
#      each later step needs only its own binary;
#   3. on the GPU: the device suite, the agreement suite, the raster-rule cases, the float-only
#      exact fallback, the GPU's keys against PoCL's bit for bit (where PoCL is there),
#      each program's build seconds on a cold cache, `clvis bench --quick` and `--rays --quick`,
#      timed 1080p renders (the 1M sphere and the bunny, both paths and mappings: the anchors of
#      the closing note), and the slow device cases;
#   4. on the same machine's PoCL (16 cores): CTest's device entry, `clvis bench --quick` and
#      `--rays --quick`, and the bunny at 1080p on both paths.
# CI runs everything else on PoCL; step 4 repeats its device entry here only for the 16 cores' figures.
#
# Time: each step has a timeout; after GPU_CHECK_DEADLINE_S seconds (default 480) the steps left
# are skipped, each saying so. Output: $OUT (default gpu-check-out/) holds summary.txt (a START
# line before each step, its END or SKIP line after) and gpu-check-logs.tar.gz (every log, bench
# files, clinfo, the tuning cache), both rewritten after every step, so a run cut short returns
# what it did. Exits non-zero when a step failed or timed out, or when OpenCL does not list the
# GPU that nvidia-smi sees.
#
#   bash scripts/gpu-check.sh                  # 8 minutes at most (the deadline); 16 cores
#   GPU_CHECK_DRY_RUN=1 bash scripts/gpu-check.sh   # no GPU, no build: each test step lists the
#       cases its filter selects (none is a failure), each tool step checks its arguments
#       (tests/gpu_check_dry.cmake, CTest gpu_check_dry)
# Knobs: GPU_CHECK_BUILD (build folder, default build-gpu), GPU_CHECK_TESTS / GPU_CHECK_CLI (use
# these binaries, build nothing), GPU_CHECK_DEVICE (default NVIDIA), GPU_CHECK_WORK (logs folder).
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
root=$PWD
t0=$(date +%s)
deadline=${GPU_CHECK_DEADLINE_S:-480}
dry=${GPU_CHECK_DRY_RUN:-0}
out=${OUT:-gpu-check-out}
mkdir -p "$out" && out=$(cd "$out" && pwd) || exit 1
work=${GPU_CHECK_WORK:-$(mktemp -d /tmp/gpu-check.XXXXXX)}
logs=$work/logs
mkdir -p "$logs" || exit 1
summary=$out/summary.txt
tarball=$out/gpu-check-logs.tar.gz
build=${GPU_CHECK_BUILD:-build-gpu}
gpu=${GPU_CHECK_DEVICE:-NVIDIA}
deps=$root/.gpu-deps/root
failed=() skipped=0
: >"$summary"
# The driver's tools where the image leaves them off the PATH (nvidia-smi with its libraries).
[ -d /usr/local/nvidia/bin ] && export PATH=$PATH:/usr/local/nvidia/bin

say() { echo "$*" | tee -a "$summary"; }
elapsed() { echo $(($(date +%s) - t0)); }

# summary.txt and the tarball of $logs into $OUT; the tarball is written beside and renamed, so
# a kill mid-write leaves the last whole one. Program binaries (*.bin) and meshes stay out.
refresh() {
    tar -czf "$out/.logs.partial" -C "$work" --exclude='*.bin' --exclude='*.ply' logs 2>/dev/null &&
        mv -f "$out/.logs.partial" "$tarball"
}

# step NAME TIMEOUT LOGFILE COMMAND...: a START line, COMMAND under timeout (capped by the global
# deadline) with its output in $logs/LOGFILE, then an END line with status, seconds and, for the
# test binary, Catch2's totals. Past the deadline: a SKIP line instead.
step() {
    local name=$1 limit=$2 log=$3 left start rc status totals
    shift 3
    left=$((t0 + deadline - $(date +%s)))
    if [ "$left" -lt 5 ]; then
        say "+$(elapsed)s SKIP  $name: the global deadline (${deadline} s) has passed"
        skipped=$((skipped + 1))
        refresh
        return 1
    fi
    [ "$limit" -le "$left" ] || limit=$left
    say "+$(elapsed)s START $name (timeout ${limit} s) [$log]"
    refresh
    start=$(date +%s)
    # bash -c: the step may be one of the functions below (exported); timeout signals the
    # whole process group, the test binary or the tool under the function included.
    timeout -k 5 "$limit" bash -c '"$@"' step "$@" >"$logs/$log" 2>&1
    rc=$?
    case $rc in
    0) status=ok ;;
    124 | 137) status="TIMEOUT after ${limit} s"; failed+=("$name") ;;
    *) status="FAILED rc=$rc"; failed+=("$name") ;;
    esac
    totals=$(grep -E '^(All tests passed|test cases|[0-9]+ matching test case)' "$logs/$log" | tail -n 1)
    say "+$(elapsed)s END   $name: $status ($(($(date +%s) - start)) s)${totals:+; $totals}"
    refresh
    return $rc
}

skip() { # skip NAME REASON: a step that cannot run, and why
    say "+$(elapsed)s SKIP  $1: $2"
    skipped=$((skipped + 1))
}

# Catch2 through the test binary: the cases FILTER selects, listed, then run with their times. A
# filter that selects nothing fails here (Catch2 2.x would pass it with exit 0; 3.x has no
# -w NoTests). Dry: the list only.
catch2() {
    local filter=$1
    shift
    env "$@" "$tests" "$filter" --list-tests >"$work/list.txt" 2>&1
    cat "$work/list.txt"
    grep -Eq '^[1-9][0-9]* matching test case' "$work/list.txt" || { echo "the filter selects no test case"; return 1; }
    [ "$dry" = 1 ] && return 0
    # exec: timeout waits for the binary itself, so its last words (the totals, or the case a
    # timeout's SIGTERM cut) are in the log before the END line.
    exec env "$@" "$tests" "$filter" --durations yes
}

# Catch2 in SHARDS processes at once (GPU_CHECK_SHARDS, default half the cores, at most 8): the
# cases FILTER selects, dealt round-robin, each shard named case by case (',', '[', ']', '*', '~',
# '"' and '\' escaped). The first lease's serial run finished 38 of 141 cases in 150 s on the GPU.
# Much of a case's work runs on the host (scenes, oracles, the referee), which more processes share
# out; how much of the GPU run's time it was is not profiled yet (docs/bench/gpu-h200.md). Each
# shard logs to LOGBASE-shardN.log; then every shard's log, and one line of totals. A timeout's SIGTERM reaches
# the shards too (timeout signals its process group): their cut cases are still reported. Dry: the
# list with tags, and each shard's spec listed again, which must select exactly its cases.
catch2_sharded() {
    local filter=$1 base=$2 shards=$3
    shift 3
    local names=$work/$base-names.txt n i rc=0 cut=0 r p
    catch2_list "$filter" "$@" >"$names"
    n=$(grep -c . "$names")
    [ "$n" -gt 0 ] || { cat "$names"; echo "the filter selects no test case"; return 1; }
    local specs=()
    for ((i = 0; i < shards; i++)); do
        specs[i]=$(awk -v k="$shards" -v i="$i" 'NF && (NR - 1) % k == i' "$names" |
            sed 's/[][\\,*~"]/\\&/g' | paste -sd, -)
    done
    if [ "$dry" = 1 ]; then
        env "$@" "$tests" "$filter" --list-tests # with their tags
        local total=0 got
        for ((i = 0; i < shards; i++)); do
            [ -n "${specs[i]}" ] || continue
            got=$(catch2_list "${specs[i]}" "$@" | grep -c .)
            echo "shard $i selects $got cases"
            total=$((total + got))
        done
        [ "$total" -eq "$n" ] || { echo "the shards select $total cases, the filter $n"; return 1; }
        echo "$n matching test cases, in $shards shards" # the summary's totals: the last such line
        return 0
    fi
    local pids=()
    trap 'cut=1' TERM
    for ((i = 0; i < shards; i++)); do
        [ -n "${specs[i]}" ] || continue
        env "$@" "$tests" "${specs[i]}" --durations yes >"$logs/$base-shard$i.log" 2>&1 &
        pids+=($!)
    done
    for p in "${pids[@]}"; do
        while :; do
            wait "$p"
            r=$?
            # A trapped signal interrupts wait with a status above 128 while the shard still runs.
            [ "$r" -gt 128 ] && kill -0 "$p" 2>/dev/null && continue
            break
        done
        [ "$r" = 0 ] || rc=1
    done
    local cases=0 passed=0 failed=0 f c pa fa
    for ((i = 0; i < shards; i++)); do
        f=$logs/$base-shard$i.log
        [ -e "$f" ] || continue
        echo "=== shard $i"
        cat "$f"
        if read -r c pa fa < <(sed -nE 's/^test cases: *([0-9]+) *\| *([0-9]+) passed *\| *([0-9]+) failed.*/\1 \2 \3/p' "$f" | tail -n 1) &&
            [ -n "$c" ]; then
            :
        elif c=$(sed -nE 's/^All tests passed \([0-9]+ assertions? in ([0-9]+) test cases?\).*/\1/p' "$f" | tail -n 1) && [ -n "$c" ]; then
            pa=$c fa=0
        else
            c=0 pa=0 fa=0
        fi
        cases=$((cases + c)) passed=$((passed + pa)) failed=$((failed + fa))
    done
    echo "test cases: $cases of $n run | $passed passed | $failed failed ($shards shards$([ "$cut" = 1 ] && echo ', cut by the timeout'))"
    [ "$cut" = 0 ] && [ "$rc" = 0 ] && [ "$cases" = "$n" ]
}

# The names FILTER selects, one a line: Catch2 2.x's --list-test-names-only, else 3.x's quiet list.
catch2_list() {
    local filter=$1
    shift
    # 2.x exits with the number of cases listed: the help says which form the binary takes.
    if "$tests" --help 2>/dev/null | grep -q -- --list-test-names-only; then
        env "$@" "$tests" "$filter" --list-test-names-only
    else
        env "$@" "$tests" "$filter" --list-tests --verbosity quiet
    fi
    return 0
}

# The tool. Dry: render and bench check their arguments instead (every flag named in the
# subcommand's --help, every value through its validators) and `clvis info` loads the mesh.
tool() {
    if [ "$dry" = 1 ] && { [ "$1" = render ] || [ "$1" = bench ]; }; then
        local help a
        help=$("$cli" "$@" --help) || return 1 # CLI11 checks the values even with --help
        for a in "${@:2}"; do
            case $a in
            --*) grep -qE -- "(^|[ ,])$a([ =,]|\$)" <<<"$help" || { echo "clvis $1 has no flag $a"; return 1; } ;;
            esac
        done
        [ "$1" != render ] || "$cli" info "$2" || return 1
        echo "dry run: clvis $* (arguments checked)"
        return
    fi
    exec "$cli" "$@"
}

dry_or() { # a build command, echoed instead in a dry run
    if [ "$dry" = 1 ]; then echo "dry run: $*"; else "$@"; fi
}
export -f catch2 catch2_sharded catch2_list tool dry_or
shards=${GPU_CHECK_SHARDS:-$(($(nproc) / 2))}
[ "$shards" -ge 1 ] || shards=1
[ "$shards" -le 8 ] || shards=8
export dry work

say "gpu-check $(date -u +%Y-%m-%dT%H:%M:%SZ), commit $(git rev-parse --short HEAD 2>/dev/null || echo '?')," \
    "deadline ${deadline} s$([ "$dry" = 1 ] && echo ', DRY RUN (no GPU, no build)')"
refresh

# --- 1. preflight ------------------------------------------------------------------------------
{
    echo "== uname"; uname -a
    echo "== os"; head -n 2 /etc/os-release 2>/dev/null
    echo "== cores"; nproc
    echo "== tools"; for t in cmake ninja c++ g++ python3 timeout tar; do echo "$t: $(command -v $t)"; done
    cmake --version 2>&1 | head -n 1; c++ --version 2>&1 | head -n 1
    echo "== carried (.gpu-deps)"; cat "$root/.gpu-deps/MANIFEST.txt" 2>/dev/null || echo none
    echo "== nvidia-smi"; timeout 30 nvidia-smi 2>&1
    echo "== OpenCL drivers and .icd files on disk"
    timeout 30 find /usr/local/nvidia /usr/lib /usr/lib64 /lib /etc/OpenCL /usr/share/OpenCL /usr/local/cuda/ \
        -maxdepth 4 \( -name '*nvidia-opencl*' -o -name 'libOpenCL.so*' -o -name '*.icd' \) 2>/dev/null
    echo "LD_LIBRARY_PATH=${LD_LIBRARY_PATH:-}"
} >"$logs/preflight.txt" 2>&1
gpu_name=$(timeout 30 nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>/dev/null |
    head -n 1)
say "host: $(nproc) cores; $(. /etc/os-release 2>/dev/null && echo "$PRETTY_NAME"); nvidia-smi: ${gpu_name:-no GPU}"

# Each prerequisite in the image or in .gpu-deps (scripts/gpu-prereqs.sh); a miss is said here,
# and the configure that needs it still runs, so its log says the rest.
have() { # have NAME PATH...: the first that exists, else a "missing" line
    local name=$1 p
    shift
    for p in "$@"; do [ -e "$p" ] && return 0; done
    say "missing: $name (looked in: $*; run scripts/gpu-prereqs.sh here and carry .gpu-deps)"
    return 1
}
inc=(/usr/include /usr/local/include "$deps/usr/include")
have "Catch2" "${inc[@]/%//catch2/catch.hpp}" "${inc[@]/%//catch2/catch_all.hpp}"
have "CLI11" "${inc[@]/%//CLI/CLI.hpp}"
have "nlohmann-json" "${inc[@]/%//nlohmann/json.hpp}"
have "OpenCL C headers" "${inc[@]/%//CL/cl.h}"
have "OpenCL C++ bindings" "${inc[@]/%//CL/opencl.hpp}"
loader=$(ldconfig -p 2>/dev/null | awk '/libOpenCL\.so\.1 .*x86-64/ {print $NF; exit}')
have "OpenCL ICD loader" $loader "$deps/usr/lib/x86_64-linux-gnu/libOpenCL.so.1"
for t in cmake c++ timeout tar python3; do command -v $t >/dev/null || say "missing: $t"; done
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
prefix=()
if [ -d "$deps/usr" ]; then
    # The carried packages first: CMake finds their configs and headers, and links their loader.
    prefix=(-DCMAKE_PREFIX_PATH="$deps/usr")
    export LD_LIBRARY_PATH=$deps/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
    export PATH=$PATH:$deps/usr/bin
fi

# NVIDIA's OpenCL driver: shipped unregistered (no nvidia.icd) on the machines seen. The ICD
# loader dlopens what an .icd file names, so the first libnvidia-opencl.so.1 found is written
# into a vendors folder of ours beside a copy of every registered .icd (PoCL's among them).
nv_lib="" nv_how=""
nv_lib=$(ldconfig -p 2>/dev/null | awk '/libnvidia-opencl\.so\.1 .*x86-64/ {print $NF; exit}')
[ -n "$nv_lib" ] && nv_how="ldconfig -p"
if [ -z "$nv_lib" ]; then
    # The soname link first; a driver folder copied without its links has only the versioned file.
    for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib \
             /lib/x86_64-linux-gnu /lib64 /lib; do
        for f in "$d/libnvidia-opencl.so.1" "$d"/libnvidia-opencl.so.[0-9]*.*; do
            [ -e "$f" ] && { nv_lib=$f nv_how="search of $d"; break 2; }
        done
    done
fi
if [ -z "$nv_lib" ]; then
    nv_lib=libnvidia-opencl.so.1 nv_how="not found: the bare soname, left to the dynamic linker"
elif [ "$nv_how" != "ldconfig -p" ]; then
    # Its own dependencies (libcuda.so.1 beside it) then resolve from the same folder.
    export LD_LIBRARY_PATH=$(dirname "$nv_lib")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
fi
vendors=$work/vendors
mkdir -p "$vendors"
icds=()
for f in /etc/OpenCL/vendors/*.icd /usr/local/nvidia/etc/OpenCL/vendors/*.icd /usr/share/OpenCL/vendors/*.icd; do
    [ -e "$f" ] || continue
    icds+=("$f -> $(head -c 200 "$f" | tr -d '\n')")
    cp "$f" "$vendors/" 2>/dev/null
done
grep -qil nvidia "$vendors"/*.icd 2>/dev/null || echo "$nv_lib" >"$vendors/nvidia.icd"
export OCL_ICD_VENDORS=$vendors
pocl=0
grep -qil pocl "$vendors"/*.icd 2>/dev/null && pocl=1
say "NVIDIA OpenCL driver: $nv_lib ($nv_how)"
say "registered .icd files: ${icds[*]:-none}; used: $(cd "$vendors" && ls | tr '\n' ' ')"
cp -r "$vendors" "$logs/vendors"

# OpenCL as the loader sees it, before anything is built. clinfo-l.txt only once clinfo -l has
# finished: a clinfo cut by its timeout proves nothing about the GPU.
opencl_list() {
    clinfo -l >"$logs/.clinfo-l" 2>&1
    mv "$logs/.clinfo-l" "$logs/clinfo-l.txt"
    clinfo
}
export -f opencl_list
export logs
if command -v clinfo >/dev/null; then
    step "clinfo" 60 clinfo.txt opencl_list
else
    skip "clinfo" "no clinfo in the image or .gpu-deps"
fi
# nvidia-smi sees a GPU, OpenCL lists none: everything after would test the wrong thing.
gpu_missing() { # by what clinfo -l and clvis devices listed, where they ran
    [ -n "$gpu_name" ] || return 1
    [ -e "$logs/clinfo-l.txt" ] || [ -e "$logs/devices.txt" ] || return 1
    ! grep -qi nvidia "$logs/clinfo-l.txt" "$logs/devices.txt" 2>/dev/null
}
check_gpu_listed() { # check_gpu_listed WHERE
    gpu_missing || return 0
    say "FAIL: nvidia-smi sees '$gpu_name' but OpenCL lists no NVIDIA device ($1); NVIDIA driver" \
        "tried: $nv_lib ($nv_how); see clinfo.txt, devices.txt and vendors/ in the tarball"
    [[ " ${failed[*]} " == *" NVIDIA OpenCL device "* ]] || failed+=("NVIDIA OpenCL device")
}
check_gpu_listed "clinfo -l"
refresh

# --- 2. build: the tool and the tests, each its own target -------------------------------------
tests=${GPU_CHECK_TESTS:-$root/$build/tests/clvis_tests}
cli=${GPU_CHECK_CLI:-$root/$build/clvis}
if [ "$dry" = 1 ] || [ -z "${GPU_CHECK_TESTS:-}${GPU_CHECK_CLI:-}" ]; then
    step "configure" 120 configure.log dry_or cmake -S . -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
        "${prefix[@]}" -DCLVIS_WITH_IMAGE_IO=OFF -DCLVIS_BUILD_BENCH_REFERENCES=OFF -DCLVIS_BUILD_PYTHON=OFF \
        -DCLVIS_WITH_MPI=OFF
    step "build the tool (clvis_cli)" 240 build-cli.log dry_or cmake --build "$build" --target clvis_cli -j "$(nproc)"
    step "build the tests (clvis_tests)" 300 build-tests.log dry_or cmake --build "$build" --target clvis_tests -j "$(nproc)"
    cp "$build/CMakeCache.txt" "$logs/" 2>/dev/null
fi
[ -x "$tests" ] || tests=""
[ -x "$cli" ] || cli=""
# A binary built elsewhere and carried may need a library this image lacks (each step would then
# end with rc 127 and nothing else said): name it, and run nothing with that binary.
unresolved() { # unresolved BINARY: the "not found" libraries of its ldd, comma-separated
    [ "$dry" = 1 ] && return 0
    ldd "$1" 2>&1 | awk '/not found/ {printf "%s%s", (n++ ? ", " : ""), $1}'
}
for b in tests cli; do
    [ -n "${!b}" ] || continue
    libs=$(unresolved "${!b}")
    if [ -n "$libs" ]; then
        say "FAIL: ${!b} needs $libs, not found here (LD_LIBRARY_PATH=${LD_LIBRARY_PATH:-}); carry them" \
            "(scripts/gpu-prereqs.sh) or build on this machine"
        failed+=("$b: missing libraries")
        printf -v "$b" '%s' ""
    fi
done
export tests cli
say "binaries: tests ${tests:-NOT BUILT}, tool ${cli:-NOT BUILT}"

# --- 3. on the GPU -----------------------------------------------------------------------------
export CLVIS_CACHE_DIR=$logs/cache CLVIS_TEST_CACHE_DIR=$logs/cache # tuned choices come back
if [ -n "$cli" ]; then
    step "clvis devices" 60 devices.txt tool devices
    check_gpu_listed "clvis devices"
fi
why=""
if gpu_missing; then
    tests="" cli="" why="OpenCL lists no NVIDIA device (see the FAIL line)"
fi
export CLVIS_DEVICE=$gpu
no_tests=${why:-clvis_tests was not built or cannot run (see above)}
no_cli=${why:-the tool was not built or cannot run (see above)}

# The device suite: what CI runs as the CTest entry "device", less what holds only on PoCL's CPU
# device or needs what this machine lacks, and less the parts that run as their own steps below.
device_filter=(
    "[device]~[.]"
    "~[slow]"          # the slow cases: their own step, last
    "~[agree]"         # the agreement suite: its own step
    "~[rule]"          # the raster-rule cases: their own step
    "~[pocl]"          # asserts PoCL's CPU device (type cpu) or PoCL's own program cache
    "~[multi_device]"  # each case opens every CPU device (cpu_devices(), multi_device_test.cpp)
    "~[gltf]"          # needs /usr/share/assimp/models/glTF2 (assimp-testmodels), not on that machine
    # opens Device::open("cpu"): fails where no CPU device is registered (no PoCL there)
    "~\"devices are picked by index*\""
)
agree_filter="[device][agree]~[.]~[gltf]" # fast and slow; the glTF samples case as above
rule_filter="[device][rule]~[.]~[slow]"
slow_filter="[device][slow]~[.]~[agree]~[multi_device]~[pocl]"
# As the CTest entry device_exact_float: the watertightness cases with every kernel built with
# the float-only exact edge fallback (CLVIS_EXACT_FLOAT=1), the form devices without fp64 use;
# one list, tests/exact_float_cases.txt, serves both.
exact_float_filter=$(head -n 1 "$root/tests/exact_float_cases.txt")

if [ -n "$tests" ]; then
    step "device suite on $gpu" 240 device.log catch2_sharded "$(printf '%s' "${device_filter[@]}")" device "$shards"
    step "agreement suite on $gpu" 150 agree.log catch2 "$agree_filter"
    step "raster-rule cases on $gpu" 60 rule.log catch2 "$rule_filter"
    step "float-only exact fallback on $gpu" 120 exact-float.log catch2_sharded "$exact_float_filter" exact-float \
        "$shards" CLVIS_EXACT_FLOAT=1
    # The GPU's keys against PoCL's, bit for bit where both round division and square root
    # correctly (reference_device_test.cpp): the one comparison CI cannot make.
    if [ "$pocl" = 1 ]; then
        step "keys on $gpu against PoCL's" 120 reference-pocl.log catch2 "[.reference]" \
            "CLVIS_REFERENCE_DEVICE=portable computing language"
    else
        skip "keys on $gpu against PoCL's" "no PoCL .icd registered in the image"
    fi
else
    for s in "device suite on $gpu" "agreement suite on $gpu" "raster-rule cases on $gpu" \
             "float-only exact fallback on $gpu" "keys on $gpu against PoCL's"; do
        skip "$s" "$no_tests"
    done
fi

# Timings: the quick sweep judged by the referee, then 1080p renders of the closing note's
# anchors (cudaraster on an H100: bunny 0.30 ms, 1M sphere 1.04 ms) and of each fine-stage and
# ray mapping on the bunny (Auto's choices are in the tarball's cache/ and devices-tuned.txt).
export sphere=$work/sphere-1M.ply
make_sphere() { # make_uv_sphere(2^20)'s mesh (host/scene/procedural.cpp) as a binary PLY
    local py
    for py in python3 /usr/bin/python3; do "$py" -c 'import numpy' 2>/dev/null && break; done
    "$py" - "$sphere" <<'EOF'
import sys, numpy as np
t = float(1 << 20)
stacks = max(2, int(np.floor((1 + np.sqrt(1 + t)) / 2 + 0.5)))
seg = max(4, int(np.floor(t / (2 * (stacks - 1)) + 0.5)))
th = np.arange(1, stacks) / (2.0 * stacks) * 2 * np.pi
ph = np.arange(seg) / float(seg) * 2 * np.pi
st, ct = np.sin(th)[:, None], np.cos(th)[:, None]
ring = np.stack([st * np.cos(ph), np.broadcast_to(ct, (stacks - 1, seg)), st * np.sin(ph)], -1).reshape(-1, 3)
pos = np.concatenate([[[0, 1, 0]], ring, [[0, -1, 0]]]).astype('<f4')
south = 1 + (stacks - 1) * seg
r = lambda i, j: 1 + (i - 1) * seg + j % seg
j = np.arange(seg)
tri = [np.stack([np.zeros(seg, int), r(1, j + 1), r(1, j)], 1)]
for i in range(1, stacks - 1):
    a, b, c, d = r(i, j), r(i, j + 1), r(i + 1, j), r(i + 1, j + 1)
    tri.append(np.stack([np.stack([a, d, c], 1), np.stack([a, b, d], 1)], 1).reshape(-1, 3))
tri.append(np.stack([np.full(seg, south), r(stacks - 1, j), r(stacks - 1, j + 1)], 1))
idx = np.concatenate(tri).astype('<u4')
face = np.zeros(len(idx), dtype=[('n', 'u1'), ('v', '<u4', 3)]); face['n'] = 3; face['v'] = idx
with open(sys.argv[1], 'wb') as f:
    f.write(('ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n'
             'property float z\nelement face %d\nproperty list uchar uint vertex_indices\nend_header\n'
             % (len(pos), len(idx))).encode())
    f.write(pos.tobytes()); f.write(face.tobytes())
print(len(pos), 'vertices', len(idx), 'triangles')
EOF
}
export -f make_sphere
if [ -n "$cli" ]; then
    # Each program's build seconds on a cold cache (CLVIS_BUILD_LOG prints them): the first case
    # of each device-suite shard and the depth-layer cases took 2-3x PoCL's time on the H200.
    step "program builds on $gpu, cold cache, both paths with 4 depth layers" 90 builds.log \
        env CLVIS_BUILD_LOG=1 CLVIS_CACHE_DIR="$work/cold-cache" bash -c 'tool "$@"' tool render \
        scenes/stanford-bunny.obj --path all --layers 4 --width 640 --height 480 --timings --device "$gpu"
    step "clvis bench --quick on $gpu" 150 bench.log tool bench --quick --no-plot --device "$gpu" --out "$logs/bench"
    # Ray queries (AO rays off the bunny and a sphere, random rays in a soup): closest, any, all.
    step "clvis bench --rays --quick on $gpu" 60 bench-rays.log tool bench --rays --quick --no-plot --device "$gpu" \
        --out "$logs/bench-rays"
    if step "1M-triangle sphere (make_uv_sphere) as PLY" 30 sphere.log make_sphere && [ -s "$sphere" ]; then
        for p in raster ray; do
            step "render sphere-1M 1920x1080 $p on $gpu" 60 "render-sphere-$p.log" \
                tool render "$sphere" --path "$p" --width 1920 --height 1080 --repeat 20 --timings --json --device "$gpu"
        done
    else
        skip "render sphere-1M 1920x1080 raster and ray on $gpu" "no sphere-1M.ply (see sphere.log)"
    fi
    for run in raster:square raster:pixel ray:packet ray:single; do
        p=${run%%:*} m=${run#*:}
        step "render bunny 1920x1080 $p $m on $gpu" 60 "render-bunny-$p-$m.log" \
            tool render scenes/stanford-bunny.obj --path "$p" "--$p-mapping" "$m" --width 1920 --height 1080 \
            --repeat 20 --timings --json --device "$gpu"
    done
else
    skip "clvis bench --quick and the 1080p renders on $gpu" "$no_cli"
fi
if [ -n "$tests" ]; then
    step "slow device cases on $gpu" 120 slow.log catch2 "$slow_filter"
else
    skip "slow device cases on $gpu" "$no_tests"
fi
# The same machine's PoCL on its 16 cores: CTest's device entry (what CI runs on 2 cores), then
# the quick sweep and the bunny at 1080p, the figures that set the GPU's beside a CPU's.
if [ "$pocl" = 1 ]; then
    if [ -n "$tests" ]; then
        # ~[gltf] as on the GPU: assimp-testmodels' files are not on that machine (a build that
        # links tinygltf compiles the samples' case in).
        step "device suite on PoCL" 180 device-pocl.log catch2_sharded "[device]~[slow]~[.]~[multi_device]~[gltf]" \
            device-pocl "$shards" CLVIS_DEVICE=cpu
    else
        skip "device suite on PoCL" "$no_tests"
    fi
    if [ -n "$cli" ]; then
        step "clvis bench --quick on PoCL" 120 bench-pocl.log tool bench --quick --no-plot --device cpu \
            --out "$logs/bench-pocl"
        step "clvis bench --rays --quick on PoCL" 60 bench-rays-pocl.log tool bench --rays --quick --no-plot \
            --device cpu --out "$logs/bench-rays-pocl"
        for p in raster ray; do
            step "render bunny 1920x1080 $p on PoCL" 60 "render-bunny-$p-pocl.log" \
                tool render scenes/stanford-bunny.obj --path "$p" --width 1920 --height 1080 --repeat 20 \
                --timings --json --device cpu
        done
    else
        skip "clvis bench --quick and the bunny on PoCL" "$no_cli"
    fi
else
    skip "device suite, bench and the bunny on PoCL" "no PoCL .icd registered in the image"
fi
# Auto's choices, as measured on the GPU.
[ -n "$cli" ] && [ "$(elapsed)" -lt "$deadline" ] && timeout 30 bash -c 'tool devices' >"$logs/devices-tuned.txt" 2>&1

if [ ${#failed[@]} -eq 0 ]; then
    say "+$(elapsed)s result: ok ($skipped skipped)"
else
    say "+$(elapsed)s result: FAILED: $(printf '%s; ' "${failed[@]}")($skipped skipped)"
fi
refresh
say "outputs: $(cd "$out" && ls | tr '\n' ' ')(tarball $(du -k "$tarball" | cut -f1) KiB)"
[ ${#failed[@]} -eq 0 ]
