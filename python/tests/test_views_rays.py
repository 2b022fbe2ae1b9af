"""Primary rays as arrays and cameras from other tools (CONVENTIONS.md "Primary rays as arrays",
"Cameras from other tools"): Camera.rays gives the ray path's rays, so their closest hits are its
render bit for bit at every sample; read_views reads NeRF's transforms.json, COLMAP's text model
and glTF camera nodes as the cameras of the same clvis views file."""

import json
import math

import numpy as np
import pytest

import clvis

W, H = 64, 48


def cameras_of(bunny):
    b = bunny.bounds()
    persp = clvis.Camera.framing(b)
    return [
        persp,
        clvis.Camera.framing(b, ortho=True),
        clvis.Camera.from_intrinsics(eye=persp.eye, target=persp.target, fx=70.5, fy=66.25, cx=29.3, cy=25.1,
                                     near=persp.near, far=persp.far),
    ]


@pytest.mark.parametrize("samples", [1, 4])
def test_closest_hits_of_the_rays_are_the_ray_paths_render_bit_for_bit(device, bunny, samples):
    renderer = clvis.Renderer(device, bunny, samples=samples)
    for camera in cameras_of(bunny):
        rays = camera.rays(W, H, samples)
        assert rays.shape == (H, W, samples, 8) and rays.dtype == np.float32
        assert (rays[..., 3] == np.float32(camera.near)).all() and (rays[..., 7] == np.float32(camera.far)).all()
        hits = renderer.cast_rays(rays.reshape(-1, 8))
        vis = renderer.render(camera, W, H, path="ray")
        shape = (H, W, samples) if samples > 1 else (H, W)
        assert (hits["id"].reshape(shape) == vis.ids).all()
        assert (hits["t"].reshape(shape).view(np.uint32) == vis.depth.view(np.uint32)).all()
        assert (vis.ids != clvis.background_id).sum() > 0.05 * W * H * samples


def test_rays_refuse_a_sample_count_and_a_size(bunny):
    camera = cameras_of(bunny)[0]
    with pytest.raises(clvis.InvalidArgumentError):
        camera.rays(W, H, 3)
    with pytest.raises(clvis.InvalidArgumentError):
        camera.rays(0, H)


def rows(pose):
    return [[float(v) for v in row] for row in np.asarray(pose)]


def same_camera(a, b):
    return (a.eye == b.eye and a.target == b.target and a.up == b.up and a.near == b.near and a.far == b.far
            and a.intrinsics == b.intrinsics and a.fov == b.fov and a.ortho == b.ortho)


def test_nerf_transforms_read_as_the_same_views_file(tmp_path, device, bunny):
    cams = cameras_of(bunny)
    poses = [cams[0].pose(), cams[2].pose()]
    nerf = {"camera_angle_x": 0.9, "frames": [{"file_path": f"{i}.png", "transform_matrix": rows(p)}
                                              for i, p in enumerate(poses)]}
    (tmp_path / "transforms.json").write_text(json.dumps(nerf))
    with pytest.raises(clvis.IoError, match="w: missing"):
        clvis.read_views(str(tmp_path / "transforms.json"))
    got, w, h, fmt = clvis.read_views(str(tmp_path / "transforms.json"), width=W, height=H)
    assert (w, h, fmt) == (W, H, "nerf")
    fx = 0.5 * W / math.tan(0.5 * 0.9)
    same = {"width": W, "height": H, "views": [{"pose": np.asarray(p).ravel().tolist(),
                                                  "intrinsics": [fx, fx, W / 2, H / 2]} for p in poses]}
    (tmp_path / "same.json").write_text(json.dumps(same))
    want, _, _, fmt = clvis.read_views(str(tmp_path / "same.json"))
    assert fmt == "clvis"
    assert all(same_camera(a, b) for a, b in zip(got, want))
    renderer = clvis.Renderer(device, bunny)
    ids_a, depth_a = renderer.render_views(got, W, H, path="ray")
    ids_b, depth_b = renderer.render_views(want, W, H, path="ray")
    assert (ids_a == ids_b).all() and (depth_a.view(np.uint32) == depth_b.view(np.uint32)).all()


def test_colmap_and_gltf_cameras(tmp_path):
    model = tmp_path / "sparse"
    model.mkdir()
    (model / "cameras.txt").write_text("# cameras\n1 SIMPLE_PINHOLE 64 48 50 32 24\n")
    (model / "images.txt").write_text("# images\n1 0 1 0 0 0 0.1 0.5 1 a.png\n\n")
    cams, w, h, fmt = clvis.read_views(str(model))
    assert (w, h, fmt, len(cams)) == (64, 48, "colmap", 1)
    # OpenCV's R = diag(1, -1, -1), t = -R eye: the camera at (0, 0.1, 0.5) looking down -z, y up
    assert np.allclose(cams[0].eye, (0, 0.1, 0.5)) and np.allclose(cams[0].up, (0, 1, 0))
    assert cams[0].intrinsics == (50, 50, 32, 24)
    (model / "cameras.txt").write_text("1 OPENCV 64 48 50 50 32 24 0.1 0 0 0\n")
    with pytest.raises(clvis.IoError, match="model OPENCV is not read"):
        clvis.read_views(str(model))
    gltf = {"asset": {"version": "2.0"},
            "cameras": [{"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 0.25, "znear": 0.1, "zfar": 3}}],
            "nodes": [{"camera": 0, "translation": [0, 0.1, 1]}], "scenes": [{"nodes": [0]}]}
    (tmp_path / "c.gltf").write_text(json.dumps(gltf))
    cams, w, h, fmt = clvis.read_views(str(tmp_path / "c.gltf"), width=32, height=16)
    assert (w, h, fmt) == (32, 16, "gltf")
    assert cams[0].ortho == 0.5 and cams[0].near == 0.1 and cams[0].far == 3
