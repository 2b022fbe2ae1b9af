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

from . import _clvis
from ._clvis import *  # noqa: F401,F403

__version__ = _clvis.__version__
