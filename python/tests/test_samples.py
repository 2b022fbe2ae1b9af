"""Several samples per pixel from Python (the samples= keyword): (H, W, N) arrays holding every
sample at CONVENTIONS.md's standard positions, judged by the referee at every sample, the same
buffer on both paths under the raster rule, and sample 1 of 1 the plain render."""

import numpy as np
import pytest

import clvis

W, H = 40, 28


@pytest.mark.parametrize("samples", [2, 4, 16])
def test_both_paths_hold_every_sample_and_the_referee_accepts_them(device, bunny, samples):
    camera = clvis.Camera.framing(bunny.bounds())
    renderer = clvis.Renderer(device, bunny, samples=samples)
    raster, ray = (renderer.render(camera, W, H, path=p) for p in ("raster", "ray"))
    for vis in (raster, ray):
        assert vis.samples == samples
        assert vis.ids.shape == (H, W, samples) and vis.depth.shape == (H, W, samples)
    # Samples of one pixel differ somewhere along the bunny's outline.
    assert (raster.ids != raster.ids[:, :, :1]).any()
    report = clvis.Referee(bunny, camera, W, H).compare(raster, ray)
    assert report.errors == 0, [v.describe() for v in report.first_errors]
    assert report.equal > 0.95 * W * H * samples


def test_the_raster_rule_gives_both_paths_the_same_samples(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    renderer = clvis.Renderer(device, bunny, samples=8, coverage="raster-rule")
    raster, ray = (renderer.render(camera, W, H, path=p) for p in ("raster", "ray"))
    np.testing.assert_array_equal(raster.ids, ray.ids)
    np.testing.assert_array_equal(raster.depth.view(np.uint32), ray.depth.view(np.uint32))


def test_one_sample_is_the_plain_render(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    one = clvis.Renderer(device, bunny, samples=1).render(camera, W, H)
    plain = clvis.Renderer(device, bunny).render(camera, W, H)
    assert one.ids.shape == (H, W) and one.samples == 1
    np.testing.assert_array_equal(one.ids, plain.ids)


def test_samples_read_into_the_callers_arrays_and_shade_averages_them(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    renderer = clvis.Renderer(device, bunny, samples=4)
    ids, depth = np.empty((H, W, 4), np.uint32), np.empty((H, W, 4), np.float32)
    vis = renderer.render(camera, W, H, path="ray", out=(ids, depth))
    assert vis.ids is ids
    np.testing.assert_array_equal(ids, renderer.render(camera, W, H, path="ray").ids)
    image = clvis.shade(renderer, vis)
    assert image.shape[:2] == (H, W)
    with pytest.raises(clvis.InvalidArgumentError, match=r"render: out ids.*\(28, 40, 4\)"):
        renderer.render(camera, W, H, out=np.empty((H, W), np.uint32))


def test_a_sample_count_other_than_a_power_of_two_to_16_is_refused(device, bunny):
    with pytest.raises(clvis.InvalidArgumentError, match="3"):
        clvis.Renderer(device, bunny, samples=3)
