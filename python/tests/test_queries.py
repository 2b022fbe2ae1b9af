"""Ray queries, cameras from intrinsics and poses, and the visibility outputs through the Python
API, each checked against the C++ meaning: primary rays cast by hand answer as the ray path's
render, occlusion is a hit, crossings count parity inside a closed sphere, the intrinsics of a
fov camera render it, barycentrics rebuild positions, and batches equal single renders."""

import numpy as np
import pytest

import clvis

from conftest import front_camera

W, H = 48, 32


@pytest.fixture(scope="module")
def sphere_mesh():
    return clvis.make_uv_sphere(2000)


@pytest.fixture(scope="module")
def sphere(sphere_mesh):
    scene = clvis.Scene()
    scene.add_mesh(sphere_mesh.positions, sphere_mesh.indices)
    return scene


@pytest.fixture(scope="module")
def renderer(device, bunny):
    return clvis.Renderer(device, bunny)


def primary_rays(camera, width, height):
    """The camera's ray through each pixel centre, in row order, as (N, 3) arrays."""
    rays = [camera.primary_ray(i + 0.5, j + 0.5, width, height) for j in range(height) for i in range(width)]
    return (np.array([r[0] for r in rays], dtype=np.float32), np.array([r[1] for r in rays], dtype=np.float32))


