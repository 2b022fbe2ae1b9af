#!/usr/bin/env bash
# Fuzzes the scene loaders: builds the libFuzzer targets of tests/fuzz/ with clang in build-fuzz
# (ASan + UBSan), then runs each for SECONDS_PER_TARGET (default 48) from its seed corpus and
# dictionary (tests/fuzz/corpus/, tests/fuzz/dict/) and prints the executions per target. A
# fuzzer is one single-threaded process, so JOBS of them (default: the cores) run side by side:
# every target still gets its whole time on a core of its own.
# A crash stops with the input under build-fuzz/artifacts/;
# once fixed, keep it in tests/fuzz/regressions/<format>/ (fuzz_regression_test.cpp replays it).
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-48}
jobs=${JOBS:-$(nproc)}

launcher=()
if command -v ccache >/dev/null; then  # as scripts/test.sh: a second run rebuilds only what changed
  export CCACHE_BASEDIR=$(pwd)
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# -O2 with line tables only (-g1): full debug information only slowed the build.
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
      "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" \
      -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCLVIS_FUZZ=ON \
      -DCLVIS_BUILD_TESTS=OFF -DCLVIS_BUILD_CLI=OFF -DCLVIS_WITH_IMAGE_IO=OFF \
      -DCLVIS_BUILD_BENCH_REFERENCES=OFF >/dev/null
cmake --build build-fuzz -j "$jobs" --target fuzz_obj fuzz_ply fuzz_stl fuzz_gltf fuzz_scene_file

# target, corpus folder, largest input in bytes (the seeds' largest is about 50 KB)
targets=("fuzz_obj obj 65536" "fuzz_ply ply 65536" "fuzz_stl stl 65536" "fuzz_gltf gltf 65536"
         "fuzz_scene_file scene 4096")
# Runs one target; its exit status is the fuzzer's.
fuzz_one() {
  local target=$1 format=$2 max_len=$3
  local work=build-fuzz/corpus/$format         # grows as the fuzzer learns; the seeds stay untouched
  local artifacts=build-fuzz/artifacts/$format/
  mkdir -p "$work" "$artifacts"
  ./build-fuzz/tests/fuzz/$target "$work" tests/fuzz/corpus/$format tests/fuzz/regressions/$format \
      -dict=tests/fuzz/dict/$format.dict \
      -max_total_time="$seconds" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$artifacts" >"build-fuzz/$target.log" 2>&1
}

pids=()
names=()
statuses=()
waited=0 # fuzzers [0, waited) have ended, their exit statuses in statuses[]
reap() { local status=0; wait "${pids[$waited]}" || status=$?; statuses+=("$status"); waited=$((waited + 1)); }
for entry in "${targets[@]}"; do
  read -r target format max_len <<<"$entry"
  # at most `jobs` fuzzers at a time: the oldest ends before another starts
  if [ $(( ${#pids[@]} - waited )) -ge "$jobs" ]; then reap; fi
  echo "[fuzz] $target for ${seconds} s"
  fuzz_one "$target" "$format" "$max_len" &
  pids+=("$!")
  names+=("$target $format")
done

while [ "$waited" -lt "${#pids[@]}" ]; do reap; done
failed=0
summary=()
for i in "${!pids[@]}"; do
  read -r target format <<<"${names[$i]}"
  status=${statuses[$i]}
  log=build-fuzz/$target.log
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  summary+=("$target: ${runs:-?} executions")
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$log"
    echo "[fuzz] $target FAILED (exit $status); the input is under build-fuzz/artifacts/$format/" >&2
    failed=1
  fi
done
printf '[fuzz] %s\n' "${summary[@]}"
exit "$failed"
