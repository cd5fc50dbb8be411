"""The library's on-disk format, written and read in this one place.

A library is a directory written by :func:`tvmedit.build` and opened by
:class:`tvmedit.engine.store.library.Library`. Nothing in it is parsed while playing: every
array opens with ``np.load(..., mmap_mode="r")``, so opening reads only the small JSON files.

``manifest.json``
    format version, tvmedit version, build parameters; per sequence its name, fps, frame count,
    rows in ``features.npy`` (and ``features_centred.npy``), r width, origin, feature cache key,
    frame files (resolved path, size, mtime_ns) and skipped frames; the size of every file
    below (checked on open), the stored meshes' bounds and largest vertex and face counts.
``features.npy``, ``features_centred.npy``
    (T, D) float32, one feature vector per frame of every sequence in order (eq. (1)-(4)):
    r histograms zero-padded to the library's widest, then theta, then phi. The optional
    second file holds the histograms about each frame's own centre (which the parser's turn
    veto reads), laid out alike, with ``centred_rows`` and ``centred_r_bins`` per sequence.
``structure.json``, ``database.json``
    per sequence its parsed structure (section 4); the motion database (section 5): nodes
    with id, default name, sequence, inclusive frame range, cluster, texton distance, intensity.
``graph.json``, ``graph.graphml``
    the complete graph's weights ``[[i, j, w], ...]`` (eq. (12)), transition frames
    ``[[i, j, exit, entry], ...]`` (eq. (10); the built graph's edges where the poses meet,
    :mod:`tvmedit.engine.inbetween.pairs`) and mu, from which the pruned graph (eq. (14)) is
    rebuilt on open with the edges the build added to connect it (``connect``, ``added``);
    the pruned graph for other tools (``networkx.read_graphml(path, node_type=int)``).
``positions.npy`` ... ``frame_keys.npy``, ``uvs.npy``, ``textures.npy``, ``texture_frames.npy``
    the stored frames' flat mesh arrays and their ranges (:mod:`tvmedit.engine.store.arrays`); only
    where some frame is textured, its texture coordinates beside ``positions``, the texels frame
    after frame, and each frame's first texel, height and width.
``part1_positions.npy`` ... ``part1_frame_keys.npy``, ``part2_...``
    frames a rebuild stored beside those it kept as they were (:mod:`tvmedit.engine.store.meshfiles`),
    laid out as the arrays above, read as their continuation (:func:`tvmedit.engine.store.arrays.parts`).
``blend_*.npy``, ``blends.json``
    the in-between frames (:mod:`tvmedit.engine.inbetween.blend`) laid out as the frames above
    (no keys), run after run; per graph edge ``{"from", "to", "first", "count", "jump", "steps", "exit",
    "entry"}`` (first row, Chamfer of the cut and of each step in metres, ``[sequence, frame]``
    exited and entered), and for a blended one ``colour`` and ``chosen_at`` (its fit, by colour or
    not, kept on a run of that many frames); ``wraps`` likewise per closed loop
    (:mod:`tvmedit.engine.inbetween.loops`, with ``at`` and ``texton``); ``fit`` (the transitions'
    fit, :data:`tvmedit.engine.inbetween.blend.FIT`), ``natural_step``, ``blend_frames``,
    ``feature_keys``, and
    ``pair_steps`` (``[sequence, frame, step, tail]`` the natural step and ``natural_tail``, its
    99th percentile, are the medians of).
``blend_draco.npy``, ``blend_draco_frames.npy``
    only for a capture read from Draco frames: each in-between frame's Draco bytes, as an
    export in the capture's format writes it (:mod:`tvmedit.engine.store.capturecopy`).
``instant_pairs.npy``, ``instant_fields.npy``
    the display-rate in-betweens (:mod:`tvmedit.engine.inbetween.instants`): per step a
    schedule can show, ``[from, to, first row, rows]`` (mesh ids: a stored frame's row, ``-1 -
    k`` for in-between frame ``k``), and the float16 displacement of each step's first mesh.
``names.json``, ``corrections.json``, ``parse.json``
    optional: node names given with ``tvmedit rename`` (``{"id": "name"}``); the corrections by
    hand (:mod:`tvmedit.engine.store.corrections`) and the automatic parse they were applied to
    (``structure.json`` then holds the corrected one).

Only the frames of database textons (after a correction by hand, maybe more: :mod:`.meshfiles`
keeps a library's arrays rather than copy them) and the transitions' in-between frames are stored.
"""

