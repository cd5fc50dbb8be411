"""The motion-structure parser: atoms, textons and clusters, section 4, eq. (5)-(8).

- :mod:`.structure` runs the parse and holds its result (:class:`~.structure.Structure`);
- :mod:`.params` holds its parameters (:class:`~.params.StructureParams`);
- :mod:`.atoms` (eq. (5)), :mod:`.boundaries`, :mod:`.partition`, :mod:`.rhythm`,
  :mod:`.onsets`, :mod:`.periods`, :mod:`.pauses`, :mod:`.joins` and :mod:`.heading` are the
  rules it applies in turn;
- :mod:`.confidence` says how sure it is; :mod:`.timeline` lays the result out for the inspector.
"""
