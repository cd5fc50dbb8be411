"""Loading TVM sequences: a folder (or glob) of frame files, one mesh per frame, or a folder
with a sequence manifest (``scvv_animation.json``, ``scvv.json``).

Every frame is reconstructed independently by a capture system, so vertex count and
topology change from frame to frame; nothing here assumes otherwise. Files are read by the
format registry of :mod:`tvmedit.engine.capture.readers` (PLY, OBJ, OFF, Draco, glTF/GLB), which keeps vertex
order, per-vertex colours, and texture coordinates with their images. Each sequence is put
into tvmedit's frame of reference (Z up, metres) by the :class:`~tvmedit.engine.capture.orientation.Orientation`
detected when it is opened. A manifest's per-frame capture times are kept; the analysis sees
the sequence resampled to a regular rate (:func:`resample`).

Bad input raises :class:`tvmedit.engine.errors.InputError` with one sentence that names the file,
the problem, and what to do.
"""

import glob as _glob
import json
import os
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, TvmError, summarise
from .orientation import Orientation, detect, sample_indices
from ..checks import MAX_FPS, json_value, listed
from .readers import READERS, natural_key as _natural_key, read_manifest, read_mesh, reader_for

#: Suffixes of frame files: those of the reader registry (tvmedit.engine.capture.readers.READERS).
MESH_SUFFIXES = tuple(READERS)
# Files that commonly sit beside frames and are not frames.
SIDECAR_SUFFIXES = (".json", ".txt", ".md", ".csv", ".log", ".yaml", ".yml")
# Companions of frames that are not meshes either (OBJ materials, textures, photos): left
# out without a word. Any other file beside the frames is reported as left out.
_QUIET_SUFFIXES = SIDECAR_SUFFIXES + (".mtl", ".png", ".jpg", ".jpeg", ".webp", ".bmp", ".bin", ".wav")
NEUTRAL_COLOUR = (180, 180, 180)
DEFAULT_FPS = 10.0
#: The file beside a sequence's frames that gives its frame rate and name (:func:`sidecar_json`).
SIDECAR = "sequence.json"
#: Largest vertex coordinate accepted: a kilometre in metres, a metre in micrometres.
MAX_COORDINATE = 1e6


