"""The parameters of a build that shape the library: defaults filled in, each checked at the door.

:class:`Settings` is what :func:`tvmedit.build` and :func:`tvmedit.engine.store.rebuild.rebuild` derive a
library with; the manifest records it (``params``).
"""

import dataclasses
from typing import NamedTuple

from .. import checks
from ..errors import ParameterError
from ..features import BinSizes

__all__ = ["Settings", "KEEP_FRAMES", "check_mu"]

#: Which frames a library stores: ``"motions"``, those of its database motions (what can be
#: played); ``"all"``, every frame of every sequence, so that a correction by hand never reads
#: a frame file, ``inspect`` shows any frame at once, and the capture folder may move.
KEEP_FRAMES = ("motions", "all")


class Settings(NamedTuple):
    """The build parameters that shape the library, with defaults filled in and checked
    (:meth:`of`)."""

    bins: BinSizes
    params: object
    mu: float
    skip_bad_frames: bool
    connect: str = "auto"
    blend_frames: int | None = None
    keep_frames: str = "motions"
    smooth: bool = True     # make the display-rate in-betweens (tvmedit.engine.inbetween.instants)

    @classmethod
    def of(cls, bins, structure, mu, skip_bad_frames, connect="auto", blend_frames=None, keep_frames="motions",
           smooth=True):
        from ..parse import structure as structure_module
        from ..inbetween.blend import check_count
        from ..graph.connect import MODES
        from ..graph.motiongraph import MU

        if connect not in MODES:
            raise checks.ParameterError(f"connect={connect!r} is not one of {', '.join(map(repr, MODES))}.")
        if keep_frames not in KEEP_FRAMES:
            raise checks.ParameterError(f"keep_frames={keep_frames!r} is not one of "
                                        f"{', '.join(map(repr, KEEP_FRAMES))}.")
        return cls(bins if bins is not None else BinSizes(), _structure_params(structure_module, structure),
                   MU if mu is None else check_mu(mu), bool(skip_bad_frames), connect,
                   check_count(blend_frames), keep_frames, bool(smooth))


def check_mu(mu):
    """``mu`` as a float, or one sentence: JSON (manifest, graph) cannot hold inf or NaN.

    >>> check_mu("inf")
    Traceback (most recent call last):
    ...
    tvmedit.engine.errors.ParameterError: mu=inf is out of range: it must be a finite number above 0 (the default is 0.9).
    """
    from ..graph.motiongraph import MU

    return checks.number("mu", mu, above=0, hint=f" (the default is {MU:g})")


def _structure_params(module, structure):
    if structure is None:
        return module.StructureParams()
    if isinstance(structure, dict):
        known = [f.name for f in dataclasses.fields(module.StructureParams)]
        unknown = sorted(set(structure) - set(known))
        if unknown:
            raise ParameterError(f"structure has no parameter {unknown[0]!r}; it has {', '.join(known)}.")
        return module.StructureParams(**structure)
    return structure