import contextlib
import dataclasses
import json
import re
import time
from pathlib import Path

import numpy as np

from .. import safewrite
from ..errors import LibraryError, TvmError, build_call, not_a_library
from ..checks import json_value

__all__ = ["FORMAT", "CHECKED_FILES", "write_json",
           "graph_to_json", "read_graph", "write_graphml", "sequence_record", "manifest",
           "write_manifest", "read_manifest", "checksum", "verify", "damaged_files", "legacy_foreign", "load_array", "read_json",
           "read_names", "write_names", "tvmedit_version", "write_corrections", "read_corrections",
           "read_parse", "link_meshes", "read_blends", "write_features", "read_features"]

#: On-disk format version; a library of another version must be rebuilt.
FORMAT = 2

#: Files whose sizes the manifest records and :func:`read_manifest` checks.
CHECKED_FILES = ("features.npy", "features_centred.npy", "structure.json", "database.json", "graph.json",
                 "positions.npy",
                 "colours.npy", "normals.npy", "faces.npy", "frames.npy", "frame_keys.npy",
                 "uvs.npy", "textures.npy", "texture_frames.npy", "corrections.json", "parse.json",
                 "blends.json", "blend_positions.npy", "blend_colours.npy", "blend_normals.npy",
                 "blend_faces.npy", "blend_frames.npy", "blend_uvs.npy", "blend_texture_frames.npy",
                 "instant_pairs.npy", "instant_fields.npy", "blend_draco.npy", "blend_draco_frames.npy")

