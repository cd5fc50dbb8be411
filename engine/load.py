"""Loading TVM sequences: a folder (or glob) of PLY, OBJ or OFF frames, one mesh per frame.

Every frame is reconstructed independently by a capture system, so vertex count and
topology change from frame to frame; nothing here assumes otherwise. Frames are loaded with
``trimesh.load(..., process=False)`` so that vertex order and per-vertex colours survive
(trimesh otherwise merges and reorders vertices).

Bad input raises :class:`engine.errors.InputError` with one sentence that names the file,
the problem, and what to do.
"""

import glob as _glob
import json
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import InputError, summarise
from .params import MAX_FPS
from .plyfast import read_ply

MESH_SUFFIXES = (".ply", ".obj", ".off")
# Files that commonly sit beside frames and are not frames.
SIDECAR_SUFFIXES = (".json", ".txt", ".md", ".csv", ".log", ".yaml", ".yml")
# Companions of frames that are not meshes either (OBJ materials, textures, photos): left
# out without a word. Any other file beside the frames is reported as left out.
_QUIET_SUFFIXES = SIDECAR_SUFFIXES + (".mtl", ".png", ".jpg", ".jpeg")
NEUTRAL_COLOUR = (180, 180, 180)
DEFAULT_FPS = 10.0
#: Largest vertex coordinate accepted: a kilometre in metres, a metre in micrometres.
MAX_COORDINATE = 1e6


class SkippedFramesWarning(UserWarning):
    """Bad frames were skipped (``skip_bad_frames=True``); the message lists them."""


class FrameListWarning(UserWarning):
    """Frame files that link to nothing, share a frame number or are one file twice; one line."""


class UnsupportedFilesWarning(UserWarning):
    """Files beside the frames of a sequence folder were left out for their extension
    (``frame_00004.stl`` among ``.ply`` frames); the message lists them."""


@dataclass(frozen=True)
class Frame:
    """One reconstructed mesh.

    positions : (N, 3) float32, metres, Z up
    colours : (N, 3) uint8, per vertex (neutral grey when the file has none)
    faces : (M, 3) uint32, triangles indexing ``positions``
    """

    positions: np.ndarray
    colours: np.ndarray
    faces: np.ndarray

    def __len__(self):
        return len(self.positions)


@dataclass
class Sequence:
    """A TVM sequence: its name, frame rate and frame files in playback order.

    ``frames`` holds the loaded meshes when the sequence was loaded eagerly
    (:func:`load_sequence`); :func:`open_sequence` only lists the files, for streaming.
    ``skipped`` lists ``(path, reason)`` of frames left out with ``skip_bad_frames``.
    """

    name: str
    fps: float
    paths: list
    frames: list = field(default_factory=list)
    skipped: list = field(default_factory=list)

    def __len__(self):
        return len(self.paths)


def _warn_listing(where, entries, paths):
    """One warning line for dangling links, repeated frame numbers and one file listed twice."""
    dangling = sorted(p.name for p in entries
                      if p.is_symlink() and not p.exists() and p.suffix.lower() in MESH_SUFFIXES)
    by_number, by_file = {}, {}
    for path in paths:
        by_number.setdefault(_natural_key(path)[0], []).append(Path(path).name)
        by_file.setdefault(Path(path).resolve(), []).append(Path(path).name)
    numbered = sorted(" and ".join(sorted(names)) for number, names in by_number.items()
                      if len(names) > 1 and number >= 0)
    twice = sorted(" and ".join(sorted(names)) for names in by_file.values() if len(names) > 1)
    problems = [f"{what}: {summarise(names)}" for what, names in (
        ("links to nothing, left out", dangling), ("frame numbers used twice", numbered),
        ("one file listed twice", twice)) if names]
    if problems:
        warnings.warn(f"{where}: " + "; ".join(problems) + "; check the frame files.",
                      FrameListWarning, stacklevel=4)


def _natural_key(path):
    """Order by the last number in the file name, so ``f2`` comes before ``f10``."""
    numbers = re.findall(r"\d+", Path(path).stem)
    return (int(numbers[-1]) if numbers else -1, Path(path).name)


