"""Results out: ids and depth are the NumPy arrays the one read-back wrote (no copy on the way to
NumPy), they outlive the Visibility, the Renderer and the Scene, and the GIL is free while the device
works."""

import gc
import threading
import time
import weakref

import numpy as np
import pytest

import clvis

from conftest import front_camera, quad_scene


def test_ids_and_depth_are_the_arrays_of_one_read_back(device, quad):
    vis = clvis.Renderer(device, quad).render(front_camera(), 32, 24)
    ids, depth = vis.ids, vis.depth
    assert ids.shape == depth.shape == (24, 32)
    assert ids.dtype == np.uint32 and depth.dtype == np.float32
    for array in (ids, depth):
        assert array.flags.owndata and array.base is None
        assert array.flags.c_contiguous and not array.flags.writeable
    # Each access gives the same array, not a copy.
    assert vis.ids is ids and vis.depth is depth
    assert not np.shares_memory(ids, depth)
    # A Visibility made from arrays keeps a copy and gives views of it.
    made = clvis.Visibility(ids, depth)
    assert not np.shares_memory(made.ids, ids) and np.shares_memory(made.ids, made.ids)
    assert not made.ids.flags.owndata and not made.ids.flags.writeable


def test_shaded_images_are_views_too(device, quad):
    renderer = clvis.Renderer(device, quad)
    vis = renderer.render(front_camera(), 16, 8)
    rgba = clvis.shade(renderer, vis, mode="ids")
    assert rgba.shape == (8, 16, 4) and rgba.dtype == np.uint8 and not rgba.flags.owndata
    assert (rgba[..., 3] == 255).all()


def test_results_outlive_their_renderer_and_scene(device):
    scene = quad_scene()
    renderer = clvis.Renderer(device, scene)
    camera = front_camera()
    vis = renderer.render(camera, 32, 32)
    expected_ids, expected_depth = vis.ids.copy(), vis.depth.copy()
    watch = weakref.ref(renderer), weakref.ref(scene)
    del renderer, scene
    gc.collect()
    assert watch[0]() is None and watch[1]() is None
    np.testing.assert_array_equal(vis.ids, expected_ids)
    np.testing.assert_array_equal(vis.depth, expected_depth)
    assert vis.camera.eye == camera.eye and vis.path == "raster"


def test_arrays_outlive_their_visibility(device, quad):
    vis = clvis.Renderer(device, quad).render(front_camera(), 32, 32, path="ray")
    expected = vis.ids.copy()
    ids = vis.ids
    watch = weakref.ref(vis)
    del vis
    gc.collect()
    assert watch() is None
    # Churn the allocator: freed storage would be overwritten here.
    junk = [np.full((32, 32), 7, np.uint32) for _ in range(64)]
    np.testing.assert_array_equal(ids, expected)
    assert junk[0][0, 0] == 7


def test_a_renderer_outlives_the_scene_it_was_made_from(device):
    scene = quad_scene()
    renderer = clvis.Renderer(device, scene)
    del scene
    gc.collect()
    vis = renderer.render(front_camera(), 16, 16, path="ray")
    assert (vis.ids != clvis.background_id).any()
    assert clvis.shade(renderer, vis).shape == (16, 16, 4)


def test_a_mesh_view_keeps_its_mesh_alive():
    positions = clvis.make_uv_sphere(100).positions
    gc.collect()
    assert positions.shape[1] == 3 and np.isfinite(positions).all()
    assert np.allclose(np.linalg.norm(positions, axis=1), 1, atol=1e-6)


def test_other_threads_run_while_the_device_works(device, bunny):
    renderer = clvis.Renderer(device, bunny)
    camera = clvis.Camera.framing(bunny.bounds())
    renderer.render(camera, 640, 480, path="ray")  # builds the BVH and the kernels
    window = []

    def render():
        window.append(time.perf_counter())
        renderer.render(camera, 640, 480, path="ray")
        window.append(time.perf_counter())

    stamps = []
    worker = threading.Thread(target=render)
    worker.start()
    while worker.is_alive():
        stamps.append(time.perf_counter())
    worker.join()
    # Both stamps of the window are taken holding the GIL: had render() kept it, this thread could
    # not have run in between.
    inside = [t for t in stamps if window[0] < t < window[1]]
    assert len(inside) > 0


def test_threads_sharing_a_renderer_and_a_scene_get_correct_answers(device):
    scene = quad_scene()
    renderer = clvis.Renderer(device, scene)
    camera = front_camera()
    expected = renderer.render(camera, 24, 24).ids.copy()
    results, errors = [], []

    def work():
        try:
            for _ in range(5):
                results.append(renderer.render(camera, 24, 24).ids)
                clvis.Renderer(device, scene)
                scene.bounds()
        except Exception as e:  # noqa: BLE001 (reported below)
            errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(results) == 20
    for ids in results:
        np.testing.assert_array_equal(ids, expected)


@pytest.mark.skipif(not clvis.HAVE_IMAGE_IO, reason="built without the image layer (OpenImageIO)")
def test_files_round_trip_through_the_image_layer(device, quad, tmp_path):
    renderer = clvis.Renderer(device, quad)
    vis = renderer.render(front_camera(), 20, 10)
    clvis.write_ids(tmp_path / "ids.tif", vis)
    clvis.write_depth(tmp_path / "depth.exr", vis)
    clvis.write_image(tmp_path / "shaded.png", clvis.shade(renderer, vis))
    clvis.write_image(tmp_path / "rgb.png", np.zeros((10, 20, 3), np.uint8))
    back = clvis.read_ids(tmp_path / "ids.tif", tmp_path / "depth.exr")
    np.testing.assert_array_equal(back.ids, vis.ids)
    np.testing.assert_array_equal(back.depth, vis.depth)
    assert (tmp_path / "shaded.png").stat().st_size > 0
    with pytest.raises(clvis.InvalidArgumentError, match=r"\(H, W, 4\) or \(H, W, 3\) uint8"):
        clvis.write_image(tmp_path / "x.png", np.zeros((10, 20), np.uint8))
    with pytest.raises(clvis.IoError):
        clvis.write_ids(tmp_path / "no" / "such" / "dir.tif", vis)


def test_a_dropped_results_arrays_serve_the_next_render_and_kept_ones_never(device, quad):
    renderer = clvis.Renderer(device, quad)
    camera = front_camera()
    address = renderer.render(camera, 32, 24).ids.__array_interface__["data"][0]
    # Nothing refers to that result's arrays any more: the next render of that size reads into them.
    kept = renderer.render(camera, 32, 24).ids
    assert kept.__array_interface__["data"][0] == address
    before = kept.copy()
    other = renderer.render(clvis.Camera(eye=(0.5, 0.2, 3), target=(0, 0, 0), near=0.5, far=10), 32, 24)
    assert not np.shares_memory(other.ids, kept)
    np.testing.assert_array_equal(kept, before)
    assert (other.ids != kept).any()
