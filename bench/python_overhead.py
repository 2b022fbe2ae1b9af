#!/usr/bin/env python3
"""The cost of a render call from Python over the same call from C++.

Times Renderer.render() (render + one read-back + the NumPy views) from Python, and the same
render + read-back timed inside C++ by Renderer._time_calls(), interleaved in rounds on the same
renderer, and prints the medians and their difference per call: the Python layer's overhead
(argument conversion, GIL release, result objects). Warm frames only; the device is named.

    CLVIS_DEVICE=cpu .venv/bin/python bench/python_overhead.py [--calls 200] [--rounds 5]
"""

import argparse
import statistics
import time

import clvis


def python_calls(renderer, camera, width, height, path, calls):
    seconds = []
    for _ in range(calls):
        start = time.perf_counter()
        renderer.render(camera, width, height, path=path)
        seconds.append(time.perf_counter() - start)
    return seconds


def measure(renderer, camera, width, height, path, calls, rounds):
    renderer.render(camera, width, height, path=path)  # kernels built, BVH built
    py, cpp = [], []
    for _ in range(rounds):
        py.append(statistics.median(python_calls(renderer, camera, width, height, path, calls)))
        cpp.append(statistics.median(renderer._time_calls(camera, width, height, path, calls)))
    # The round with the least disturbance from other processes: the smallest median of each.
    return min(py), min(cpp)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default=None, help="device spec (default: CLVIS_DEVICE, else GPU, else CPU)")
    parser.add_argument("--calls", type=int, default=200, help="calls per round and side")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--triangles", type=int, default=2000, help="triangles of the UV sphere")
    args = parser.parse_args()

    device = clvis.Device(args.device)
    scene = clvis.Scene()
    scene.add_mesh(clvis.make_uv_sphere(args.triangles))
    camera = clvis.Camera.framing(scene.bounds())
    renderer = clvis.Renderer(device, scene)
    print(f"device: {device.name}; scene: UV sphere, {scene.triangle_count} triangles; "
          f"medians of {args.calls} warm calls, best of {args.rounds} rounds")
    print(f"{'path':6} {'size':>9} {'python us':>10} {'c++ us':>10} {'overhead us':>12}")
    for path in ("raster", "ray"):
        for width, height in ((64, 64), (640, 360)):
            py, cpp = measure(renderer, camera, width, height, path, args.calls, args.rounds)
            print(f"{path:6} {width:>4}x{height:<4} {py * 1e6:10.1f} {cpp * 1e6:10.1f} {(py - cpp) * 1e6:12.1f}")


if __name__ == "__main__":
    main()
