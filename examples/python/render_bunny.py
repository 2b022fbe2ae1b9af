#!/usr/bin/env python3
"""Renders the Stanford bunny by rasterization and by ray casting, lets the referee compare the
two, writes shaded images, and plots frame time against triangle count for both paths.

    CLVIS_DEVICE=cpu .venv/bin/python examples/python/render_bunny.py --out out/python

Writes OUT/bunny-raster.png, OUT/bunny-ray.png (where clvis has its image layer) and
OUT/frame_time.png, and prints the referee's counts and the timings.
"""

import argparse
import pathlib
import statistics

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import clvis  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]


def frame_ms(renderer, camera, width, height, path, frames):
    """Median device-side frame time of warm frames (the first builds kernels and the BVH)."""
    renderer.render(camera, width, height, path=path)
    return statistics.median(renderer.render(camera, width, height, path=path).timing.frame_ms
                             for _ in range(frames))


def compare_paths(device, width, height, out):
    scene = clvis.load_scene(REPO / "scenes" / "stanford-bunny.obj")
    camera = clvis.Camera.framing(scene.bounds())
    renderer = clvis.Renderer(device, scene)
    raster = renderer.render(camera, width, height, path="raster")
    ray = renderer.render(camera, width, height, path="ray")
    report = clvis.Referee(scene, camera, width, height).compare(raster, ray)
    covered = np.count_nonzero(raster.ids != clvis.background_id)
    print(f"bunny, {scene.triangle_count} triangles, {width}x{height}: {covered} pixels covered")
    print(f"referee: {report.equal} equal, {report.explained} differ but both right, {report.errors} errors")
    for verdict in report.first_errors:
        print("  ", verdict.describe())
    if clvis.HAVE_IMAGE_IO:
        for vis in (raster, ray):
            clvis.write_image(out / f"bunny-{vis.path}.png", clvis.shade(renderer, vis))
    return report.errors


def sweep(device, counts, width, height, frames):
    """Frame times of UV spheres of each triangle count, framed alike, by both paths."""
    times = {"raster": [], "ray": []}
    for count in counts:
        scene = clvis.Scene()
        scene.add_mesh(clvis.make_uv_sphere(count))
        camera = clvis.Camera.framing(scene.bounds())
        renderer = clvis.Renderer(device, scene)
        for path in times:
            times[path].append(frame_ms(renderer, camera, width, height, path, frames))
        print(f"{scene.triangle_count:>9} triangles: raster {times['raster'][-1]:8.2f} ms, "
              f"ray {times['ray'][-1]:8.2f} ms")
    return times


def plot(counts, times, device, width, height, path):
    fig, ax = plt.subplots(figsize=(6, 4))
    for name, ms in times.items():
        ax.plot(counts, ms, marker="o", label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles (UV sphere)")
    ax.set_ylabel("frame time, ms (median of warm frames)")
    ax.set_title(f"{width}x{height} on {device.name}", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default=None, help="device spec (default: CLVIS_DEVICE, else GPU, else CPU)")
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("out/python"))
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=360)
    parser.add_argument("--frames", type=int, default=5, help="warm frames per measurement")
    parser.add_argument("--max-triangles", type=int, default=256_000)
    args = parser.parse_args()

    args.out.mkdir(parents=True, exist_ok=True)
    device = clvis.Device(args.device)
    print(f"device: {device.name}")
    errors = compare_paths(device, args.width, args.height, args.out)
    counts = [n for n in (1_000, 4_000, 16_000, 64_000, 256_000, 1_024_000) if n <= args.max_triangles]
    times = sweep(device, counts, args.width, args.height, args.frames)
    plot(counts, times, device, args.width, args.height, args.out / "frame_time.png")
    return 1 if errors else 0


if __name__ == "__main__":
    raise SystemExit(main())
