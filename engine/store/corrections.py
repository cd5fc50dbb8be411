"""Corrections by hand: a user's edits to the automatic parse (section 4), kept as data.

Automatic parsing is sometimes wrong on a user's own capture: a boundary late, two
exercises merged, a texton of half a period. A :class:`Corrections` holds, per sequence,
what to change on top of the parse, and is stored in the library (``corrections.json``),
so a rebuild with other parameters applies it again::

    {"sequences": {"gym": {
        "boundaries": {"add": [412], "remove": [118], "move": [[240, 236]]},
        "textons": {"add": [300], "remove": [310], "move": [[150, 152]]},
        "representatives": [305],
        "drop": ["gym/06"]}}}

Frames are 0-based within the sequence. What each entry does, in this order:

``boundaries``
    A boundary is the first frame of a cluster (frame 0 always begins the first one).
    ``remove`` and ``move`` take the boundary nearest the frame given, within
    :data:`REACH` seconds (a rebuild with other parameters may have shifted it a little);
    ``add`` starts a cluster at that frame. A cluster the boundaries changed gets its
    textons found anew as the parser finds them (:func:`tvmedit.engine.parse.structure.textons_for`); the
    other clusters keep theirs.
``textons``
    Texton starts, likewise: ``remove`` joins a texton to the one before it (or drops the
    first of its cluster), ``move`` moves a start between its neighbours, ``add`` splits
    the texton it falls in (or begins one that runs to the next texton or the cluster's
    end). A texton a correction makes must be at least one atom window long (eq. (5)).
``representatives``
    The texton holding each frame becomes its cluster's representative, whatever eq. (9)
    says (a one-shot cluster so becomes a cycle).
``drop``
    Motions, by their names in the corrected database, left out of it and of the graph.

An entry that cannot be applied (a frame outside the sequence, a cluster or texton shorter
than the atom window, a motion that does not exist) is a :class:`CorrectionError`, one sentence
naming the entry; a ``remove`` or ``move`` that finds nothing near (the parse changed) is
a note, not an error.
"""

import copy
import json
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..parse.atoms import atom_distance, atom_window
from ..parse.confidence import texton_confidence
from ..errors import InputError
from ..checks import json_value

__all__ = ["Corrections", "SequenceCorrections", "CorrectionError", "REACH", "apply_structure",
           "apply_structures", "apply_database"]

#: How far (seconds) a ``remove`` or ``move`` looks for the boundary or texton start it names.
REACH = 0.5

_KINDS = ("boundaries", "textons")
_OPS = ("add", "remove", "move")


class CorrectionError(InputError):
    """A correction that cannot be applied: one sentence naming the entry."""


@dataclass
class SequenceCorrections:
    """The corrections of one sequence (see the module docstring for what each does).

    Attributes
    ----------
    boundaries, textons : dict of str to list
        ``{"add": [frame], "remove": [frame], "move": [[from, to]]}``.
    representatives : list of int
        Frames whose texton is forced as its cluster's representative.
    drop : list of str
        Motion names to leave out of the database.
    """

    boundaries: dict = field(default_factory=lambda: {op: [] for op in _OPS})
    textons: dict = field(default_factory=lambda: {op: [] for op in _OPS})
    representatives: list = field(default_factory=list)
    drop: list = field(default_factory=list)

    def __bool__(self):
        return bool(self.representatives or self.drop
                    or any(self.boundaries[op] or self.textons[op] for op in _OPS))

    def to_json(self):
        """Plain dict; empty parts left out."""
        out = {}
        for kind in _KINDS:
            ops = {op: copy.deepcopy(v) for op, v in getattr(self, kind).items() if v}
            if ops:
                out[kind] = ops
        if self.representatives:
            out["representatives"] = list(self.representatives)
        if self.drop:
            out["drop"] = list(self.drop)
        return out


