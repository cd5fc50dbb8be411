"""Everything that touches OpenGL: context, camera, renderer, headless output, the window, the report.

The player consumes a ``MeshSource`` (``tvmedit.player.source``): the library implements it, and
``ArraySource`` holds frames in memory for tests and small scripts.

>>> import numpy as np
>>> from tvmedit import player
>>> p = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1]], np.float32)
>>> source = player.ArraySource({("demo", 0): (p, np.full((3, 3), 200, np.uint8), [[0, 1, 2]])})
>>> player.render_frame(source, ("demo", 0), size=(64, 48)).shape      # doctest: +SKIP
(48, 64, 3)
>>> player.render_frames(source, [("demo", 0)] * 10, "demo.mp4")       # doctest: +SKIP
PosixPath('demo.mp4')
"""

from .camera import Camera
from .context import ContextError, headless_context
from .headless import contact_sheet, render, render_frame, render_frames, spread_frames
from .renderer import Renderer
from .source import ArraySource, MeshSource, vertex_normals

__all__ = [
    "ArraySource", "Camera", "ContextError", "MeshSource", "Renderer", "contact_sheet",
    "headless_context", "render", "render_frame", "render_frames", "spread_frames", "vertex_normals",
]