def frame_paths(source):
    """Frame files of a sequence folder or glob, in natural order.

    >>> frame_paths("/no/such/folder")
    Traceback (most recent call last):
    ...
    engine.errors.InputError: sequence folder /no/such/folder does not exist; give a folder of PLY, OBJ or OFF frames or a glob such as 'capture/*.ply'.
    """
    text = str(source)
    if any(ch in text for ch in "*?["):
        paths = [Path(p) for p in _glob.glob(text) if Path(p).is_file()]
        if not paths:
            raise InputError(f"no files match {text}; check the pattern (quote it so the shell does not expand it).")
        for path in paths:
            if path.suffix.lower() not in MESH_SUFFIXES:
                raise InputError(f"{path} has the unsupported extension '{path.suffix}'; "
                                 f"frames must be {', '.join(MESH_SUFFIXES)} files.")
        _warn_listing(text, [Path(p) for p in _glob.glob(text)], paths)
        return sorted(paths, key=_natural_key)
    folder = Path(source)
    if not folder.exists():
        raise InputError(f"sequence folder {folder} does not exist; give a folder of PLY, OBJ or OFF "
                         "frames or a glob such as 'capture/*.ply'.")
    if folder.is_file():
        raise InputError(f"{folder} is a file, not a sequence folder; give the folder that holds the frames.")
    entries = [p for p in folder.iterdir() if not p.name.startswith(".")]
    files = [p for p in entries if p.is_file()]
    paths = [p for p in files if p.suffix.lower() in MESH_SUFFIXES]
    if not paths:
        others = sorted(p for p in files if p.suffix.lower() not in SIDECAR_SUFFIXES)
        if others:
            raise InputError(f"{others[0]} has the unsupported extension '{others[0].suffix}' and {folder} "
                             f"holds no {', '.join(MESH_SUFFIXES)} frames; convert the frames to PLY, OBJ or OFF.")
        raise InputError(f"sequence folder {folder} is empty: it holds no PLY, OBJ or OFF frames.")
    _warn_listing(folder, entries, paths)
    left_out = sorted((p for p in files if p.suffix and p.suffix.lower() not in MESH_SUFFIXES + _QUIET_SUFFIXES),
                      key=_natural_key)
    if left_out:
        listing = ", ".join(p.name for p in left_out[:10]) + (", ..." if len(left_out) > 10 else "")
        warnings.warn(f"{folder}: left out {len(left_out)} file(s) with an unsupported extension "
                      f"({listing}); convert them to {', '.join(MESH_SUFFIXES)} to use them as frames.",
                      UnsupportedFilesWarning, stacklevel=3)
    return sorted(paths, key=_natural_key)


def _read_off(path):
    """(vertices, faces, colours or None) of an OFF/COFF file.

    trimesh's OFF reader drops per-vertex colours (COFF), which TVM frames carry, so OFF is
    parsed here: a header line, counts, one vertex per line with optional RGB(A) as 0-255
    integers or 0-1 floats, then polygons (fan-triangulated).
    """
    tokens_by_line = [line.split("#")[0].split() for line in Path(path).read_text().splitlines()]
    lines = [t for t in tokens_by_line if t]
    if not lines or not lines[0][0].upper().endswith("OFF"):
        raise ValueError("no OFF header")
    header = lines[0]
    rest = header[1:] if len(header) > 1 else None
    counts, body = (rest, lines[1:]) if rest else (lines[1], lines[2:])
    n_vertices, n_faces = int(counts[0]), int(counts[1])
    if len(body) < n_vertices + n_faces:
        raise ValueError(f"expected {n_vertices} vertices and {n_faces} faces, found {len(body)} lines")
    rows = body[:n_vertices]
    vertices = np.array([[float(v) for v in row[:3]] for row in rows], dtype=np.float64).reshape(-1, 3)
    colours = None
    if rows and all(len(row) >= 6 for row in rows):
        values = np.array([[float(v) for v in row[3:6]] for row in rows])
        colours = values * 255.0 if values.max(initial=0) <= 1.0 and any("." in v for v in rows[0][3:6]) else values
        colours = np.clip(np.rint(colours), 0, 255).astype(np.uint8)
    triangles = []
    for row in body[n_vertices:n_vertices + n_faces]:
        count = int(row[0])
        ids = [int(v) for v in row[1:1 + count]]
        triangles += [(ids[0], ids[k], ids[k + 1]) for k in range(1, count - 1)]
    return vertices, np.array(triangles, dtype=np.int64).reshape(-1, 3), colours


def _read_trimesh(path):
    """(vertices, faces, colours or None) through trimesh, keeping vertex order.

    Binary little-endian PLY triangle meshes, what capture systems write, take the fast
    path of :mod:`engine.plyfast`; every other file goes through trimesh.
    """
    if Path(path).suffix.lower() == ".ply":
        fast = read_ply(path)
        if fast is not None:
            return fast
    import trimesh

    mesh = trimesh.load(path, process=False, force="mesh")
    vertices = np.asarray(getattr(mesh, "vertices", np.empty((0, 3))), dtype=np.float64)
    faces = np.asarray(getattr(mesh, "faces", np.empty((0, 3))))
    colours = None
    visual = getattr(mesh, "visual", None)
    if visual is not None and getattr(visual, "kind", None) == "vertex":
        colours = np.asarray(visual.vertex_colors)[:, :3]
    return vertices, faces, colours


