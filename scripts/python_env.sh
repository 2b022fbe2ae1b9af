#!/usr/bin/env bash
# The Python package in a virtual environment at the repository's root (.venv), for the README's
# set-up and test commands. Idempotent; a second run only rebuilds what changed.
#  - Debian's /usr/bin/python3, never a pyenv shim on the PATH (it lacks Debian's modules).
#  - --system-site-packages: numpy and matplotlib come from Debian (python3-numpy,
#    python3-matplotlib), one numpy that matplotlib was built against; PyPI gives only what Debian
#    lacks or has too old: nanobind, scikit-build-core (the build) and pytest.
#  - pip install --no-build-isolation: builds with the tools above, with no download per build;
#    ccache (when installed) makes rebuilds from a fresh clone quick.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
venv="$repo/.venv"

if [ ! -x "$venv/bin/python" ]; then
  echo "[python] creating $venv"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
if ! "$venv/bin/python" -c 'import nanobind, scikit_build_core, pytest, numpy' 2>/dev/null; then
  echo "[python] installing nanobind, scikit-build-core, pytest from PyPI"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check "nanobind>=2" "scikit-build-core>=0.10" pytest
fi

if command -v ccache >/dev/null; then
  export CMAKE_ARGS="${CMAKE_ARGS:-} -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache"
  export CCACHE_BASEDIR="$repo"
fi
echo "[python] building and installing clvis into $venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation "$repo"
(cd / && "$venv/bin/python" -c 'import clvis; print("[python] clvis", clvis.__version__, "imports")')
