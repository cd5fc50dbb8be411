"""What plays next: the queue of key motions, holds, and the frame after this one.

:class:`Playhead` is the realtime player's state; the window only reads it.
"""

from .playhead import Playhead

__all__ = ["Playhead"]
