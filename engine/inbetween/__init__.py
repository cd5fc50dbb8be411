"""In-between frames: surfaces between two reconstructions of different topology.

- :mod:`.blend`: one frame warped onto another (alignment, Chamfer steps), the frames of a transition;
- :mod:`.loops`: a motion's loop closed from its last frame back to its first.

The library stores them (:mod:`tvmedit.engine.store.inbetweens`); the schedule plays them.
"""
