"""What a build starts from: its input sequences opened, and the library it replaces.

A build opens every input sequence (its frames listed, its rate and frame of reference found
from a few frames) before reading any frame in full, and refuses a target that is not a
library of ours. The library being replaced lends what the user gave it before: its
corrections by hand (for the sequences still built) and a front given to a sequence (so
``--front``, given once, holds through every rebuild that gives none).
"""

import os
import warnings

from .. import safewrite
from . import layout
from ..capture.load import expand_inputs, open_sequence, rate_assumed
from ..errors import InputError, TvmError

__all__ = ["open_inputs", "open_old", "check_target", "kept_corrections", "check_kept", "pass_on"]


def open_inputs(inputs, fps, log, frame=None, old=None):
    """Open every input sequence (no mesh read yet, but a few to detect its frame of
    reference, unless ``frame``, a dict of ``up``, ``units``, ``mirror``, ``front`` and ``body_frame``,
    fixes it); names must be unique. A front given to a sequence of the library being replaced
    (``old``) holds where none is given now: given once, it is kept."""
    expanded = expand_inputs(inputs)
    if not expanded:
        raise InputError("no input sequences given; name at least one sequence folder.")
    frame = dict(frame or {})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sequences = [open_sequence(source, name=name, fps=fps, **frame) for name, source in expanded]
        if frame.get("front") is None:
            for k, ((name, source), sequence) in enumerate(zip(expanded, sequences)):
                kept = _kept_front(old, sequence)
                if kept is None:
                    continue
                try:
                    sequences[k] = open_sequence(source, name=name, fps=fps, **{**frame, "front": kept})
                except InputError:  # it lies along the up this build has (an --up given anew)
                    warnings.warn(f"{sequence.name}: the front {kept} given before lies along the up axis "
                                  f"{sequence.orientation.up} of this build, so it is not kept; give --front anew.")
    pass_on(caught, log)
    for sequence in sequences:
        assumed = rate_assumed(sequence)
        if assumed:
            warnings.warn(assumed, stacklevel=3)
    seen = {}
    for (_, source), sequence in zip(expanded, sequences):
        if sequence.name in seen:
            raise InputError(f"{seen[sequence.name]} and {source} are both named {sequence.name!r}; "
                             "name them apart with NAME=PATH.")
        seen[sequence.name] = source
    return sequences


def _kept_front(old, sequence):
    """The front given to ``sequence`` (by name) in the library being replaced, where it
    differs from the one ``sequence`` has now; None where there is none."""
    if old is None or sequence.orientation.reasons.get("front") == "given":
        return None
    try:
        was = old.orientation(sequence.name)
    except (TvmError, KeyError, ValueError):    # not in it, or an entry that cannot be read
        return None
    if was is None or was.reasons.get("front") != "given" or was.front == sequence.orientation.front:
        return None
    return was.front


def check_target(out, force, sequences):
    """Refuse an ``out`` that is not a library of ours, holds user files or lies in an input."""
    inputs = {os.path.dirname(os.fspath(path)) or "." for seq in sequences for path in seq.paths}
    safewrite.check_target(out, "library", force, inputs=sorted(inputs), legacy=layout.legacy_foreign)


def open_old(out, open_library):
    """The library being replaced, to reuse its features; None if it cannot be read."""
    if open_library is None or not (out / "manifest.json").exists():
        return None
    try:
        return open_library(out)
    except TvmError:
        return None


def kept_corrections(old, sequences, run):
    """The corrections by hand of the library being replaced, for the sequences still built."""
    from .corrections import Corrections

    kept = old.corrections() if old is not None else Corrections()
    gone = sorted(name for name, entry in kept.sequences.items() if entry and name not in {s.name for s in sequences})
    if gone:
        run.say(f"warning: the corrections by hand of {', '.join(gone)} are left out: this build has no such sequence")
    return Corrections({n: e for n, e in kept.sequences.items() if n not in gone}, kept.source)


def check_kept(corrections, sequences, computed):
    """Kept corrections that no longer fit the frames (a shorter take) say how to drop them."""
    from .corrections import CorrectionError

    try:
        corrections.check_sequences({seq.name: len(entry.features) for seq, entry in zip(sequences, computed)})
    except CorrectionError as error:
        raise CorrectionError(f"the corrections by hand kept from the library being replaced no longer fit "
                              f"({str(error).rstrip('.')}); build with corrections=False to drop them.") from None


def pass_on(caught, log):
    """Warnings caught during the build go to ``log`` as ``warning: ...`` lines, if given; each
    once (a sequence opened again with the front it was given before warns again)."""
    said = set()
    for warning in caught:
        if str(warning.message) in said:
            continue
        said.add(str(warning.message))
        if log is None:
            warnings.warn(warning.message, warning.category, stacklevel=3)
        else:
            log(f"warning: {warning.message}")
