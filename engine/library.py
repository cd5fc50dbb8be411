"""A built library on disk, and :class:`Library`, its reader: what edits and the player use.

A library is a directory written by :func:`engine.build` (:mod:`engine.builder`); nothing in it is parsed
while playing. Its files:

``manifest.json``
    format version, tvmedit version, build parameters, and per sequence its name, fps,
    frame count, rows in ``features.npy``, r width, origin, feature cache key, frame files
    (resolved path, size, mtime_ns) and skipped frames; the size of every file below (checked
    on open), the bounds of the stored meshes and their largest vertex and face counts.
``features.npy``
    (T, D) float32: one feature vector per frame of every sequence in order (eq. (1)-(4)),
    r histograms zero-padded to the library's widest, then theta, then phi.
``structure.json``
    per sequence, its parsed structure (section 4): clusters, textons, the atom-distance curve.
``database.json``
    the motion database (section 5): nodes with id, default name, sequence, inclusive frame
    range, cluster, texton distance and intensity.
``graph.json``
    the complete graph's weights ``[[i, j, w], ...]`` (eq. (12)), transition frames
    ``[[i, j, exit, entry], ...]`` (eq. (10), frames within each node's sequence) and mu; the
    pruned graph (eq. (14)) is rebuilt from them on open.
``graph.graphml``
    the pruned graph for other tools (``networkx.read_graphml(path, node_type=int)``).
``positions.npy``, ``colours.npy``, ``normals.npy``
    (V, 3) float32, uint8, float32: vertices of every stored frame, one after another.
``faces.npy``
    (F, 3) uint32, indices local to each frame.
``frames.npy``
    (n, 4) int64 per stored frame: vertex start, vertex count, face start, face count.
``frame_keys.npy``
    (n, 2) int64 per stored frame: sequence index (manifest order) and frame number.
``names.json``
    optional; node names given with ``tvmedit rename`` (``{"id": "name"}``).

Only the frames of database textons are stored. Every array opens with
``np.load(..., mmap_mode="r")``, so opening reads only the small JSON files.
"""

import json
import os
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from .database import Node
from .errors import LibraryError

__all__ = ["Library", "LibrarySequence", "FORMAT", "INFO_SCHEMA"]

#: On-disk format version; a library of another version must be rebuilt.
FORMAT = 1

#: Files whose sizes the manifest records and :meth:`Library.open` checks.
CHECKED_FILES = ("features.npy", "structure.json", "database.json", "graph.json", "positions.npy",
                 "colours.npy", "normals.npy", "faces.npy", "frames.npy", "frame_keys.npy")

_INT = {"type": "integer", "minimum": 0}
_NUM = {"type": "number"}
_RANGE = {"start": _INT, "end": _INT}