def tvmedit_version():
    """The installed tvmedit's version, recorded in every manifest."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("tvmedit")
    except PackageNotFoundError:  # running from a source tree that was never installed
        return "0.0.0+unknown"


def _json_default(value):
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, tuple):
        return list(value)
    if dataclasses.is_dataclass(value):
        return dataclasses.asdict(value)
    raise TypeError(f"cannot store {type(value).__name__} in JSON")


def write_json(path, data):
    """Write ``data`` compactly (numpy scalars and arrays, tuples and dataclasses allowed)."""
    Path(path).write_text(json.dumps(data, default=_json_default, separators=(",", ":")))


#: The files of the stored meshes (:class:`tvmedit.engine.store.arrays.MeshWriter` writes them).
MESH_FILES = ("positions.npy", "colours.npy", "normals.npy", "faces.npy", "frames.npy", "frame_keys.npy",
              "uvs.npy", "textures.npy", "texture_frames.npy")
#: The files of the stored frames a rebuild added beside a library's (``part1_positions.npy``
#: ...; :func:`tvmedit.engine.store.arrays.parts`): checked as the file each continues.
PART_FILE = re.compile(r"part[1-9][0-9]*_((?:positions|colours|normals|faces|frames|frame_keys)\.npy)")


def mesh_file(name):
    """Whether the library file ``name`` holds stored frames: one of :data:`MESH_FILES` or a part."""
    return name in MESH_FILES or PART_FILE.fullmatch(name) is not None


def checked(name):
    """Whether the library file ``name`` gets a checksum: one of :data:`CHECKED_FILES` or a part."""
    return name in CHECKED_FILES or PART_FILE.fullmatch(name) is not None


def _wanted(name, names):
    """Whether file ``name`` is among ``names`` (None: all), a part as the file it continues."""
    part = PART_FILE.fullmatch(name)
    return names is None or name in names or (part is not None and part.group(1) in names)


def link_meshes(library, folder):
    """Give ``folder`` the stored meshes of ``library`` (a :class:`tvmedit.engine.store.library.Library`) as
    they are: hard links, copies where links cannot be made (each checked against the checksum
    ``library`` records: damaged bytes are not copied into a library that would sum them
    anew). Nothing in a library is changed in place, so the two may share them. Returns what :class:`~tvmedit.engine.store.arrays.MeshWriter` would: an object with
    ``frames``, ``bounds`` and ``max_counts``."""
    import os
    import shutil
    from types import SimpleNamespace

    sums = library.manifest.get("checksums", {})
    for name in library.manifest.get("files", {}):
        source = Path(library.path) / name
        if mesh_file(name):
            try:
                os.link(source, Path(folder) / name)
            except OSError:     # another file system: a copy, whose checksum is taken anew,
                shutil.copyfile(source, Path(folder) / name)
                if name in sums and checksum(Path(folder) / name) != sums[name]:   # so not of damage
                    raise damaged_files(library.path, [name])
    return SimpleNamespace(frames=int(library.manifest["counts"]["stored_frames"]),
                           bounds=library.manifest["bounds"], max_counts=library.manifest["max_counts"])


def graph_to_json(graph):
    """What ``graph.json`` holds: the complete graph's weights, transition frames and mu, and
    the edges added to connect the graph at that mu and why (read back: :func:`read_graph`)."""
    unpruned = graph.graph["unpruned"]
    transitions = graph.graph["transitions"]
    return {
        "mu": graph.graph["mu"],
        "connect": graph.graph.get("connect"),
        "added": [[int(i), int(j)] for i, j, added in sorted(graph.edges(data="added")) if added],
        "unpruned": [[int(i), int(j), float(w)] for (i, j), w in sorted(unpruned.items())],
        "transitions": [[int(i), int(j), int(a), int(b)] for (i, j), (a, b) in sorted(transitions.items())],
    }


def write_graphml(graph, path):
    """Export the pruned graph as GraphML (only mu among the graph attributes), atomically."""
    import networkx as nx

    plain = nx.DiGraph(mu=float(graph.graph["mu"]))
    for i, data in graph.nodes(data=True):
        plain.add_node(i, **{k: v for k, v in data.items() if v is not None})
    plain.add_edges_from(graph.edges(data=True))
    with safewrite.replacing_file(path) as tmp:
        nx.write_graphml(plain, tmp)


def write_corrections(folder, corrections, parses):
    """Write ``corrections.json`` (as :meth:`tvmedit.engine.store.corrections.Corrections.to_json` gives it)
    and ``parse.json`` (the automatic parse, per sequence as ``Structure.to_json``)."""
    write_json(Path(folder) / "corrections.json", corrections)
    write_json(Path(folder) / "parse.json", parses)


def read_corrections(path):
    """The corrections stored in the library at ``path`` as a dict, or None when it has none."""
    return read_json(path, "corrections.json") if (Path(path) / "corrections.json").exists() else None


def read_parse(path):
    """The automatic parse stored beside corrections (``{name: Structure JSON}``), or None."""
    return read_json(path, "parse.json") if (Path(path) / "parse.json").exists() else None


def write_features(folder, features):
    """Write ``features.npy`` from the :class:`tvmedit.engine.features.Features` of every sequence, in
    order (r padded to one width), and ``features_centred.npy`` from their ``centred`` ones
    where any has them; returns each sequence's rows in ``features_centred.npy`` (None where
    it has none) and their r width, for :func:`sequence_record` and :func:`manifest`."""
    folder = Path(folder)
    vectors = np.concatenate([f.vectors for f in features]) if features else np.zeros((0, 0), np.float32)
    np.save(folder / "features.npy", np.ascontiguousarray(vectors, dtype=np.float32))
    kept = [f.centred for f in features if f.centred is not None]
    rows, at = [], 0
    for f in features:
        rows.append(None if f.centred is None else (at, at + len(f.centred)))
        at += 0 if f.centred is None else len(f.centred)
    if not kept:
        return rows, 0
    width = max(c.r.shape[1] for c in kept)
    np.save(folder / "features_centred.npy",
            np.ascontiguousarray(np.concatenate([c.pad_r(width).vectors for c in kept]), dtype=np.float32))
    return rows, width


def read_features(manifest, record, bins, rows, centred_rows):
    """The :class:`tvmedit.engine.features.Features` of the sequence of manifest ``record``, r at the
    library's width, with its centred features where it has them (r at their own width).
    ``rows``: ``features.npy`` memory-mapped (:func:`load_array`); ``centred_rows``: a callable
    giving ``features_centred.npy`` so, called only where the record has rows in it."""
    from ..features import Features

    columns = manifest["feature_columns"]
    w_r, w_t = columns["r"], columns["theta"]
    origin = np.array(record["origin"], dtype=np.float64)

    def split(array, start, stop, width, own, centred=None):
        block = array[start:stop]
        return Features(block[:, :own], block[:, width:width + w_t], block[:, width + w_t:], origin, bins, centred)

    centred = None
    if record.get("centred_rows") is not None:
        centred = split(centred_rows(), *record["centred_rows"], columns["centred_r"], record["centred_r_bins"])
    return split(rows, *record["rows"], w_r, w_r, centred)


def sequence_record(name, fps, rows, features, feature_key, files, skipped, format=None,
                    orientation=None, centred_rows=None):
    """One sequence's entry in the manifest; ``features`` are its own (unpadded) ones; ``format``
    names its reader, ``orientation`` (JSON) the map into tvmedit's frame it was read with;
    ``centred_rows`` its rows in ``features_centred.npy`` (:func:`write_features`)."""
    extra = {} if format is None else {"format": format}
    if orientation is not None:
        extra["orientation"] = orientation
    if centred_rows is not None:
        extra["centred_rows"] = list(centred_rows)
        extra["centred_r_bins"] = int(features.centred.r.shape[1])
    return {
        "name": name,
        "fps": fps,
        "frames": rows[1] - rows[0],
        "rows": list(rows),
        "r_bins": int(features.r.shape[1]),
        "origin": [float(x) for x in features.origin],
        "feature_key": feature_key,
        "files": files,
        "skipped": [list(s) for s in skipped],
        **extra,
    }


def manifest(records, params, feature_columns, counts, bounds, max_counts):
    """The manifest's contents but for the file sizes (added by :func:`write_manifest`)."""
    return {
        "format": FORMAT,
        "tvmedit": tvmedit_version(),
        "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "params": json.loads(json.dumps(params, default=_json_default)),
        "feature_columns": feature_columns,
        "sequences": records,
        "counts": counts,
        "bounds": [list(bounds[0]), list(bounds[1])],
        "max_counts": list(max_counts),
    }


