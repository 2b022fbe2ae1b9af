#!/usr/bin/env python3
"""clvis's Python ray queries against Open3D's RaycastingScene (Embree 4 underneath).

Issue 37's comparison from Python: the same rays, the same mesh, both on --threads threads, in
interleaved rounds (clvis, Open3D, clvis, Open3D, ...), medians and spread; every answer
cross-checked. Run through scripts/bench_open3d.sh (a venv with Open3D); see bench/README.md.

  query    clvis                              Open3D
  closest  RayQuery.closest                   cast_rays
  any      RayQuery.occluded                  test_occlusions
  count    RayQuery.count                     count_intersections
  all      RayQuery.all(K, counts=True)       list_intersections (every hit, no K)
  resolve  render(path="ray") + resolve        cast_rays (t, ids, primitive_uvs, geometry_ids)
           (barycentrics) of the same pixels
"""
import argparse
import json
import os
import platform
import statistics
import sys
import time

from bench_open3d_check import check, ratio_summary, summary  # noqa: E402  (this folder)

MESHES = {  # name: triangles (a UV sphere) or a file under scenes/
    "sphere-5k": 5000,
    "bunny": "scenes/stanford-bunny.obj",
    "sphere-1M": 1_000_000,
    "sphere-4M": 4_000_000,
}
QUICK_MESHES = ["sphere-5k", "bunny"]


def parse():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--meshes", default=",".join(QUICK_MESHES),
                   help=f"comma-separated, of {', '.join(MESHES)} (default %(default)s)")
    p.add_argument("--big", action="store_true", help="add sphere-1M and sphere-4M")
    p.add_argument("--size", default="320x180", help="primary rays' image, WxH (default %(default)s)")
    p.add_argument("--ao-rays", type=int, default=4, help="AO rays per covered pixel of that image")
    p.add_argument("--random", type=int, default=100_000, help="random rays (default %(default)s)")
    p.add_argument("--max-hits", type=int, default=4, help="K of RayQuery.all (default %(default)s)")
    p.add_argument("--rounds", type=int, default=5, help="interleaved timed rounds (default %(default)s)")
    p.add_argument("--min-ms", type=float, default=50.0,
                   help="each side's round repeats its call until it lasts this long (default %(default)s)")
    p.add_argument("--threads", type=int, default=2, help="threads on both sides (default %(default)s)")
    p.add_argument("--queries", default="closest,any,count,all,resolve")
    p.add_argument("--json", default="bench-out/open3d.json", help="JSON output (default %(default)s)")
    p.add_argument("--md", default="", help="also write the markdown table there (docs/bench/open3d.md)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--note", default="", help="a paragraph added under the markdown table")
    a = p.parse_args()
    a.meshes = a.meshes.split(",") + (["sphere-1M", "sphere-4M"] if a.big else [])
    a.queries = a.queries.split(",")
    a.width, a.height = (int(x) for x in a.size.split("x"))
    for m in a.meshes:
        if m not in MESHES:
            p.error(f"--meshes: unknown mesh {m!r}")
    return a


ARGS = parse()
# PoCL's CPU device: as many threads as Open3D gets (PoCL 3 reads the first, PoCL 5 the second).
for var in ("POCL_MAX_PTHREAD_COUNT", "POCL_CPU_MAX_CU_COUNT"):
    os.environ.setdefault(var, str(ARGS.threads))

import numpy as np  # noqa: E402
import open3d as o3d  # noqa: E402
import clvis  # noqa: E402


def load(name):
    spec = MESHES[name]
    mesh = clvis.make_uv_sphere(spec) if isinstance(spec, int) else clvis.load_mesh(spec)
    return np.asarray(mesh.positions, np.float32), np.asarray(mesh.indices, np.uint32), mesh


