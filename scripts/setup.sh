#!/usr/bin/env bash
# Installs everything clvis needs from Debian 12's packages, then the Python package into .venv
# (scripts/python_env.sh). Idempotent; run as root.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git ca-certificates python3 ccache
  # OpenCL: the ICD loader, headers, C++ bindings and PoCL's CPU device
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  # a second OpenCL implementation for the rusticl CTest: Mesa's Rusticl (RUSTICL_ENABLE=llvmpipe)
  mesa-opencl-icd
  # libraries
  libopenimageio-dev openimageio-tools catch2 libcli11-dev nlohmann-json3-dev
  # glTF 2.0 files
  libtinygltf-dev
  # MPI (optional at build time: clvis::dist, clvis render --distribute)
  libopenmpi-dev openmpi-bin
  # reference renderers for the benchmark: Embree and Mesa's llvmpipe through EGL
  libembree-dev libegl-dev libopengl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri
  # plots; the Python package's virtual environment (scripts/python_env.sh)
  python3-matplotlib python3-numpy python3-venv python3-dev
  # hardening: Oclgrind, clang's sanitizers and libFuzzer, malformed test files
  oclgrind clang libclang-rt-14-dev assimp-testmodels valgrind
  # peak memory of the tool (/usr/bin/time -v): the instances_memory and memory_per_triangle CTests
  time
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "[setup] installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
echo "[setup] dependencies present"

# The Python package, installed into .venv at the repository's root.
bash "$(dirname "$0")/python_env.sh"