class Corrections:
    """Corrections of a library's parse, per sequence; edited by the methods below.

    Edits are kept minimal: removing a boundary that was added by hand takes the ``add``
    away rather than recording both, so a saved file says what differs from the parse.

    Examples
    --------
    >>> c = Corrections()
    >>> c.add_boundary("gym", 120)
    >>> c.remove_boundary("gym", 300)
    >>> c.remove_boundary("gym", 120)
    >>> c.to_json()
    {'sequences': {'gym': {'boundaries': {'remove': [300]}}}}
    """

    def __init__(self, sequences=None, source="corrections"):
        self.sequences = dict(sequences or {})
        self.source = source

    def __bool__(self):
        return any(self.sequences.values())

    def __eq__(self, other):
        return isinstance(other, Corrections) and self.to_json() == other.to_json()

    def __repr__(self):
        return f"Corrections({self.to_json()!r})"

    def of(self, name):
        """The :class:`SequenceCorrections` of sequence ``name`` (created empty when absent)."""
        return self.sequences.setdefault(name, SequenceCorrections())

    def copy(self):
        return Corrections.from_json(self.to_json(), self.source)

    def _add(self, name, kind, frame):
        ops = getattr(self.of(name), kind)
        frame = int(frame)
        if frame in ops["remove"]:
            ops["remove"].remove(frame)
        elif frame not in ops["add"]:
            ops["add"].append(frame)

    def _remove(self, name, kind, frame):
        ops = getattr(self.of(name), kind)
        frame = int(frame)
        if frame in ops["add"]:
            ops["add"].remove(frame)
            return
        for pair in ops["move"]:
            if pair[1] == frame:
                ops["move"].remove(pair)
                frame = pair[0]
                break
        if frame not in ops["remove"]:
            ops["remove"].append(frame)

    def _move(self, name, kind, frame, to):
        ops = getattr(self.of(name), kind)
        frame, to = int(frame), int(to)
        if frame == to:
            return
        if frame in ops["add"]:
            ops["add"][ops["add"].index(frame)] = to
            return
        for pair in ops["move"]:
            if pair[1] == frame:
                pair[1] = to
                if pair[0] == to:
                    ops["move"].remove(pair)
                return
        ops["move"].append([frame, to])

    def add_boundary(self, sequence, frame):
        """Begin a cluster at ``frame``."""
        self._add(sequence, "boundaries", frame)

    def remove_boundary(self, sequence, frame):
        """Remove the cluster boundary at (or near) ``frame``."""
        self._remove(sequence, "boundaries", frame)

    def move_boundary(self, sequence, frame, to):
        """Move the cluster boundary at (or near) ``frame`` to ``to``."""
        self._move(sequence, "boundaries", frame, to)

    def add_texton(self, sequence, frame):
        """Begin a texton at ``frame``."""
        self._add(sequence, "textons", frame)

    def remove_texton(self, sequence, frame):
        """Remove the texton start at (or near) ``frame``."""
        self._remove(sequence, "textons", frame)

    def move_texton(self, sequence, frame, to):
        """Move the texton start at (or near) ``frame`` to ``to``."""
        self._move(sequence, "textons", frame, to)

    def represent(self, sequence, frame):
        """Force the texton holding ``frame`` as its cluster's representative."""
        reps = self.of(sequence).representatives
        if int(frame) not in reps:
            reps.append(int(frame))

    def drop(self, sequence, name):
        """Leave motion ``name`` (of ``sequence``) out of the database."""
        if name not in self.of(sequence).drop:
            self.of(sequence).drop.append(str(name))

    def to_json(self):
        """``{"sequences": {name: {...}}}`` with empty parts left out."""
        return {"sequences": {name: c.to_json() for name, c in self.sequences.items() if c}}

    def save(self, path):
        """Write ``corrections.json`` to ``path`` atomically."""
        from .. import safewrite

        entries = [f"  {json.dumps(name)}: {json.dumps(entry)}" for name, entry in self.to_json()["sequences"].items()]
        safewrite.write_text(path, "{\"sequences\": {\n" + ",\n".join(entries) + "\n}}\n")

    @classmethod
    def load(cls, path):
        """Read a corrections file; one sentence naming the file when it is not one."""
        path = Path(path)
        try:
            data = json_value(path.read_text())
        except OSError as error:
            raise CorrectionError(f"cannot read corrections file {path} ({error.strerror}); "
                                  "give an existing JSON file.") from None
        except ValueError as error:
            raise CorrectionError(f"corrections file {path} is not valid JSON ({error}); fix it.") from None
        return cls.from_json(data, str(path))

    @classmethod
    def from_json(cls, data, source="corrections"):
        """Check the shape of ``data`` (types and keys; frames are checked when applied)."""
        if not isinstance(data, dict) or set(data) - {"sequences", "format"} \
                or not isinstance(data.get("sequences", {}), dict):
            raise CorrectionError(f"{source} must hold {{\"sequences\": {{NAME: {{...}}}}}}, one "
                                  "entry per sequence name; see tvmedit.engine.store.corrections for the keys.")
        return cls({str(name): _sequence_from_json(source, name, entry)
                    for name, entry in data.get("sequences", {}).items()}, source)

    @classmethod
    def coerce(cls, value):
        """A :class:`Corrections` from one, a dict as in the file, a path, or None (empty)."""
        if value is None:
            return cls()
        if isinstance(value, Corrections):
            return value
        if isinstance(value, dict):
            return cls.from_json(value)
        return cls.load(value)

    def check_sequences(self, frames):
        """Every sequence named must exist, every frame lie in it: ``frames`` is ``{name: T}``."""
        for name, entry in self.sequences.items():
            if name not in frames:
                raise CorrectionError(f"{self.source} corrects sequence {name!r}, which the library "
                                      f"does not have; it has {', '.join(frames) or 'none'}.")
            for where, frame in _frames_of(entry):
                if not 0 <= frame < frames[name]:
                    raise CorrectionError(f"{_entry(self.source, name, where)} = {frame} lies outside "
                                          f"the sequence (frames 0-{frames[name] - 1}); give a frame "
                                          "inside it.")