def checksum(path, stop=None):
    """CRC-32 of a file's bytes as 8 hex digits (zlib, a gigabyte a second or more): enough to
    tell damage of any size from the bytes written, where a file's size alone tells only
    truncation. None where the event ``stop`` is set before the end (looked at every 4 MB).

    >>> import tempfile; f = tempfile.NamedTemporaryFile(delete=False); _ = f.write(b"tvm"); f.close()
    >>> checksum(f.name)
    'e6dfda0b'
    """
    import zlib

    crc = 0
    with open(path, "rb") as handle:
        while chunk := handle.read(1 << 22):
            if stop is not None and stop.is_set():
                return None
            crc = zlib.crc32(chunk, crc)
    return f"{crc:08x}"


def write_manifest(folder, data, old=None):
    """Record the sizes and checksums of the :data:`CHECKED_FILES` in ``folder`` and write
    ``manifest.json`` last.

    A file that is ``old``'s own (a hard link to the same bytes, as :func:`link_meshes` gives
    a rebuild) keeps the checksum ``old``'s manifest records for it, not read again: the 60 fps
    13_29's meshes took 0.6 s of a correction's second to sum. It is the checksum of the
    bytes as they were written, so damage done to them since is still found."""
    folder = Path(folder)
    names = [path.name for path in sorted(folder.iterdir()) if checked(path.name)]
    known = _linked_checksums(folder, names, old)
    todo = [name for name in names if name not in known]
    sums = dict(zip(todo, _checksums(folder, todo)), **known)
    data = dict(data, files={name: (folder / name).stat().st_size for name in names},
                checksums={name: sums[name] for name in names})
    write_json(folder / "manifest.json", data)


