"""clvis: visibility by rasterization and by ray casting on OpenCL, with an exact referee.

Example::

    import clvis
    scene = clvis.load_scene("scenes/stanford-bunny.obj")
    camera = clvis.Camera.framing(scene.bounds())
    renderer = clvis.Renderer(clvis.Device("cpu"), scene)
    raster = renderer.render(camera, 640, 360, path="raster")
    ray = renderer.render(camera, 640, 360, path="ray")
    print(clvis.Referee(scene, camera, 640, 360).compare(raster, ray))

The compiled module ``clvis._clvis`` holds everything (its type stubs: ``_clvis.pyi``); this
package re-exports its public names. See docs/python.md.
"""

import numpy as _numpy

from . import _clvis
from ._clvis import *  # noqa: F401,F403

__version__ = _clvis.__version__

#: A ray record (CONVENTIONS.md "Ray queries"): its points are o + t d for t in [tmin, tmax].
#: An (N,) array of it is the same memory as an (N, 8) float32 array; RayQuery takes either.
ray_dtype = _numpy.dtype({"names": ["ox", "oy", "oz", "tmin", "dx", "dy", "dz", "tmax"], "formats": ["<f4"] * 8})
#: A closest hit as RayQuery.closest writes it (AoS, 16 bytes): t, id (background_id for a miss),
#: barycentrics u, v with the hit point (1 - u - v) v0 + u v1 + v v2.
hit_dtype = _numpy.dtype({"names": ["t", "id", "u", "v"], "formats": ["<f4", "<u4", "<f4", "<f4"]})
