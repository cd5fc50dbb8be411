"""tvmedit's analysis and editing engine: pure numpy, scipy and networkx, never OpenGL.

Data flows one way, family by family::

    capture -> features -> parse -> graph -> inbetween -> playback -> store

``capture`` reads frames as they come, :mod:`~tvmedit.engine.features` summarises them
(eq. (1)-(4)), ``parse`` finds the motion structure (eq. (5)-(8)), ``graph`` holds the
database, the motion graph and the edits made on it (eq. (9)-(16)), ``inbetween`` makes the
frames between two reconstructions, ``playback`` decides what plays next, and ``store``
builds and reads the library on disk. ``lab`` (the synthetic actor and the scorer) sits
beside them. Beside the families stand what they all use: ``errors``, ``checks`` (one
sentence for bad input), ``safewrite`` (write under a temporary name, then rename) and
``parallel`` (tasks on worker processes or a dask cluster, results in order). The player (:mod:`tvmedit.player`) consumes what this package produces.
"""

from .errors import InputError, LibraryError, NoPath, TvmError, UnknownMotion

__all__ = ["Corrections", "InputError", "Library", "LibraryError", "NoPath", "TvmError", "UnknownMotion", "build"]

# Loaded on first use, so importing the engine stays light (no networkx, no trimesh).
_LAZY = {"Library": "tvmedit.engine.store.library", "build": "tvmedit.engine.store.library",
         "Corrections": "tvmedit.engine.store.corrections"}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
