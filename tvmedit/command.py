"""The ``tvmedit`` command's first step: a Ctrl-C while Python loads the command line ends it
as a Ctrl-C does later ("interrupted", exit 130), not with a traceback of an import."""

import sys


def entry():
    """Load :mod:`tvmedit.cli` and run :func:`tvmedit.cli.entry`."""
    try:
        from .cli import entry as run
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        sys.exit(130)
    run()