def _linked_checksums(folder, names, old):
    """``{name: checksum}`` from ``old``'s manifest for each of ``names`` in ``folder`` that is
    the same file as ``old``'s of that name (a hard link) and of the size recorded there."""
    if old is None:
        return {}
    sums, sizes = old.manifest.get("checksums", {}), old.manifest.get("files", {})
    known = {}
    for name in names:
        if name not in sums:
            continue
        try:
            mine, theirs = (Path(folder) / name).stat(), (Path(old.path) / name).stat()
        except OSError:
            continue
        if (mine.st_dev, mine.st_ino) == (theirs.st_dev, theirs.st_ino) and mine.st_size == sizes.get(name):
            known[name] = sums[name]
    return known


def _checksums(folder, names, stop=None):
    """:func:`checksum` of each of the files ``names`` in ``folder``, files side by side on every
    core: reading and zlib's CRC both let go of the GIL, so threads share the work."""
    from ..parallel import default_workers, helper_threads

    with helper_threads(default_workers()) as pool:
        return list(pool.map(lambda name: checksum(Path(folder) / name, stop), names))


def verify(path, manifest, names=None, stop=None):
    """The names of the library's files whose bytes differ from those written (checksums in
    the manifest; ``names`` limits which), in manifest order; [] for a library built before
    checksums, and for files not read to their end because the event ``stop`` was set."""
    sums = manifest.get("checksums", {})
    names = [name for name in sums if _wanted(name, names)]
    return [name for name, found in zip(names, _checksums(path, names, stop)) if found not in (None, sums[name])]


@contextlib.contextmanager
def verifying(path, manifest, names=None, beside=True):
    """:func:`verify` on a thread while the body reads frames (an export, a render): the
    checksums of a large library take a second or more, and the frames need not wait for them.

    Leaving the body waits for them and raises their LibraryError where files are damaged, so
    a body inside a temporary output (:mod:`tvmedit.engine.safewrite`) leaves nothing. Where the
    body fails first (a frame off its bounds, an array that does not match its offsets), the
    checksums still name the damaged files; where they find none, or cannot read a file, the
    body's own error stands. A Ctrl-C stops them within 4 MB of reading. Their threads never
    take Ctrl-C (:func:`tvmedit.engine.parallel.helper_threads`); enter this after worker
    processes are forked, which no running thread may see. With ``beside`` False they run only
    where the body fails (reads made before such a fork)."""
    import threading

    from ..parallel import helper_threads

    stop = threading.Event()
    with helper_threads(1) as pool:
        checking = pool.submit(verify, path, manifest, names, stop) if beside else None
        try:
            yield
        except Exception as error:
            bad = _found(checking or pool.submit(verify, path, manifest, names))
            if bad:
                raise damaged_files(path, bad) from error
            raise
        except BaseException:   # Ctrl-C, SIGTERM: no wait for the rest of the checksums
            stop.set()
            raise
        bad = checking.result() if beside else []
        if bad:
            raise damaged_files(path, bad)


def _found(checking):
    """The damaged files a finished :func:`verify` found; [] where it could not read a file (the
    error of the body it ran beside says more)."""
    try:
        return checking.result()
    except Exception:
        return []


def damaged_files(path, names):
    """The LibraryError for a library whose files ``names`` fail their checksums."""
    return LibraryError(f"library {path} is damaged: {', '.join(names)} {'does' if len(names) == 1 else 'do'} "
                        f"not hold the bytes written (changed on disk); {_rebuild_hint(path)}.")


