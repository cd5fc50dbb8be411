"""Export an edit as a new TVM sequence: binary PLY frames with their vertex colours, plus ``edit.json``.

The exported folder is an ordinary TVM sequence: tvmedit's own loader and any mesh tool read
it. ``edit.json`` records, for each output frame, its source sequence, frame and file, and for
each transition the edge taken and its weight, so the edit can be traced back to the capture.
The folder is written under a temporary name and renamed into place, so a failure never
leaves a half-written export.
"""

import json
import os
import shutil
from pathlib import Path

from .errors import TvmError
from .plyfast import write_ply

__all__ = ["export_edit"]


def export_edit(edit, out, overwrite=False, progress=False):
    """Write ``edit`` (a composition of ``library.edit``) as PLY frames into folder ``out``.

    Parameters
    ----------
    edit : engine.compose.Composition
        With ``edit.library`` set (``Library.edit`` does that); a forever-looping edit exports
        its schedule as composed (one cycle of the last key motion).
    out : path of the folder to create
    overwrite : replace an existing folder
    progress : show a progress bar on stderr

    Returns
    -------
    dict : the contents of ``edit.json``
    """
    library = edit.library
    out = Path(out)
    if out.exists() and not overwrite:
        raise TvmError(f"{out} already exists; choose another folder or pass --force to replace it.")
    tmp = out.parent / f".{out.name}.tmp-{os.getpid()}"
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    try:
        frames = []
        schedule = edit.schedule
        iterator = schedule
        if progress:
            from tqdm import tqdm
            iterator = tqdm(schedule, desc="export", unit="frame", leave=False)
        for index, entry in enumerate(iterator):
            positions, colours, faces = library.frame(entry.sequence, entry.frame)
            name = f"frame_{index:05d}.ply"
            write_ply(tmp / name, positions, faces, colours)
            frames.append({"index": index, "file": name, "node": int(entry.node),
                           "sequence": entry.sequence, "frame": int(entry.frame)})
        record = {
            "library": str(Path(library.path).resolve()),
            "fps": library.sequence(schedule[0].sequence).fps if schedule else None,
            "keys": [int(k) for k in edit.keys],
            "legs": [leg.to_json() for leg in edit.legs],
            "frames": frames,
            "transitions": [t.to_json() for t in edit.transitions],
        }
        (tmp / "edit.json").write_text(json.dumps(record, indent=1))
        (tmp / "sequence.json").write_text(json.dumps({"fps": record["fps"], "name": out.name}))
        if out.exists():
            shutil.rmtree(out)
        tmp.rename(out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return record
