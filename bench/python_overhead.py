#!/usr/bin/env python3
"""The cost of a render call from Python over the same call from C++.

Each Renderer.render() times its own C++ work (render + the one read-back) inside the call
(Visibility._call_seconds, and _call_span_ns: when it began and ended on perf_counter_ns's clock);
the Python side times the whole call plus the access to both arrays. Their difference, call by
call, is what the Python layer adds (argument conversion, the GIL released and taken back, the
lock, the result and its arrays), free of the device's own jitter, which is large on a shared CPU.
It is split into entry (call to the C++ start), exit (C++ end to the return) and arrays (vis.ids,
vis.depth). Warm calls only; the device is named. Two modes: new result arrays per call, and
out=(ids, depth), arrays the caller made once.

The last column is a control: the same access to both arrays of a finished result, after the
thread slept as long as a frame. Caches grow cold while the device works (on a loaded CPU most of
all), and whatever runs first after a long call pays for it, in Python or in C++.

    CLVIS_DEVICE=cpu .venv/bin/python bench/python_overhead.py [--calls 1000]
"""

import argparse
import statistics
import time

import numpy as np

import clvis


def measure(renderer, camera, width, height, path, calls, out):
    renderer.render(camera, width, height, path=path)  # kernels built, BVH built
    whole, inner, entry, exit_, arrays = [], [], [], [], []
    for _ in range(calls):
        start = time.perf_counter_ns()
        vis = renderer.render(camera, width, height, path=path, out=out)
        returned = time.perf_counter_ns()
        vis.ids, vis.depth
        end = time.perf_counter_ns()
        whole.append((end - start) * 1e-9)
        inner.append(vis._call_seconds)
        span = getattr(vis, "_call_span_ns", None)  # absent from builds without the breakdown
        if span:
            entry.append((span[0] - start) * 1e-9)
            exit_.append((returned - span[1]) * 1e-9)
        arrays.append((end - returned) * 1e-9)
        del vis  # freeing the result (host arrays, device buffer) is not part of the call
    extra = sorted(w - i for w, i in zip(whole, inner))
    med = statistics.median
    return dict(whole=med(whole), inner=med(inner), extra=med(extra), p90=extra[int(0.9 * calls)],
                entry=med(entry) if entry else float("nan"), exit=med(exit_) if exit_ else float("nan"),
                arrays=med(arrays))


def views_after_sleep(vis, seconds, calls):
    times = []
    for _ in range(calls):
        time.sleep(seconds)
        start = time.perf_counter()
        vis.ids, vis.depth
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def ray_batches(renderer, scene, calls):
    """RayQuery.closest from Python against the C++ call's own wall time (RayQueryStats.wall_ms)."""
    query = clvis.RayQuery(renderer)
    rng = np.random.default_rng(1)
    radius = 3 * max(scene.bounds().extent)
    print(f"{'rays':>7} {'mode':>6} {'python us':>10} {'c++ us':>10} {'overhead us':>12}")
    for n in (1000, 100000):
        rays = np.zeros((n, 8), np.float32)
        rays[:, 0:3] = rng.normal(size=(n, 3)) * radius
        rays[:, 4:7], rays[:, 7] = -rays[:, 0:3], np.inf
        hits = np.empty(n, clvis.hit_dtype)
        for mode, out in (("new", None), ("out=", hits)):
            query.closest(rays, out=out)
            whole, inner = [], []
            for _ in range(calls if n == 1000 else max(calls // 20, 5)):
                start = time.perf_counter()
                result = query.closest(rays, out=out)
                whole.append(time.perf_counter() - start)
                inner.append(query.stats.wall_ms * 1e-3)
                del result
            extra = statistics.median(w - i for w, i in zip(whole, inner))
            print(f"{n:7} {mode:>6} {statistics.median(whole) * 1e6:10.1f} {statistics.median(inner) * 1e6:10.1f} "
                  f"{extra * 1e6:12.1f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default=None, help="device spec (default: CLVIS_DEVICE, else GPU, else CPU)")
    parser.add_argument("--calls", type=int, default=1000, help="calls per path and size")
    parser.add_argument("--triangles", type=int, default=2000, help="triangles of the UV sphere")
    args = parser.parse_args()

    device = clvis.Device(args.device)
    scene = clvis.Scene()
    scene.add_mesh(clvis.make_uv_sphere(args.triangles))
    camera = clvis.Camera.framing(scene.bounds())
    renderer = clvis.Renderer(device, scene)
    print(f"device: {device.name}; scene: UV sphere, {scene.triangle_count} triangles; {args.calls} warm calls each")
    print(f"{'path':6} {'size':>9} {'mode':>6} {'python us':>10} {'c++ us':>10} {'overhead us':>12} {'p90 us':>8} "
          f"{'entry':>6} {'exit':>6} {'arrays':>6} {'arrays after sleep us':>22}")
    for path in ("raster", "ray"):
        for width, height in ((64, 64), (640, 360)):
            outs = {"new": None, "out=": (np.empty((height, width), np.uint32), np.empty((height, width), np.float32))}
            for mode, out in outs.items():
                m = measure(renderer, camera, width, height, path, args.calls, out)
                control = views_after_sleep(renderer.render(camera, width, height, path=path), m["inner"],
                                            args.calls // 10)
                print(f"{path:6} {width:>4}x{height:<4} {mode:>6} {m['whole'] * 1e6:10.1f} {m['inner'] * 1e6:10.1f} "
                      f"{m['extra'] * 1e6:12.1f} {m['p90'] * 1e6:8.1f} {m['entry'] * 1e6:6.1f} {m['exit'] * 1e6:6.1f} "
                      f"{m['arrays'] * 1e6:6.1f} {control * 1e6:22.1f}")
    ray_batches(renderer, scene, args.calls)

if __name__ == "__main__":
    main()
