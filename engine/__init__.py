"""tvmedit's analysis and editing engine: pure numpy and networkx, never OpenGL.

Data flows one way: load -> features -> structure -> database -> graph -> search ->
compose -> library. The player consumes what this package produces.
"""

from .errors import InputError, LibraryError, NoPath, TvmError, UnknownMotion

__all__ = ["InputError", "LibraryError", "NoPath", "TvmError", "UnknownMotion"]