def _sequence_from_json(source, name, entry):
    def bad(where, what):
        return CorrectionError(f"{_entry(source, name, where)} must be {what}.")

    if not isinstance(entry, dict) or set(entry) - {*_KINDS, "representatives", "drop"}:
        raise bad("", "an object with keys boundaries, textons, representatives, drop")
    out = SequenceCorrections()
    for kind in _KINDS:
        ops = entry.get(kind, {})
        if not isinstance(ops, dict) or set(ops) - set(_OPS):
            raise bad(kind, "an object with keys add, remove, move")
        for op in _OPS:
            items = ops.get(op, [])
            if not isinstance(items, list):
                raise bad(f"{kind}.{op}", "a list")
            for k, item in enumerate(items):
                pair = op == "move"
                ok = (isinstance(item, list) and len(item) == 2 and all(_is_frame(x) for x in item)) \
                    if pair else _is_frame(item)
                if not ok:
                    raise bad(f"{kind}.{op}[{k}]", "a pair of frames [from, to]" if pair else "a frame number")
            getattr(out, kind)[op] = [list(map(int, i)) if op == "move" else int(i) for i in items]
    reps, drop = entry.get("representatives", []), entry.get("drop", [])
    if not isinstance(reps, list) or not all(_is_frame(x) for x in reps):
        raise bad("representatives", "a list of frame numbers")
    if not isinstance(drop, list) or not all(isinstance(x, str) and x for x in drop):
        raise bad("drop", "a list of motion names")
    out.representatives, out.drop = [int(x) for x in reps], list(drop)
    return out


def _is_frame(value):
    return isinstance(value, int) and not isinstance(value, bool)


