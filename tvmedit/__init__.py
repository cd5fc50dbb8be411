"""tvmedit: motion editing for time-varying meshes. The command line lives in :mod:`tvmedit.cli`."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("tvmedit")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"
