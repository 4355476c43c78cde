"""gnomon: shadow-map setups of every classic technique, measured.

Cameras, lights and scenes in; shadow-map matrices, projections, aliasing curves and
renders out, as numpy arrays. The same core as the `gnomon` command line, which gives the
same answers: ``setup(...).to_json()`` is what ``gnomon setup --json`` prints.

>>> import gnomon
>>> scene = gnomon.Scene.demo()
>>> camera, light = scene.view("street")
>>> s = gnomon.setup("lispsm", camera, light, scene)
>>> s.maps[0].clip_from_world.shape
(4, 4)
"""

from ._gnomon import (
    TECHNIQUES,
    Analysis,
    Camera,
    Frame,
    GnomonError,
    Map,
    Point,
    Scene,
    Setup,
    Spot,
    Sun,
    __version__,
    analyze,
    compare,
    project,
    render,
    setup,
)

__all__ = [
    "TECHNIQUES",
    "Analysis",
    "Camera",
    "Frame",
    "GnomonError",
    "Map",
    "Point",
    "Scene",
    "Setup",
    "Spot",
    "Sun",
    "__version__",
    "analyze",
    "compare",
    "project",
    "render",
    "setup",
]