def test_cast_rays_answers_as_the_ray_paths_render(renderer, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    vis = renderer.render(camera, W, H, path="ray")
    origins, directions = primary_rays(camera, W, H)
    hits = renderer.cast_rays(origins, directions, tmin=camera.near, tmax=camera.far)
    assert hits["invalid"] == 0
    assert hits["id"].dtype == np.uint32 and hits["t"].dtype == np.float32 and hits["t"].shape == (W * H,)
    ids = hits["id"].reshape(H, W)
    assert (ids != clvis.background_id).sum() > 0.05 * W * H
    np.testing.assert_array_equal(ids, vis.ids)
    np.testing.assert_allclose(hits["t"].reshape(H, W), vis.depth, rtol=1e-5)
    missed = hits["id"] == clvis.background_id
    assert np.all(np.isinf(hits["t"][missed])) and np.all(hits["u"][missed] == 0)
    u, v = hits["u"][~missed], hits["v"][~missed]
    assert np.all((u >= -1e-6) & (v >= -1e-6) & (u + v <= 1 + 1e-6))


def test_cast_rays_takes_ray_records_in_place(renderer, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    origins, directions = primary_rays(camera, W, H)
    records = np.zeros((W * H, 8), dtype=np.float32)
    records[:, 0:3], records[:, 3], records[:, 4:7], records[:, 7] = origins, camera.near, directions, camera.far
    records[0, 4:7] = 0  # a zero direction: invalid, answered as a miss
    a = renderer.cast_rays(origins, directions, tmin=camera.near, tmax=camera.far)
    b = renderer.cast_rays(records)
    assert b["invalid"] == 1 and b["id"][0] == clvis.background_id
    np.testing.assert_array_equal(a["id"][1:], b["id"][1:])
    np.testing.assert_array_equal(a["t"][1:], b["t"][1:])


def test_occluded_is_a_closest_hit(renderer, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    origins, directions = primary_rays(camera, W, H)
    for tmax in (np.inf, 1.05 * np.linalg.norm(np.subtract(camera.eye, camera.target))):
        hits = renderer.cast_rays(origins, directions, tmax=tmax)
        any_hit = renderer.occluded(origins, directions, tmax=tmax)
        assert any_hit["occluded"].dtype == np.uint8 and any_hit["invalid"] == 0
        np.testing.assert_array_equal(any_hit["occluded"], (hits["id"] != clvis.background_id).astype(np.uint8))


def test_crossings_are_odd_inside_a_closed_sphere_and_even_outside(device, sphere):
    renderer = clvis.Renderer(device, sphere)
    rng = np.random.default_rng(5)
    directions = rng.normal(size=(400, 3)).astype(np.float32)
    inside = (rng.uniform(-1, 1, size=(400, 3)) * 0.3).astype(np.float32)
    outside = (directions / np.linalg.norm(directions, axis=1, keepdims=True) * 3 +
               rng.uniform(-0.5, 0.5, size=(400, 3))).astype(np.float32)
    counts_in = renderer.count_intersections(inside, directions)["count"]
    counts_out = renderer.count_intersections(outside, rng.normal(size=(400, 3)).astype(np.float32))["count"]
    assert counts_in.dtype == np.uint32
    assert np.all(counts_in % 2 == 1) and np.all(counts_in == 1)
    assert np.all(counts_out % 2 == 0) and np.any(counts_out == 2)
    # a ray interval that ends inside the sphere crosses once from outside
    ends_inside = renderer.count_intersections(np.array([[0, 0, 3]], np.float32), np.array([[0, 0, -1]], np.float32),
                                               tmax=3.0)["count"]
    assert ends_inside.tolist() == [1]


def test_ray_queries_reject_mismatched_or_misshapen_arrays(renderer):
    with pytest.raises(clvis.InvalidArgumentError, match="cast_rays: origins has 2 rays, directions 3"):
        renderer.cast_rays(np.zeros((2, 3)), np.ones((3, 3)))
    with pytest.raises(clvis.InvalidArgumentError, match="occluded: rays"):
        renderer.occluded(np.zeros((4, 4), np.float32))
    empty = renderer.count_intersections(np.zeros((0, 3)), np.zeros((0, 3)))
    assert empty["count"].shape == (0,) and empty["invalid"] == 0


def test_ambient_occlusion_is_a_fraction_and_one_on_the_background(renderer, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    vis = renderer.render(camera, W, H)
    ao = renderer.ambient_occlusion(vis, rays=8, seed=3)
    assert ao.shape == (H, W) and ao.dtype == np.float32
    background = vis.ids == clvis.background_id
    assert np.all(ao[background] == 1)
    assert np.all((ao >= 0) & (ao <= 1)) and ao[~background].min() < 1
    np.testing.assert_array_equal(ao, renderer.ambient_occlusion(vis, rays=8, seed=3))
    with pytest.raises(clvis.InvalidArgumentError, match="ambient_occlusion"):
        renderer.ambient_occlusion(clvis.Visibility(vis.ids))


def test_a_fov_cameras_intrinsics_render_it(renderer, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    fx, fy, cx, cy = camera.raster_map(W, H)
    assert camera.intrinsics is None and cx == W / 2 and cy == H / 2 and fx == pytest.approx(fy)
    k = clvis.Camera.from_intrinsics(eye=camera.eye, target=camera.target, up=camera.up, fx=fx, fy=fy, cx=cx, cy=cy,
                                     near=camera.near, far=camera.far)
    assert k.intrinsics == pytest.approx((fx, fy, cx, cy))
    posed = clvis.Camera.from_pose(camera.pose(), lens=camera)
    for path in ("raster", "ray"):
        want = renderer.render(camera, W, H, path=path)
        for other in (k, posed):
            got = renderer.render(other, W, H, path=path)
            np.testing.assert_array_equal(got.ids, want.ids)
            np.testing.assert_allclose(got.depth, want.depth, rtol=1e-5)


def test_an_opencv_camera_is_the_intrinsics_camera_half_a_pixel_on():
    pose = np.eye(4)
    pose[2, 3] = 3.0  # OpenCV camera at z = -3 looking down +z, x right, y down
    cv = clvis.Camera.from_opencv(100, 100, 31.5, 23.5, pose, near=0.5, far=10)
    assert cv.intrinsics == pytest.approx((100, 100, 32, 24))
    assert cv.eye == pytest.approx((0, 0, -3)) and cv.up == pytest.approx((0, -1, 0), abs=1e-12)
    x, y, depth = cv.to_raster((0.3, 0.2, 1.0), 64, 48)
    assert (x, y, depth) == pytest.approx((32 + 100 * 0.3 / 4, 24 + 100 * 0.2 / 4, 4))
    with pytest.raises(clvis.InvalidArgumentError, match="pose"):
        clvis.Camera.from_pose(np.diag([2.0, 1, 1, 1]))


def test_barycentrics_rebuild_the_resolved_positions(device, sphere, sphere_mesh):
    renderer = clvis.Renderer(device, sphere)
    camera = front_camera()
    for path in ("raster", "ray"):
        vis = renderer.render(camera, W, H, path=path)
        out = renderer.resolve(vis, ["barycentrics", "position", "normal"])
        bary, position, normal = out["barycentrics"], out["position"], out["normal"]
        assert bary.shape == (H, W, 2) and position.shape == (H, W, 3) and normal.shape == (H, W, 3)
        covered = vis.ids != clvis.background_id
        assert covered.sum() > 0.2 * W * H
        tri = np.asarray(sphere_mesh.indices)[vis.ids[covered]]
        p = np.asarray(sphere_mesh.positions, dtype=np.float64)
        u, v = bary[covered, 0:1], bary[covered, 1:2]
        rebuilt = (1 - u - v) * p[tri[:, 0]] + u * p[tri[:, 1]] + v * p[tri[:, 2]]
        np.testing.assert_allclose(rebuilt, position[covered], atol=1e-5)
        assert np.all(np.isnan(position[~covered])) and np.all(bary[~covered] == 0)
        np.testing.assert_allclose(np.linalg.norm(normal[covered], axis=1), 1, atol=1e-5)
    with pytest.raises(clvis.InvalidArgumentError, match="resolve: attribute"):
        renderer.resolve(vis, ["colour"])


def test_visible_ids_are_the_ids_seen_in_the_views(renderer, bunny):
    a = clvis.Camera.framing(bunny.bounds())
    b = clvis.Camera(eye=(0, 0.1, -0.3), target=a.target, near=0.01, far=10)
    views = [renderer.render(c, W, H) for c in (a, b)]
    seen = [np.unique(v.ids[v.ids != clvis.background_id]) for v in views]
    np.testing.assert_array_equal(renderer.visible_ids(views[0]), seen[0])
    both = renderer.visible_ids(views)
    assert both.dtype == np.uint32
    np.testing.assert_array_equal(both, np.union1d(seen[0], seen[1]))


@pytest.mark.parametrize("path", ["raster", "ray"])
def test_a_batch_of_views_equals_the_views_rendered_alone(renderer, bunny, path):
    base = clvis.Camera.framing(bunny.bounds())
    eye = np.array(base.eye)
    cameras = [clvis.Camera(eye=tuple(eye + d), target=base.target, near=base.near, far=base.far)
               for d in ((0, 0, 0), (0.05, 0, 0), (0, 0.05, 0.02))]
    ids, depth = renderer.render_views(cameras, W, H, path=path)
    assert ids.shape == (3, H, W) and depth.shape == (3, H, W) and ids.dtype == np.uint32
    for v, camera in enumerate(cameras):
        alone = renderer.render(camera, W, H, path=path)
        np.testing.assert_array_equal(ids[v], alone.ids)
        np.testing.assert_array_equal(depth[v], alone.depth)
    with pytest.raises(clvis.InvalidArgumentError):
        renderer.render_views([], W, H)
