"""Errors a user sees: each message is one sentence naming the file or motion and what to do.

The command line prints ``str(error)`` after ``error:`` and exits non-zero, with no traceback.
"""


def summarise(names, limit=3, noun="files", separator=", "):
    """Names for a one-line message: ``a, b`` or, when long, ``412 files, e.g. a, b, c``: a
    message lists a few, never ten thousand.

    >>> summarise(["a", "b"]), summarise([str(i) for i in range(5)])
    ('a, b', '5 files, e.g. 0, 1, 2')
    >>> summarise(["x (empty)", "y (NaN)", "z (empty)", "w (empty)"], noun="frames", separator="; ")
    '4 frames, e.g. x (empty); y (NaN); z (empty)'
    """
    names = [str(n) for n in names]
    if len(names) <= limit:
        return separator.join(names)
    return f"{len(names)} {noun}, e.g. {separator.join(names[:limit])}"


class TvmError(Exception):
    """Base class of every error tvmedit reports to a user."""

    exit_code = 2


class InputError(TvmError):
    """A TVM sequence or frame file cannot be used (missing, not a mesh, truncated, NaN...)."""


class LibraryError(TvmError):
    """A library directory is missing, incomplete, truncated or of another format version."""


class UnknownMotion(TvmError):
    """A key motion name or id that the library does not have."""

    #: Most motion names one message lists.
    LISTED = 30

    @classmethod
    def among(cls, key, names, role=""):
        """The one message for ``key`` among the motions ``names`` (``{id: name}``).

        >>> print(UnknownMotion.among("jump", {0: "walk/01", 1: "run/01"}))
        there is no motion 'jump'; known motions are walk/01, run/01 (or an id from 0 to 1).
        """
        what = f"{role} motion" if role else "motion"
        if not names:
            return cls(f"there is no {what} {key!r}; the library has no motions.")
        ids = list(names)
        listed = ", ".join(str(names[i]) for i in ids[:cls.LISTED]) + (", ..." if len(ids) > cls.LISTED else "")
        numbered = all(isinstance(i, int) for i in ids)
        span = f" (or an id from {min(ids)} to {max(ids)})" if numbered else ""
        return cls(f"there is no {what} {key!r}; known motions are {listed}{span}.")


class NoPath(TvmError):
    """No path in the pruned motion graph leads from one key motion to the next."""

    exit_code = 3

    def __init__(self, message, source=None, target=None, mu=None):
        super().__init__(message)
        self.source = source
        self.target = target
        self.mu = mu


class DurationError(TvmError):
    """A leg asked to last a time no schedule makes within a frame, where ``strict`` was asked."""

    exit_code = 3


class DurationWarning(UserWarning):
    """A leg lasts the nearest time any schedule makes, not the time asked (:mod:`tvmedit.engine.graph.timing`)."""


class OutputError(TvmError):
    """An output would replace or land inside something tvmedit did not write."""


class ParameterError(TvmError, ValueError):
    """A parameter given by the caller is not a finite number in its range (or not a choice)."""


# --- what to say about a library that cannot be opened ------------------------------------

def build_call(inputs, out, force=False):
    """How to (re)build a library, said in Python; the command line says it as a command.

    >>> build_call(None, "lib", force=True)
    "build(inputs, 'lib', force=True)"
    """
    sources = "inputs" if inputs is None else repr([str(i) for i in inputs])
    return f"build({sources}, {str(out)!r}{', force=True' if force else ''})"


def not_a_library(path, frames=False):
    """The sentence for a folder without a manifest: a sequence folder (``frames``: it holds
    frame files, :func:`tvmedit.engine.capture.load.holds_frames`) is told how to build one."""
    if frames:
        plain = path if path.name not in ("", ".", "..") else path.resolve()
        target = plain.with_name(f"{plain.name}.tvmlib")
        return (f"{path} is a sequence folder (frame files, no manifest.json), not a library; "
                f"build a library from it with {build_call([path], target)}.")
    return (f"{path} is not a tvmedit library (it has no manifest.json); give a library folder, "
            f"or build one with {build_call(None, path)}.")
