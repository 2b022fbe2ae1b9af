"""The command line's render options from Python: coverage='raster-rule' makes the ray path's
buffers bit-identical to the raster path's; a region renders those pixels of the whole image; out=
reads back into the caller's arrays; several devices draw the frame one device draws; bad values
raise InvalidArgumentError naming the argument."""

import numpy as np
import pytest

import clvis

W, H = 64, 40


@pytest.fixture(scope="module")
def camera(bunny):
    return clvis.Camera.framing(bunny.bounds())


@pytest.fixture(scope="module")
def renderer(device, bunny):
    return clvis.Renderer(device, bunny)


@pytest.fixture(scope="module")
def whole(renderer, camera):
    return {path: renderer.render(camera, W, H, path=path) for path in ("raster", "ray")}


def test_raster_rule_coverage_makes_the_ray_path_the_raster_paths_twin(device, bunny, camera, whole):
    ray = clvis.Renderer(device, bunny, coverage="raster-rule").render(camera, W, H, path="ray")
    np.testing.assert_array_equal(ray.ids, whole["raster"].ids)
    np.testing.assert_array_equal(ray.depth, whole["raster"].depth)
    # The watertight test differs from it somewhere on the bunny's many shared edges, or at least in depth.
    assert (whole["ray"].ids != ray.ids).any() or (whole["ray"].depth != ray.depth).any()


@pytest.mark.parametrize("path", ["raster", "ray"])
def test_a_region_holds_those_pixels_of_the_whole_render(renderer, camera, whole, path):
    vis = renderer.render(camera, W, H, path=path, region=(10, 5, 23, 17))
    assert (vis.width, vis.height, vis.region) == (23, 17, (10, 5, 23, 17))
    np.testing.assert_array_equal(vis.ids, whole[path].ids[5:22, 10:33])
    np.testing.assert_array_equal(vis.depth, whole[path].depth[5:22, 10:33])
    assert whole[path].region is None
    assert len(renderer.visible_ids(vis)) > 0  # ids only: a region is fine
    with pytest.raises(clvis.InvalidArgumentError, match="resolve: the Visibility holds a region"):
        renderer.resolve(vis)


def test_out_reads_back_into_the_callers_arrays(renderer, camera, whole, bunny):
    ids = np.full((H, W), 7, np.uint32)
    depth = np.zeros((H, W), np.float32)
    vis = renderer.render(camera, W, H, out=(ids, depth))
    assert vis.ids is ids and vis.depth is depth
    np.testing.assert_array_equal(ids, whole["raster"].ids)
    np.testing.assert_array_equal(depth, whole["raster"].depth)
    only_ids = np.zeros((17, 23), np.uint32)
    vis = renderer.render(camera, W, H, path="ray", region=(10, 5, 23, 17), out=only_ids)
    assert vis.ids is only_ids and vis.depth is None
    np.testing.assert_array_equal(only_ids, whole["ray"].ids[5:22, 10:33])
    # The referee and the device-side outputs read such a Visibility as any other.
    vis = renderer.render(camera, W, H, out=[ids, depth])
    report = clvis.Referee(bunny, camera, W, H).compare(vis, whole["ray"])
    assert report.errors == 0 and report.depth_errors == 0
    assert renderer.resolve(vis, ["barycentrics"])["barycentrics"].shape == (H, W, 2)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(region=(60, 0, 10, 10)), "region"),
        (dict(region=(0, 0, 0, 10)), "render: region: width and height must be positive"),
        (dict(region=(0, 0, 10)), r"render: region: expected \(x, y, width, height\)"),
        (dict(out=np.zeros((H, W), np.int32)), "render: out ids: expected a writable C-contiguous uint32 array of shape"),
        (dict(out=np.zeros((W, H), np.uint32)), r"render: out ids: .*got dtype uint32, shape \(64, 40\)"),
        (dict(out=np.zeros((H, 2 * W), np.uint32)[:, ::2]), "render: out ids: .*not C-contiguous"),
        (dict(out=(np.zeros((H, W), np.uint32), np.zeros((H, W), np.float64))), "render: out depth: .*float64"),
        (dict(out=(np.zeros((H, W), np.uint32),)), r"render: out: expected an ids array or \(ids, depth\), got 1 items"),
        (dict(out=[[0] * W] * 2), "render: out ids: .*got list"),
    ],
)
def test_render_options_errors_name_the_argument(renderer, camera, kwargs, message):
    with pytest.raises(clvis.InvalidArgumentError, match=message):
        renderer.render(camera, W, H, **kwargs)


def test_a_read_only_out_array_is_refused(renderer, camera):
    ids = np.zeros((H, W), np.uint32)
    ids.setflags(write=False)
    with pytest.raises(clvis.InvalidArgumentError, match="render: out ids: .*read-only"):
        renderer.render(camera, W, H, out=ids)


def test_coverage_names_its_choices(device, bunny):
    with pytest.raises(clvis.InvalidArgumentError, match="coverage: expected one of watertight, raster-rule"):
        clvis.Renderer(device, bunny, coverage="exact")


@pytest.mark.parametrize("path", ["raster", "ray"])
def test_two_devices_draw_the_frame_one_device_draws(device, bunny, camera, whole, path):
    multi = clvis.MultiDeviceRenderer([device, device], bunny)
    assert multi.device_count == 2
    vis = multi.render(camera, W, H, path=path, screen_tile=16, device_map=True)
    np.testing.assert_array_equal(vis.ids, whole[path].ids)
    np.testing.assert_array_equal(vis.depth, whole[path].depth)
    assert multi.tiles == 12 and sum(s.tiles for s in multi.shares) == 12
    assert multi.device_of.shape == (H, W) and set(np.unique(multi.device_of)) <= {0, 1}
    ids = np.empty((H, W), np.uint32)
    assert multi.render(camera, W, H, path=path, out=ids).ids is ids
    np.testing.assert_array_equal(ids, whole[path].ids)
    assert multi.device_of is None


def test_multi_device_errors_name_the_argument(device, bunny, camera):
    with pytest.raises(clvis.InvalidArgumentError):
        clvis.MultiDeviceRenderer([], bunny)
    multi = clvis.MultiDeviceRenderer([device], bunny)
    with pytest.raises(clvis.InvalidArgumentError, match="tile"):
        multi.render(camera, W, H, screen_tile=0)
    with pytest.raises(clvis.InvalidArgumentError, match="render: out ids"):
        multi.render(camera, W, H, out=np.zeros((H, W), np.float32))


def test_options_are_keywords_of_the_libraries_names(device, bunny):
    with pytest.raises(TypeError, match="unexpected keyword argument 'tiles'"):
        clvis.Renderer(device, bunny, tiles=16)
    with pytest.raises(TypeError, match="tile: expected an int"):
        clvis.Renderer(device, bunny, tile="16")
    with pytest.raises(TypeError):
        clvis.Renderer(device, bunny, 16)  # keywords only
    with pytest.raises(clvis.InvalidArgumentError, match="bvh_update: expected one of refit, rebuild, got 'x'"):
        clvis.MultiDeviceRenderer([device], bunny, bvh_update="x")
    renderer = clvis.Renderer(device, bunny, raster_mapping="pixel", ray_mapping="single")
    assert (renderer.raster_mapping["mapping"], renderer.ray_mapping["mapping"]) == ("pixel", "single")