def _entry(source, name, where):
    return f"{source}, sequence {name!r}" + (f", {where}" if where else "")


def _frames_of(entry):
    """``(where, frame)`` of every frame an entry names, for range checks."""
    for kind in _KINDS:
        ops = getattr(entry, kind)
        for op in ("add", "remove"):
            for k, frame in enumerate(ops[op]):
                yield f"{kind}.{op}[{k}]", frame
        for k, (a, b) in enumerate(ops["move"]):
            yield f"{kind}.move[{k}][0]", a
            yield f"{kind}.move[{k}][1]", b
    for k, frame in enumerate(entry.representatives):
        yield f"representatives[{k}]", frame


def _nearest(candidates, frame, reach):
    near = [c for c in candidates if abs(c - frame) <= reach]
    return min(near, key=lambda c: (abs(c - frame), c)) if near else None


def _boundaries(structure, entry, reach, say, where):
    """The corrected cluster starts, and a note for every entry that found nothing."""
    T = len(structure.curve)
    starts = [s for s, _ in structure.clusters]
    for k, frame in enumerate(entry.boundaries["remove"]):
        found = _nearest(starts[1:], frame, reach)
        if found is None:
            say(f"{where(f'boundaries.remove[{k}]')} = {frame}: no boundary within {reach} frames; nothing removed")
        else:
            starts.remove(found)
    for k, (frame, to) in enumerate(entry.boundaries["move"]):
        found = _nearest(starts[1:], frame, reach)
        if found is None:
            say(f"{where(f'boundaries.move[{k}]')} = {frame}: no boundary within {reach} frames; nothing moved")
            continue
        starts.remove(found)
        starts.append(_inner(to, T, where(f"boundaries.move[{k}][1]")))
    for k, frame in enumerate(entry.boundaries["add"]):
        starts.append(_inner(frame, T, where(f"boundaries.add[{k}]")))
    starts = sorted(set(starts))
    return [(s, e - 1) for s, e in zip(starts, starts[1:] + [T])]


def _inner(frame, T, where):
    if frame == 0:
        raise CorrectionError(f"{where} = 0: frame 0 always begins the first cluster; give a "
                              f"boundary from 1 to {T - 1}.")
    return frame


class _Textons:
    """The textons of a sequence as ``[start, end, cluster]`` lists while they are edited."""

    def __init__(self, textons, clusters):
        self.clusters = clusters
        self.items = sorted([[t.start, t.end, t.cluster] for t in textons])

    def cluster_of(self, frame):
        return next(k for k, (s, e) in enumerate(self.clusters) if s <= frame <= e)

    def at(self, start):
        return next(t for t in self.items if t[0] == start)

    def before(self, item):
        """The texton just before ``item`` in its cluster, when it ends where ``item`` starts."""
        return next((t for t in self.items if t[2] == item[2] and t[1] == item[0] - 1), None)

    def remove(self, start):
        item = self.at(start)
        prev = self.before(item)
        if prev is not None:
            prev[1] = item[1]
        self.items.remove(item)
        return prev

    def add(self, frame):
        k = self.cluster_of(frame)
        inside = next((t for t in self.items if t[0] < frame <= t[1]), None)
        if inside is not None:
            made = [frame, inside[1], k]
            inside[1] = frame - 1
            touched = [inside, made]
        else:
            later = [t[0] for t in self.items if t[2] == k and t[0] > frame]
            made = [frame, (min(later) - 1) if later else self.clusters[k][1], k]
            touched = [made]
        self.items.append(made)
        self.items.sort()
        return touched

    def move(self, start, to):
        item = self.at(start)
        prev = self.before(item)
        low = prev[0] if prev is not None else self.clusters[item[2]][0] - 1
        if low < to <= item[1]:
            item[0] = to
            if prev is not None:
                prev[1] = to - 1
            self.items.sort()
            return [t for t in (prev, item) if t is not None]
        kept = self.remove(start)
        return [t for t in [kept] if t is not None] + self.add(to)


