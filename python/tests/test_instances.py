"""Prototypes and instances from Python: an instance renders as its prototype added as a mesh with
the same transform (ids and depths bit for bit, both paths), follows set_transform through
Renderer.update, and a glTF mesh used by two nodes loads as one prototype with two instances."""

import base64
import json

import numpy as np
import pytest

import clvis

W, H = 40, 30


def translation(x, y, z, scale=1.0):
    m = np.eye(4) * scale
    m[3, 3] = 1
    m[:3, 3] = (x, y, z)
    return m


@pytest.fixture(scope="module")
def sphere_mesh():
    return clvis.make_uv_sphere(300)


def instanced(mesh, transforms):
    scene = clvis.Scene()
    scene.add_mesh(clvis.make_grid(50), translation(0, -1.5, 0, 3))
    proto = scene.add_prototype(mesh.positions, mesh.indices, name="ball")
    items = [scene.add_instance(proto, m) for m in transforms]
    return scene, proto, items


def expanded(mesh, transforms):
    scene = clvis.Scene()
    scene.add_mesh(clvis.make_grid(50), translation(0, -1.5, 0, 3))
    for m in transforms:
        scene.add_mesh(mesh.positions, mesh.indices, m)
    return scene


def render_both(device, scene, camera):
    renderer = clvis.Renderer(device, scene)
    return [renderer.render(camera, W, H, path=p) for p in ("raster", "ray")]


TRANSFORMS = [translation(-1.2, 0, 0), translation(1.2, 0.3, -0.5, 0.7), translation(0, 0.2, -2)]


def test_instances_render_as_the_meshes_they_stand_for(device, sphere_mesh):
    scene, proto, items = instanced(sphere_mesh, TRANSFORMS)
    reference = expanded(sphere_mesh, TRANSFORMS)
    assert (scene.prototype_count, scene.mesh_count, proto, items) == (1, 4, 0, [1, 2, 3])
    assert scene.triangle_count == reference.triangle_count
    assert [scene.prototype_of(i) for i in range(4)] == [None, 0, 0, 0]
    np.testing.assert_array_equal(scene.transform(2), TRANSFORMS[1])
    camera = clvis.Camera.framing(reference.bounds())
    for got, want in zip(render_both(device, scene, camera), render_both(device, reference, camera)):
        assert len(np.unique(got.ids)) > 3
        np.testing.assert_array_equal(got.ids, want.ids)
        np.testing.assert_array_equal(got.depth, want.depth)


def test_a_moved_instance_is_seen_after_update(device, sphere_mesh):
    scene, _, items = instanced(sphere_mesh, TRANSFORMS)
    camera = clvis.Camera.framing(expanded(sphere_mesh, TRANSFORMS).bounds())
    renderer = clvis.Renderer(device, scene)
    before = renderer.render(camera, W, H, path="ray").ids.copy()
    moved = [TRANSFORMS[0], translation(0.4, -0.2, 0.3), TRANSFORMS[2]]
    scene.set_transform(items[1], moved[1])
    renderer.update(scene)
    want = render_both(device, expanded(sphere_mesh, moved), camera)
    for path, reference in zip(("raster", "ray"), want):
        np.testing.assert_array_equal(renderer.render(camera, W, H, path=path).ids, reference.ids)
    assert (before != want[1].ids).any()


def test_moving_an_instance_rebuilds_only_the_top_level(device, sphere_mesh):
    scene, _, items = instanced(sphere_mesh, TRANSFORMS)
    camera = clvis.Camera.framing(expanded(sphere_mesh, TRANSFORMS).bounds())
    renderer = clvis.Renderer(device, scene)
    renderer.render(camera, W, H, path="ray")
    first = renderer.bvh_stats
    assert (first.instances, first.prototype_builds) == (4, 1)  # three instances and the plain mesh
    assert first.device_bytes > 0 and first.top_build_ms >= 0
    scene.set_transform(items[0], translation(-1.0, 0.1, 0))
    renderer.update(scene)
    renderer.render(camera, W, H, path="ray")
    assert renderer.bvh_stats.prototype_builds == 1


def write_gltf(path):
    """One triangle mesh used by two nodes (translated by x = -1 and x = +1)."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32).tobytes()
    doc = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(positions),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(positions).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": len(positions)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0, "translation": [-1, 0, 0]}, {"mesh": 0, "translation": [1, 0, 0]}],
        "scenes": [{"nodes": [0, 1]}],
    }
    path.write_text(json.dumps(doc))


def test_a_gltf_mesh_used_twice_loads_as_one_prototype_and_two_instances(device, tmp_path):
    write_gltf(tmp_path / "two.gltf")
    scene = clvis.load_scene(tmp_path / "two.gltf")
    assert (scene.prototype_count, scene.mesh_count, scene.triangle_count) == (1, 2, 2)
    assert [scene.prototype_of(i) for i in range(2)] == [0, 0]
    np.testing.assert_array_equal(scene.transform(1), translation(1, 0, 0))
    camera = clvis.Camera(eye=(0, 0.4, 5), target=(0, 0.4, 0), near=1, far=10)
    ids = clvis.Renderer(device, scene).render(camera, W, H).ids
    assert set(np.unique(ids)) == {0, 1, clvis.background_id}
    assert (ids[:, : W // 2] != 1).all() and (ids[:, W // 2:] != 0).all()


def test_instance_errors_name_the_argument(sphere_mesh):
    scene = clvis.Scene()
    with pytest.raises(clvis.InvalidArgumentError, match="Scene.add_prototype: positions"):
        scene.add_prototype(np.zeros((4, 2), np.float32), [[0, 1, 2]])
    with pytest.raises(clvis.InvalidArgumentError, match="Scene.add_prototype: indices"):
        scene.add_prototype(np.zeros((4, 3), np.float32), [[0.5, 1, 2]])
    with pytest.raises(clvis.InvalidArgumentError):
        scene.add_instance(0, np.eye(4))  # no prototype yet
    proto = scene.add_prototype(sphere_mesh)
    with pytest.raises(clvis.InvalidArgumentError, match="Scene: transform"):
        scene.add_instance(proto, np.eye(3))
    with pytest.raises(clvis.InvalidArgumentError, match="Scene.prototype_of: no item 0"):
        scene.prototype_of(0)
    assert scene.add_instance(proto) == 0 and scene.triangle_count == sphere_mesh.triangle_count
