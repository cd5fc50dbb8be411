"""The library on disk: how it is built, written, read and corrected.

- :mod:`.builder` builds a library (:func:`~.library.build`) from the inputs :mod:`.inputs`
  opens, :mod:`.rebuild` derives it again;
- :mod:`.library` reads it (:class:`~.library.Library`); :mod:`.layout` owns its on-disk format;
- :mod:`.settings` holds a build's settings; :mod:`.corrections` the parse corrected by hand;
- :mod:`.featurecache`, :mod:`.meshfiles` and :mod:`.inbetweens` store features, meshes and
  in-between frames; :mod:`.infoschema` describes ``tvmedit info --json``. Tasks run on
  workers through :mod:`tvmedit.engine.parallel`, which the synthetic actor and the export
  share.
"""
