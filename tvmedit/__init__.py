"""tvmedit: motion editing for time-varying meshes.

>>> from tvmedit import Library, NoPath
>>> Library.open                                   # doctest: +ELLIPSIS
<bound method Library.open of <class 'tvmedit.engine.store.library.Library'>>

The engine is :mod:`tvmedit.engine` (no OpenGL), the renderer and windows
:mod:`tvmedit.player`, the command line :mod:`tvmedit.cli`.
"""

__all__ = ["Corrections", "InputError", "Library", "LibraryError", "NoPath", "TvmError", "UnknownMotion", "build"]


def __getattr__(name):
    # Looked up on first use: `tvmedit` should start (and take Ctrl-C as a command) at once.
    if name == "__version__":
        from tvmedit.engine.store.layout import tvmedit_version

        return tvmedit_version()
    if name in __all__:
        from tvmedit import engine

        return getattr(engine, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
