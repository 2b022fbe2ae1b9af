#!/usr/bin/env bash
# clvis's Python ray queries against Open3D's RaycastingScene (Embree 4), bench/bench_open3d.py.
# Open3D is an optional reference: it lives in its own virtual environment, .venv-bench at the
# repository's root (git-ignored), never in the set-up's .venv.
#  - Debian's /usr/bin/python3 without --system-site-packages: numpy and Open3D come from PyPI
#    (open3d-cpu where it has a wheel for this Python, else open3d, whose wheel carries a CUDA
#    module that runs on the CPU as well).
#  - clvis is built and installed into it as scripts/python_env.sh does for .venv (same
#    build-python/ folder, ccache when installed). CLVIS_BENCH_PYTHONPATH=DIR skips that build and
#    puts DIR (a site-packages holding a built clvis, e.g. .venv/lib/python3.11/site-packages) first
#    on PYTHONPATH instead; the module needs no numpy of its own build (nanobind).
# Usage: bash scripts/bench_open3d.sh [bench_open3d.py flags]   (--help lists them)
# Idempotent: a second run installs nothing unless the sources changed since clvis was installed
# (another commit, or other uncommitted changes: then it is rebuilt; CLVIS_BENCH_REBUILD=1 forces
# it). Timings of the install go to stderr.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
venv="$repo/.venv-bench"
py="$venv/bin/python"
pipq() { "$py" -m pip install -q --disable-pip-version-check "$@"; }

if [ ! -x "$py" ]; then
  echo "[bench-open3d] creating $venv" >&2
  /usr/bin/python3 -m venv "$venv"
fi
if ! "$py" -c 'import open3d, numpy' 2>/dev/null; then
  t0=$(date +%s)
  echo "[bench-open3d] installing Open3D and numpy from PyPI" >&2
  pipq numpy
  pipq open3d-cpu || pipq open3d
  echo "[bench-open3d] Open3D installed in $(( $(date +%s) - t0 )) s;" \
       "$venv holds $(du -sh "$venv" | cut -f1)" >&2
fi

# What the installed module was built from: the commit and a hash of the uncommitted changes to
# tracked files (empty outside a git checkout: then it is rebuilt every run). A module built from
# other sources is rebuilt, so the bench never times stale code.
source_state() {
  local head
  head=$(git -C "$repo" rev-parse HEAD 2>/dev/null) || return 0
  echo "$head $(git -C "$repo" diff HEAD 2>/dev/null | sha1sum | cut -c1-12)"
}
stamp="$venv/.clvis-source"
source_id=$(source_state)

# Whether the installed clvis was built from these sources (and no rebuild is asked for).
installed_current() {
  [ -z "${CLVIS_BENCH_REBUILD:-}" ] && [ -n "$source_id" ] &&
    [ "$(cat "$stamp" 2>/dev/null)" = "$source_id" ] && (cd / && "$py" -c 'import clvis' 2>/dev/null)
}

if [ -n "${CLVIS_BENCH_PYTHONPATH:-}" ]; then
  export PYTHONPATH="$CLVIS_BENCH_PYTHONPATH${PYTHONPATH:+:$PYTHONPATH}"
elif ! installed_current; then
  if ! "$py" -c 'import nanobind, scikit_build_core' 2>/dev/null; then
    pipq "nanobind>=2" "scikit-build-core>=0.10"
  fi
  if command -v ccache >/dev/null; then
    export CMAKE_ARGS="${CMAKE_ARGS:-} -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache"
    export CCACHE_BASEDIR="$repo"
  fi
  t0=$(date +%s)
  echo "[bench-open3d] building and installing clvis into $venv" >&2
  pipq --no-build-isolation "$repo"
  printf '%s\n' "$source_id" > "$stamp"
  echo "[bench-open3d] clvis installed in $(( $(date +%s) - t0 )) s" >&2
fi

cd "$repo"
exec "$py" bench/bench_open3d.py "$@"
