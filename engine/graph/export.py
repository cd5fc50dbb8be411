"""Export an edit as a new TVM sequence: binary PLY frames with their vertex colours, plus ``edit.json``.

The exported folder is an ordinary TVM sequence: tvmedit's own loader and any mesh tool read
it. ``edit.json`` records, for each output frame, its file, its source sequence and frame, and
the capture's frame file it came from (``source_file``, as the library's manifest records it,
so frames skipped at build time do not shift it), and for each transition the edge taken and
its weight, so the edit can be traced back to the capture; ``key_starts`` gives the frame at
which each key motion begins and each leg its ``asked_s`` and ``achieved_s`` seconds. An
in-between frame made at a transition (:mod:`tvmedit.engine.inbetween.blend`) is marked
``"blend": [[from, to], i]``; its source is the captured frame it was warped from. A frame of
a loop's closing (:mod:`tvmedit.engine.inbetween.loops`) is marked ``"blend": [[n, n], i]``; its source is the
texton frame it warps. The folder is written under a temporary name and renamed into place,
so a failure never leaves a half-written export.

Replacing an existing folder (``force``) is allowed only where that folder is a previous
export holding nothing else (:func:`tvmedit.engine.safewrite.check_target`); any other folder, the
current folder or one that holds it, and a folder inside the library or one of its
sequences are refused, so a mistyped ``-o`` never deletes a capture.
"""

import json
import re
from pathlib import Path

from .. import safewrite
from ..capture.load import SIDECAR, sidecar_json
from ..capture.plyfast import write_ply

__all__ = ["export_edit"]

_EXPORT_FILE = re.compile(r"frame_\d+\.ply|edit\.json|sequence\.json")


def _legacy(folder):
    """An export written before the ownership marker: edit.json and nothing but its frames."""
    names = [p.name for p in Path(folder).iterdir()]
    if "edit.json" not in names:
        return None
    return [n for n in names if not _EXPORT_FILE.fullmatch(n)]


def _check_target(out, force, library):
    safewrite.check_target(out, "export", force, inputs=library.sources(), legacy=_legacy)


def export_edit(edit, out, force=False, progress=False):
    """Write ``edit`` (a composition of ``library.edit``) as PLY frames into folder ``out``.

    Parameters
    ----------
    edit : tvmedit.engine.graph.compose.Composition
        With ``edit.library`` set (``Library.edit`` does that); a forever-looping edit exports
        its schedule as composed (one cycle of the last key motion).
    out : path of the folder to create
    force : replace a previous export at ``out`` (see :func:`tvmedit.engine.safewrite.check_target`)
    progress : show a progress bar on stderr

    Returns
    -------
    dict : the contents of ``edit.json``
    """
    library = edit.library
    out = Path(out)
    _check_target(out, force, library)
    # Checked again before the swap: the folder may have changed meanwhile.
    recheck = lambda target: _check_target(target, force, library)  # noqa: E731
    with safewrite.replacing_folder(out, recheck=recheck, kind="export") as tmp:
        frames = []
        schedule = edit.schedule
        iterator = schedule
        if progress:
            from tqdm import tqdm
            iterator = tqdm(schedule, desc="export", unit="frame", leave=False)
        for index, entry in enumerate(iterator):
            positions, colours, faces, _ = library.frame_mesh(entry.key)
            name = f"frame_{index:05d}.ply"
            write_ply(tmp / name, positions, faces, colours)
            frames.append({"index": index, "file": name, **entry.to_json(),
                           "source_file": _source_file(library, entry.sequence, entry.frame)})
        record = {
            "library": str(Path(library.path).resolve()),
            "fps": library.sequence(schedule[0].sequence).fps if schedule else None,
            "keys": [int(k) for k in edit.keys],
            "legs": edit.legs_json(),
            "key_starts": list(edit.starts),
            "frames": frames,
            "transitions": [t.to_json() for t in edit.transitions],
        }
        (tmp / "edit.json").write_text(json.dumps(record, indent=1))
        (tmp / SIDECAR).write_text(sidecar_json(record["fps"], out.name))
    return record


def _source_file(library, sequence, frame):
    """The capture's file of ``frame`` of ``sequence``, as the library recorded it, or None."""
    paths = library.sequence(sequence).paths
    return str(paths[frame]) if 0 <= frame < len(paths) else None
