"""Flow between views from Python (Renderer.flow): an instance moved with Scene.set_transform and
Renderer.update between two renders flows by exactly its projected displacement, checked in NumPy
in double from the depth of the first view; the still one does not move; the masks are bool, the
background NaN; bad items are refused by name."""

import numpy as np
import pytest

import clvis

W, H = 96, 64


def translation(x, y, z):
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


@pytest.mark.parametrize("path", ["raster", "ray"])
def test_flow_follows_a_moved_instance(device, path):
    scene = clvis.Scene()
    ball = clvis.make_uv_sphere(800)
    proto = scene.add_prototype(ball.positions, ball.indices, name="ball")
    still = scene.add_instance(proto, translation(-1.5, 0, 0))
    moving = scene.add_instance(proto, translation(1.5, 0, 0))
    camera = clvis.Camera(eye=(0, 0, 8), target=(0, 0, 0), fov=45, near=0.1, far=100)
    renderer = clvis.Renderer(device, scene)
    a = renderer.render(camera, W, H, path=path)
    scene.set_transform(moving, translation(1.5, 0.4, 0))
    renderer.update(scene)
    b = renderer.render(camera, W, H, path=path)
    f = renderer.flow(a, b, items_a={moving: translation(1.5, 0, 0)})
    assert f["flow"].shape == (H, W, 2) and f["flow"].dtype == np.float32
    assert f["valid"].dtype == np.bool_ and f["occluded"].dtype == np.bool_
    background = a.ids == 0xFFFFFFFF
    assert np.isnan(f["flow"][background]).all()
    assert not f["valid"][background].any() and not f["occluded"][background].any()
    # A move of 0.4 up, parallel to the image: 0.4 fy / depth px up (y down), nothing sideways.
    fy = H / (2 * np.tan(np.radians(45) / 2))
    first_moving = ball.triangle_count  # the still instance's ids come first
    on_moving = (a.ids != 0xFFFFFFFF) & (a.ids >= first_moving) & f["valid"]
    on_still = (a.ids != 0xFFFFFFFF) & (a.ids < first_moving) & f["valid"]
    assert on_moving.sum() > 200 and on_still.sum() > 200
    expected = -0.4 * fy / a.depth.astype(np.float64)
    assert np.abs(f["flow"][..., 1][on_moving] - expected[on_moving]).max() < 1e-3
    assert np.abs(f["flow"][..., 0][on_moving]).max() < 1e-3
    assert np.abs(f["flow"][on_still]).max() < 1e-3
    assert not f["occluded"][on_still].any()
    # Without items_a the renderer's scene (moved) is used at both views: the moved sphere is still.
    g = renderer.flow(a, b)
    assert np.abs(g["flow"][g["valid"]]).max() < 1e-3


def test_flow_refuses_bad_items_by_name(device):
    scene = clvis.Scene()
    ball = clvis.make_uv_sphere(100)
    scene.add_mesh(ball.positions, ball.indices)
    camera = clvis.Camera(eye=(0, 0, 5), target=(0, 0, 0), near=0.1, far=100)
    renderer = clvis.Renderer(device, scene)
    a = renderer.render(camera, 16, 12)
    with pytest.raises(Exception, match="items_b\\[4\\]"):
        renderer.flow(a, a, items_b={4: np.eye(4)})
    with pytest.raises(Exception, match="items_a"):
        renderer.flow(a, a, items_a=[np.eye(4)])
