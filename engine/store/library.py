"""A built library on disk, and :class:`Library`, its reader: what edits and the player use.

A library is a directory written by :func:`build` (the stages are :mod:`tvmedit.engine.store.builder`'s);
its files and their checks are described and handled in :mod:`tvmedit.engine.store.layout`. Every array
opens memory-mapped, so opening reads only the small JSON files. This module is the top of
the engine: it builds, corrects (:mod:`tvmedit.engine.store.rebuild`) and opens libraries, and nothing
below it imports it (the builder is handed :meth:`Library.open` to read the library it
replaces).
"""

import os
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from . import arrays, capturecopy, layout
from ..graph.database import Node
from ..errors import LibraryError, build_call
from .infoschema import INFO_SCHEMA  # re-exported: tvmedit.engine.store.library.INFO_SCHEMA
from .layout import FORMAT
from .steps import DisplaySteps

__all__ = ["Library", "LibrarySequence", "FORMAT", "INFO_SCHEMA", "build"]


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
    structure : tvmedit.engine.parse.structure.Structure
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


_reads_format = layout.reads_format


class Library(DisplaySteps, capturecopy.CaptureCopies):
    """A library opened for editing and playing; use :meth:`open`.

    Implements the player's ``MeshSource`` protocol (:meth:`frame_mesh`, :meth:`bounds`,
    :meth:`max_counts`, and :meth:`frame_texture` for textured captures) over the stored texton
    frames, keyed ``(sequence_name, frame)``.
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

        Raises ``LibraryError`` as :func:`tvmedit.engine.store.layout.read_manifest` does, or when a
        file does not hold what the format says.
        """
        if not isinstance(path, (str, os.PathLike)):
            raise LibraryError(f"a library is opened from its folder's path, not {path!r}.")
        path = Path(path)
        manifest = layout.read_manifest(path)
        try:
            return cls(path, manifest)
        except (OSError, ValueError, KeyError, TypeError) as error:
            raise layout.damaged(path, error) from None

    @classmethod
    def opened(cls, path, report):
        """The library just written at ``path``, opened, with the writer's ``report``."""
        library = cls.open(path)
        library.report = report
        return library

    def __repr__(self):
        return (f"Library({str(self.path)!r}: {len(self.sequences)} sequences, "
                f"{len(self._nodes)} motions, {self.manifest['counts']['stored_frames']} stored frames)")

    @property
    def params(self):
        """Build parameters: ``bins``, ``structure``, ``mu``, ``skip_bad_frames``, ``connect``."""
        return self.manifest["params"]

    @property
    def mu(self):
        return float(self.params["mu"])

    @property
    def connect(self):
        """``"auto"`` (every motion reaches every other, :mod:`tvmedit.engine.graph.connect`) or ``"off"``;
        libraries built before the option existed are connected too."""
        return self.params.get("connect", "auto")

    def sequence(self, name):
        """The :class:`LibrarySequence` called ``name``."""
        try:
            return self.sequences[self._sequence_index[name]]
        except KeyError:
            known = ", ".join(s.name for s in self.sequences)
            raise LibraryError(f"library {self.path} has no sequence {name!r}; it has {known}.") from None

    @cached_property
    @_reads_format
    def _structures(self):
        from ..parse.structure import Structure

        data = layout.read_json(self.path, "structure.json")
        return {name: Structure.from_json(value) for name, value in data.items()}

    def structure(self, name):
        """The parsed structure (section 4) of sequence ``name``, corrections applied."""
        self.sequence(name)
        return self._structures[name]

    @cached_property
    @_reads_format
    def _parses(self):
        from ..parse.structure import Structure

        data = layout.read_parse(self.path) or {}
        return {name: Structure.from_json(value) for name, value in data.items()}

    def parse(self, name):
        """The automatic parse of sequence ``name``, before any correction by hand."""
        self.sequence(name)
        return self._parses.get(name) or self._structures[name]

    @_reads_format
    def corrections(self):
        """The corrections by hand stored with the library (:class:`tvmedit.engine.store.corrections.Corrections`;
        empty when none)."""
        from .corrections import Corrections

        data = layout.read_corrections(self.path)
        return Corrections.from_json(data, f"{self.path / 'corrections.json'}") if data else Corrections()

    def correct(self, corrections=None, out=None, *, force=None, log=None):
        """Apply ``corrections`` (a :class:`tvmedit.engine.store.corrections.Corrections`, a dict as in
        ``corrections.json`` or its path; the whole set, replacing the stored one) and derive
        database and graph again from the stored features, writing a new library atomically
        (``out``, default: this one). Returns it opened; see :func:`tvmedit.engine.store.rebuild.rebuild`.
        """
        from .rebuild import rebuild

        report = rebuild(self, out, corrections=corrections, force=force, log=log)
        return Library.opened(self.path if out is None else out, report)

    @cached_property
    @_reads_format
    def _features(self):
        return layout.load_array(self.path, "features.npy")

    @cached_property
    @_reads_format
    def _centred(self):
        return layout.load_array(self.path, "features_centred.npy")

    def _record(self, name):
        """Sequence ``name``'s entry in the manifest."""
        return self.manifest["sequences"][self._sequence_index[self.sequence(name).name]]

    def orientation(self, name):
        """The :class:`tvmedit.engine.capture.orientation.Orientation` sequence ``name``'s frames were read with
        (None: as their files are)."""
        from ..capture.orientation import Orientation

        where = self._record(name).get("orientation")
        return Orientation.from_json(where) if where else None

    @_reads_format
    def features(self, name):
        """Features of sequence ``name``, memory-mapped (r padded to the library's width).

        Returns an ``tvmedit.engine.features.Features`` whose arrays are read-only views of
        ``features.npy``; ``.vectors`` of two sequences compare directly. Its ``centred``
        (the histograms about each frame's own centre, where the origin stays put, for
        :func:`tvmedit.engine.parse.structure.parse`) are views of ``features_centred.npy``, or None.
        """
        from ..features import BinSizes

        return layout.read_features(self.manifest, self._record(name), BinSizes(**self.params["bins"]),
                                       self._features, lambda: self._centred)

    def _read_nodes(self, renamed=True):
        nodes = [Node(**row) for row in layout.read_json(self.path, "database.json")]
        names = layout.read_names(self.path) if renamed else {}
        if names:
            nodes = [replace(node, name=names.get(str(node.id), node.name)) for node in nodes]
            layout.check_unique(self.path, nodes)
        return nodes

    @property
    def nodes(self):
        """The motion database: list of ``tvmedit.engine.graph.database.Node``, by id, names applied."""
        return list(self._nodes)

    def node(self, key):
        """The node a user means by ``key`` (an id, digits, or a name); UnknownMotion if none."""
        from ..graph.motiongraph import node_by_key

        return self._nodes[node_by_key(self._nodes, key)]

    @cached_property
    @_reads_format
    def _graph_data(self):
        return layout.read_graph(self.path)

    @cached_property
    def graph(self):
        """The pruned motion graph (networkx DiGraph, see ``tvmedit.engine.graph.motiongraph.graph_from``)."""
        return self.graph_at(None)

    @_reads_format
    def graph_at(self, mu=None):
        """The motion graph pruned at ``mu`` (default: the library's) and connected as the
        library was built (:attr:`connect`), names applied."""
        from ..graph.motiongraph import graph_from
        from .settings import check_mu

        unpruned, transitions, stored_mu, connected = self._graph_data
        graph = graph_from(self._nodes, unpruned, transitions, stored_mu if mu is None else check_mu(mu),
                           self.connect, connected if mu is None else None)  # at its own mu, as built
        for (i, j), (_, count) in self._blends[1].items():
            if count and i != j and graph.has_edge(i, j):
                graph.edges[i, j]["blend"] = count
        for wrap in self._blends[2].get("wraps", []):   # loops closed (tvmedit.engine.inbetween.loops)
            if wrap["count"] and graph.has_node(wrap["from"]):
                graph.nodes[wrap["from"]].update(wrap=int(wrap["count"]), wrap_at=wrap.get("at", "end"))
        return graph

    @cached_property
    @_reads_format
    def _blends(self):
        return layout.read_blends(self.path, int(self.manifest["counts"].get("blend_frames", 0)))

    @property
    def natural_step(self):
        """The median step between consecutive texton frames (Chamfer, metres), as the build
        measured it (:func:`tvmedit.engine.inbetween.blend.natural_step`); 0 for a library without textons."""
        return self._blends[0]

    def blend_data(self):
        """The contents of ``blends.json`` (see :mod:`tvmedit.engine.store.layout`)."""
        return self._blends[2]

    def blend_runs(self):
        """Per graph edge ``(from, to)``: ``{"count", "jump", "steps"}`` of its in-between frames
        (:mod:`tvmedit.engine.inbetween.blend`; count 0 where the cut is kept)."""
        return {(int(e["from"]), int(e["to"])): {"count": int(e["count"]), "jump": float(e["jump"]),
                                                 "steps": [float(x) for x in e["steps"]]}
                for e in self._blends[2]["edges"]}

    def rename(self, node, name):
        """Give a node a new, unique name, stored at once in ``names.json``; returns the node."""
        from ..graph.motiongraph import rename as rename_node

        nodes = [replace(n) for n in self._nodes]
        i = rename_node(nodes, node, name)
        defaults = {n.id: n.name for n in self._read_nodes(renamed=False)}
        names = {str(n.id): n.name for n in nodes if n.name != defaults.get(n.id)}
        layout.write_names(self.path, names)
        self._nodes = nodes
        if "graph" in self.__dict__:
            self.graph.nodes[i]["name"] = nodes[i].name
        try:
            layout.write_graphml(self.graph, self.path / "graph.graphml")
        except OSError:
            pass  # the export is a convenience; names.json is what tvmedit reads
        return nodes[i]

    @cached_property
    @_reads_format
    def _arrays(self):
        return arrays.mesh_arrays(self.path)

    @cached_property
    @_reads_format
    def _offsets(self):
        return arrays.frame_offsets(self.path, self._arrays)

    @cached_property
    @_reads_format
    def _frame_rows(self):
        keys = arrays.frame_keys(self.path, len(self._offsets), len(self.sequences))
        names = [s.name for s in self.sequences]
        return {(names[s], int(f)): row for row, (s, f) in enumerate(keys.tolist())}

    def sources(self):
        """The library's folder and its sequences' folders: no output may go inside them."""
        folders = {str(Path(path).parent) for seq in self.sequences for path in seq.paths[:1]}
        return [self.path, *sorted(folders)]

    def stored_frames(self):
        """Keys ``(sequence, frame)`` of every stored frame (texton frames, the frames their loops are
        closed onto, every frame with ``keep_frames="all"``), in storage order (the
        in-between frames are stored apart; an edit's schedule names them by their ``key``)."""
        return list(self._frame_rows)

    def _row(self, sequence, frame):
        try:
            return self._frame_rows[sequence, int(frame)]
        except KeyError:
            self.sequence(sequence)
            raise LibraryError(f"frame {frame} of {sequence} is not stored in library {self.path}: "
                               "only the frames of database motions are.") from None

    @cached_property
    @_reads_format
    def _blend_arrays(self):
        return arrays.mesh_arrays(self.path, "blend_")

    @cached_property
    @_reads_format
    def _blend_offsets(self):
        return arrays.frame_offsets(self.path, self._blend_arrays, "blend_")

    def _locate(self, key):
        """``(arrays, offsets, row, textures)`` of the stored frame ``key`` (see :meth:`frame_mesh`)."""
        sequence, frame, *blend = key
        if blend and blend[0] is not None:
            return self._blend_arrays, self._blend_offsets, self._blend_row(blend[0]), "_blend_textures"
        return self._arrays, self._offsets, self._row(sequence, frame), "_textures"

    def _blend_row(self, blend):
        (i, j), index = blend
        first, count = self._blends[1].get((int(i), int(j)), (0, 0))
        if not 0 <= int(index) < count:
            raise LibraryError(f"library {self.path} holds {count} in-between frame(s) for transition "
                               f"{i} -> {j}, so it has no in-between frame {index}; compose the edit "
                               "from this library.")
        return first + int(index)

    def frame_mesh(self, key):
        """``(positions, colours, faces, normals)`` of frame ``key``.

        ``key`` is ``(sequence, frame)``, or ``(sequence, frame, ((from, to), i))`` for the
        ``i``-th in-between frame of a transition (``ScheduleEntry.key``). (N, 3) float32,
        (N, 3) uint8, (M, 3) uint32 and (N, 3) float32, memory-mapped; only the frames of
        database motions (:meth:`stored_frames`) and the in-between frames are stored.
        """
        arrays, offsets, row, _ = self._locate(key)
        return self._mesh_at(arrays, offsets, row, f"frame {key[1]} of {key[0]}")

    #: The files a frame's geometry, colours and in-betweens come from: what export and render
    #: check beside the frames they write (:meth:`verifying`).
    MESH_FILES = ("positions.npy", "colours.npy", "normals.npy", "faces.npy", "frames.npy", "uvs.npy", "textures.npy",
                  "texture_frames.npy", "blend_positions.npy", "blend_colours.npy", "blend_normals.npy", "blend_faces.npy",
                  "blend_frames.npy", "blend_uvs.npy", "blend_texture_frames.npy", "instant_pairs.npy",
                  "instant_fields.npy", "blend_draco.npy", "blend_draco_frames.npy")

    def verify(self, names=None):
        """Raise LibraryError, naming them, where files of the library (``names``: only those)
        no longer hold the bytes the build wrote (checksums in the manifest: same-size damage
        that sizes miss); returns the number of files verified. A library built before
        checksums verifies nothing."""
        wanted = None if names is None else set(names)
        bad = layout.verify(self.path, self.manifest, wanted)
        if bad:
            raise layout.damaged_files(self.path, bad)
        return sum(1 for name in self.manifest.get("checksums", {}) if wanted is None or name in wanted)

    def verifying(self, names=None, beside=True):
        """:meth:`verify` beside the reads of an export or a render (:func:`tvmedit.engine.store.layout.verifying`)."""
        return layout.verifying(self.path, self.manifest, None if names is None else set(names), beside)

    def blend_row(self, row):
        """:meth:`frame_mesh` of the ``row``-th in-between frame stored (runs one after another,
        as ``blends.json`` lists them)."""
        return self._mesh_at(self._blend_arrays, self._blend_offsets, row, f"in-between frame {row}")

    def _mesh_at(self, a, offsets, row, label):
        v0, nv, f0, nf = offsets[row].tolist()
        faces = a["faces"][f0:f0 + nf]
        most_v, most_f = self.max_counts()
        if nv > most_v or nf > most_f or (nf and int(faces.max()) >= nv):
            raise layout.damaged(self.path, ValueError(f"{label} does not match its vertex and face counts"))
        positions = a["positions"][v0:v0 + nv]
        self._check_bounds(positions, label)
        return positions, a["colours"][v0:v0 + nv], faces, a["normals"][v0:v0 + nv]

    def _check_bounds(self, positions, label):
        """Refuse a frame whose vertices are not finite or leave the bounds the build recorded:
        damage on disk caught where the frame is read, for a fraction of a millisecond, before
        a 300 m vertex reaches a file or the screen."""
        if not len(positions):
            return
        low, high = self.bounds()
        slack = 1e-3 * max(1.0, max(h - lo for lo, h in zip(low, high)))
        # Reduced as (3, N) rows: numpy reduces (N, 3) over axis 0 twenty times slower.
        columns = np.ascontiguousarray(np.asarray(positions).T)
        for k, (least, most) in enumerate(zip(columns.min(axis=1).tolist(), columns.max(axis=1).tolist())):
            if not (low[k] - slack <= least and most <= high[k] + slack):
                raise LibraryError(f"library {self.path} is damaged: {label} has vertices at "
                                   f"{least:.3g}..{most:.3g} m on axis {'xyz'[k]}, outside the bounds the build "
                                   f"recorded ({low[k]:.3g}..{high[k]:.3g} m); "
                                   f"rebuild it with {build_call(None, self.path, force=True)}.")

    def source_mesh(self, key):
        """:meth:`frame_mesh` of any frame of a sequence: the stored one, else read from its frame
        file as the build read it (slower; InputError when the file is gone)."""
        from ..capture.load import read_frame
        from ..capture.normals import vertex_normals

        sequence, frame = key
        if (sequence, int(frame)) in self._frame_rows:
            return self.frame_mesh(key)
        mesh = read_frame(self.sequence(sequence).paths[int(frame)], self.orientation(sequence))
        return mesh.positions, mesh.colours, mesh.faces, vertex_normals(mesh.positions, mesh.faces)

    @cached_property
    @_reads_format
    def _textures(self):
        if "uvs.npy" not in self.manifest.get("files", {}):
            return None
        return arrays.texture_arrays(self.path, len(self._arrays["positions"]), len(self._offsets))

    @cached_property
    @_reads_format
    def _blend_textures(self):
        if "blend_uvs.npy" not in self.manifest.get("files", {}):
            return None
        return arrays.texture_arrays(self.path, len(self._blend_arrays["positions"]),
                                        len(self._blend_offsets), "blend_")

    @property
    def textured(self):
        """Whether any stored frame has a texture (then :meth:`frame_texture` gives it)."""
        return self._textures is not None

    @_reads_format
    def frame_texture(self, key):
        """``(uv (N, 2) float32, image (H, W, 3) uint8)`` of frame ``key``, memory-mapped, or None
        when the frame has no texture (the player then draws its vertex colours)."""
        if self._textures is None:
            return None
        _, offsets, row, textures = self._locate(key)
        if getattr(self, textures) is None:
            return None
        uvs, texels, rows = getattr(self, textures)
        start, height, width = rows[row].tolist()
        if not height:
            return None
        v0, nv = offsets[row, :2].tolist()
        return uvs[v0:v0 + nv], texels[start:start + height * width].reshape(height, width, 3)

    @_reads_format
    def texture_origin(self, key):
        """``(sequence, frame)`` of the captured frame whose texture image frame ``key`` shows, or
        None when it has none. An in-between frame is a captured frame moved, and shows that
        frame's image (the library stores it once), so an export can copy the capture's own
        image file instead of encoding it again."""
        if self._textures is None:
            return None
        _, _, row, textures = self._locate(key)
        if getattr(self, textures) is None:
            return None
        start, height, _ = getattr(self, textures)[2][row].tolist()
        return self._texture_starts.get(start) if height else None

    @cached_property
    def _texture_starts(self):
        rows = self._textures[2].tolist()
        return {rows[row][0]: key for key, row in reversed(self._frame_rows.items()) if rows[row][1]}

    @_reads_format
    def bounds(self):
        """``((xmin, ymin, zmin), (xmax, ymax, zmax))`` over every stored frame."""
        low, high = (tuple(float(x) for x in corner) for corner in self.manifest["bounds"])
        if len(low) != 3 or len(high) != 3 or not np.isfinite([*low, *high]).all():
            raise ValueError(f"bounds {low}, {high} are not two finite corners")
        return low, high

    @_reads_format
    def max_counts(self):
        """``(max_vertices, max_faces)`` over every stored frame."""
        return tuple(int(n) for n in self.manifest["max_counts"])

    @_reads_format
    def info(self):
        """A JSON-ready summary following :data:`INFO_SCHEMA`."""
        sequences = []
        corrections = self.corrections().to_json()["sequences"]
        for seq in self.sequences:
            s = self.structure(seq.name)
            fixes = {"corrections": corrections[seq.name]} if seq.name in corrections else {}
            sure = list(s.boundary_confidence) + [None] * (len(s.clusters) - len(s.boundary_confidence))
            sequences.append({
                "name": seq.name, "frames": seq.frames, "fps": seq.fps,
                "clusters": [{"start": int(a), "end": int(b), "confidence": c}
                             for (a, b), c in zip(s.clusters, sure)],
                "textons": [{"start": int(t.start), "end": int(t.end), "cluster": int(t.cluster),
                             "distance": float(t.distance),
                             "confidence": None if t.confidence is None else float(t.confidence)}
                            for t in s.textons],
                **fixes,
            })
        nodes = [{"id": n.id, "name": n.name, "sequence": n.sequence, "start": n.start, "end": n.end,
                  "cluster": n.cluster, "texton_distance": n.texton_distance, "intensity": n.intensity,
                  "kind": n.kind, "closing_frames": int(self.graph.nodes[n.id].get("wrap", 0))}
                 for n in self._nodes]
        runs = self.blend_runs()
        edges = [{"from": int(i), "to": int(j), "weight": float(d["weight"]),
                  "exit_frame": int(d["exit_frame"]), "entry_frame": int(d["entry_frame"]),
                  "added": bool(d.get("added", False)), "blend_frames": int(d.get("blend", 0)),
                  **({"jump": runs[i, j]["jump"]} if (i, j) in runs else {})}
                 for i, j, d in sorted(self.graph.edges(data=True))]
        return {"format": self.manifest["format"], "tvmedit": self.manifest.get("tvmedit", ""),
                "params": self.params, "natural_step": self.natural_step, "sequences": sequences,
                "nodes": nodes, "edges": edges, "connect": self.graph.graph["connect"]}

    def edit(self, keys, forbid=(), loops=1, durations=None, at=None, holds=None, strict=False):
        """Compose an edit through the key motions ``keys`` (ids or names), sections 7-8.

        ``forbid`` names motions no path may visit; ``loops`` is the number of cycles of the
        last key motion (None: forever). Lengths in seconds at the library's frame rate
        (:mod:`tvmedit.engine.graph.timing`): ``durations`` gives each leg's (None: as short as section 8
        plays it), or ``at`` the time each key motion begins; ``holds`` maps a key motion to
        the seconds it keeps looping once it begins (a key repeated in ``keys`` with a
        duration between is a hold too). A leg no schedule makes within a frame lasts the
        nearest time one makes, with a :class:`~tvmedit.engine.errors.DurationWarning`, or raises
        :class:`~tvmedit.engine.errors.DurationError` with ``strict``.

        Returns ``tvmedit.engine.graph.compose.Composition`` with ``library`` and ``fps`` set to this
        library's; its ``schedule`` entries carry ``sequence`` and ``frame``, which
        :meth:`frame_mesh` plays, and its ``starts`` the frame each key motion begins at.
        """
        from ..graph.compose import compose
        from ..graph.motiongraph import node_by_key
        from ..graph.timing import Timing

        from ..checks import listed

        keys, forbid = listed("keys", [] if keys is None else keys), listed("forbid", forbid)
        durations, at = listed("durations", durations, "seconds"), listed("at", at, "seconds")
        graph = self.graph
        ids = [node_by_key(graph, key) for key in keys]
        fps = self.sequence(graph.nodes[ids[0]]["sequence"]).fps if ids else None
        timing = None
        if len(ids) >= 2:
            ids, timing = Timing.request(graph, ids, fps, durations=durations, at=at, holds=holds, strict=strict)
        composition = compose(graph, ids, forbidden=forbid, loops=loops, timing=timing)
        composition.library = self
        composition.fps = fps
        return composition

    def wander(self, seconds=None, seed=None, only=None, forbid=(), temperature=1.0, start=None):
        """A walk that plays the library by itself (:mod:`tvmedit.engine.playback.wander`).

        Without ``seconds``, an endless lazy iterable of schedule entries (a ``Wander``);
        with ``seconds``, that long a walk as an edit, which export and render take like
        :meth:`edit`'s. ``seed`` makes it reproducible; ``only`` and ``forbid`` name the
        motions it may play; ``temperature`` (times the median transition weight) sets how
        freely it takes costly transitions; ``start`` is the motion it begins at.
        """
        from ..checks import listed
        from ..playback.wander import library_walk

        only, forbid = listed("only", only), listed("forbid", forbid)
        return library_walk(self, seconds, seed=seed, only=only, forbid=forbid, temperature=temperature,
                            start=start)


def build(inputs, out, **options):
    """Build a library from TVM sequences and return it opened: ``engine.build``.

    Every option is described in :func:`tvmedit.engine.store.builder.build`, which writes the library; the
    library it replaces, if any, lends its features, corrections and meshes. The returned
    :class:`Library` has ``report``: counts, reused sequences and timings.
    """
    from . import builder

    out = Path(out).absolute()
    return Library.opened(out, builder.build(inputs, out, open_library=Library.open, **options))
