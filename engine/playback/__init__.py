"""What plays next: the queue of key motions, holds, and the frame after this one.

- :mod:`.playhead`: :class:`Playhead`, an edit played frame by frame while key motions are queued;
- :mod:`.wander`: an endless walk over the graph, for when nothing is queued.

The realtime player's window only reads this state.
"""

from .playhead import Playhead

__all__ = ["Playhead"]