def _rebuild_hint(path):
    return f"rebuild it with {build_call(None, path, force=True)}"


#: Every file a library may hold besides the marker.
LIBRARY_FILES = (*CHECKED_FILES, "manifest.json", "graph.graphml", "names.json")


def legacy_foreign(path):
    """For a library built before the ownership marker: the files in it that a build did not write.

    None when ``path`` is not such a library (see :func:`tvmedit.engine.safewrite.check_target`).
    """
    # A marker too damaged to read is the build's own file all the same.
    names = sorted(str(p.relative_to(path)) for p in Path(path).rglob("*") if p.name != safewrite.MARKER)
    if safewrite.owner(path) != "library":
        # A manifest too damaged to read: still a library when it holds nothing but library files.
        whole = {"manifest.json", "features.npy", "database.json"} <= set(names)
        return [] if whole and all(name in LIBRARY_FILES or checked(name) for name in names) else None
    return [name for name in names if name not in LIBRARY_FILES and not checked(name)]


def read_manifest(path):
    """The manifest of the library at ``path``, its format and file sizes checked.

    Raises
    ------
    LibraryError
        When ``path`` is not a library, is of another format version, or misses or
        has a truncated file; the message says how to rebuild it.
    """
    path = Path(path)
    manifest_path = path / "manifest.json"
    if not manifest_path.is_file():
        leftovers = sorted(path.parent.glob(f".{path.name}.old-*"))
        if leftovers and not path.exists():
            raise LibraryError(f"no library at {path}, but an interrupted build left the previous "
                               f"one at {leftovers[0]}; rename it back to {path.name}.")
        if path.is_dir():
            from ..capture.load import holds_frames  # only here: opening a library reads no mesh code

            raise LibraryError(not_a_library(path, holds_frames(path)))
        raise LibraryError(f"no library at {path}; build one with {build_call(None, path)}.")
    try:
        data = json_value(manifest_path.read_text())
    except (OSError, ValueError) as error:
        raise LibraryError(f"library {path} has an unreadable manifest.json ({error}); "
                           f"{_rebuild_hint(path)}.") from None
    version = data.get("format") if isinstance(data, dict) else None
    if version != FORMAT:
        shown = "no format version" if version is None else f"format version {version!r}"
        shown += f" (a {type(version).__name__}, not a number)" if version is not None and not isinstance(version, int) else ""
        raise LibraryError(f"library {path} has {shown} but this tvmedit reads version "
                           f"{FORMAT!r}; {_rebuild_hint(path)}.")
    for name, size in data.get("files", {}).items():
        try:
            actual = (path / name).stat().st_size
        except OSError:
            raise LibraryError(f"library {path} is incomplete: {name} is missing; "
                               f"{_rebuild_hint(path)}.") from None
        if actual != size:
            raise LibraryError(f"library {path} is damaged: {name} has {actual} bytes where "
                               f"{size} were written (truncated or changed); {_rebuild_hint(path)}.")
    return data


def reads_format(method):
    """Files that do not hold what the format says become one LibraryError, whenever read (a
    decorator of the methods of a library, which has ``path``)."""
    import functools

    @functools.wraps(method)
    def checked(self, *args, **kwargs):
        try:
            return method(self, *args, **kwargs)
        except TvmError:
            raise
        except (OSError, ValueError, KeyError, TypeError, IndexError, AttributeError) as error:
            raise damaged(self.path, error) from None

    return checked


def damaged(path, error):
    """The LibraryError for a library whose files cannot be read as the format says."""
    return LibraryError(f"library {path} cannot be read ({type(error).__name__}: {error}); "
                        f"{_rebuild_hint(path)}.")


def read_json(path, name):
    """The JSON file ``name`` of the library at ``path``; LibraryError when it is not JSON."""
    try:
        return json_value((Path(path) / name).read_text())
    except (OSError, ValueError) as error:
        raise damaged(path, error) from None


