"""Export an edit as a new TVM sequence, in the format the capture came in, plus ``edit.json``.

Formats (:data:`FORMATS`): ``ply``, binary PLY with vertex colours in tvmedit's frame (Z up,
metres); ``scvv``, a Draco mesh and a JPG texture per frame with ``scvv_animation.json``, as
depth-camera apps export, in the capture's own coordinates and units; ``obj``, OBJ with MTL
and a texture per frame, in the capture's own coordinates; ``glb``, one binary glTF per
frame with its texture, Y up and metres as glTF says. The default is the format of the
library's first sequence (:func:`default_format`), so a textured capture's edit stays
textured. Frames without a texture carry vertex colours; in-between frames carry the texture
of the captured frame they were warped from, as the capture's own image file where it is
still there (copied or embedded as it came: no second loss, no encoder). The writers are
:mod:`tvmedit.engine.capture.writers`, the readers' twins. Captured frames already in the
format are copied, and so are in-between frames whose Draco the build kept
(:mod:`tvmedit.engine.store.capturecopy`); the others are encoded where they are made fastest: Draco on threads, OBJ
on worker processes, glTF in this thread as PLY (:data:`THREADED`, :data:`POOL_FROM`,
:data:`IN_THIS_THREAD`).

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

import contextlib
import json
import re
import shutil
from pathlib import Path

import numpy as np

from .. import safewrite
from ..capture.load import SIDECAR, sidecar_json
from ..capture.plyfast import write_ply
from ..capture.readers import MANIFEST_NAMES, is_draco, texture_for
from ..capture.writers import SUFFIXES, TAKES, prepare, write_frame
from ..errors import ParameterError
from ..parallel import Workers, helper_threads
from ..checks import json_value

__all__ = ["export_edit", "default_format", "FORMATS", "has_sound", "POOL_FROM", "THREADED", "IN_THIS_THREAD"]

#: Frames to encode as OBJ from which an export starts worker processes. Below it, starting
#: them costs more than they save (about 50 ms on two cores).
POOL_FROM = 16

#: Formats encoded on threads of this process whatever their number: DracoPy's encoder lets
#: go of the GIL (two threads encode twice as fast as one).
THREADED = ("scvv",)
#: Formats written in this thread, as the PLY export is: a GLB is its arrays' bytes and its
#: JPG's laid end to end, faster here than on threads (which wait for the GIL: 0.13 s against
#: 0.10-0.11 s for the card's edit) or on processes (which pickle every frame).
IN_THIS_THREAD = ("glb",)


def _encoders(fmt, encoded):
    """Where ``encoded`` frames in ``fmt`` are made: threads for :data:`THREADED` formats,
    this thread for :data:`IN_THIS_THREAD`, else worker processes from :data:`POOL_FROM`
    frames."""
    if fmt in THREADED:
        return Workers(None, threads=True)
    return Workers(None if encoded >= POOL_FROM and fmt not in IN_THIS_THREAD else 1)


#: Formats an edit can be written in.
FORMATS = ("ply", "scvv", "obj", "glb")
#: The export format of a capture read as each input format (others: ``ply``).
_AS_CAPTURED = {"scvv": "scvv", "draco": "scvv", "obj": "obj", "gltf": "glb"}
#: glTF is Y up: tvmedit's (x, y, z), Z up, is glTF's (x, z, -y).
_Y_UP_AXES, _Y_UP_SIGNS = [0, 2, 1], np.array([1.0, 1.0, -1.0], np.float32)

_EXPORT_FILE = re.compile(r"frame_\d+\.(ply|draco|drc|jpg|jpeg|obj|mtl|png|glb)|edit\.json|sequence\.json|scvv_animation\.json")


def _legacy(folder):
    """An export written before the ownership marker: edit.json and nothing but its frames."""
    names = [p.name for p in Path(folder).iterdir()]
    if "edit.json" not in names:
        return None
    return [n for n in names if not _EXPORT_FILE.fullmatch(n)]


def _check_target(out, force, library):
    """Refuse an ``out`` folder this export may not write or replace (:func:`tvmedit.engine.safewrite.check_target`)."""
    safewrite.check_target(out, "export", force, inputs=library.sources(), legacy=_legacy)


def default_format(library):
    """The format a library's edits are written in by default: its first sequence's."""
    records = library.manifest.get("sequences") or [{}]
    return _AS_CAPTURED.get(records[0].get("format"), "ply")


def has_sound(library):
    """Whether a sequence of ``library`` came with a sound track (an scvv manifest's ``audio``)."""
    for sequence in library.sequences:
        folder = Path(sequence.paths[0]).parent if sequence.paths else None
        for name in MANIFEST_NAMES if folder else ():
            try:
                if json_value((folder / name).read_text()).get("audio"):
                    return True
            except (OSError, ValueError, AttributeError):
                continue
    return False


def export_edit(edit, out, force=False, progress=False, fmt=None, fps=None, smooth=True):
    """Write ``edit`` (a composition of ``library.edit``) as frames into folder ``out``.

    Parameters
    ----------
    edit : tvmedit.engine.graph.compose.Composition
        With ``edit.library`` set (``Library.edit`` does that); a forever-looping edit exports
        its schedule as composed (one cycle of the last key motion).
    out : path of the folder to create
    force : replace a previous export at ``out`` (see :func:`tvmedit.engine.safewrite.check_target`)
    progress : show a progress bar on stderr
    fmt : one of :data:`FORMATS`, or None for the library's own (:func:`default_format`)
    fps : frames a second to write, the edit's timing kept (:func:`tvmedit.engine.inbetween.instants.instants`);
        None: one frame per schedule frame, at the capture's rate
    smooth : write the surfaces the player shows between stored frames (the display-rate
        in-betweens the library holds); False: each stored frame held until the next

    Returns
    -------
    dict : the contents of ``edit.json``
    """
    library = edit.library
    fmt = default_format(library) if fmt is None else fmt
    if fmt not in FORMATS:
        raise ParameterError(f"format {fmt!r} is not one of {', '.join(FORMATS)}.")
    out = Path(out)
    _check_target(out, force, library)
    # Checked again before the swap: the folder may have changed meanwhile.
    recheck = lambda target: _check_target(target, force, library)  # noqa: E731
    schedule = edit.schedule
    capture_fps = library.sequence(schedule[0].sequence).fps if schedule else None
    # Damage on disk stops the export and leaves nothing: the checksums name the damaged
    # files, here where a read fails, then beside the frames written.
    with library.verifying(library.MESH_FILES, beside=False):
        shown = _shown(library, schedule, capture_fps, fps, smooth)
        frame = _frame(library, schedule)   # the coordinates every frame of a capture's format is written in
        copies = [None] * len(shown) if fmt == "ply" else [_copy_source(library, item, fmt, frame) for item in shown]
    encoded = 0 if fmt == "ply" else copies.count(None)
    if encoded >= POOL_FROM or fmt in THREADED:
        prepare(fmt)    # imported once here, not once in each worker process
    with safewrite.replacing_folder(out, recheck=recheck, kind="export") as tmp, \
            _encoders(fmt, encoded) as pool:   # left only once no worker writes
        pool.start()    # forked before any thread of this export runs
        record = _write_all(library, edit, shown, copies, fmt, tmp, pool, frame, (fps, capture_fps), progress, out)
    return record


def _write_all(library, edit, shown, copies, fmt, tmp, pool, frame, rates, progress, out):
    """Write every frame of ``shown`` and the export's own files into ``tmp``, the checksums
    running beside them; returns the record ``edit.json`` holds."""
    fps, capture_fps = rates
    with library.verifying(library.MESH_FILES):
        if fmt == "ply":
            writing = ((index, (_write_ply_frame(library, item, tmp, index), None)) for index, item in enumerate(shown))
        else:
            writing = _written(library, shown, copies, fmt, tmp, pool, frame)
        # Closed whatever happens, so that no copy still runs into the folder once it is left.
        with contextlib.closing(writing):
            if progress:
                from tqdm import tqdm
                writing = tqdm(writing, total=len(shown), desc="export", unit="frame", leave=False)
            names = dict(writing)
        frames, textures = [], []
        for index, item in enumerate(shown):
            name, texture = names[index]
            textures.append(texture)
            entry = item[0]
            frames.append({"index": index, "file": name, **entry.to_json(),
                           "source_file": _source_file(library, entry.sequence, entry.frame),
                           **_instant_json(item, edit.schedule, fps)})
        fps = capture_fps if fps is None else fps
        record = {
            "library": str(Path(library.path).resolve()),
            "fps": fps,
            **({"capture_fps": capture_fps} if fps != capture_fps else {}),
            "keys": [int(k) for k in edit.keys],
            "legs": edit.legs_json(),
            "key_starts": list(edit.starts),
            "frames": frames,
            "transitions": [t.to_json() for t in edit.transitions],
        }
        if fmt != "ply":
            record["format"] = fmt
        (tmp / "edit.json").write_text(json.dumps(record, indent=1))
        (tmp / SIDECAR).write_text(sidecar_json(record["fps"], out.name, **_frame_of(frame, edit.schedule, fmt)))
        if fmt == "scvv":
            _write_scvv_manifest(tmp, frames, textures, fps)
    return record


def _shown(library, schedule, capture_fps, fps, smooth):
    """``(entry, schedule index, s, field)`` of each output frame: schedule frame ``index`` and
    the field of its step to the next, to be moved ``s`` of the way (field None: as stored;
    :func:`tvmedit.engine.inbetween.instants.shown`). With ``fps`` None, one output frame per
    schedule frame."""
    from ..inbetween.instants import shown

    if fps is None:
        return [(entry, index, 0.0, None) for index, entry in enumerate(schedule)]
    field_of = (lambda i: library.instant_field(schedule[i].key, schedule[i + 1].key)) if smooth else (lambda i: None)
    return [(schedule[index], index, s, field) for index, s, field in shown(len(schedule), capture_fps, fps, field_of)]


def _instant_json(item, schedule, fps):
    """What ``edit.json`` says of an output frame written at ``fps``: the schedule frame it
    shows (``schedule_index``) and, between two, the next one and how far (``at``)."""
    if fps is None:
        return {}
    entry, index, s, _ = item
    if not s:
        return {"schedule_index": index}
    return {"schedule_index": index, "at": s, "next": schedule[index + 1].to_json()}


def _frame_mesh(library, item):
    """``(positions, colours, faces)`` of an output frame: the stored mesh, moved ``s`` of its step."""
    from ..inbetween.instants import moved

    entry, _, s, field = item
    positions, colours, faces, _ = library.frame_mesh(entry.key)
    return (positions if field is None else moved(positions, field, s)), colours, faces


def _write_ply_frame(library, item, folder, index):
    """One frame as binary PLY with its vertex colours, in tvmedit's frame; returns its file name."""
    positions, colours, faces = _frame_mesh(library, item)
    name = f"frame_{index:05d}.ply"
    write_ply(folder / name, positions, faces, colours)
    return name


def _written(library, shown, copies, fmt, folder, pool, frame):
    """Write each output frame in ``fmt``; yield ``(index, (mesh file, texture file or None))``
    as each is written, the encoded ones first.

    A frame with a capture's file already in ``fmt`` (``copies``; or an in-between frame's
    Draco bytes the build kept) is copied as it came:
    lossless, and as fast as a copy, on a thread of its own (a copy waits on the disk, not
    on the GIL), all the while the others are encoded. Those are encoded on ``pool``: threads
    for the formats of :data:`THREADED`; OBJ's text formatting holds the GIL, so only worker
    processes share it; a GLB is written in this thread (:data:`IN_THIS_THREAD`)."""
    stems = [f"frame_{index:05d}" for index in range(len(shown))]
    with helper_threads(1) as copier:
        copied = {index: copier.submit(_copy, source, folder, stems[index])
                  for index, source in enumerate(copies) if source is not None}
        try:
            made = [index for index in range(len(shown)) if index not in copied]
            if pool.kind == "processes":    # each reads its frames from the library: no frame pickled
                opening = (type(library), str(library.path))
                done = pool.map(_read_and_encode, ((opening, shown[index], fmt, frame, str(folder), stems[index])
                                                   for index in made))
            else:   # on threads each reads its frame too: all cores
                done = pool.map(lambda index: _encode((fmt, str(folder), stems[index],
                                                       *_encoding(library, shown[index], fmt, frame))), made)
            yield from zip(made, done)
            for index, done in copied.items():
                yield index, done.result()
        finally:    # an interrupted export leaves no copy running into the folder
            for done in copied.values():
                done.cancel()


def _encode(task):
    """One frame written by :func:`tvmedit.engine.capture.writers.write_frame`."""
    return write_frame(*task)


#: Worker process: the libraries it has opened, by path (a pool lives for one export).
_OPENED = {}


def _read_and_encode(task):
    """Worker task: one output frame read from the library and written by :func:`_encode`.

    The worker opens the library itself (a few milliseconds, once a process) and reads the
    frame from its memory-mapped files, so nothing but the frame's place crosses to it: sent
    from this process, each frame's arrays were pickled there and unpickled here, and that
    made this process, not the encoders, what an export waited on."""
    (kind, path), item, fmt, frame, folder, stem = task
    library = _OPENED.get(path)
    if library is None:
        library = _OPENED[path] = kind.open(path)
    return _encode((fmt, folder, stem, *_encoding(library, item, fmt, frame)))


def _frame(library, schedule):
    """The orientation of the edit's first sequence (the identity for a library read as its
    files are): the capture's coordinates an export in a capture's format is written in."""
    from ..capture.orientation import Orientation

    return (library.orientation(schedule[0].sequence) if schedule else None) or Orientation()


def _encoding(library, item, fmt, orientation):
    """``(positions, faces, colours, uv, image)`` of an output frame as ``fmt`` writes it: glTF's
    Y up, else the capture's coordinates and units of ``orientation`` (:func:`_frame`; the
    build's orientation undone); the texture as the capture's own image file where it is
    still there, else as stored."""
    entry = item[0]
    positions, colours, faces = _frame_mesh(library, item)
    texture = library.frame_texture(entry.key) if library.textured else None
    uv, image = texture if texture is not None else (None, None)
    if fmt == "glb":    # glTF's (x, y, z) is tvmedit's (x, z, -y): exact, no product
        positions = np.asarray(positions, dtype=np.float32)[:, _Y_UP_AXES] * _Y_UP_SIGNS + np.float32(0.0)  # no -0
    else:
        positions, faces = orientation.undo(positions, faces)
    if uv is not None:
        image = _texture_file(library, entry) or np.ascontiguousarray(image)
        uv = np.ascontiguousarray(uv)
    return (positions.astype(np.float32, copy=False), np.ascontiguousarray(faces),
            None if uv is not None else np.ascontiguousarray(colours), uv, image)


def _copy_source(library, item, fmt, orientation):
    """``(mesh file, texture file or None)`` of the capture's own files of a captured frame
    shown as stored, when they are already in ``fmt``, still there, and in the coordinates
    the export is written in (``orientation``); for an in-between frame, its Draco bytes as
    the build made them (:mod:`tvmedit.engine.store.capturecopy`) in place of the file; None
    otherwise."""
    entry = item[0]
    if fmt != "scvv" or (item[3] is not None and item[2]):
        return None
    if not orientation.same_coordinates(library.orientation(entry.sequence)):
        return None
    if entry.blend is not None:     # an in-between frame, as the build encoded it, where it did
        data = library.capture_bytes(entry.key)
        texture = _texture_file(library, entry)
        if texture is not None and texture.suffix.lower() not in TAKES[fmt]:
            return None     # an image the format does not take as it is: encoded as a JPG
        return None if data is None or (library.textured and texture is None) else (data, texture)
    path = Path(_source_file(library, entry.sequence, entry.frame) or "")
    if not is_draco(path) or not path.is_file():
        return None
    texture = _draco_texture(path)
    if library.textured and texture is None:
        return None
    return path, texture


def _copy(source, folder, stem):
    """Copy a frame's files ``source`` (a mesh file or its bytes, and a texture file or None)
    into ``folder`` as ``stem``; their names there."""
    names = []
    for item in source:
        if isinstance(item, bytes):
            names.append(f"{stem}{SUFFIXES['scvv']}")
            (Path(folder) / names[-1]).write_bytes(item)
        elif item is not None:
            names.append(f"{stem}{item.suffix.lower()}")
            shutil.copyfile(item, Path(folder) / names[-1])
    return names[0], (names[1] if len(names) > 1 else None)


def _texture_file(library, entry):
    """The capture's own image file of the texture ``entry`` shows (an in-between frame shows
    the one of the captured frame it moves), for a Draco capture, whose reader takes the image
    by the rule of :func:`tvmedit.engine.capture.readers.texture_for`; None where it is gone or the capture
    is of another format (an OBJ's or a glTF's texture is the one its MTL names or it embeds)."""
    origin = library.texture_origin(entry.key)
    return None if origin is None else _draco_texture(_source_file(library, *origin))


def _draco_texture(path):
    """The texture image of the Draco capture file ``path`` by its reader's rule
    (:func:`tvmedit.engine.capture.readers.texture_for`), where it is there; None for a file of
    another format, or no image."""
    if path is None or not is_draco(path):
        return None
    texture = texture_for(path)     # a KTX2 file's layer is no image file to copy
    return texture if isinstance(texture, Path) and texture.is_file() else None


def _frame_of(orientation, schedule, fmt):
    """The up axis, units, front and mirror an export in the capture's coordinates states beside
    its frames, so it reads back upright and facing the camera whatever its motions (none for
    PLY and glTF: tvmedit's and glTF's). Every frame is written in these coordinates,
    ``orientation``, those of the edit's first sequence (:func:`_frame`, :func:`_encoding`)."""
    if fmt in ("ply", "glb") or not schedule:
        return {}
    return {"up": orientation.up, "units": orientation.units, "front": orientation.front,
            **({"mirror": True} if orientation.mirrored else {})}


def _write_scvv_manifest(folder, frames, textures, fps):
    """``scvv_animation.json``: each frame's mesh, texture and time since the previous one."""
    delay = int(round(1e6 / fps)) if fps else 0
    data = {"frames": [{"mesh_path": frame["file"], "texture_path": texture or "", "delay_us": delay if k else 0}
                       for k, (frame, texture) in enumerate(zip(frames, textures))],
            "average_fps": f"{fps:g}" if fps else ""}
    (folder / "scvv_animation.json").write_text(json.dumps(data, indent=1))


def _source_file(library, sequence, frame):
    """The capture's file of ``frame`` of ``sequence``, as the library recorded it, or None."""
    paths = library.sequence(sequence).paths
    return str(paths[frame]) if 0 <= frame < len(paths) else None
