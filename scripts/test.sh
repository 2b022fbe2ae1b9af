#!/usr/bin/env bash
# The whole test suite, as CI runs it (the README's test command runs scripts/setup.sh first):
#  1. Release build; CTest: host tests, device tests on PoCL's CPU device, the agreement suites,
#     Oclgrind over every kernel, the installed package built and run by examples/;
#     then the Python package (reinstalled into .venv) and its pytest suite, the clean-clone
#     install included;
#  2. AddressSanitizer + UndefinedBehaviorSanitizer build; the host tests under it;
#  3. libFuzzer over each scene loader for FUZZ_SECONDS each (default 48, five loaders).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
fuzz_seconds=${FUZZ_SECONDS:-48}
start=$(date +%s)
stage() { echo; echo "[test] $* ($(( $(date +%s) - start )) s)"; }

stage "Release build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs"

stage "CTest: host, device, agreement, Oclgrind, consumer"
ctest --test-dir build --output-on-failure -j 1

stage "Python package: pytest (python/tests)"
bash scripts/python_env.sh
rc=0
CLVIS_DEVICE=cpu .venv/bin/python -m pytest -q -p no:cacheprovider python/tests || rc=$?
# pytest exits 5 when it collected nothing: a suite that silently vanished is a failure too.
if [ "$rc" -eq 5 ]; then echo "[test] pytest collected no tests in python/tests"; fi
if [ "$rc" -ne 0 ]; then exit "$rc"; fi

stage "Sanitizer build (ASan + UBSan)"
# -Og -g1 (line tables: reports still name file and line): a quarter of the compile time of
# -O2 -g, which took 12 of the suite's 45 minutes on 2 cores, for host tests that run as fast.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-Og -g1" \
      "-DCMAKE_C_FLAGS_DEBUG=-Og -g1" -DCLVIS_SANITIZE=ON \
      -DCLVIS_BUILD_CLI=OFF -DCLVIS_BUILD_BENCH_REFERENCES=OFF >/dev/null
cmake --build build-asan -j "$jobs" --target clvis_tests
stage "Host tests under the sanitizers"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -L host

stage "Fuzzing the scene loaders (${fuzz_seconds} s per format)"
bash scripts/fuzz.sh "$fuzz_seconds"

stage "All tests passed"
