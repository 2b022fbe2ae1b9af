#!/usr/bin/env bash
# The whole test suite, as CI runs it (the README's test command runs scripts/setup.sh first):
#  1. Release build; CTest, two entries at a time: host tests, device tests on PoCL's CPU device,
#     the agreement suites, Oclgrind over every kernel, Rusticl, MPI, the installed package built
#     and run by examples/; then the Python package (reinstalled into .venv) and its pytest suite,
#     the clean-clone install included;
#  2. AddressSanitizer + UndefinedBehaviorSanitizer build; the host tests under it;
#  3. libFuzzer over each scene loader for FUZZ_SECONDS each (default 48, five loaders).
#  4. With --extended (or CLVIS_TEST_EXTENDED=1): the CTest entries labelled `extended` too, the
#     long sweeps that repeat a class of check the stages above already make on more inputs
#     (tests/CMakeLists.txt says what each holds). .ci/run picks when CI runs them.
# Every build goes through ccache where it is installed (scripts/setup.sh installs it), with the
# repository as its base folder: the Python wheel's library objects (scripts/python_env.sh, which
# the set-up runs first) serve the Release build, and a second run rebuilds only what changed.
# The end of the run prints what each stage cost.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
extended=${CLVIS_TEST_EXTENDED:-0}
for arg in "$@"; do
  case "$arg" in
    --extended) extended=1 ;;
    *) echo "usage: scripts/test.sh [--extended]" >&2; exit 2 ;;
  esac
done
jobs=$(nproc)
fuzz_seconds=${FUZZ_SECONDS:-48}
start=$(date +%s)
costs=()
last_stage=""
last_start=$start
stage() {
  local now
  now=$(date +%s)
  if [ -n "$last_stage" ]; then costs+=("$(printf '%5d s  %s' $((now - last_start)) "$last_stage")"); fi
  last_stage="$*"
  last_start=$now
  echo; echo "[test] $* ($((now - start)) s)"
}
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$repo"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi

stage "Release build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" >/dev/null
cmake --build build -j "$jobs"

stage "CTest: host, device, agreement, Oclgrind, Rusticl, MPI, consumer"
# Two entries at a time: Oclgrind simulates on one thread, the consumer and CLI entries wait on
# compilers and processes, so a second entry fills the other core (tests/CMakeLists.txt).
ctest --test-dir build --output-on-failure -j "$jobs" -LE extended

stage "Python package: pytest (python/tests)"
bash scripts/python_env.sh
rc=0
CLVIS_DEVICE=cpu .venv/bin/python -m pytest -q -p no:cacheprovider python/tests || rc=$?
# pytest exits 5 when it collected nothing: a suite that silently vanished is a failure too.
if [ "$rc" -eq 5 ]; then echo "[test] pytest collected no tests in python/tests"; fi
if [ "$rc" -ne 0 ]; then exit "$rc"; fi

stage "Sanitizer build (ASan + UBSan)"
# -Og -g1 (line tables: reports still name file and line): a quarter of the compile time of
# -O2 -g, for host tests that run as fast.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug "-DCMAKE_CXX_FLAGS_DEBUG=-Og -g1" \
      "-DCMAKE_C_FLAGS_DEBUG=-Og -g1" -DCLVIS_SANITIZE=ON "${launcher[@]}" \
      -DCLVIS_BUILD_CLI=OFF -DCLVIS_BUILD_BENCH_REFERENCES=OFF >/dev/null
cmake --build build-asan -j "$jobs" --target clvis_tests
stage "Host tests under the sanitizers"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -L host -LE extended

stage "Fuzzing the scene loaders (${fuzz_seconds} s per format)"
bash scripts/fuzz.sh "$fuzz_seconds"

if [ "$extended" = 1 ]; then
  stage "Extended CTest entries (label extended)"
  ctest --test-dir build --output-on-failure -j "$jobs" -L extended
fi

stage "All tests passed"
echo "[test] what each stage cost (wall clock, $jobs cores):"
printf '[test] %s\n' "${costs[@]}"