def load_array(path, name):
    """Array file ``name`` of the library at ``path``, memory-mapped."""
    try:
        return np.load(Path(path) / name, mmap_mode="r")
    except Exception as error:  # noqa: BLE001 - a damaged header fails in numpy's parser in many ways
        detail = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise LibraryError(f"library {path} has an unreadable {name} ({detail}); "
                           f"{_rebuild_hint(path)}.") from None


def read_graph(path):
    """``(unpruned, transitions, mu, connected)`` from ``graph.json``: ``{(i, j): w}``,
    ``{(i, j): (exit, entry)}``, and how the build connected the graph (None if not said)."""
    data = read_json(path, "graph.json")
    unpruned = {(i, j): w for i, j, w in data["unpruned"]}
    transitions = {(i, j): (a, b) for i, j, a, b in data["transitions"]}
    connected = data.get("connect"), data.get("added")
    fits = isinstance(connected[0], dict) and isinstance(connected[1], list)
    return unpruned, transitions, float(data["mu"]), connected if fits else None


def read_blends(path, frames):
    """``(natural_step, {(from, to): (first row, count)}, data)`` from ``blends.json``, checked
    against the ``frames`` rows of ``blend_frames.npy``."""
    data = read_json(path, "blends.json")
    try:
        runs = {(int(e["from"]), int(e["to"])): (int(e["first"]), int(e["count"]))
                for e in [*data["edges"], *data.get("wraps", [])]}
        natural = float(data["natural_step"])
    except (KeyError, TypeError, ValueError) as error:
        raise damaged(path, error) from None
    if any(first < 0 or count < 0 or first + count > frames for first, count in runs.values()):
        raise damaged(path, ValueError("blends.json names rows beyond blend_frames.npy"))
    return natural, runs, data


def read_names(path):
    """The names given with ``rename`` (``{"id": "name"}``), checked; ``{}`` when none."""
    names_path = Path(path) / "names.json"
    if not names_path.exists():
        return {}
    try:
        names = json_value(names_path.read_text())
    except ValueError as error:
        raise LibraryError(f"{names_path} is not valid JSON ({error}); fix it or delete it "
                           "to go back to the default names.") from None
    _check_names(names_path, names)
    return names


def write_names(path, names):
    """Store ``names`` (``{"id": "name"}``) in ``names.json`` atomically."""
    target = Path(path) / "names.json"
    try:
        safewrite.write_text(target, json.dumps(names, indent=1, sort_keys=True))
        safewrite.note_written(path, "names.json")
    except OSError as error:
        raise LibraryError(f"cannot write {target} ({error.strerror}); "
                           "check that the library is writable.") from None


def _check_names(names_path, names):
    """``names.json`` is edited by hand at times: it must map ids to names, as rename writes it."""
    if not isinstance(names, dict):
        shown = json.dumps(names)
        shown = shown if len(shown) <= 40 else shown[:37] + "..."
        raise LibraryError(f"{names_path} must hold a JSON object of motion names such as "
                           f"{{\"3\": \"squats\"}}, not {shown}; fix it or delete it "
                           "to go back to the default names.")
    for key, name in names.items():
        if (not key.strip().isdigit() or not isinstance(name, str) or not name.strip() or name.strip().isdigit()
                or not name.strip().isprintable()):
            raise LibraryError(f"{names_path} maps {key!r} to {name!r}, but it must map motion ids to "
                               "one-line names with at least one non-digit, such as {\"3\": \"squats\"}; "
                               "fix it or delete it to go back to the default names.")


def check_unique(path, nodes):
    """Names applied from ``names.json`` must not give two motions one name."""
    seen = {}
    for node in nodes:
        if node.name in seen:
            raise LibraryError(f"{Path(path) / 'names.json'} gives motions {seen[node.name]} and "
                               f"{node.id} the same name {node.name!r}; fix it or delete it to go "
                               "back to the default names.")
        seen[node.name] = node.id
