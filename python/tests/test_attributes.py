"""Named vertex attributes, object ids and camera-space normals through Renderer.resolve: shapes
and dtypes by the names asked, values against the barycentrics and the corners in NumPy, NaN on
the background and on a mesh without the attribute, instances reading their prototype's corners,
object ids equal to Scene.mesh_of of the ids, and camera-space normals the world ones rotated."""

import numpy as np
import pytest

import clvis

W, H = 96, 72


def with_attributes(mesh):
    corners = mesh.positions[mesh.indices.reshape(-1)]  # (3T, 3): each corner's position
    n = len(corners)
    seam = (np.arange(n) // 3 % 2).astype(np.float32) * 0.5  # one vertex, two uvs: seams
    mesh.set_attribute("uv", np.stack([corners[:, 0] + seam, corners[:, 1]], axis=1))
    mesh.set_attribute("color", np.concatenate([0.5 + 0.4 * np.sin(3 * corners), np.ones((n, 1), np.float32)], 1))
    mesh.set_attribute("temperature", (300 + 50 * corners[:, 2]).reshape(n, 1))
    return corners


def translation(x, y, z, scale=1.0):
    m = np.eye(4) * scale
    m[3, 3] = 1
    m[:3, 3] = (x, y, z)
    return m


@pytest.fixture(scope="module")
def scene():
    sphere = clvis.make_uv_sphere(400)
    with_attributes(sphere)
    scene = clvis.Scene()
    scene.add_mesh(clvis.make_grid(50), translation(0, -2, 0, 3))  # item 0: no attributes
    scene.add_mesh(sphere, translation(-0.6, 0, 0, 0.6))  # item 1
    proto = scene.add_prototype(sphere)
    scene.add_instance(proto, translation(0.7, 0.2, 0, 0.5))  # item 2: the prototype's corners
    return scene, sphere


@pytest.mark.parametrize("path", ["raster", "ray"])
def test_attributes_and_objects(device, scene, path):
    scene, sphere = scene
    renderer = clvis.Renderer(device, scene)
    camera = clvis.Camera.framing(scene.bounds())
    vis = renderer.render(camera, W, H, path=path)
    names = ["uv", "color", "temperature", "object", "barycentrics"]
    out = renderer.resolve(vis, names)
    assert list(out) == names
    assert out["uv"].shape == (H, W, 2) and out["uv"].dtype == np.float32
    assert out["color"].shape == (H, W, 4)
    assert out["temperature"].shape == (H, W) and out["temperature"].dtype == np.float32
    assert out["object"].shape == (H, W) and out["object"].dtype == np.uint32

    ids = vis.ids
    background = ids == 0xFFFFFFFF
    items = np.array([scene.mesh_of(int(i)) if i != 0xFFFFFFFF else 0xFFFFFFFF for i in ids.reshape(-1)],
                     dtype=np.uint32).reshape(H, W)
    assert np.array_equal(out["object"], items)
    assert set(np.unique(items)) >= {0, 1, 2}

    # The value is (1 - u - v) a0 + u a1 + v a2 of the triangle's corners (here with resolve's
    # float barycentrics: the C++ referee judges the exact ones).
    temp = out["temperature"]
    assert np.isnan(temp[background]).all() and np.isnan(temp[items == 0]).all()
    sphere_items = (items == 1) | (items == 2)
    values = 300 + 50 * sphere.positions[sphere.indices.reshape(-1)][:, 2]
    # Each item's first id: the plain sphere's after the grid's triangles, the instance's after it.
    grid_triangles = clvis.make_grid(50).triangle_count
    starts = {1: grid_triangles, 2: grid_triangles + sphere.triangle_count}
    for y, x in zip(*np.nonzero(sphere_items)):
        local = int(ids[y, x]) - starts[int(items[y, x])]
        u, v = out["barycentrics"][y, x]
        a = values[3 * local: 3 * local + 3]
        want = (1 - u - v) * a[0] + u * a[1] + v * a[2]
        assert abs(temp[y, x] - want) < 1e-3 * max(abs(a).max(), 1), (y, x)
    assert np.isfinite(out["color"][sphere_items]).all()
    assert np.allclose(out["color"][sphere_items][:, 3], 1)


def test_unknown_attribute_is_named(device, scene):
    scene, _ = scene
    renderer = clvis.Renderer(device, scene)
    vis = renderer.render(clvis.Camera.framing(scene.bounds()), W, H)
    with pytest.raises(ValueError, match="'albedo'.*uv, color, temperature"):
        renderer.resolve(vis, ["albedo"])


def test_camera_space_normals(device, scene):
    scene, _ = scene
    renderer = clvis.Renderer(device, scene)
    camera = clvis.Camera.framing(scene.bounds())
    vis = renderer.render(camera, W, H)
    world = renderer.resolve(vis, ["normal", "smooth_normal"])
    cam = renderer.resolve(vis, ["normal", "smooth_normal"], normals_space="camera")
    rotation = camera.pose()[:3, :3]  # columns r, u, -f: camera -> world
    for name in ("normal", "smooth_normal"):
        w, c = world[name], cam[name]
        covered = ~np.isnan(w[..., 0])
        assert covered.sum() > W * H // 10
        assert np.isnan(c[~covered]).all()
        assert np.allclose(w[covered] @ rotation, c[covered], atol=1e-6)
