"""Fixtures of the Python suite: the pinned device (CLVIS_DEVICE, default 'cpu', as the C++
tests), the repository's meshes and small scenes with their framing cameras."""

import os
import pathlib
import tempfile

import numpy as np
import pytest

import clvis

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: builds the package from a clean clone (minutes)")
    # What clvis keeps between runs (raster_mapping='auto' measurements, program binaries) goes to
    # a folder of the session's own, never to the user's cache folder.
    os.environ["CLVIS_CACHE_DIR"] = tempfile.mkdtemp(prefix="clvis-pytest-cache-")


@pytest.fixture(scope="session")
def device():
    # A missing device fails loudly: the set-up installs PoCL, so a skip would hide a broken install.
    return clvis.Device(os.environ.get("CLVIS_DEVICE", "cpu"))


@pytest.fixture(scope="session")
def bunny():
    return clvis.load_scene(SCENES / "stanford-bunny.obj")


def quad_scene():
    """Two triangles sharing a diagonal: the unit square in z = 0, ids 0 and 1."""
    scene = clvis.Scene()
    positions = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
    scene.add_mesh(positions, np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32))
    return scene


@pytest.fixture
def quad():
    return quad_scene()


def front_camera(**lens):
    return clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), near=0.5, far=10, **lens)
