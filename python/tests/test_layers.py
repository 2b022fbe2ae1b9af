"""Depth layers from Python (the layers= keyword): (H, W, K) arrays, each pixel's K nearest
triangles nearest first; layer 0 the one-layer render; the raster path's layers equal the ray
path's under the raster rule, ids and depth bits."""

import numpy as np
import pytest

import clvis

W, H = 40, 28


@pytest.mark.parametrize("layers", [2, 4, 8])
def test_layers_are_sorted_and_layer_0_is_the_plain_render(device, bunny, layers):
    camera = clvis.Camera.framing(bunny.bounds())
    for path in ("raster", "ray"):
        vis = clvis.Renderer(device, bunny, layers=layers).render(camera, W, H, path=path)
        assert vis.layers == layers
        assert vis.ids.shape == (H, W, layers) and vis.depth.shape == (H, W, layers)
        one = clvis.Renderer(device, bunny).render(camera, W, H, path=path)
        assert one.layers == 1 and one.ids.shape == (H, W)
        assert np.array_equal(vis.ids[:, :, 0], one.ids)
        assert np.array_equal(vis.depth[:, :, 0].view(np.uint32), one.depth.view(np.uint32))
        # nearest first: depths never decrease; the bunny has a back behind its front
        assert (vis.depth[:, :, 1:] >= vis.depth[:, :, :-1]).all()
        assert (vis.ids[:, :, 1] != clvis.background_id).sum() > 100


def test_the_raster_rule_gives_both_paths_the_same_layers(device, bunny):
    camera = clvis.Camera.framing(bunny.bounds())
    renderer = clvis.Renderer(device, bunny, layers=4, coverage="raster-rule")
    raster, ray = (renderer.render(camera, W, H, path=p) for p in ("raster", "ray"))
    assert np.array_equal(raster.ids, ray.ids)
    assert np.array_equal(raster.depth.view(np.uint32), ray.depth.view(np.uint32))


def test_layers_with_samples_are_refused(device, bunny):
    with pytest.raises(clvis.Error, match="layers"):
        clvis.Renderer(device, bunny, layers=2, samples=4)
    with pytest.raises(clvis.Error, match="layers"):
        clvis.Renderer(device, bunny, layers=9)


def test_a_layer_taken_out_resolves_as_a_plain_render(device, bunny):
    """Visibility.layer(k): that layer's ids and depths as an (H, W) Visibility, which resolve
    reads: the object of every covered sample is the bunny (item 0), barycentrics in range."""
    camera = clvis.Camera.framing(bunny.bounds())
    renderer = clvis.Renderer(device, bunny, layers=3)
    vis = renderer.render(camera, W, H)
    for k in range(3):
        one = vis.layer(k)
        assert one.layers == 1 and one.ids.shape == (H, W)
        assert np.array_equal(one.ids, vis.ids[:, :, k])
        assert np.array_equal(one.depth.view(np.uint32), vis.depth[:, :, k].view(np.uint32))
        out = renderer.resolve(one, ["barycentrics", "object"])
        covered = one.ids != clvis.background_id
        assert covered.sum() > (100 if k < 2 else 0)  # the bunny: a front, a back, a few ears
        assert (out["object"][covered] == 0).all()
        assert (out["object"][~covered] == clvis.background_id).all()
        uv = out["barycentrics"][covered]
        assert (uv >= -1e-6).all() and (uv.sum(axis=-1) <= 1 + 1e-6).all()
    with pytest.raises(clvis.Error, match="layer 3 of a buffer of 3"):
        vis.layer(3)
