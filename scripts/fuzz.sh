#!/usr/bin/env bash
# Fuzzes the scene loaders: builds the libFuzzer targets of tests/fuzz/ with clang in build-fuzz
# (ASan + UBSan), then runs each for SECONDS_PER_TARGET (default 48: five formats in about the
# four minutes four took) from its seed corpus and
# dictionary (tests/fuzz/corpus/, tests/fuzz/dict/) and prints the executions per target.
# A crash stops with the input under build-fuzz/artifacts/;
# once fixed, keep it in tests/fuzz/regressions/<format>/ (fuzz_regression_test.cpp replays it).
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-48}
jobs=${JOBS:-$(nproc)}

cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCLVIS_FUZZ=ON \
      -DCLVIS_BUILD_TESTS=OFF -DCLVIS_BUILD_CLI=OFF -DCLVIS_WITH_IMAGE_IO=OFF \
      -DCLVIS_BUILD_BENCH_REFERENCES=OFF >/dev/null
cmake --build build-fuzz -j "$jobs" --target fuzz_obj fuzz_ply fuzz_stl fuzz_gltf fuzz_scene_file

# target, corpus folder, largest input in bytes (the seeds' largest is about 50 KB)
targets=("fuzz_obj obj 65536" "fuzz_ply ply 65536" "fuzz_stl stl 65536" "fuzz_gltf gltf 65536"
         "fuzz_scene_file scene 4096")
summary=()
for entry in "${targets[@]}"; do
  read -r target format max_len <<<"$entry"
  work=build-fuzz/corpus/$format         # grows as the fuzzer learns; the seeds stay untouched
  artifacts=build-fuzz/artifacts/$format/
  log=build-fuzz/$target.log
  mkdir -p "$work" "$artifacts"
  echo "[fuzz] $target for ${seconds} s"
  status=0
  ./build-fuzz/tests/fuzz/$target "$work" tests/fuzz/corpus/$format tests/fuzz/regressions/$format \
      -dict=tests/fuzz/dict/$format.dict \
      -max_total_time="$seconds" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$artifacts" >"$log" 2>&1 || status=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  summary+=("$target: ${runs:-?} executions")
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$log"
    echo "[fuzz] $target FAILED (exit $status); the input is under $artifacts" >&2
    exit 1
  fi
done
printf '[fuzz] %s\n' "${summary[@]}"