def _texton_edits(textons, entry, reach, window, say, where):
    """Apply the texton entries to ``textons`` (a :class:`_Textons`); ``(start, end)`` of every
    texton an entry made or changed, which must be at least ``window`` frames long."""
    changed = set()

    def check(touched, label, frame):
        for start, end, _ in touched:
            if end - start + 1 < window:
                raise CorrectionError(
                    f"{where(label)} = {frame} makes texton {start}-{end} {end - start + 1} frame(s) "
                    f"long, shorter than the {window}-frame atom window; keep texton starts at "
                    f"least {window} frames apart.")
            changed.add((start, end))

    starts = lambda: [t[0] for t in textons.items]  # noqa: E731
    for k, frame in enumerate(entry.textons["remove"]):
        found = _nearest(starts(), frame, reach)
        if found is None:
            say(f"{where(f'textons.remove[{k}]')} = {frame}: no texton start within {reach} frames; nothing removed")
            continue
        kept = textons.remove(found)
        check([kept] if kept else [], f"textons.remove[{k}]", frame)
    for k, (frame, to) in enumerate(entry.textons["move"]):
        found = _nearest(starts(), frame, reach)
        if found is None:
            say(f"{where(f'textons.move[{k}]')} = {frame}: no texton start within {reach} frames; nothing moved")
            continue
        check(textons.move(found, to), f"textons.move[{k}][1]", to)
    for k, frame in enumerate(entry.textons["add"]):
        if frame not in starts():
            check(textons.add(frame), f"textons.add[{k}]", frame)
    return changed


def apply_structure(structure, vectors, entry, *, theta=None, centred=None, source="corrections", name="", say=None):
    """The structure of one sequence with its corrections applied (see the module docstring).

    Parameters
    ----------
    structure : tvmedit.engine.parse.structure.Structure
        The automatic parse.
    vectors : (T, D) array
        The sequence's feature vectors (rows of ``Features.vectors``).
    entry : SequenceCorrections
    theta : slice, optional
        The theta columns, as for :func:`tvmedit.engine.parse.structure.parse`.
    centred : tvmedit.engine.features.Features, optional
        The rows about each frame's own centre (``Features.centred``), as for
        :func:`tvmedit.engine.parse.structure.parse`: the textons of a cluster drawn by hand are found as
        the parser finds them.
    source, name : str
        The corrections' file and the sequence's name, for messages.
    say : callable, optional
        Called with a note for each ``remove`` or ``move`` that found nothing to act on.

    Returns
    -------
    tvmedit.engine.parse.structure.Structure
        A new structure; ``structure`` is not changed.
    """
    from ..parse.structure import Structure, StructureParams, Texton, parser_view, texton_curve, textons_for

    say = say or (lambda message: None)
    where = lambda label: _entry(source, name, label)  # noqa: E731
    v = np.asarray(vectors, dtype=np.float64)
    fps = structure.fps
    reach = max(1, int(round(REACH * fps)))
    params = StructureParams.recorded(structure.params)
    view = parser_view(v, params, theta, fps)   # what the parser measured textons on
    clusters = _boundaries(structure, entry, reach, say, where)
    kept = {c: k for k, c in enumerate(structure.clusters)}
    w = atom_window(fps, params.window_taps, params.window_fps)
    textons, new = [], []
    for k, (cs, ce) in enumerate(clusters):
        if (cs, ce) in kept:
            textons += [replace(t, cluster=k) for t in structure.textons_of(kept[(cs, ce)])]
            continue
        if ce - cs + 1 < len(w):  # it would be a motion of a frame or two
            raise CorrectionError(f"{where('boundaries')} make cluster {cs}-{ce} {ce - cs + 1} frame"
                                  f"{'s' * (ce != cs)} long, shorter than the {len(w)}-frame atom window; "
                                  f"keep boundaries at least {len(w)} frames apart and from the last frame.")
        new.append(k)
    # The new clusters' textons in one call: it reads the take's view and headings once.
    if new:
        found = textons_for(v, [clusters[k] for k in new], fps, params, theta, centred)
        textons += [replace(t, cluster=new[t.cluster]) for t in found]
    edited = _Textons(textons, clusters)
    changed = _texton_edits(edited, entry, reach, len(w), say, where)
    old = {(t.start, t.end): t for t in textons}
    out = []
    for start, end, k in edited.items:
        if (start, end) in old and (start, end) not in changed:
            out.append(replace(old[start, end], cluster=k))
        else:
            out.append(Texton(start, end, k, atom_distance(view, end, start, w), texton_confidence(view, start, end, w)))
    for k, frame in enumerate(entry.representatives):
        if not any(t.start <= frame <= t.end for t in out):
            raise CorrectionError(f"{where(f'representatives[{k}]')} = {frame} lies in no texton; "
                                  "add a texton start before it first.")
    curve = texton_curve(v, clusters, out, fps, params, theta)
    # A boundary kept from the automatic parse keeps its confidence; one drawn by hand is sure.
    sure = dict(zip((cs for cs, _ in structure.clusters), structure.boundary_confidence))
    return Structure(clusters, out, curve, fps, dict(structure.params),
                     [sure.get(cs, 1.0) if k else 1.0 for k, (cs, _) in enumerate(clusters)])


