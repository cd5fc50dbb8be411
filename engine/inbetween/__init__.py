"""In-between surfaces: between two reconstructions of different topology, one alignment for all.

- :mod:`.blend`: one frame warped onto another (alignment, Chamfer steps), the frames of a transition;
- :mod:`.loops`: a motion's loop closed from its last frame back to its first;
- :mod:`.instants`: the surface at any instant between two frames shown one after the other
  (display-rate in-betweens), one field a step, drawn by the vertex shader.

The library stores them (:mod:`tvmedit.engine.store.inbetweens`); the schedule plays them.
"""
