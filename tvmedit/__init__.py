"""tvmedit: motion editing for time-varying meshes. The command line lives in :mod:`tvmedit.cli`."""


def __getattr__(name):
    # The version is looked up on first use: importlib.metadata takes a while to import, and
    # `tvmedit` should start (and take Ctrl-C as a command) at once.
    if name == "__version__":
        from engine.libformat import tvmedit_version

        return tvmedit_version()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