#: JSON schema of ``tvmedit info --json`` (:meth:`Library.info`). Frame ranges are inclusive
#: and 0-based within their sequence, exit and entry frames likewise; edges are those of the
#: pruned graph, ``from`` and ``to`` are node ids.
INFO_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "tvmedit library info",
    "type": "object",
    "required": ["format", "params", "sequences", "nodes", "edges"],
    "properties": {
        "format": {"type": "integer", "description": "on-disk format version"},
        "tvmedit": {"type": "string", "description": "version that built the library"},
        "params": {
            "type": "object",
            "description": "build parameters: bins (r in metres, theta and phi in radians), "
                           "structure (the parser's parameters), mu, skip_bad_frames",
            "required": ["bins", "structure", "mu"],
            "properties": {
                "bins": {"type": "object", "required": ["r", "theta", "phi"],
                         "properties": {"r": _NUM, "theta": _NUM, "phi": _NUM}},
                "structure": {"type": "object"},
                "mu": _NUM,
                "skip_bad_frames": {"type": "boolean"},
            },
        },
        "sequences": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["name", "frames", "fps", "clusters", "textons"],
                "properties": {
                    "name": {"type": "string"},
                    "frames": _INT,
                    "fps": {"type": "number", "exclusiveMinimum": 0},
                    "clusters": {"type": "array", "items": {
                        "type": "object", "required": ["start", "end"], "properties": _RANGE}},
                    "textons": {"type": "array", "items": {
                        "type": "object", "required": ["start", "end", "cluster"],
                        "properties": {**_RANGE, "cluster": _INT, "distance": _NUM}}},
                },
            },
        },
        "nodes": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["id", "name", "sequence", "start", "end", "texton_distance", "intensity"],
                "properties": {"id": _INT, "name": {"type": "string"}, "sequence": {"type": "string"},
                               **_RANGE, "cluster": _INT, "texton_distance": _NUM,
                               "intensity": {"type": ["number", "null"]},
                               "kind": {"enum": ["cycle", "once"],
                                        "description": "cycle: a texton played cyclically; once: a "
                                                       "one-shot motion played through once"}},
            },
        },
        "edges": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["from", "to", "weight", "exit_frame", "entry_frame"],
                "properties": {"from": _INT, "to": _INT, "weight": _NUM,
                               "exit_frame": _INT, "entry_frame": _INT},
            },
        },
    },
}


@dataclass(frozen=True)
class LibrarySequence:
    """One input sequence of a library.

    Attributes
    ----------
    name : str
    fps : float
    frames : int
        Frames analysed (bad frames skipped at build time are not counted).
    paths : list of str
        The frame files it was built from, in order.
    structure : engine.structure.Structure
        Its parsed structure (section 4), read on first use.
    """

    name: str
    fps: float
    frames: int
    paths: list
    _library: object = field(default=None, repr=False, compare=False)

    def __len__(self):
        return self.frames

    @property
    def structure(self):
        return self._library.structure(self.name)


