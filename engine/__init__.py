"""tvmedit's analysis and editing engine: pure numpy and networkx, never OpenGL.

Data flows one way: load -> features -> structure -> database -> graph -> search ->
compose -> library. The player consumes what this package produces.
"""

from .errors import InputError, LibraryError, NoPath, TvmError, UnknownMotion

__all__ = ["Corrections", "InputError", "Library", "LibraryError", "NoPath", "TvmError", "UnknownMotion", "build"]

# Loaded on first use, so ``import engine`` stays light (no networkx, no trimesh).
_LAZY = {"Library": ("library", "Library"), "build": ("library", "build"),
         "Corrections": ("corrections", "Corrections")}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        module, attribute = _LAZY[name]
        return getattr(importlib.import_module(f".{module}", __name__), attribute)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