def primary_rays(camera, w, h):
    """docs/conventions.md "Primary rays", in NumPy: d = s.x r + s.y u + f, t = view depth."""
    if hasattr(camera, "rays"):
        return np.ascontiguousarray(np.asarray(camera.rays(w, h), np.float32).reshape(-1, 8))
    view = np.asarray(camera.view_matrix())
    r, u, f = view[0, :3], view[1, :3], -view[2, :3]
    fx, fy, cx, cy = camera.raster_map(w, h)
    x, y = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    sx, sy = ((x - cx) / fx).ravel(), ((cy - y) / fy).ravel()
    rays = np.empty((w * h, 8), np.float32)
    rays[:, 0:3] = camera.eye
    rays[:, 3], rays[:, 7] = camera.near, camera.far
    rays[:, 4:7] = sx[:, None] * r + sy[:, None] * u + f
    # The NumPy rays against the library's own camera.primary_ray (double, rounded to float32).
    for i in (0, w * h // 2, w * h - 1):
        o, d = camera.primary_ray(i % w + 0.5, i // w + 0.5, w, h)
        assert np.allclose(rays[i, :3], o, rtol=1e-6) and np.allclose(rays[i, 4:7], d, rtol=1e-5), i
    return rays


def ray_sets(renderer, query, camera, bounds, rng):
    """name -> (rays (N, 8) float32, note); also the primary render for the resolve workload."""
    prim = primary_rays(camera, ARGS.width, ARGS.height)
    vis = renderer.render(camera, ARGS.width, ARGS.height, path="ray")
    ao = query.ambient_occlusion_rays(vis, rays=ARGS.ao_rays)
    ao = ao[np.repeat(vis.ids.ravel() != clvis.background_id, ARGS.ao_rays)]  # covered pixels only
    n = ARGS.random
    lo, hi = np.asarray(bounds.lo), np.asarray(bounds.hi)
    rnd = np.zeros((n, 8), np.float32)
    rnd[:, 0:3] = lo + rng.random((n, 3)) * (hi - lo)
    d = rng.normal(size=(n, 3))
    rnd[:, 4:7] = d / np.linalg.norm(d, axis=1, keepdims=True)
    rnd[:, 7] = np.inf
    return {"primary": prim, "ao": np.ascontiguousarray(ao), "random": rnd}, vis


def o3d_rays(rays):
    return o3d.core.Tensor(np.ascontiguousarray(rays[:, [0, 1, 2, 4, 5, 6]]))


def unbounded(rays):
    """The same rays over [0, inf]: Open3D's cast_rays, count and list have no interval."""
    r = rays.copy()
    r[:, 3], r[:, 7] = 0, np.inf
    return r


def workloads(set_name, query, renderer, scene, rays, camera):
    """{query: (clvis callable, Open3D callable, the rays both answer)} for one ray set."""
    T, K = ARGS.threads, ARGS.max_hits
    any_rays = rays
    tnear, tfar = float(rays[0, 3]), float(rays[0, 7])
    if not (np.all(rays[:, 3] == tnear) and np.all(rays[:, 7] == tfar)):
        # test_occlusions takes one interval: each origin moved to tmin, then [0, tmax - tmin]
        any_rays = rays.copy()
        any_rays[:, 0:3] += rays[:, 3:4] * rays[:, 4:7]
        any_rays[:, 3], any_rays[:, 7] = 0, rays[:, 7] - rays[:, 3]
        tnear, tfar = 0.0, float(any_rays[0, 7])
        assert np.all(any_rays[:, 7] == tfar), "test_occlusions needs one interval for all rays"
    o_any = o3d_rays(any_rays)
    # closest, count, all: Open3D's cast_rays, count_intersections and list_intersections have no
    # interval, so clvis gets [0, inf] too, except primary rays, whose [near, far] (framing
    # camera) holds the whole mesh: the same answers over the interval a user gives.
    cl = rays if set_name == "primary" else unbounded(rays)
    o_cl = o3d_rays(cl)
    hits = np.empty(len(cl), clvis.hit_dtype)
    occ = np.empty(len(any_rays), np.uint8)
    cnt = np.empty(len(cl), np.uint32)
    out = {"closest": (lambda: query.closest(cl, out=hits), lambda: scene.cast_rays(o_cl, nthreads=T), cl),
           "any": (lambda: query.occluded(any_rays, out=occ),
                   lambda: scene.test_occlusions(o_any, tnear=tnear, tfar=tfar, nthreads=T), any_rays),
           "count": (lambda: query.count(cl, out=cnt),
                     lambda: scene.count_intersections(o_cl, nthreads=T), cl),
           "all": (lambda: query.all(cl, K, counts=True),
                   lambda: scene.list_intersections(o_cl, nthreads=T), cl)}
    if set_name == "primary":
        W, H = ARGS.width, ARGS.height
        out["resolve"] = (lambda: renderer.resolve(renderer.render(camera, W, H, path="ray"), ["barycentrics"]),
                          lambda: scene.cast_rays(o_cl, nthreads=T), cl)
    return out


def timed(fn):
    t0 = time.perf_counter()
    res = fn()
    return (time.perf_counter() - t0) * 1e3, res


def reps_for(fn):
    """Calls per round so that a round lasts at least --min-ms (one call's latency on a loaded
    machine, a thread woken late, is then a small part of the sample)."""
    t = min(timed(fn)[0] for _ in range(2))
    return max(1, min(1000, int(np.ceil(ARGS.min_ms / max(t, 1e-3)))))


def round_ms(fn, reps):
    t0 = time.perf_counter()
    for _ in range(reps):
        fn()
    return (time.perf_counter() - t0) * 1e3 / reps


def make_clvis(device, scene):
    renderer = clvis.Renderer(device, scene)
    query = clvis.RayQuery(renderer)
    query.occluded(np.zeros((1, 8), np.float32))  # the BVH is built here at the latest
    return renderer, query


def main():
    rng = np.random.default_rng(ARGS.seed)
    device = clvis.Device("cpu")
    points, setups = [], {}
    load0 = os.getloadavg()
    t_start = time.time()
    for mesh_name in ARGS.meshes:
        pos, idx, mesh = load(mesh_name)
        scene = clvis.Scene()
        scene.add_mesh(mesh)
        camera = clvis.Camera.framing(scene.bounds())
        t_build_c, (renderer, query) = timed(lambda: make_clvis(device, scene))
        oscene = o3d.t.geometry.RaycastingScene(nthreads=ARGS.threads)
        oscene.add_triangles(o3d.core.Tensor(pos), o3d.core.Tensor(idx))
        sets, vis = ray_sets(renderer, query, camera, scene.bounds(), rng)
        t_build_o, _ = timed(lambda: oscene.test_occlusions(o3d_rays(sets["random"][:1]), nthreads=ARGS.threads))
        print(f"[{mesh_name}] {len(idx)} triangles; set-up clvis {t_build_c:.0f} ms (upload, BVH, kernels "
              f"from the cache), Open3D {t_build_o:.0f} ms (its first query builds the BVH)", flush=True)
        setups[mesh_name] = {"clvis_ms": t_build_c, "open3d_ms": t_build_o}
        for set_name, rays in sets.items():
            wl = workloads(set_name, query, renderer, oscene, rays, camera)
            for qname in ARGS.queries:
                if qname not in wl or (qname == "all" and not hasattr(query, "all")):
                    continue  # RayQuery.all came with the all-hits work: an older clvis skips it
                fc, fo, used = wl[qname]
                _, rc = timed(fc)  # warm-up, also the answers checked
                _, ro = timed(fo)
                verdict = check(qname, used, rc, ro, ARGS.max_hits,
                                vis_ids=vis.ids if qname == "resolve" else None,
                                bary=renderer.resolve(vis, ["barycentrics"])["barycentrics"]
                                if qname == "resolve" else None)
                nc, no = reps_for(fc), reps_for(fo)
                tc, to, dev = [], [], []
                for _ in range(ARGS.rounds):  # interleaved: clvis, Open3D, clvis, Open3D, ...
                    tc.append(round_ms(fc, nc))
                    dev.append(query.stats.device_ms if qname != "resolve" else float("nan"))
                    to.append(round_ms(fo, no))
                pt = {"mesh": mesh_name, "triangles": int(len(idx)), "rays": set_name, "n": int(len(used)),
                      "query": qname, "clvis_ms": summary(tc), "open3d_ms": summary(to),
                      "ratio": ratio_summary(tc, to), "check": verdict, "calls_per_round": [nc, no],
                      "clvis_device_ms_last_call": dev,
                      "load": os.getloadavg()[0]}
                points.append(pt)
                r = pt["ratio"]
                print(f"  {set_name:8s} {qname:8s} n={len(used):8d} clvis {pt['clvis_ms']['median']:9.2f} ms  "
                      f"Open3D {pt['open3d_ms']['median']:9.2f} ms  ratio {r['median']:.2f} "
                      f"[{r['lo']:.2f}, {r['hi']:.2f}]  {verdict['text']}", flush=True)
    doc = {"command": " ".join([os.path.basename(sys.argv[0])] + sys.argv[1:]),
           "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(t_start)),
           "machine": {"cores": os.cpu_count(), "cpu": platform.processor() or platform.machine(),
                       "load_before": load0, "load_after": os.getloadavg()},
           "threads": ARGS.threads, "pocl_env": {k: os.environ[k] for k in os.environ if k.startswith("POCL_")},
           "clvis": clvis.__version__, "clvis_module": clvis.__file__, "open3d": o3d.__version__,
           "numpy": np.__version__,
           "device": device.name,
           "params": {k: v for k, v in vars(ARGS).items() if k not in ("json", "md", "note")},
           "note": ARGS.note, "setup_ms": setups, "points": points}
    os.makedirs(os.path.dirname(ARGS.json) or ".", exist_ok=True)
    with open(ARGS.json, "w") as f:
        json.dump(doc, f, indent=1)
    print(f"wrote {ARGS.json}")
    if ARGS.md:
        from bench_open3d_check import markdown
        with open(ARGS.md, "w") as f:
            f.write(markdown(doc))
        print(f"wrote {ARGS.md}")


if __name__ == "__main__":
    main()