def graph_to_json(graph):
    """What ``graph.json`` holds: the complete graph's weights, transition frames and mu."""
    unpruned = graph.graph["unpruned"]
    transitions = graph.graph["transitions"]
    return {
        "mu": graph.graph["mu"],
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
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    nx.write_graphml(plain, tmp)
    os.replace(tmp, path)


def _rebuild_hint(path):
    return f"rebuild it with `tvmedit build INPUT... -o {path} --force`"


def _not_a_library(path):
    """The sentence for a folder without a manifest: a sequence folder is told how to build one."""
    from .load import MESH_SUFFIXES

    try:
        frames = any(p.is_file() and p.suffix.lower() in MESH_SUFFIXES for p in path.iterdir())
    except OSError:
        frames = False
    if frames:
        plain = path if path.name not in ("", ".", "..") else path.resolve()
        target = plain.with_name(f"{plain.name}.tvmlib")
        return (f"{path} is a sequence folder (frame files, no manifest.json), not a library; "
                f"build a library from it with `tvmedit build {path} -o {target}`.")
    return (f"{path} is not a tvmedit library (it has no manifest.json); give a library folder, "
            "or build one with `tvmedit build INPUT... -o LIB`.")


def _check_names(names_path, names):
    """``names.json`` is edited by hand at times: it must map ids to names, as rename writes it."""
    if not isinstance(names, dict):
        shown = json.dumps(names)
        shown = shown if len(shown) <= 40 else shown[:37] + "..."
        raise LibraryError(f"{names_path} must hold a JSON object of motion names such as "
                           f"{{\"3\": \"squats\"}}, not {shown}; fix it or delete it "
                           "to go back to the default names.")
    for key, name in names.items():
        if not key.strip().isdigit() or not isinstance(name, str) or not name.strip() or name.strip().isdigit():
            raise LibraryError(f"{names_path} maps {key!r} to {name!r}, but it must map motion ids to "
                               "names with at least one non-digit, such as {\"3\": \"squats\"}; "
                               "fix it or delete it to go back to the default names.")


def _check_unique(names_path, nodes):
    seen = {}
    for node in nodes:
        if node.name in seen:
            raise LibraryError(f"{names_path} gives motions {seen[node.name]} and {node.id} the same "
                               f"name {node.name!r}; fix it or delete it to go back to the default names.")
        seen[node.name] = node.id


def _write_atomic(path, text):
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(text)
    os.replace(tmp, path)


class Library:
    """A library opened for editing and playing; use :meth:`open`.

    Implements the player's ``MeshSource`` protocol (:meth:`frame_mesh`, :meth:`bounds`,
    :meth:`max_counts`) over the stored texton frames, keyed ``(sequence_name, frame)``.
    """

    def __init__(self, path, manifest):
        self.path = Path(path)
        self.manifest = manifest
        self.report = None
        self.sequences = [LibrarySequence(s["name"], float(s["fps"]), int(s["frames"]),
                                          [row[0] for row in s["files"]], self)
                          for s in manifest["sequences"]]
        self._sequence_index = {s.name: k for k, s in enumerate(self.sequences)}
        self._nodes = self._read_nodes()

    @classmethod
    def open(cls, path):
        """Open the library at ``path``, checking its format and files (no array is read).

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
                raise LibraryError(_not_a_library(path))
            raise LibraryError(f"no library at {path}; build one with `tvmedit build INPUT... -o {path}`.")
        try:
            manifest = json.loads(manifest_path.read_text())
        except (OSError, ValueError) as error:
            raise LibraryError(f"library {path} has an unreadable manifest.json ({error}); "
                               f"{_rebuild_hint(path)}.") from None
        version = manifest.get("format") if isinstance(manifest, dict) else None
        if version != FORMAT:
            raise LibraryError(f"library {path} has format version {version} but this tvmedit "
                               f"reads version {FORMAT}; {_rebuild_hint(path)}.")
        for name, size in manifest.get("files", {}).items():
            try:
                actual = (path / name).stat().st_size
            except OSError:
                raise LibraryError(f"library {path} is incomplete: {name} is missing; "
                                   f"{_rebuild_hint(path)}.") from None
            if actual != size:
                raise LibraryError(f"library {path} is damaged: {name} has {actual} bytes where "
                                   f"{size} were written (truncated or changed); {_rebuild_hint(path)}.")
        try:
            return cls(path, manifest)
        except (OSError, ValueError, KeyError, TypeError) as error:
            raise LibraryError(f"library {path} cannot be read ({type(error).__name__}: {error}); "
                               f"{_rebuild_hint(path)}.") from None

    def __repr__(self):
        return (f"Library({str(self.path)!r}: {len(self.sequences)} sequences, "
                f"{len(self._nodes)} motions, {self.manifest['counts']['stored_frames']} stored frames)")

    # --- parameters, sequences, structure, features --------------------------------------

    @property
    def params(self):
        """Build parameters: ``bins``, ``structure``, ``mu``, ``skip_bad_frames``."""
        return self.manifest["params"]

    @property
    def mu(self):
        return float(self.params["mu"])

    def sequence(self, name):
        """The :class:`LibrarySequence` called ``name``."""
        try:
            return self.sequences[self._sequence_index[name]]
        except KeyError:
            known = ", ".join(s.name for s in self.sequences)
            raise LibraryError(f"library {self.path} has no sequence {name!r}; it has {known}.") from None

    @cached_property
    def _structures(self):
        from .structure import Structure

        data = json.loads((self.path / "structure.json").read_text())
        return {name: Structure.from_json(value) for name, value in data.items()}

    def structure(self, name):
        """The parsed structure (section 4) of sequence ``name``."""
        self.sequence(name)
        return self._structures[name]

    @cached_property
    def _features(self):
        return self._load("features.npy")

    def features(self, name):
        """Features of sequence ``name``, memory-mapped (r padded to the library's width).

        Returns an ``engine.features.Features`` whose arrays are read-only views of
        ``features.npy``; ``.vectors`` of two sequences compare directly.
        """
        from .features import BinSizes, Features

        record = self.manifest["sequences"][self._sequence_index[self.sequence(name).name]]
        columns = self.manifest["feature_columns"]
        rows = self._features[record["rows"][0]:record["rows"][1]]
        w_r, w_t = columns["r"], columns["theta"]
        return Features(rows[:, :w_r], rows[:, w_r:w_r + w_t], rows[:, w_r + w_t:],
                        np.array(record["origin"], dtype=np.float64), BinSizes(**self.params["bins"]))

    # --- the database and the graph ------------------------------------------------------

    def _read_nodes(self, renamed=True):
        nodes = [Node(**row) for row in json.loads((self.path / "database.json").read_text())]
        names_path = self.path / "names.json"
        if renamed and names_path.exists():
            try:
                names = json.loads(names_path.read_text())
            except ValueError as error:
                raise LibraryError(f"{names_path} is not valid JSON ({error}); fix it or delete it "
                                   "to go back to the default names.") from None
            _check_names(names_path, names)
            nodes = [replace(node, name=names.get(str(node.id), node.name)) for node in nodes]
            _check_unique(names_path, nodes)
        return nodes

    @property
    def nodes(self):
        """The motion database: list of ``engine.database.Node``, by id, names applied."""
        return list(self._nodes)

    def node(self, key):
        """The node a user means by ``key`` (an id, digits, or a name); UnknownMotion if none."""
        from .graph import node_by_key

        return self._nodes[node_by_key(self._nodes, key)]

    @cached_property
    def _graph_data(self):
        data = json.loads((self.path / "graph.json").read_text())
        unpruned = {(i, j): w for i, j, w in data["unpruned"]}
        transitions = {(i, j): (a, b) for i, j, a, b in data["transitions"]}
        return unpruned, transitions, float(data["mu"])

    @cached_property
    def graph(self):
        """The pruned motion graph (networkx DiGraph, see ``engine.graph.graph_from``)."""
        return self.graph_at(None)

    def graph_at(self, mu=None):
        """The motion graph pruned at ``mu`` (default: the library's), names applied."""
        from .graph import graph_from

        unpruned, transitions, stored_mu = self._graph_data
        return graph_from(self._nodes, unpruned, transitions, stored_mu if mu is None else mu)

    def rename(self, node, name):
        """Give a node a new, unique name, stored at once in ``names.json``; returns the node."""
        from .graph import rename as rename_node

        nodes = [replace(n) for n in self._nodes]
        i = rename_node(nodes, node, name)
        defaults = {n.id: n.name for n in self._read_nodes(renamed=False)}
        names = {str(n.id): n.name for n in nodes if n.name != defaults.get(n.id)}
        try:
            _write_atomic(self.path / "names.json", json.dumps(names, indent=1, sort_keys=True))
        except OSError as error:
            raise LibraryError(f"cannot write {self.path / 'names.json'} ({error.strerror}); "
                               "check that the library is writable.") from None
        self._nodes = nodes
        if "graph" in self.__dict__:
            self.graph.nodes[i]["name"] = nodes[i].name
        try:
            write_graphml(self.graph, self.path / "graph.graphml")
        except OSError:
            pass  # the export is a convenience; names.json is what tvmedit reads
        return nodes[i]

    # --- meshes: the MeshSource protocol -------------------------------------------------

    def _load(self, name):
        try:
            return np.load(self.path / name, mmap_mode="r")
        except (OSError, ValueError) as error:
            raise LibraryError(f"library {self.path} has an unreadable {name} ({error}); "
                               f"{_rebuild_hint(self.path)}.") from None

    @cached_property
    def _arrays(self):
        return {name: self._load(f"{name}.npy") for name in ("positions", "colours", "normals", "faces")}

    @cached_property
    def _offsets(self):
        return np.asarray(self._load("frames.npy"))

    @cached_property
    def _frame_rows(self):
        keys = np.asarray(self._load("frame_keys.npy"))
        names = [s.name for s in self.sequences]
        return {(names[s], int(f)): row for row, (s, f) in enumerate(keys.tolist())}

    def stored_frames(self):
        """Keys ``(sequence, frame)`` of every stored frame, in storage order."""
        return list(self._frame_rows)

    def has_frame(self, sequence, frame):
        """Whether the meshes of ``frame`` of ``sequence`` are stored (texton frames only)."""
        return (sequence, int(frame)) in self._frame_rows

    def _row(self, sequence, frame):
        try:
            return self._frame_rows[sequence, int(frame)]
        except KeyError:
            self.sequence(sequence)
            raise LibraryError(f"frame {frame} of {sequence} is not stored in library {self.path}: "
                               "only the frames of database motions are.") from None

    def frame(self, sequence, frame):
        """``(positions (N,3) float32, colours (N,3) uint8, faces (M,3) uint32)``, memory-mapped."""
        positions, colours, faces, _ = self.frame_mesh((sequence, frame))
        return positions, colours, faces

    def frame_mesh(self, key):
        """``(positions, colours, faces, normals)`` of frame ``key = (sequence, frame)``."""
        sequence, frame = key
        v0, nv, f0, nf = self._offsets[self._row(sequence, frame)].tolist()
        a = self._arrays
        return (a["positions"][v0:v0 + nv], a["colours"][v0:v0 + nv], a["faces"][f0:f0 + nf],
                a["normals"][v0:v0 + nv])

    def bounds(self):
        """``((xmin, ymin, zmin), (xmax, ymax, zmax))`` over every stored frame."""
        low, high = self.manifest["bounds"]
        return tuple(low), tuple(high)

    def max_counts(self):
        """``(max_vertices, max_faces)`` over every stored frame."""
        return tuple(self.manifest["max_counts"])

    # --- summaries and edits ---------------------------------------------------------------

    def info(self):
        """A JSON-ready summary following :data:`INFO_SCHEMA`."""
        sequences = []
        for seq in self.sequences:
            s = self.structure(seq.name)
            sequences.append({
                "name": seq.name, "frames": seq.frames, "fps": seq.fps,
                "clusters": [{"start": int(a), "end": int(b)} for a, b in s.clusters],
                "textons": [{"start": int(t.start), "end": int(t.end), "cluster": int(t.cluster),
                             "distance": float(t.distance)} for t in s.textons],
            })
        nodes = [{"id": n.id, "name": n.name, "sequence": n.sequence, "start": n.start, "end": n.end,
                  "cluster": n.cluster, "texton_distance": n.texton_distance, "intensity": n.intensity,
                  "kind": n.kind}
                 for n in self._nodes]
        edges = [{"from": int(i), "to": int(j), "weight": float(d["weight"]),
                  "exit_frame": int(d["exit_frame"]), "entry_frame": int(d["entry_frame"])}
                 for i, j, d in sorted(self.graph.edges(data=True))]
        return {"format": self.manifest["format"], "tvmedit": self.manifest.get("tvmedit", ""),
                "params": self.params, "sequences": sequences, "nodes": nodes, "edges": edges}

    def edit(self, keys, forbid=(), loops=1):
        """Compose an edit through the key motions ``keys`` (ids or names), sections 7-8.

        ``forbid`` names motions no path may visit; ``loops`` is the number of cycles of the
        last key motion (None: forever). Returns ``engine.compose.Composition`` with
        ``library`` set to this library; its ``schedule`` entries carry ``sequence`` and
        ``frame``, which :meth:`frame_mesh` plays.
        """
        from .compose import compose

        composition = compose(self.graph, keys, forbidden=forbid, loops=loops)
        composition.library = self
        return composition
