"""What the Python API answers to a new user: resolve's keys are the names asked for, RayQuery
takes any array NumPy can convert (and names the argument when it cannot), DeviceShare names the
device's index, result structs print their fields, and docs/python.md's primary-rays example runs
as written."""

import re

import numpy as np
import pytest

import clvis

from conftest import REPO, quad_scene

W, H = 48, 32


def test_resolve_keys_are_the_names_asked_for(device, bunny):
    renderer = clvis.Renderer(device, bunny)
    vis = renderer.render(clvis.Camera.framing(bunny.bounds()), W, H)
    names = ["smooth_normal", "barycentrics", "position", "normal"]
    out = renderer.resolve(vis, names)
    assert list(out) == names
    assert out["smooth_normal"].shape == (H, W, 3)


class ForeignDtype:
    """A dtype object of another library: == with a NumPy dtype raises (Open3D) ..."""

    def __eq__(self, other):
        raise TypeError("unsupported comparison")

    __hash__ = object.__hash__


class NotImplementedDtype:
    """... or answers NotImplemented on both sides (what ended in std::bad_cast)."""

    def __eq__(self, other):
        return NotImplemented

    __hash__ = object.__hash__


class Tensor:
    """An array-like with its own dtype object that NumPy converts through __array__."""

    def __init__(self, values, dtype):
        self.values, self.dtype, self.shape = values, dtype, values.shape

    def __array__(self, dtype=None, copy=None):
        return self.values if dtype is None else self.values.astype(dtype)


@pytest.fixture(scope="module")
def query_and_rays(device):
    renderer = clvis.Renderer(device, quad_scene())
    rays = np.zeros((3, 8), np.float64)  # float64: converted as np.asarray(..., float32) would
    rays[:, 0:3] = [[0.5, -0.5, 3], [-0.5, 0.5, 3], [5, 5, 3]]
    rays[:, 4:7] = [0, 0, -1]
    rays[:, 7] = np.inf
    return clvis.RayQuery(renderer), rays


@pytest.mark.parametrize("dtype", [ForeignDtype(), NotImplementedDtype()])
def test_ray_query_takes_array_likes_with_their_own_dtype(query_and_rays, dtype):
    query, rays = query_and_rays
    want = query.closest(rays)
    assert list(want["id"]) == [0, 1, clvis.background_id]
    tensor = Tensor(rays, dtype)
    np.testing.assert_array_equal(query.closest(tensor)["id"], want["id"])
    np.testing.assert_array_equal(query.occluded(tensor), query.occluded(rays))
    np.testing.assert_array_equal(query.count(tensor), query.count(rays))
    # A list of lists converts too.
    np.testing.assert_array_equal(query.closest(rays.tolist())["id"], want["id"])


@pytest.mark.parametrize("method", ["closest", "occluded", "count"])
def test_ray_query_names_the_argument_numpy_cannot_convert(query_and_rays, method):
    query, _ = query_and_rays

    class Unconvertible:
        dtype = ForeignDtype()

        def __array__(self, dtype=None, copy=None):
            raise ValueError("no array here")

    with pytest.raises(clvis.Error, match=f"RayQuery.{method}: rays: not an array NumPy can convert"):
        getattr(query, method)(Unconvertible())
    with pytest.raises(clvis.Error, match=f"RayQuery.{method}: rays: expected numbers"):
        getattr(query, method)(np.array([["a"] * 8]))


def test_device_shares_name_the_device_index(device, bunny):
    multi = clvis.MultiDeviceRenderer([device, device], bunny)
    multi.render(clvis.Camera.framing(bunny.bounds()), W, H, screen_tile=16)
    assert [s.index for s in multi.shares] == [device.info.index] * 2
    for s in multi.shares:
        assert repr(s) == f"<clvis.DeviceShare device {device.info.index} ({device.name}): {s.tiles} tiles>"


def test_last_frame_names_the_depth_test_auto_drew_with(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    renderer = clvis.Renderer(device, bunny)
    renderer.render(camera, W, H, path="ray")
    assert renderer.last_frame.raster_atomics == "auto"  # not a raster frame
    renderer.render(camera, W, H, path="raster")
    # 69k triangles over 48x32 keys: far more than one a 16 keys, so atomics where the device has them
    assert renderer.last_frame.raster_atomics == ("on" if device.info.int64_atomics else "off")
    owned = clvis.Renderer(device, bunny, raster_atomics="off")
    owned.render(camera, W, H, path="raster")
    assert owned.last_frame.raster_atomics == "off"


def test_result_structs_print_their_fields(device, bunny):
    renderer = clvis.Renderer(device, bunny)
    renderer.render(clvis.Camera.framing(bunny.bounds()), W, H, path="ray")
    stats = renderer.bvh_stats
    text = repr(stats)
    assert text.startswith("<clvis.BvhStats build_ms=") and "object at 0x" not in text
    for field in ("upload_ms", "nodes", "leaves", "depth", "sah_cost", "refitted", "instances", "top_build_ms",
                  "prototype_builds", "device_bytes"):
        assert f" {field}=" in text
    assert f" nodes={stats.nodes} " in text and f" depth={stats.depth} " in text
    query = clvis.RayQuery(renderer)
    query.closest(np.zeros((2, 8), np.float32))
    q = repr(query.stats)
    assert q.startswith("<clvis.RayQueryStats rays=2 invalid=2 batches=") and " device_ms=" in q and " wall_ms=" in q
    for obj in (stats, query.stats, renderer.last_frame, renderer.last_frame.stages[0]):
        assert "object at 0x" not in repr(obj)


def doc_example(marker):
    """The first ```python block after `marker` in docs/python.md."""
    text = (REPO / "docs" / "python.md").read_text()
    at = text.index(marker)
    match = re.search(r"```python\n(.*?)```", text[at:], re.S)
    return match.group(1)


def test_the_primary_ray_example_of_the_docs_runs_as_written(device, bunny):
    code = doc_example("of `camera.rays(w, h)`")
    camera = clvis.Camera.framing(bunny.bounds())
    scope = {"np": np, "clvis": clvis, "scene": bunny, "camera": camera, "renderer": clvis.Renderer(device, bunny)}
    exec(compile(code, "docs/python.md", "exec"), scope)
    assert scope["w"] * scope["h"] == 230400
    assert (scope["ids"] != clvis.background_id).sum() > 0.05 * 230400
    # As the text says: bit for bit, ids and depths
    ray = scope["ray"]
    assert (scope["ids"] == ray.ids).all()
    assert (scope["hits"]["t"].reshape(360, 640).view(np.uint32) == ray.depth.view(np.uint32)).all()
