"""Every clvis::Error reaches Python as the clvis.Error subclass of its kind, with the library's
message; misuse gives an exception, never a crash."""

import numpy as np
import pytest

import clvis

from conftest import SCENES, front_camera

KINDS = {
    "invalid argument": clvis.InvalidArgumentError,
    "io": clvis.IoError,
    "device": clvis.DeviceError,
    "build": clvis.BuildError,
    "limit": clvis.LimitError,
}


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_each_error_kind_becomes_its_class_with_the_same_message(kind):
    with pytest.raises(KINDS[kind]) as info:
        clvis._clvis._raise_error(kind, f"a {kind} message\nwith a second line")
    assert str(info.value) == f"a {kind} message\nwith a second line"
    assert info.value.kind == kind
    assert isinstance(info.value, clvis.Error) and isinstance(info.value, RuntimeError)


def test_the_kinds_are_also_the_builtin_exceptions_python_code_catches():
    assert issubclass(clvis.InvalidArgumentError, ValueError)
    assert issubclass(clvis.IoError, OSError)
    assert not issubclass(clvis.DeviceError, (ValueError, OSError))


def test_a_bad_camera_is_an_invalid_argument():
    with pytest.raises(clvis.InvalidArgumentError, match="near"):
        clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), near=0, far=10)
    with pytest.raises(clvis.InvalidArgumentError, match="one of fov, ortho and focal_length"):
        clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), fov=40, ortho=2)
    with pytest.raises(clvis.InvalidArgumentError, match="focal_length needs film_gate"):
        clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), focal_length=35)
    with pytest.raises(clvis.InvalidArgumentError, match="fit: expected one of fill, overscan, got 'crop'"):
        clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), focal_length=35, film_gate=(36, 24), fit="crop", aspect=1)


def test_a_missing_or_malformed_file_is_an_io_error(tmp_path):
    with pytest.raises(clvis.IoError, match="missing.obj"):
        clvis.load_mesh(tmp_path / "missing.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with pytest.raises(clvis.IoError, match="bad.obj:3"):
        clvis.load_scene(bad)
    with pytest.raises(clvis.InvalidArgumentError, match="no files given"):
        clvis.load_scene([])


def test_an_unknown_device_is_a_device_error():
    with pytest.raises(clvis.DeviceError, match="no device matches 'no such device'"):
        clvis.Device("no such device")
    with pytest.raises(TypeError):
        clvis.Device(2.5)


def test_a_buffer_beyond_the_device_memory_is_a_limit_error(device, quad):
    renderer = clvis.Renderer(device, quad)
    with pytest.raises(clvis.LimitError, match="100000x100000 visibility buffer"):
        renderer.render(front_camera(), 100000, 100000)


@pytest.mark.parametrize("call, error", [
    (lambda r, c: r.render(c, 0, 16), "image size must be positive"),
    (lambda r, c: r.render(c, 16, 16, path="rays"), "path: expected one of raster, ray, brute, got 'rays'"),
    (lambda r, c: r.prepare("nope"), "path: expected one of"),
    (lambda r, c: clvis.shade(r, clvis.Visibility(np.zeros((4, 4), np.uint32))), "no device buffer"),
    (lambda r, c: clvis.shade(r, r.render(c, 8, 8), mode="plastic"), "mode: expected one of"),
    (lambda r, c: clvis.shade(r, r.render(c, 8, 8), light_direction=(0, 0, 0)), "light direction"),
    (lambda r, c: clvis.Referee(clvis.Scene(), c, 8, 8).compare(r.render(c, 8, 8), r.render(c, 9, 8)), "9x8"),
    (lambda r, c: clvis.Referee(clvis.Scene(), c, 8, 8).judge(8, 0, 0), "pixel (8, 0) outside"),
    (lambda r, c: clvis.Renderer(r.device, clvis.Scene(), cull="sideways"), "cull: expected one of"),
    (lambda r, c: clvis.Renderer(r.device, clvis.Scene(), raster_atomics="maybe"), "raster_atomics: expected one of"),
])
def test_misuse_raises_an_invalid_argument_error(device, quad, call, error):
    renderer = clvis.Renderer(device, quad)
    with pytest.raises(clvis.InvalidArgumentError) as info:
        call(renderer, front_camera())
    assert error in str(info.value)


def test_wrong_types_raise_type_errors(device, quad):
    renderer = clvis.Renderer(device, quad)
    with pytest.raises(TypeError):
        renderer.render("camera", 8, 8)
    with pytest.raises(TypeError):
        clvis.Renderer(quad, device)
    with pytest.raises(TypeError):
        clvis.Referee(quad, front_camera(), 8, 8).compare(np.zeros((8, 8)), np.zeros((8, 8)))


def test_an_empty_scene_renders_background(device):
    vis = clvis.Renderer(device, clvis.Scene()).render(front_camera(), 8, 8, path="ray")
    assert (vis.ids == clvis.background_id).all() and np.isinf(vis.depth).all()


def test_objects_made_without_init_or_initialised_twice_raise_type_errors(device):
    scene = clvis.Scene()
    renderer = clvis.Renderer(device, scene)
    # nanobind also warns (RuntimeWarning) about the instance before it raises.
    with pytest.warns(RuntimeWarning, match="already-initialized"), pytest.raises(TypeError):
        renderer.__init__(device, scene)
    with pytest.warns(RuntimeWarning, match="uninitialized"), pytest.raises(TypeError):
        clvis.Visibility.__new__(clvis.Visibility).ids
    with pytest.warns(RuntimeWarning, match="uninitialized"), pytest.raises(TypeError):
        clvis.Renderer.__new__(clvis.Renderer).render(front_camera(), 8, 8)
    with pytest.raises(TypeError):
        clvis.Mesh()
