"""In-between surfaces: between two reconstructions of different topology, one alignment for all.

- :mod:`.fit`: the non-rigid fit that lays one frame onto another, by position or by colour too;
- :mod:`.blend`: the frames of a transition, warped both ways to meet in the middle (Chamfer steps);
- :mod:`.loops`: a motion's loop closed from its last frame back to its first;
- :mod:`.instants`: the surface at any instant between two frames shown one after the other
  (display-rate in-betweens), one field a step, drawn by the vertex shader.

The library stores them (:mod:`tvmedit.engine.store.inbetweens`); the schedule plays them.
"""
