#!/usr/bin/env bash
# Builds clvis and runs it on a bundled real mesh: lists the OpenCL devices and reports the mesh.
# Run scripts/setup.sh first (the README's run command does both).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
./build/clvis devices
./build/clvis info scenes/stanford-bunny.obj scenes/spot.obj
