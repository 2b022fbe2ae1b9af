#!/usr/bin/env bash
# Run HERE (Debian 12, with its package registry), before a GPU run: the GPU machine reaches no
# registry, and its image may lack the build's header-only prerequisites. Downloads Debian 12's
# packages of them (no install: `apt-get download`), unpacks each (`dpkg -x`) into .gpu-deps/root
# (ignored by git; the device run carries it: `carry: [".gpu-deps"]`), and writes
# .gpu-deps/MANIFEST.txt (package, version, what it gives). scripts/gpu-check.sh points CMake at
# .gpu-deps/root/usr (CMAKE_PREFIX_PATH) and runs the carried ICD loader and clinfo.
#
#   catch2 2.13 (header and CMake config)   libcli11-dev (CLI11)   nlohmann-json3-dev
#   opencl-c-headers, opencl-clhpp-headers (<CL/cl.h>, <CL/opencl.hpp>)
#   ocl-icd-libopencl1, ocl-icd-opencl-dev (the ICD loader and its link name: the image may have none)
#   clinfo (lists the platforms before anything is built)
#   libtinygltf2d, libstb0 (the runtime libraries of glTF loading: a build made here, where
#     libtinygltf-dev is installed, links them, and the GPU machine's image has neither)
#
# Every file is plain data or an x86-64 library and program that needs only glibc (the H200
# image's Ubuntu 24.04 has a newer glibc than Debian 12's). Idempotent: re-run to refresh.
#   bash scripts/gpu-prereqs.sh            # about 4 MiB, under 10 s
set -euo pipefail
cd "$(dirname "$0")/.."
deps=.gpu-deps
packages=(catch2 libcli11-dev nlohmann-json3-dev opencl-c-headers opencl-clhpp-headers
          ocl-icd-libopencl1 ocl-icd-opencl-dev clinfo libtinygltf2d libstb0)

rm -rf "$deps"
mkdir -p "$deps/debs" "$deps/root"
apt_opts=()
if [ "$(dpkg --print-architecture)" != amd64 ]; then
    # The GPU machine is x86-64: fetch amd64 packages through lists of their own (device README).
    mkdir -p /tmp/gpu-prereqs-lists/partial
    apt_opts=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/gpu-prereqs-lists)
    apt-get "${apt_opts[@]}" update -qq
fi
# apt-get download writes into the current folder; as root it warns that _apt cannot write there.
(cd "$deps/debs" && apt-get "${apt_opts[@]}" download "${packages[@]}" 2>&1 | grep -v '^W: Download is performed unsandboxed' || true)
for p in "${packages[@]}"; do
    deb=$(ls "$deps"/debs/"${p}"_*.deb 2>/dev/null | head -n 1)
    if [ -z "$deb" ]; then
        echo "gpu-prereqs: $p was not downloaded" >&2
        exit 1
    fi
    dpkg -x "$deb" "$deps/root"
done
rm -rf "$deps/root/usr/share/doc" "$deps/root/usr/share/man" "$deps/root/usr/share/lintian"

# What each package must give, checked here rather than found missing on the GPU machine.
need=(usr/include/catch2/catch.hpp usr/lib/cmake/Catch2/Catch2Config.cmake
      usr/include/CLI/CLI.hpp usr/share/cmake/CLI11/CLI11Config.cmake
      usr/include/nlohmann/json.hpp usr/share/cmake/nlohmann_json/nlohmann_jsonConfig.cmake
      usr/include/CL/cl.h usr/include/CL/opencl.hpp
      usr/lib/x86_64-linux-gnu/libOpenCL.so.1 usr/lib/x86_64-linux-gnu/libOpenCL.so usr/bin/clinfo
      usr/lib/x86_64-linux-gnu/libtinygltf.so.2d usr/lib/x86_64-linux-gnu/libstb.so.0)
for f in "${need[@]}"; do
    if [ ! -e "$deps/root/$f" ]; then
        echo "gpu-prereqs: $f is missing from the unpacked packages" >&2
        exit 1
    fi
done

{
    echo "# Debian 12 packages unpacked by scripts/gpu-prereqs.sh on $(date -u +%Y-%m-%dT%H:%MZ)"
    for deb in "$deps"/debs/*.deb; do
        dpkg-deb -W --showformat='${Package} ${Version}\n' "$deb"
    done
} >"$deps/MANIFEST.txt"
rm -rf "$deps/debs" # the unpacked tree is what travels
size_kib=$(du -sk "$deps" | cut -f1)
if [ "$size_kib" -gt $((16 * 1024)) ]; then
    echo "gpu-prereqs: $deps is ${size_kib} KiB, more than the 16 MiB planned (carry allows 64 MiB in all)" >&2
    exit 1
fi
cat "$deps/MANIFEST.txt"
echo "gpu-prereqs: $deps holds ${size_kib} KiB; the device run carries it (carry: [\".gpu-deps\"])"
