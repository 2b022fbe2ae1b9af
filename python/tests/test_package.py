"""The package as a user gets it: `pip install` of a clean clone into a fresh virtual environment,
then imported and used with the clone's build folder deleted (the module needs no build tree)."""

import os
import pathlib
import shutil
import subprocess
import sys

import pytest

from conftest import REPO

USE = """
import clvis, numpy as np, pathlib, sys
scene = clvis.Scene()
scene.add_mesh(np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0]]), [[0, 1, 2]])
camera = clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), near=1, far=5)
vis = clvis.Renderer(clvis.Device(), scene).render(camera, 16, 16, path="ray")
assert vis.ids[8, 8] == 0 and vis.ids[0, 0] == clvis.background_id
print(pathlib.Path(clvis._clvis.__file__).resolve())
"""


def run(*command, **kwargs):
    return subprocess.run(command, check=True, capture_output=True, text=True, **kwargs)


@pytest.mark.slow
def test_a_clean_clone_installs_into_a_fresh_virtual_environment(tmp_path):
    clone = tmp_path / "clone"
    run("git", "clone", "-q", str(REPO), str(clone))
    venv = clone / ".venv"
    run("/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv))
    python = str(venv / "bin" / "python")
    run(python, "-m", "pip", "install", "-q", "--disable-pip-version-check", "nanobind>=2", "scikit-build-core>=0.10")

    env = dict(os.environ)
    if shutil.which("ccache"):  # the same sources at the same relative paths hit the cache
        env["CMAKE_ARGS"] = "-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache"
        env["CCACHE_BASEDIR"] = str(clone)
    try:
        run(python, "-m", "pip", "install", "-q", "--disable-pip-version-check", "--no-build-isolation",
            str(clone), env=env, timeout=1500)
    except subprocess.CalledProcessError as e:
        sys.stderr.write(e.stdout[-5000:] + e.stderr[-5000:])
        raise
    shutil.rmtree(clone / "build-python")

    env.setdefault("CLVIS_DEVICE", "cpu")
    module = run(python, "-c", USE, cwd=tmp_path, env=env).stdout.strip()
    site = run(python, "-c", "import sysconfig; print(sysconfig.get_paths()['platlib'])").stdout.strip()
    installed = os.path.join(site, "clvis")
    assert os.path.dirname(module) == os.path.realpath(installed)
    for name in ("__init__.py", "_clvis.pyi", "py.typed"):
        assert os.path.isfile(os.path.join(installed, name)), name
    linked = run("ldd", module).stdout
    assert "libclvis" not in linked and "not found" not in linked


def test_the_stubs_name_every_public_name_of_the_module():
    import ast

    import clvis

    stub = pathlib.Path(clvis._clvis.__file__).with_name("_clvis.pyi")
    tree = ast.parse(stub.read_text())
    named = {n.name for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    named |= {n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)}
    public = {name for name in dir(clvis._clvis) if not name.startswith("_")}
    assert public <= named, public - named
    assert (stub.parent / "py.typed").is_file()
    assert {name for name in dir(clvis) if not name.startswith("_")} >= public
