"""clvis.RayQuery.all: each ray's max_hits nearest hits, ordered by t then id, as an (N, K)
clvis.hit_dtype array whose first column is the closest hit; with counts=True the number of all
hits (edges inclusive: a ray through the quad's shared diagonal meets both triangles, where the
half-open count sees one crossing); bad max_hits raise InvalidArgumentError naming it."""

import numpy as np
import pytest

import clvis

from conftest import quad_scene


@pytest.fixture(scope="module")
def query(device, bunny):
    return clvis.RayQuery(clvis.Renderer(device, bunny))


@pytest.fixture(scope="module")
def rays(bunny):
    b = bunny.bounds()
    lo, hi = np.array(b.lo, np.float32), np.array(b.hi, np.float32)
    rng = np.random.default_rng(4)
    n = 500
    r = np.zeros((n, 8), np.float32)
    r[:, 0:3] = lo + (hi - lo) * rng.uniform(0, 1, (n, 3))
    r[:, 4:7] = rng.normal(size=(n, 3))
    r[:, 7] = np.inf
    return r


def test_all_hits_lead_with_the_closest_hit_and_are_ordered(query, rays):
    hits, counts = query.all(rays, 3, counts=True)
    assert hits.shape == (len(rays), 3) and hits.dtype == clvis.hit_dtype
    assert counts.shape == (len(rays),) and counts.dtype == np.uint32
    np.testing.assert_array_equal(hits[:, 0].copy().view(np.uint32).reshape(-1, 4),
                                  query.closest(rays).view(np.uint32).reshape(-1, 4))
    kept = hits["id"] != clvis.background_id
    np.testing.assert_array_equal(kept.sum(axis=1), np.minimum(counts, 3))
    assert (counts > 3).any()
    t = np.where(kept, hits["t"], np.inf)
    assert (t[:, 1:] >= t[:, :-1]).all()
    assert (hits["t"][~kept] == np.inf).all() and (hits["u"][~kept] == 0).all()
    only = query.all(rays, 3)
    np.testing.assert_array_equal(only.view(np.uint32), hits.view(np.uint32))
    np.testing.assert_array_equal(query.all(rays, 2).view(np.uint32), hits[:, :2].copy().view(np.uint32))


def test_a_ray_through_a_shared_edge_meets_both_triangles(device):
    query = clvis.RayQuery(clvis.Renderer(device, quad_scene()))
    rays = np.array([[0, 0, 3, 0, 0, 0, -1, np.inf], [0.5, -0.5, 3, 0, 0, 0, -1, np.inf]], np.float32)
    hits, counts = query.all(rays, 4, counts=True)
    np.testing.assert_array_equal(counts, [2, 1])
    np.testing.assert_array_equal(hits["id"][0, :2], [0, 1])
    np.testing.assert_array_equal(hits["t"][0, :2], [3, 3])
    np.testing.assert_array_equal(query.count(rays), [1, 1])


@pytest.mark.parametrize("k", [0, 65, -1])
def test_all_hits_refuse_a_bad_max_hits(query, rays, k):
    with pytest.raises(clvis.InvalidArgumentError, match=rf"RayQuery.all: max_hits must lie in \[1, 64\], got {k}"):
        query.all(rays, k)
