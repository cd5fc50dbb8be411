"""Everything that touches OpenGL: context, camera, renderer, headless output (and later the window).

The player consumes a ``MeshSource`` (``player.source``): the library implements it, and
``ArraySource`` holds frames in memory for tests and small scripts.

>>> import player
>>> sorted(player.__all__)[:4]
['ArraySource', 'Camera', 'MeshSource', 'Renderer']
"""

from player.camera import Camera
from player.context import ContextError, headless_context
from player.headless import contact_sheet, render, render_frame, render_frames
from player.renderer import Renderer
from player.source import ArraySource, MeshSource, vertex_normals

__all__ = [
    "ArraySource", "Camera", "ContextError", "MeshSource", "Renderer", "contact_sheet",
    "headless_context", "render", "render_frame", "render_frames", "vertex_normals",
]
