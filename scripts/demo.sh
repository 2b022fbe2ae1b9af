#!/usr/bin/env bash
# The main job on a bundled real mesh: builds clvis, lists the OpenCL devices, reports the mesh,
# renders the Stanford bunny by rasterization and by ray casting (warm frames timed), compares the
# two with the referee, and writes images and buffers into out/.
# Run scripts/setup.sh first (the README's run command does both).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
clvis=./build/clvis
set -x
$clvis devices
$clvis info scenes/stanford-bunny.obj
$clvis render scenes/stanford-bunny.obj --path all --repeat 5 \
    --image out/bunny.png --ids out/bunny-ids.tif --depth out/bunny-depth.exr
$clvis render scenes/stanford-bunny.obj --path raster --shade ids --image out/bunny-ids.png
