"""Deriving a library again from what it stores: corrections by hand applied in seconds.

A library keeps its features, its automatic parse and its frame files' records, so the cheap
stages (corrections, database, graph) can run again without reading a frame file or
computing a feature: :func:`rebuild` makes the sequences and features the builder's last
stages need (:func:`tvmedit.engine.store.builder.derive`) from the library itself. Meshes are linked, grown
(new frames stored beside) or copied from the library (:mod:`tvmedit.engine.store.meshfiles`); only the frames of a motion it never stored (a new representative texton,
after a boundary was added) are read from their files, and none from a library built with
``keep_frames="all"``. The library's natural step is kept, so only the transitions the
correction changed get their in-between frames made anew (:mod:`tvmedit.engine.inbetween.blend`). A library
built before loops were closed (:mod:`tvmedit.engine.inbetween.loops`) has its loops closed by its first
rebuild, which reads the few neighbouring frames they are closed onto. A library whose files
no longer hold the bytes written (checksums, verified beside the work; stored frames where
they are copied rather than linked) is not derived again: what a rebuild takes from it would
carry the damage on, so it says to build from the capture.
"""

from pathlib import Path
from typing import NamedTuple

from .. import safewrite
from .builder import derive, library_features, report_of
from .inputs import check_target
from .layout import mesh_file
from ..features import BinSizes
from ..inbetween.blend import preload
from ..parallel import Workers
from ..parse.params import StructureParams
from .settings import Settings

__all__ = ["rebuild"]


class _Recorded(NamedTuple):
    """A sequence as a library records it: what the stages after the features need of it."""

    name: str
    fps: float
    format: str
    orientation: object
    paths: list


def rebuild(library, out=None, *, corrections=None, mu=None, force=None, log=None, workers=None):
    """Derive ``library`` again from its stored features, with corrections by hand.

    The automatic parse is the stored one, so nothing is parsed again; corrections
    (:mod:`tvmedit.engine.store.corrections`), database, graph and meshes are made again and written
    atomically. No feature is recomputed and no frame file is read, except those of a motion
    whose frames ``library`` does not store (none when it keeps every frame). The natural step
    is ``library``'s: transitions the correction leaves as they were keep their in-between
    frames, and only the others are blended.

    Parameters
    ----------
    library : tvmedit.engine.store.library.Library
    out : str or Path, optional
        Where to write; default: replace ``library`` itself.
    corrections : Corrections, dict, str, Path or None
        The corrections (the whole set, replacing the library's); None keeps the library's.
    mu : float, optional
        Pruning parameter of eq. (14); default: the library's.
    force : bool, optional
        Replace an existing ``out``; default: only when ``out`` is ``library`` itself.
    log : callable, optional
        Called with one-line messages (a correction that found nothing to act on).
    workers : int or None
        Processes that make the in-between frames of the transitions a correction changed
        and read the frames of new motions; None (default): all cores, whose worker processes
        are forked with scipy already imported (``tvmedit.engine.inbetween.blend.preload``); 1: this process
        only. The in-between frames of changed transitions are most of a correction of a
        blended library (``benchmarks/correct_speed.py``).

    Returns
    -------
    dict
        The report, as :func:`tvmedit.engine.store.builder.build` gives it (``Library.correct`` returns the
        library opened, with it as ``report``); ``read_frames`` counts the
        frame files read.
    """
    from .corrections import Corrections

    out = Path(library.path if out is None else out).absolute()
    force = out == Path(library.path).absolute() if force is None else force
    params = library.params
    settings = Settings.of(BinSizes(**params["bins"]), StructureParams.recorded(params["structure"]),
                           params["mu"] if mu is None else mu, params.get("skip_bad_frames", False),
                           library.connect, params.get("blend_frames"), params.get("keep_frames", "motions"),
                           params.get("smooth", True))
    corrections = library.corrections() if corrections is None else Corrections.coerce(corrections)
    sequences, computed = [], []
    for record in library.manifest["sequences"]:
        sequences.append(_Recorded(record["name"], float(record["fps"]), record.get("format"),
                                   library.orientation(record["name"]), [row[0] for row in record["files"]]))
        entry = library_features(library, record["feature_key"], settings.bins)
        entry.stats = {row[0]: row for row in record["files"]}
        computed.append(entry)
    parses = {s.name: library.parse(s.name) for s in library.sequences}
    check_target(out, force, sequences)
    recheck = lambda target: check_target(target, force, sequences)  # noqa: E731
    with safewrite.replacing_folder(out, recheck=recheck, kind="library") as tmp, Workers(workers) as pool:
        preload()
        pool.start()    # forked before the checksums' threads run
        # A rebuild takes everything from the library itself: where the files it reads no
        # longer hold the bytes written, it stops (nothing written) and says to build from the
        # capture, rather than carry the damage into a library whose checksums would then pass.
        # Stored frames are linked, keeping their checksums (damage there stays found), or
        # verified before they are copied (meshfiles.write): not read here for nothing.
        with library.verifying([name for name in library.manifest.get("checksums", {}) if not mesh_file(name)]):
            derived = derive(tmp, library, sequences, computed, settings, corrections, pool=pool, log=log,
                             parses=parses, keep_natural=True)
    return report_of(derived)
