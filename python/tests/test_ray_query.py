"""clvis.RayQuery, made once and reused: primary rays as records (AoS), planes (SoA) or
clvis.ray_dtype answer as the ray path's render; results land in the caller's arrays (out=) in
every layout; occlusion and counts agree with closest hits; the BVH is not rebuilt per call; the
ambient-occlusion and shadow rays generated on the device answer as those rays cast by hand; bad
arrays raise InvalidArgumentError naming the argument."""

import numpy as np
import pytest

import clvis

from test_queries import primary_rays

W, H = 48, 32


@pytest.fixture(scope="module")
def renderer(device, bunny):
    return clvis.Renderer(device, bunny)


@pytest.fixture(scope="module")
def query(renderer):
    return clvis.RayQuery(renderer)


@pytest.fixture(scope="module")
def camera(bunny):
    return clvis.Camera.framing(bunny.bounds())


@pytest.fixture(scope="module")
def records(camera):
    origins, directions = primary_rays(camera, W, H)
    rays = np.zeros((W * H, 8), np.float32)
    rays[:, 0:3], rays[:, 3], rays[:, 4:7], rays[:, 7] = origins, camera.near, directions, camera.far
    return rays


@pytest.fixture(scope="module")
def render(renderer, camera):
    return renderer.render(camera, W, H, path="ray")


def test_closest_hits_of_records_are_the_ray_paths_render(query, records, render):
    hits = query.closest(records)
    assert hits.dtype == clvis.hit_dtype and hits.shape == (W * H,) and hits.flags.writeable
    np.testing.assert_array_equal(hits["id"].reshape(H, W), render.ids)
    np.testing.assert_allclose(hits["t"].reshape(H, W), render.depth, rtol=1e-5)
    assert (hits["id"] != clvis.background_id).sum() > 0.05 * W * H
    assert query.stats.rays == W * H and query.stats.invalid == 0 and query.stats.batches >= 1


def test_every_layout_in_and_out_gives_the_same_hits(query, records):
    want = query.closest(records)
    aos = np.empty(W * H, clvis.hit_dtype)
    assert query.closest(records.view(clvis.ray_dtype).ravel(), out=aos) is aos
    soa = (np.empty(W * H, np.float32), np.empty(W * H, np.uint32), np.empty(W * H, np.float32), np.empty(W * H, np.float32))
    got = query.closest(np.ascontiguousarray(records.T), "soa", out=soa)
    assert got is soa
    for field, array in zip(("t", "id", "u", "v"), soa):
        np.testing.assert_array_equal(aos[field], want[field])
        np.testing.assert_array_equal(array, want[field])


def test_occluded_and_counts_agree_with_closest_hits_in_place(query, records):
    hit = query.closest(records)["id"] != clvis.background_id
    flags = np.full(W * H, 7, np.uint8)
    counts = np.zeros(W * H, np.uint32)
    assert query.occluded(records, out=flags) is flags
    assert query.count(np.ascontiguousarray(records.T), "soa", out=counts) is counts
    np.testing.assert_array_equal(flags, hit)
    assert (counts[hit] >= 1).all() and (counts[~hit] == 0).all()
    # The bunny is closed almost everywhere: most rays that enter it leave it again.
    assert np.mean(counts[hit] % 2 == 0) > 0.9


def test_rays_walked_interleaved_give_the_same_answers(query, bunny):
    rng = np.random.default_rng(11)
    n = 1001  # not a multiple of any run of lanes: the last work-items' lanes run dry at different steps
    box = bunny.bounds()
    lo, hi = np.asarray(box.lo, np.float64), np.asarray(box.hi, np.float64)
    origins = rng.uniform(lo, hi, (n, 3)).astype(np.float32)  # inside the box: rays of every length
    directions = rng.normal(size=(n, 3)).astype(np.float32)
    rays = np.zeros((n, 8), np.float32)
    rays[:, 0:3], rays[:, 4:7], rays[:, 7] = origins, directions, np.where(np.arange(n) % 3, np.inf, 0.01)
    want = query.closest(rays), query.occluded(rays), query.count(rays)
    assert (want[0]["id"] != clvis.background_id).sum() > n // 4
    for lanes in (2, 3, 8):
        interleaved = clvis.RayQuery(query.renderer, lanes=lanes)
        assert interleaved.lanes == lanes
        got = interleaved.closest(rays), interleaved.occluded(rays), interleaved.count(rays)
        np.testing.assert_array_equal(got[0].view(np.uint32), want[0].view(np.uint32))
        np.testing.assert_array_equal(got[1], want[1])
        np.testing.assert_array_equal(got[2], want[2])


