#!/usr/bin/env bash
# Builds clvis and runs the whole test suite: the Release build's tests (host, device on PoCL's
# CPU device, the agreement suites), the consumer project against the installed package.
# Run scripts/setup.sh first (the README's test command does both).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)

echo "[test] Release build"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$PWD/build/install" >/dev/null
cmake --build build -j "$jobs"
cmake --install build >/dev/null
echo "[test] ctest"
ctest --test-dir build --output-on-failure -j 1