def holds_frames(folder):
    """Whether ``folder`` holds frame files of a format tvmedit reads (a sequence folder)."""
    try:
        return any(p.is_file() and p.suffix.lower() in MESH_SUFFIXES for p in Path(folder).iterdir())
    except OSError:
        return False


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
    colours : (N, 3) uint8, per vertex (from the texture when the file has none; neutral
        grey when it has neither)
    faces : (M, 3) uint32, triangles indexing ``positions``
    uv : (N, 2) float32 texture coordinates (v = 0 at the image's bottom row), or None
    texture : (H, W, 3) uint8, the frame's texture image, or None
    """

    positions: np.ndarray
    colours: np.ndarray
    faces: np.ndarray
    uv: np.ndarray = None
    texture: np.ndarray = None

    def __len__(self):
        return len(self.positions)


@dataclass
class Sequence:
    """A TVM sequence: its name, frame rate and frame files in playback order.

    ``paths`` are the frames the analysis sees, one per 1/``fps`` seconds: where the capture
    gives its own frame times (``times``, seconds, one per file of ``captured``) they are the
    captured frames resampled to ``fps`` (:func:`resample`), else the files themselves.
    ``frames`` holds the loaded meshes when the sequence was loaded eagerly
    (:func:`load_sequence`); :func:`open_sequence` only lists the files, for streaming.
    ``skipped`` lists ``(path, reason)`` of frames left out with ``skip_bad_frames``.
    ``format`` names the reader (``"ply"``, ``"draco"``...) or the manifest (``"scvv"``);
    ``orientation`` maps the files' coordinates to tvmedit's (see :mod:`tvmedit.engine.capture.orientation`).
    ``rate_from`` says where ``fps`` came from: ``"given"``, ``"sequence.json"``, ``"frame times"``
    (a manifest's), or ``"assumed"`` (:data:`DEFAULT_FPS`, nothing stated a rate).
    """

    name: str
    fps: float
    paths: list
    frames: list = field(default_factory=list)
    skipped: list = field(default_factory=list)
    format: str = "ply"
    orientation: Orientation = field(default_factory=Orientation)
    times: np.ndarray = None
    captured: list = None
    manifest: Path = None
    rate_from: str = "given"

    def __len__(self):
        return len(self.paths)


def resolved(paths):
    """``str(Path(path).resolve())`` of every one of ``paths``: each folder resolved once (an
    ``lstat`` per folder of its path), each file only asked whether it is a link itself, and
    resolved in full where it is (2,296 frames in 7 ms rather than 44 ms, the same strings)."""
    folders, out = {}, []
    for path in paths:
        text = os.fspath(path)
        parent, name = os.path.split(text)
        if not name or name in (".", "..") or os.path.islink(text):
            out.append(str(Path(text).resolve()))
            continue
        if parent not in folders:
            folders[parent] = str(Path(parent or ".").resolve())
        out.append(os.path.join(folders[parent], name))
    return out


def _warn_listing(where, entries, paths):
    """One warning line for dangling links, repeated frame numbers and one file listed twice."""
    dangling = sorted(p.name for p in entries
                      if p.is_symlink() and not p.exists() and p.suffix.lower() in MESH_SUFFIXES)
    by_number, by_file = {}, {}
    for path, real in zip(paths, resolved(paths)):
        by_number.setdefault(_natural_key(path)[0], []).append(Path(path).name)
        by_file.setdefault(real, []).append(Path(path).name)
    numbered = sorted(" and ".join(sorted(names)) for number, names in by_number.items()
                      if len(names) > 1 and number >= 0)
    twice = sorted(" and ".join(sorted(names)) for names in by_file.values() if len(names) > 1)
    problems = [f"{what}: {summarise(names)}" for what, names in (
        ("links to nothing, left out", dangling), ("frame numbers used twice", numbered),
        ("one file listed twice", twice)) if names]
    if problems:
        warnings.warn(f"{where}: " + "; ".join(problems) + "; check the frame files.",
                      FrameListWarning, stacklevel=4)


def _manifest(source):
    """The :class:`~tvmedit.engine.capture.readers.Manifest` of a folder or manifest file, or None; its frame
    files must exist."""
    path = Path(str(source))
    if any(ch in str(source) for ch in "*?[") or not path.exists():
        return None
    if path.is_file() and path.suffix.lower() != ".json":
        return None
    try:
        manifest = read_manifest(path)
    except ValueError as error:
        raise InputError(f"{error}.") from None
    if manifest is None:
        return None
    for mesh in manifest.meshes:
        if not mesh.is_file():
            raise InputError(f"{manifest.path} lists the frame {mesh.name}, which is not in {mesh.parent}; "
                             "restore the file or remove it from the manifest.")
        if reader_for(mesh) is None:
            raise InputError(f"{manifest.path} lists the frame {mesh.name}, whose format '{mesh.suffix}' "
                             f"tvmedit cannot read; frames must be {', '.join(MESH_SUFFIXES)} files.")
    return manifest


_KINDS = "PLY, OBJ, OFF, Draco or glTF"


def frame_paths(source):
    """Frame files of a sequence folder, manifest or glob, in playback order.

    A folder with a sequence manifest (``scvv_animation.json``, ``scvv.json``) plays the
    frames it lists, in its order; any other folder or glob its frame files in natural order.
    A folder without frames of its own whose one subfolder holds them (a player's export:
    ``geometry_draco/`` beside textures and sound) plays that subfolder's.

    >>> frame_paths("/no/such/folder")
    Traceback (most recent call last):
    ...
    tvmedit.engine.errors.InputError: sequence folder /no/such/folder does not exist; give a folder of PLY, OBJ, OFF, Draco or glTF frames or a glob such as 'capture/*.ply'.
    """
    manifest = _manifest(source)
    if manifest is not None:
        return list(manifest.meshes)
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
        raise InputError(f"sequence folder {folder} does not exist; give a folder of {_KINDS} "
                         "frames or a glob such as 'capture/*.ply'.")
    if folder.is_file():
        raise InputError(f"{folder} is a file, not a sequence folder; give the folder that holds the frames.")
    entries = [p for p in folder.iterdir() if not p.name.startswith(".")]
    files = [p for p in entries if p.is_file()]
    paths = [p for p in files if p.suffix.lower() in MESH_SUFFIXES]
    if not paths:
        # A player's export keeps the frames one folder down, beside textures and sound.
        holders = sorted((p for p in entries if p.is_dir() and holds_frames(p)), key=_natural_key)
        if len(holders) == 1:
            return frame_paths(holders[0])
        if holders:
            raise InputError(f"{folder} holds frames in {len(holders)} subfolders ({', '.join(p.name for p in holders)}); "
                             "give the one to read.")
        others = sorted(p for p in files if p.suffix.lower() not in SIDECAR_SUFFIXES)
        if others:
            raise InputError(f"{others[0]} has the unsupported extension '{others[0].suffix}' and {folder} "
                             f"holds no {', '.join(MESH_SUFFIXES)} frames; convert the frames to one of these.")
        raise InputError(f"sequence folder {folder} is empty: it holds no {_KINDS} frames.")
    _warn_listing(folder, entries, paths)
    left_out = sorted((p for p in files if p.suffix and p.suffix.lower() not in MESH_SUFFIXES + _QUIET_SUFFIXES),
                      key=_natural_key)
    if left_out:
        listing = ", ".join(p.name for p in left_out[:10]) + (", ..." if len(left_out) > 10 else "")
        warnings.warn(f"{folder}: left out {len(left_out)} file(s) with an unsupported extension "
                      f"({listing}); convert them to {', '.join(MESH_SUFFIXES)} to use them as frames.",
                      UnsupportedFilesWarning, stacklevel=3)
    return sorted(paths, key=_natural_key)


def read_frame(path, orientation=None, detail="full"):
    """Load one frame file into a :class:`Frame`, checking it on the way in.

    ``orientation`` (an :class:`~tvmedit.engine.capture.orientation.Orientation`) maps it into tvmedit's frame;
    ``detail`` says what to read (``"geometry"``, ``"colours"``, ``"full"``: see
    :data:`tvmedit.engine.capture.readers.READERS`). Colours not read are neutral grey.
    """
    path = Path(path)
    if reader_for(path) is None:
        raise InputError(f"{path} has the unsupported extension '{path.suffix}'; "
                         f"frames must be {', '.join(MESH_SUFFIXES)} files.")
    if not path.exists():
        raise InputError(f"frame {path} does not exist.")
    if path.stat().st_size == 0:
        raise InputError(f"frame {path} is an empty file; re-export it or remove it (or pass skip_bad_frames=True).")
    try:
        mesh = read_mesh(path, detail)
    except TvmError:    # a frame's texture that says what is wrong with it (ktx2)
        raise
    except Exception as error:  # trimesh, DracoPy and Pillow raise many types for broken files
        reason = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise InputError(f"frame {path} is not a readable mesh (truncated or corrupt: {reason}); "
                         "re-export it or pass skip_bad_frames=True.") from None
    vertices, faces, colours = mesh.vertices, np.asarray(mesh.faces), mesh.colours
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
    if orientation is not None:
        vertices = orientation.apply(vertices)
        faces = orientation.apply_faces(faces)
    uv = texture = None
    if mesh.uv is not None and mesh.texture is not None:
        uv = np.ascontiguousarray(mesh.uv, dtype=np.float32)
        texture = np.ascontiguousarray(mesh.texture, dtype=np.uint8)
    return Frame(positions=np.ascontiguousarray(vertices, dtype=np.float32),
                 colours=np.ascontiguousarray(colours, dtype=np.uint8),
                 faces=np.ascontiguousarray(faces, dtype=np.uint32), uv=uv, texture=texture)


def sidecar_json(fps, name=None, **frame):
    """Text of the :data:`SIDECAR` that gives frames their rate (and name, and with ``frame``
    their ``up`` axis, ``units``, ``front`` and ``mirror``), as read here.

    >>> sidecar_json(5), sidecar_json(30.0, "walk")
    ('{"fps": 5}', '{"fps": 30.0, "name": "walk"}')
    >>> sidecar_json(30.0, "card", up="-x", units="m")
    '{"fps": 30.0, "name": "card", "up": "-x", "units": "m"}'
    """
    return json.dumps({"fps": fps, **({} if name is None else {"name": name}), **frame})


def _sidecar(paths):
    """:data:`SIDECAR` beside the frames, or ``{}``."""
    candidate = Path(paths[0]).parent / SIDECAR
    if not candidate.exists():
        return {}
    try:
        data = json_value(candidate.read_text())
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


def resample(times, fps):
    """Which captured frame to show at each tick of a regular ``fps`` clock: the nearest in time.

    A capture's frames arrive at irregular moments (``times``, seconds, increasing); the
    analysis (section 4 works in frames of one rate) sees the frame nearest to each tick
    ``k / fps`` from the first frame to the last. A frame that came late is shown on its own
    tick all the same; across a gap the frames beside it are held, and of frames closer
    together than a tick one is dropped, so each frame stays on screen about as long as it
    lasted in the capture.

    Five frames at 30 fps with a gap of four ticks after the third:

    >>> resample([0.0, 0.034, 0.066, 0.2, 0.233], 30).tolist()
    [0, 1, 2, 2, 3, 3, 3, 4]
    """
    times = np.asarray(times, dtype=np.float64)
    ticks = np.arange(int(round((times[-1] - times[0]) * fps)) + 1) / fps + times[0]
    right = np.clip(np.searchsorted(times, ticks), 1, len(times) - 1) if len(times) > 1 else np.zeros(len(ticks), int)
    if len(times) == 1:
        return right
    left = right - 1
    return np.where(ticks - times[left] <= times[right] - ticks, left, right)


def _format_of(paths, manifest):
    entry = reader_for(paths[0])
    name = entry[0] if entry else "unknown"
    return f"{manifest.format}" if manifest is not None else name


def _positive(value):
    try:
        value = float(value) if not isinstance(value, bool) else float("nan")
    except (TypeError, ValueError):
        value = float("nan")
    return value if np.isfinite(value) and value > 0 else None


def expand_inputs(inputs):
    """``(name or None, source)`` for every sequence that ``inputs`` names.

    An input is a folder, a quoted glob of frame files (one sequence), a glob of folders
    (one sequence per folder), or a ``(name, source)`` pair. A glob that matches frame
    files is left to the loader, which orders them.

    >>> expand_inputs([("walk", "captures/a"), "captures/b"])
    [('walk', 'captures/a'), (None, 'captures/b')]
    """
    expanded = []
    for item in listed("inputs", [] if inputs is None else inputs, "sequence folders or (name, folder) pairs"):
        name, source = item if isinstance(item, tuple) and len(item) == 2 else (None, item)
        if not isinstance(source, (str, os.PathLike)) or not isinstance(name, (str, type(None))):
            raise InputError(f"input {item!r} is not a sequence folder or a (name, folder) pair; give a "
                             "folder, a glob of frame files, or (name, folder) with both as text.")
        text = str(source)
        if any(ch in text for ch in "*?[") and not Path(text).exists():
            matches = sorted(_glob.glob(text.rstrip("/\\")))
            folders = [m for m in matches if os.path.isdir(m)]
            if folders and len(folders) == len(matches):
                if name is not None and len(folders) > 1:
                    raise InputError(f"{text} matches {len(folders)} sequence folders, so it cannot "
                                     f"take the one name {name!r}; name each folder separately.")
                expanded += [(name, folder) for folder in folders]
                continue
        expanded.append((name, source))
    return expanded


def open_sequence(source, name=None, fps=None, up=None, units=None, mirror=None, body_frame=True, front=None):
    """List a sequence's frames, read its timing and detect its frame of reference.

    The frame rate comes from ``fps`` when given, else ``sequence.json`` beside the frames
    (``{"fps": 25}``), else, for a manifest with frame times, the median rate of its frames,
    else 10. A manifest's frames are resampled to that rate (:func:`resample`). The name
    defaults to the folder's name.

    ``up``, ``units``, ``mirror`` and ``front`` fix the frame of reference (:func:`tvmedit.engine.capture.orientation.detect`);
    what is not given is detected from up to a dozen frames sampled across the sequence, read
    without their textures. ``body_frame`` (the default) has features computed in the body's
    own frame (:func:`tvmedit.engine.capture.orientation.feature_frame`), so the take parses alike however it
    is turned; False computes them in tvmedit's axes.
    """
    manifest = _manifest(source)
    captured = frame_paths(source)
    meta = _sidecar(captured)
    times = None
    if manifest is not None and len(manifest.times) > 1 and manifest.times[-1] > 0:
        times = manifest.times
    given = fps if fps is not None else meta.get("fps")
    rate_from = "given" if fps is not None else SIDECAR
    if given is None:
        if times is not None and (np.diff(times) > 0).any():
            steps = np.diff(times)
            given, rate_from = 1.0 / float(np.median(steps[steps > 0])), "frame times"
        else:
            stated = None
            if captured:
                folder = Path(captured[0]).parent
                stated = _rate_in_uvol(folder) or _rate_in_names(folder)
            given, rate_from = stated or (DEFAULT_FPS, "assumed")
    rate = _positive(given)
    if rate is None or rate > MAX_FPS:
        raise InputError(f"the frame rate of {source} must be a number above 0 and at most "
                         f"{MAX_FPS}, not {given!r}; set it with fps=FPS or in sequence.json.")
    if name is None and "name" in meta:
        name = meta["name"]
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"{Path(captured[0]).parent / SIDECAR} gives the sequence name "
                             f"{json.dumps(name)}, but a name must be a non-empty string such as "
                             "\"walk\"; fix it or remove the name.")
    paths = [captured[k] for k in resample(times, rate)] if times is not None else list(captured)
    fmt = _format_of(captured, manifest)
    # A frame of reference stated beside the frames (an export's) holds where none is given.
    given = {"up": up, "units": units, "front": front, "mirror": mirror}
    stated = [key for key, value in given.items() if value is None and key in meta]
    up, units, front, mirror = (meta.get(key) if value is None else value for key, value in given.items())
    try:
        if mirror is not None and not isinstance(mirror, bool):
            raise ValueError(f"mirror must be true or false, not {mirror!r}")
        orientation = detect(_sample_positions(captured), fmt, up=up, units=units, mirror=mirror,
                             body_frame=body_frame, front=front)
    except ValueError as error:
        where = f" ({', '.join(stated)} as {Path(captured[0]).parent / SIDECAR} states)" if stated else ""
        raise InputError(f"{error}{where}.") from None
    return Sequence(name=name or _default_name(source), fps=rate, paths=paths, format=fmt,
                    orientation=orientation, times=times, captured=list(captured),
                    manifest=manifest.path if manifest is not None else None, rate_from=rate_from)


def _rate_in_uvol(folder):
    """``(fps, "uvol manifest 'NAME'")`` from a web volumetric player's manifest (``*.uvol.json``)
    beside the frames' folder or in it: ``geometry.frameRate``, or the first of
    ``geometry.targets``, or a top-level ``frameRate``; else None (also where a folder holds
    several). A manifest that cannot be read (a Git LFS pointer left by a clone without
    ``git lfs pull``, or bad JSON) is named in a warning, and the rate is looked for elsewhere.

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as top:
    ...     os.mkdir(os.path.join(top, "geometry_draco"))
    ...     _ = Path(top, "talk.uvol.json").write_text('{"geometry": {"frameRate": 30, "compression": "draco"}}')
    ...     _rate_in_uvol(Path(top) / "geometry_draco")
    (30.0, "uvol manifest 'talk.uvol.json'")
    """
    folder = Path(folder)
    # The frames' folder's own manifest, else the one beside it; several in one folder belong
    # to several takes, and none of them is taken.
    manifests = [paths[0] for paths in (sorted(folder.glob("*.uvol.json")), sorted(folder.parent.glob("*.uvol.json")))
                 if len(paths) == 1][:1]
    for path in manifests:
        try:
            text = path.read_text(errors="replace")
            if text.startswith("version https://git-lfs"):
                raise ValueError("it is a Git LFS pointer, not the file: run `git lfs pull` where it was cloned")
            data = json_value(text)
        except (OSError, ValueError) as error:
            warnings.warn(f"{path} cannot be read as a uvol manifest ({error}); its frame rate is not used.",
                          stacklevel=3)
            continue
        geometry = data.get("geometry") if isinstance(data, dict) else None
        targets = geometry.get("targets") if isinstance(geometry, dict) else None
        candidates = [geometry.get("frameRate") if isinstance(geometry, dict) else None,
                      *([t.get("frameRate") for t in targets.values() if isinstance(t, dict)]
                        if isinstance(targets, dict) else []),
                      data.get("frameRate") if isinstance(data, dict) else None]
        for rate in candidates:
            rate = _positive(rate)
            if rate is not None and rate <= MAX_FPS:
                return rate, f"uvol manifest {path.name!r}"
    return None


#: A rate stated in a folder's name as players' exports write it: ``fps30``, ``fps-29.97``.
_RATE_IN_NAME = re.compile(r"(?<![a-z0-9])fps[-_]?(\d{1,3}(?:\.\d+)?)(?![0-9])", re.I)


def _rate_in_names(folder):
    """``(fps, "folder name 'NAME'")`` where the frames' folder, the folder above it or a folder
    beside it states a rate in its name (``texture_ktx2-fps30-1k``), else None.

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as top:
    ...     for name in ("geometry_draco", "texture_ktx2-fps30-1k"):
    ...         os.mkdir(os.path.join(top, name))
    ...     _rate_in_names(Path(top) / "geometry_draco")
    (30.0, "folder name 'texture_ktx2-fps30-1k'")
    """
    folder = Path(folder)
    try:
        beside = sorted(p.name for p in folder.parent.iterdir() if p.is_dir() and p != folder)
    except OSError:
        beside = []
    for name in [folder.name, folder.parent.name, *beside]:
        match = _RATE_IN_NAME.search(name)
        if match:
            rate = float(match.group(1))
            if 0 < rate <= MAX_FPS:
                return rate, f"folder name {name!r}"
    return None


def rate_assumed(sequence):
    """One sentence where ``sequence``'s frame rate was assumed, else None.

    >>> rate_assumed(Sequence("walk", 10.0, [], rate_from="assumed"))
    'walk: no manifest, frame times or sequence.json states a frame rate, so 10 fps was assumed; set it with --fps (or {"fps": 30} in sequence.json beside the frames).'
    """
    if sequence.rate_from != "assumed":
        return None
    return (f"{sequence.name}: no manifest, frame times or {SIDECAR} states a frame rate, so {sequence.fps:g} fps "
            f"was assumed; set it with --fps (or {{\"fps\": 30}} in {SIDECAR} beside the frames).")


def _sample_positions(paths):
    """Vertex positions of up to :data:`~tvmedit.engine.capture.orientation.SAMPLES` frames spread over the
    sequence, in the files' coordinates; unreadable frames are passed over (they are
    reported when the sequence is read)."""
    sample = []
    for k in sample_indices(len(paths)):
        try:
            sample.append(read_frame(paths[k], detail="geometry").positions)
        except InputError:
            continue
    return sample


def iter_frames(paths, skip_bad_frames=False, skipped=None, orientation=None, detail="full"):
    """Yield ``(path, Frame)`` for each frame file, in order, mapped by ``orientation``.

    A bad frame raises :class:`InputError`, or with ``skip_bad_frames`` is left out and
    appended to ``skipped`` as ``(path, reason)``.
    """
    for path in paths:
        try:
            frame = read_frame(path, orientation, detail)
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
        listing = summarise([f"{p.name} ({reason.split('; ')[0]})" for p, reason in skipped], noun="frames",
                            separator="; ")
        warnings.warn(f"skipped {len(skipped)} bad frame(s): {listing}", SkippedFramesWarning, stacklevel=3)


def load_sequence(source, name=None, fps=None, skip_bad_frames=False, up=None, units=None, mirror=None,
                  front=None):
    """Load every frame of a sequence into memory, in tvmedit's frame of reference.

    Suitable for short sequences and tests; the builder streams with :func:`iter_frames`.
    """
    sequence = open_sequence(source, name=name, fps=fps, up=up, units=units, mirror=mirror, front=front)
    kept = list(iter_frames(sequence.paths, skip_bad_frames, sequence.skipped, sequence.orientation))
    if not kept:
        raise InputError(f"no usable frames in {source}: all {len(sequence.paths)} were bad.")
    sequence.paths = [p for p, _ in kept]
    sequence.frames = [f for _, f in kept]
    warn_skipped(sequence.skipped)
    return sequence