def read_frame(path):
    """Load one frame file into a :class:`Frame`, checking it on the way in."""
    path = Path(path)
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise InputError(f"{path} has the unsupported extension '{path.suffix}'; "
                         f"frames must be {', '.join(MESH_SUFFIXES)} files.")
    if not path.exists():
        raise InputError(f"frame {path} does not exist.")
    if path.stat().st_size == 0:
        raise InputError(f"frame {path} is an empty file; re-export it or remove it (or pass skip_bad_frames=True).")
    try:
        reader = _read_off if path.suffix.lower() == ".off" else _read_trimesh
        vertices, faces, colours = reader(path)
    except Exception as error:  # trimesh raises many types for broken files
        detail = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise InputError(f"frame {path} is not a readable mesh (truncated or corrupt: {detail}); "
                         "re-export it or pass skip_bad_frames=True.") from None
    if len(vertices) == 0:
        raise InputError(f"frame {path} has no vertices; re-export it or pass skip_bad_frames=True.")
    if not np.isfinite(vertices).all():
        bad = int((~np.isfinite(vertices)).any(axis=1).sum())
        raise InputError(f"frame {path} has {bad} vertices with NaN or infinite coordinates; "
                         "repair the reconstruction or pass skip_bad_frames=True.")
    reach = float(np.abs(vertices).max())
    if reach > MAX_COORDINATE:
        raise InputError(f"frame {path} has a vertex coordinate of {reach:.3g}, beyond the "
                         f"{MAX_COORDINATE:g} that any capture reaches in metres or millimetres; "
                         "repair the reconstruction or pass skip_bad_frames=True.")
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        raise InputError(f"frame {path} has no triangles (a point cloud or polygon soup); "
                         "tvmedit needs triangle meshes.")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise InputError(f"frame {path} has faces that index missing vertices (the file is probably "
                         "truncated); re-export it or pass skip_bad_frames=True.")
    if colours is None or len(colours) != len(vertices):
        colours = np.broadcast_to(np.array(NEUTRAL_COLOUR, np.uint8), (len(vertices), 3))
    return Frame(positions=np.ascontiguousarray(vertices, dtype=np.float32),
                 colours=np.ascontiguousarray(colours, dtype=np.uint8),
                 faces=np.ascontiguousarray(faces, dtype=np.uint32))


def _sidecar(paths):
    """``sequence.json`` beside the frames, or ``{}``."""
    candidate = Path(paths[0]).parent / "sequence.json"
    if not candidate.exists():
        return {}
    try:
        data = json.loads(candidate.read_text())
    except (OSError, ValueError) as error:
        raise InputError(f"{candidate} is not valid JSON ({error}); fix or remove it.") from None
    if not isinstance(data, dict):
        raise InputError(f"{candidate} must hold a JSON object such as {{\"fps\": 10}}.")
    return data


def _default_name(source):
    text = str(source)
    if any(ch in text for ch in "*?["):
        text = text.split("*")[0].split("?")[0].split("[")[0]
        text = text if text.endswith(("/", "\\")) else str(Path(text).parent)
    return Path(text.rstrip("/\\")).resolve().name or "sequence"


def open_sequence(source, name=None, fps=None):
    """List a sequence's frames and read its frame rate, without loading any mesh.

    The frame rate comes from ``fps`` when given, else ``sequence.json`` beside the frames
    (``{"fps": 25}``), else 10. The name defaults to the folder's name.
    """
    paths = frame_paths(source)
    meta = _sidecar(paths)
    given = meta.get("fps", DEFAULT_FPS) if fps is None else fps
    try:
        fps = float(given) if not isinstance(given, bool) else float("nan")
    except (TypeError, ValueError):
        fps = float("nan")
    if not np.isfinite(fps) or fps <= 0 or fps > MAX_FPS:
        raise InputError(f"the frame rate of {source} must be a number above 0 and at most "
                         f"{MAX_FPS}, not {given!r}; set it with fps=FPS or in sequence.json.")
    if name is None and "name" in meta:
        name = meta["name"]
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"{Path(paths[0]).parent / 'sequence.json'} gives the sequence name "
                             f"{json.dumps(name)}, but a name must be a non-empty string such as "
                             "\"walk\"; fix it or remove the name.")
    return Sequence(name=name or _default_name(source), fps=fps, paths=paths)


def iter_frames(paths, skip_bad_frames=False, skipped=None):
    """Yield ``(path, Frame)`` for each frame file, in order.

    A bad frame raises :class:`InputError`, or with ``skip_bad_frames`` is left out and
    appended to ``skipped`` as ``(path, reason)``.
    """
    for path in paths:
        try:
            frame = read_frame(path)
        except InputError as error:
            if not skip_bad_frames:
                raise
            if skipped is not None:
                skipped.append((Path(path), str(error)))
            continue
        yield Path(path), frame


def warn_skipped(skipped):
    """One warning that lists every skipped frame and why."""
    if skipped:
        listing = "; ".join(f"{p.name} ({reason.split('; ')[0]})" for p, reason in skipped)
        warnings.warn(f"skipped {len(skipped)} bad frame(s): {listing}", SkippedFramesWarning, stacklevel=3)


def load_sequence(source, name=None, fps=None, skip_bad_frames=False):
    """Load every frame of a sequence into memory.

    Suitable for short sequences and tests; the builder streams with :func:`iter_frames`.
    """
    sequence = open_sequence(source, name=name, fps=fps)
    kept = list(iter_frames(sequence.paths, skip_bad_frames, sequence.skipped))
    if not kept:
        raise InputError(f"no usable frames in {source}: all {len(sequence.paths)} were bad.")
    sequence.paths = [p for p, _ in kept]
    sequence.frames = [f for _, f in kept]
    warn_skipped(sequence.skipped)
    return sequence