def test_a_query_reuses_the_bvh_and_sees_updates(device):
    scene = clvis.Scene()
    triangle = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], np.float32)
    scene.add_mesh(triangle, [[0, 1, 2]])
    renderer = clvis.Renderer(device, scene)
    query = clvis.RayQuery(renderer, batch_rays=3)
    built = renderer.bvh_stats
    ray = np.array([[0, 0, 5, 0, 0, 0, -1, np.inf]] * 7, np.float32)
    for _ in range(3):
        np.testing.assert_array_equal(query.closest(ray)["t"], 5)
    assert query.stats.batches == 3  # 7 rays, 3 per launch
    after = renderer.bvh_stats
    assert (after.build_ms, after.nodes, after.refitted) == (built.build_ms, built.nodes, built.refitted)
    scene.set_positions(0, triangle + np.float32([0, 0, 1]))
    renderer.update(scene)
    np.testing.assert_array_equal(query.closest(ray)["t"], 4)
    assert renderer.bvh_stats.refitted


def test_generated_ao_rays_cast_by_hand_give_the_ambient_occlusion(query, render):
    ao = query.ambient_occlusion(render, rays=4, seed=3)
    out = np.empty((H, W), np.float32)
    assert query.ambient_occlusion(render, rays=4, seed=3, out=out) is out
    np.testing.assert_array_equal(out, ao)
    rays = query.ambient_occlusion_rays(render, rays=4, seed=3)
    assert rays.shape == (W * H * 4, 8) and rays.dtype == np.float32
    occluded = query.occluded(rays).reshape(H, W, 4)
    np.testing.assert_allclose(ao, 1 - occluded.mean(axis=2), atol=1e-6)
    assert ((ao >= 0) & (ao <= 1)).all() and (ao[render.ids == clvis.background_id] == 1).all()
    assert (ao < 1).any()


def test_shadow_rays_light_what_the_light_sees(query, render, camera):
    visible = render.ids != clvis.background_id
    at_eye = query.shadows(render, camera.eye)
    assert at_eye.shape == (H, W) and set(np.unique(at_eye)) <= {0.0, 1.0}
    assert at_eye[visible].mean() > 0.98 and (at_eye[~visible] == 1).all()
    eye, target = np.array(camera.eye), np.array(camera.target)
    side = target + np.cross(eye - target, camera.up)  # as far as the eye, 90 degrees to the side
    out = np.empty((H, W), np.float32)
    assert query.shadows(render, tuple(side), out=out) is out
    assert 0.05 < out[visible].mean() < 0.95


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda q, r: q.closest(np.zeros((4, 3), np.float32)), r"RayQuery.closest: rays: expected an array of shape \(N, 8\)"),
        (lambda q, r: q.closest(np.zeros((7, 4), np.float32), "soa"), r"RayQuery.closest: rays: expected an array of shape \(8, N\)"),
        (lambda q, r: q.closest(np.zeros((4, 8)), "planes"), "RayQuery.closest: layout: expected one of aos, soa"),
        (lambda q, r: q.closest(np.zeros((4, 8)), out=np.empty(4, np.float32)), "RayQuery.closest: out: expected a writable"),
        (lambda q, r: q.closest(np.zeros((4, 8)), out=np.empty(5, clvis.hit_dtype)), r"shape \(4,\)"),
        (lambda q, r: q.closest(np.zeros((4, 8)), out=(np.empty(4, np.float32),) * 3), r"\(t, id, u, v\), got 3 items"),
        (lambda q, r: q.closest(np.zeros((4, 8)), out=(np.empty(4, np.float32),) * 4), "RayQuery.closest: out id: .*dtype float32"),
        (lambda q, r: q.occluded(np.zeros((4, 8)), out=np.empty(4, np.uint32)), "RayQuery.occluded: out: .*got dtype uint32"),
        (lambda q, r: q.count(np.zeros((4, 8)), out=np.empty(8, np.uint32)[::2]), "RayQuery.count: out: .*not C-contiguous"),
        (lambda q, r: q.count(np.zeros((4, 8)), out=np.zeros(4, np.uint32).setflags(write=False) or None), None),
        (lambda q, r: q.ambient_occlusion(clvis.Visibility(np.zeros((2, 2), np.uint32))), "RayQuery.ambient_occlusion: the Visibility must come from"),
        (lambda q, r: q.shadows(r, (0, 0, 0), out=np.empty((H, W + 1), np.float32)), "RayQuery.shadows: out"),
        (lambda q, r: clvis.RayQuery(q.renderer, batch_rays=0), "RayQuery: batch_rays must be positive"),
        (lambda q, r: clvis.RayQuery(q.renderer, lanes=9), r"lanes must lie in \[0, 8\], got 9"),
    ],
)
def test_ray_query_errors_name_the_argument(query, render, call, message):
    if message is None:  # a read-only out array
        readonly = np.zeros(4, np.uint32)
        readonly.setflags(write=False)
        with pytest.raises(clvis.InvalidArgumentError, match="RayQuery.count: out: .*read-only"):
            query.count(np.zeros((4, 8)), out=readonly)
        return
    with pytest.raises(clvis.InvalidArgumentError, match=message):
        call(query, render)


def test_a_query_keeps_its_renderer_alive(device, bunny, records):
    query = clvis.RayQuery(clvis.Renderer(device, bunny))
    import gc

    gc.collect()
    assert (query.closest(records)["id"] != clvis.background_id).any()
    assert isinstance(query.renderer, clvis.Renderer)