def apply_structures(parses, vectors, corrections, thetas=None, say=None, centreds=None):
    """:func:`apply_structure` for every sequence: ``{name: Structure}`` from the automatic
    ``parses`` and ``vectors`` (``{name: (T, D) array}``); uncorrected sequences as parsed.
    ``thetas`` and ``centreds``: each sequence's theta columns and centred rows, by name."""
    thetas, centreds = thetas or {}, centreds or {}
    return {name: apply_structure(parse, vectors[name], corrections.of(name), theta=thetas.get(name),
                                  centred=centreds.get(name), source=corrections.source, name=name, say=say)
            if corrections.sequences.get(name) else parse for name, parse in parses.items()}


def apply_database(nodes, structures, corrections, whole=True):
    """The database ``nodes`` (from :func:`tvmedit.engine.graph.database.build_database` on the corrected
    ``structures``) with forced representatives and dropped motions; ids renumbered 0, 1, ...
    in the same order, names kept. Where ``nodes`` are the ``whole`` library's, drops that
    leave none are refused.

    Returns
    -------
    list of tvmedit.engine.graph.database.Node
    """
    from ..graph.database import CYCLE

    nodes = list(nodes)
    for name, entry in corrections.sequences.items():
        textons = structures[name].textons if name in structures else []
        for frame in entry.representatives:
            texton = next(t for t in textons if t.start <= frame <= t.end)
            k = next(i for i, n in enumerate(nodes) if n.sequence == name and n.cluster == texton.cluster)
            nodes[k] = replace(nodes[k], start=texton.start, end=texton.end,
                               texton_distance=float(texton.distance), kind=CYCLE)
        for k, motion in enumerate(entry.drop):
            mine = [n.name for n in nodes if n.sequence == name]
            if motion not in mine:
                raise CorrectionError(f"{_entry(corrections.source, name, f'drop[{k}]')} = {motion!r} "
                                      f"names no motion of the corrected sequence; its motions are "
                                      f"{', '.join(mine) or 'none'}.")
            nodes = [n for n in nodes if n.name != motion]
    if whole and not nodes and any(entry.drop for entry in corrections.sequences.values()):
        raise CorrectionError(f"{corrections.source}: drop leaves the library no motion; keep at least one "
                              "(an edit needs two).")
    return [replace(n, id=k) for k, n in enumerate(nodes)]
