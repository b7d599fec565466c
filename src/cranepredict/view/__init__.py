"""The operator's display: the crane now and where it will be, in a browser (docs/display.md).

:class:`Frame` (what is shown at one moment: predicted samples and the guard's verdict) needs only
the core install; :class:`Viewer` (the local web page) needs the ``[view]`` extra (viser).
"""

from .frame import SIGNALS, Frame
from .scene import Scene, banner, frame_scene, obstacle_instances
from .server import DEFAULT_HOST, DEFAULT_PORT, Viewer

__all__ = ["Frame", "SIGNALS", "Viewer", "Scene", "frame_scene", "obstacle_instances", "banner",
           "DEFAULT_HOST", "DEFAULT_PORT"]
