"""Arrays in: float32 (V, 3) positions and uint32 (T, 3) indices read as they are, other dtypes
and layouts converted once, wrong shapes and values refused with errors naming the argument."""

import numpy as np
import pytest

import clvis

from conftest import front_camera

POSITIONS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
INDICES = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)


def ids_of(device, scene):
    return clvis.Renderer(device, scene).render(front_camera(), 16, 16).ids.copy()


@pytest.fixture(scope="module")
def reference_ids(device):
    scene = clvis.Scene()
    scene.add_mesh(POSITIONS, INDICES)
    return ids_of(device, scene)


@pytest.mark.parametrize("positions, indices", [
    (POSITIONS.astype(np.float64), INDICES.astype(np.int64)),
    (POSITIONS.astype(np.int32), INDICES.astype(np.uint8)),
    (POSITIONS.tolist(), INDICES.tolist()),
    (np.asfortranarray(POSITIONS), np.asfortranarray(INDICES)),
    (np.repeat(POSITIONS, 2, axis=0)[::2], np.repeat(INDICES, 3, axis=1)[:, ::3]),
    (POSITIONS[:, ::-1][:, ::-1], INDICES.astype(np.int16)),
])
def test_other_dtypes_and_layouts_give_the_same_scene(device, reference_ids, positions, indices):
    scene = clvis.Scene()
    assert scene.add_mesh(positions, indices) == 0
    assert (scene.vertex_count, scene.triangle_count) == (4, 2)
    np.testing.assert_array_equal(ids_of(device, scene), reference_ids)


def test_the_scene_keeps_its_own_copy_of_the_arrays(device, reference_ids):
    positions, indices = POSITIONS.copy(), INDICES.copy()
    scene = clvis.Scene()
    scene.add_mesh(positions, indices)
    positions[:] = 100
    indices[:] = 0
    np.testing.assert_array_equal(ids_of(device, scene), reference_ids)


@pytest.mark.parametrize("positions, indices, message", [
    (POSITIONS[:, :2], INDICES, "positions: expected an array of shape (V, 3), got shape (4, 2)"),
    (POSITIONS.ravel(), INDICES, "positions: expected an array of shape (V, 3), got shape (12,)"),
    (POSITIONS, INDICES.ravel(), "indices: expected an array of shape (T, 3), got shape (6,)"),
    (POSITIONS, INDICES.astype(np.float32), "indices: expected integers, got dtype float32"),
    (POSITIONS, INDICES.astype(np.int64) - 1, "indices: negative value -1"),
    (POSITIONS, INDICES.astype(np.int64) + 2**32, "does not fit 32 bits"),
    (POSITIONS.astype(str), INDICES, "positions: expected numbers, got dtype <U"),
    ([[0, 0, 0], [1, 0]], INDICES, "positions: not an array"),
    (POSITIONS, [[0, 1, 4]], "refers to vertex 4"),
    (np.where(POSITIONS == 1, np.nan, POSITIONS), INDICES, "vertex 1 has a non-finite coordinate"),
])
def test_wrong_arrays_are_refused_naming_the_argument(positions, indices, message):
    scene = clvis.Scene()
    with pytest.raises(clvis.InvalidArgumentError) as info:
        scene.add_mesh(positions, indices)
    assert message in str(info.value)
    assert scene.triangle_count == 0


def test_a_transform_must_be_four_by_four():
    scene = clvis.Scene()
    with pytest.raises(clvis.InvalidArgumentError, match=r"transform: expected an array of shape \(4, 4\)"):
        scene.add_mesh(POSITIONS, INDICES, transform=np.eye(3))
    index = scene.add_mesh(POSITIONS, INDICES, transform=[[2, 0, 0, 1], [0, 2, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]])
    assert scene.bounds().lo == (-1.0, -2.0, 0.0) and scene.bounds().hi == (3.0, 2.0, 0.0)
    with pytest.raises(clvis.InvalidArgumentError, match="last row must be 0 0 0 1"):
        scene.set_transform(index, np.ones((4, 4)))


def test_positions_can_be_replaced_for_the_renderer_to_follow(device):
    scene = clvis.Scene()
    scene.add_mesh(POSITIONS, INDICES)
    renderer = clvis.Renderer(device, scene)
    camera = front_camera()
    before = renderer.render(camera, 16, 16, path="ray")
    scene.set_positions(0, POSITIONS.astype(np.float64) * 0.25)
    renderer.update(scene)
    after = renderer.render(camera, 16, 16, path="ray")
    covered = lambda v: int((v.ids != clvis.background_id).sum())
    assert 0 < covered(after) < covered(before)
    with pytest.raises(clvis.InvalidArgumentError, match="3 vertices"):
        scene.set_positions(0, POSITIONS[:3])


def test_a_visibility_from_arrays_checks_its_shapes():
    vis = clvis.Visibility(np.arange(6, dtype=np.int64).reshape(2, 3), np.ones((2, 3)))
    assert (vis.width, vis.height) == (3, 2) and vis.ids.dtype == np.uint32 and vis.depth.dtype == np.float32
    assert vis.path is None and vis.camera is None
    with pytest.raises(clvis.InvalidArgumentError, match="depth: shape differs"):
        clvis.Visibility(np.zeros((2, 3), np.uint32), np.zeros((3, 2)))
    with pytest.raises(clvis.InvalidArgumentError, match=r"ids: expected an array of shape \(H, W\)"):
        clvis.Visibility(np.zeros(6, np.uint32))
    with pytest.raises(clvis.InvalidArgumentError, match="empty image"):
        clvis.Visibility(np.zeros((0, 3), np.uint32))


def test_loaded_meshes_expose_their_arrays_read_only():
    mesh = clvis.make_uv_sphere(64)
    assert mesh.positions.dtype == np.float32 and mesh.positions.shape == (mesh.vertex_count, 3)
    assert mesh.indices.dtype == np.uint32 and mesh.indices.shape == (mesh.triangle_count, 3)
    assert not mesh.positions.flags.writeable
    with pytest.raises(ValueError):
        mesh.positions[0, 0] = 1


def test_camera_vectors_take_any_sequence():
    camera = clvis.Camera(eye=np.array([0, 0, 3.0]), target=[0, 0, 0], up=(0, 1, 0), fov=60, near=1, far=5)
    assert camera.eye == (0.0, 0.0, 3.0) and camera.fov == 60 and camera.ortho is None
    assert camera.view_matrix().shape == (4, 4)
    x, y, depth = camera.to_raster((0, 0, 0), 64, 32)
    assert (x, y, depth) == pytest.approx((32, 16, 3))
