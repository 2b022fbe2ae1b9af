#!/usr/bin/env python3
"""The cost of a render call from Python over the same call from C++.

Each Renderer.render() times its own C++ work (render + the one read-back) inside the call
(Visibility._call_seconds); the Python side times the whole call plus the access to both NumPy
views. Their difference, call by call, is what the Python layer adds (argument conversion, the
GIL released and taken back, the lock, the result and its views), free of the device's own jitter,
which is large on a shared CPU. Warm calls only; the device is named.

The last column is a control: the same access to both views of a finished result, after the
thread slept as long as a frame. Caches grow cold while the device works (on a loaded CPU most of
all), and whatever runs first after a long call pays for it, in Python or in C++.

    CLVIS_DEVICE=cpu .venv/bin/python bench/python_overhead.py [--calls 1000]
"""

import argparse
import statistics
import time

import clvis


def measure(renderer, camera, width, height, path, calls):
    renderer.render(camera, width, height, path=path)  # kernels built, BVH built
    whole, inner = [], []
    for _ in range(calls):
        start = time.perf_counter()
        vis = renderer.render(camera, width, height, path=path)
        vis.ids, vis.depth
        whole.append(time.perf_counter() - start)
        inner.append(vis._call_seconds)
        del vis  # freeing the result (host arrays, device buffer) is not part of the call
    extra = sorted(w - i for w, i in zip(whole, inner))
    return statistics.median(whole), statistics.median(inner), statistics.median(extra), extra[int(0.9 * calls)]


def views_after_sleep(vis, seconds, calls):
    times = []
    for _ in range(calls):
        time.sleep(seconds)
        start = time.perf_counter()
        vis.ids, vis.depth
        times.append(time.perf_counter() - start)
    return statistics.median(times)


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
    print(f"{'path':6} {'size':>9} {'python us':>10} {'c++ us':>10} {'overhead us':>12} {'p90 us':>8} "
          f"{'views after sleep us':>21}")
    for path in ("raster", "ray"):
        for width, height in ((64, 64), (640, 360)):
            whole, inner, extra, p90 = measure(renderer, camera, width, height, path, args.calls)
            control = views_after_sleep(renderer.render(camera, width, height, path=path), inner, args.calls // 10)
            print(f"{path:6} {width:>4}x{height:<4} {whole * 1e6:10.1f} {inner * 1e6:10.1f} {extra * 1e6:12.1f} "
                  f"{p90 * 1e6:8.1f} {control * 1e6:21.1f}")


if __name__ == "__main__":
    main()
