"""Raster and ray answers judged by the referee through the Python API, as the C++ agreement
suite does: on meshes, procedural scenes and every kind of camera, no pixel may be an error."""

import numpy as np
import pytest

import clvis

from conftest import SCENES

W, H = 96, 64


def agree(device, scene, camera, width=W, height=H, paths=("raster", "ray")):
    renderer = clvis.Renderer(device, scene)
    results = [renderer.render(camera, width, height, path=p) for p in paths]
    referee = clvis.Referee(scene, camera, width, height)
    report = referee.compare(results[0], results[1])
    assert report.pixels == width * height
    assert report.errors == 0, [v.describe() for v in report.first_errors]
    return results, report


def test_raster_and_ray_agree_on_the_bunny(device, bunny):
    (raster, ray), report = agree(device, bunny, clvis.Camera.framing(bunny.bounds()))
    covered = raster.ids != clvis.background_id
    assert 0.05 * W * H < covered.sum() < W * H  # the bunny is in the frame, not filling it
    assert report.equal > 0.95 * W * H


def test_both_raster_depth_tests_give_the_same_buffer(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    want = clvis.Renderer(device, bunny, raster_atomics="auto").render(camera, W, H)
    got = clvis.Renderer(device, bunny, raster_atomics="off").render(camera, W, H)
    assert (want.ids != clvis.background_id).sum() > 0.05 * W * H
    assert np.array_equal(want.ids, got.ids)
    assert np.array_equal(want.depth.view(np.uint32), got.depth.view(np.uint32))


def test_every_raster_mapping_gives_the_same_buffer(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    renders = {}
    for mapping in ("auto", "square", "pixel"):
        renderer = clvis.Renderer(device, bunny, raster_mapping=mapping)
        renders[mapping] = renderer.render(camera, W, H)
        chosen = renderer.raster_mapping
        if mapping == "auto":  # measured by this session (its own cache folder, conftest.py) or read back
            assert chosen["source"] in ("measured", "cache")
            assert chosen["square_ms"] > 0 and chosen["pixel_ms"] > 0
            fastest = "pixel" if chosen["pixel_ms"] < chosen["square_ms"] else "square"
            assert chosen["mapping"] == fastest
        else:
            assert chosen == {"mapping": mapping, "source": "option", "square_ms": None, "pixel_ms": None}
    assert renders["auto"].ids.tolist() == renders["square"].ids.tolist() == renders["pixel"].ids.tolist()
    for mapping in ("square", "pixel"):
        assert np.array_equal(renders["auto"].depth.view(np.uint32), renders[mapping].depth.view(np.uint32))
    with pytest.raises(ValueError, match="raster_mapping"):
        clvis.Renderer(device, bunny, raster_mapping="tiles")


def test_every_ray_mapping_gives_the_same_buffer(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    renders = {}
    for mapping in ("auto", "packet", "single"):
        renderer = clvis.Renderer(device, bunny, ray_mapping=mapping)
        renders[mapping] = renderer.render(camera, W, H, path="ray")
        chosen = renderer.ray_mapping
        if mapping == "auto":  # measured by this session (its own cache folder, conftest.py) or read back
            assert chosen["source"] in ("measured", "cache")
            assert chosen["packet_ms"] > 0 and chosen["single_ms"] > 0
            fastest = "single" if chosen["single_ms"] < chosen["packet_ms"] else "packet"
            assert chosen["mapping"] == fastest
        else:
            assert chosen == {"mapping": mapping, "source": "option", "packet_ms": None, "single_ms": None}
    assert (renders["packet"].ids != clvis.background_id).sum() > 0.05 * W * H
    for mapping in ("auto", "single"):
        assert np.array_equal(renders[mapping].ids, renders["packet"].ids)
        assert np.array_equal(renders[mapping].depth.view(np.uint32), renders["packet"].depth.view(np.uint32))
    with pytest.raises(ValueError, match="ray_mapping"):
        clvis.Renderer(device, bunny, ray_mapping="warp")


@pytest.mark.parametrize("mesh", ["spot.obj", "teapot.obj", "suzanne.obj"])
def test_raster_and_ray_agree_on_the_bundled_meshes(device, mesh):
    scene = clvis.load_scene(SCENES / mesh)
    agree(device, scene, clvis.Camera.framing(scene.bounds()))


@pytest.mark.parametrize("make", [lambda: clvis.make_uv_sphere(2000), lambda: clvis.make_grid(3000, 7),
                                  lambda: clvis.make_soup(1500, 3)])
def test_raster_and_ray_agree_on_procedural_meshes(device, make):
    scene = clvis.Scene()
    scene.add_mesh(make())
    agree(device, scene, clvis.Camera.framing(scene.bounds()))


def test_raster_and_ray_agree_through_an_orthographic_camera(device, bunny):
    agree(device, bunny, clvis.Camera.framing(bunny.bounds(), ortho=True))


def test_raster_and_ray_agree_through_a_physical_camera(device, bunny):
    f = clvis.Camera.framing(bunny.bounds())
    camera = clvis.Camera(eye=f.eye, target=f.target, near=f.near, far=f.far, focal_length=50,
                          film_gate=(36, 24), fit="overscan", aspect=W / H)
    agree(device, bunny, camera)


def test_transformed_meshes_agree_with_the_brute_force_path(device):
    scene = clvis.Scene()
    sphere = clvis.make_uv_sphere(400)
    shift = np.eye(4)
    shift[0, 3] = 1.5
    scene.add_mesh(sphere)
    scene.add_mesh(sphere, transform=shift)
    camera = clvis.Camera.framing(scene.bounds())
    (raster, brute), _ = agree(device, scene, camera, paths=("raster", "brute"))
    ids = brute.ids[brute.ids != clvis.background_id]
    assert {scene.mesh_of(int(i)) for i in np.unique(ids)} == {0, 1}


def test_each_answer_is_judged_correct_on_its_own(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    renderer = clvis.Renderer(device, bunny)
    referee = clvis.Referee(bunny, camera, 48, 32)
    for path in ("raster", "ray"):
        report = referee.check(renderer.render(camera, 48, 32, path=path))
        assert report.errors == 0, path


def test_the_referee_reports_a_wrong_buffer(device, quad):
    camera = clvis.Camera(eye=(0, 0, 3), target=(0, 0, 0), near=0.5, far=10)
    vis = clvis.Renderer(device, quad).render(camera, 32, 32)
    wrong = vis.ids.copy()
    covered = np.argwhere(wrong != clvis.background_id)
    y, x = covered[len(covered) // 2]
    wrong[y, x] = clvis.background_id
    report = clvis.Referee(quad, camera, 32, 32).compare(vis, clvis.Visibility(wrong))
    assert report.errors == 1 and report.errors_b == 1 and report.errors_a == 0
    verdict = report.first_errors[0]
    assert (verdict.x, verdict.y, verdict.error) == (x, y, "missed")
