"""The meshes a library stores: which frames, and whether they are linked, grown, copied or read.

Only the frames of database motions can ever be played, so by default only they are stored,
with the few frames of the neighbouring repetitions their loops are closed onto
(:mod:`tvmedit.engine.inbetween.loops`), or every frame with ``keep_frames="all"``
(:class:`tvmedit.engine.store.arrays.MeshWriter` writes the flat arrays). Which ones is known only
after the database is made, and reading them is what a build costs after the features, so
a build or a rebuild takes them from the library being replaced wherever it can:

* every frame needed is stored there already, under the same sequence, and it stores at
  most :data:`SPARE_SHARE` more: its arrays are kept as they are (hard links), in no time;
* every frame it stores is of a sequence kept at the same index, it stores at most
  :data:`SPARE_SHARE` more than needed, and it and the frames it lacks are untextured (a
  correction that adds motions or moves their frames): its arrays are kept as they are, and
  the frames it lacks are read and stored beside them, in a part of their own (``part1_positions.npy`` ...,
  :func:`tvmedit.engine.store.arrays.parts`, at most :data:`MAX_PARTS`): nothing stored is
  written again, however large the library;
* otherwise the stored frames are copied from it (byte for byte, in runs of consecutive
  frames) and only the others are read from their files (:func:`tvmedit.engine.capture.load.read_frame`) on
  the workers, with their vertex normals, and come back through spool files (:func:`_spools`).

``run.read_frames`` then says how many frame files were read.
"""

import contextlib
import os
import shutil
import time

import numpy as np

from . import arrays, layout
from ..errors import InputError
from ..capture.load import read_frame
from ..capture.normals import vertex_normals

__all__ = ["reusable", "write", "MESH_CHUNK", "SPARE_SHARE"]

#: Frames per mesh task; each frame is about 1 MB on its way back, so chunks stay small.
MESH_CHUNK = 4
#: Frames a library may store besides those of its motions, as a share of them, when its
#: meshes are kept as they are by a rebuild rather than copied: a correction that drops a
#: motion keeps its frames (disk) rather than copying all others (time), up to twice the size.
SPARE_SHARE = 1.0
#: Parts a library's stored frames may lie in (each rebuild that adds frames adds one); the
#: rebuild after that writes them all anew, in one.
MAX_PARTS = 8


def _mesh_task(task):
    """Meshes of a chunk ``(paths, spool)`` of ``(path, orientation)`` with their normals and
    textures: ``(meshes, read_s, compute_s)``; with a ``spool`` path, each mesh is an
    :class:`tvmedit.engine.store.arrays.Spooled` in that file instead of its arrays."""
    paths, spool = task
    meshes, read_s, compute_s = [], 0.0, 0.0
    for path, orientation in paths:
        t0 = time.perf_counter()
        frame = read_frame(path, orientation)
        t1 = time.perf_counter()
        normals = vertex_normals(frame.positions, frame.faces)
        meshes.append((frame.positions, frame.colours, frame.faces, normals, frame.uv, frame.texture))
        read_s += t1 - t0
        compute_s += time.perf_counter() - t1
    if spool is not None:
        t1 = time.perf_counter()
        meshes = arrays.spool(spool, meshes)
        compute_s += time.perf_counter() - t1
    return meshes, read_s, compute_s


def _read_tasks(items, spools=None):
    """Worker tasks of :data:`MESH_CHUNK` frames ``(sequence index, frame, path, orientation)``
    each, for :func:`_mesh_task`, each spooled to a file of folder ``spools`` where given."""
    return (([(path, orientation) for _, _, path, orientation in items[i:i + MESH_CHUNK]],
             None if spools is None else os.path.join(spools, str(i)))
            for i in range(0, len(items), MESH_CHUNK))


@contextlib.contextmanager
def _spools(tmp, pool):
    """A folder of its own in ``tmp`` that worker processes spool the meshes they read to (None
    where the tasks run in this process, on threads or on a cluster, which may not see
    ``tmp``); on the way out it is removed with every spool folder left in ``tmp``.

    A frame handed back from a worker process is pickled there and unpickled here, about
    1 ms for 17,000 vertices, a third of storing it; a spooled frame's arrays go from the
    worker's file to the library's by ``os.copy_file_range``, in the kernel. With the faster
    normals of the same change, the meshes stage of the 60 fps 13_29 (967 frames stored, two
    workers) fell from 3.0 s to 1.5-1.6 s, the library byte for byte the same.

    Each use has a folder of its own: where growing a library stops at a textured frame
    (:class:`_Textured`), the tasks it had sent still run and write into theirs, not into the
    files the rewrite that follows copies from; the rewrite's own removal, after the workers
    ran everything sent before its tasks, takes their folder too."""
    import tempfile

    if pool.kind != "processes":
        yield None
        return
    folder = tempfile.mkdtemp(prefix=".spool-", dir=tmp)
    try:
        yield folder
    finally:
        for name in os.listdir(tmp):
            if name.startswith(".spool-"):
                shutil.rmtree(os.path.join(tmp, name), ignore_errors=True)


def _store(writer, seq_index, frame, mesh):
    """Append ``mesh`` (its arrays, or :class:`tvmedit.engine.store.arrays.Spooled`) to ``writer``."""
    if isinstance(mesh, arrays.Spooled):
        writer.add_spooled(seq_index, frame, mesh)
    else:
        writer.add(seq_index, frame, *mesh)


def _drop(meshes):
    """Remove the spool file of a chunk of ``meshes`` once they are stored (none if not spooled)."""
    if meshes and isinstance(meshes[0], arrays.Spooled):
        os.unlink(meshes[0].path)


def _textured(mesh):
    """Whether ``mesh`` (its arrays, or :class:`tvmedit.engine.store.arrays.Spooled`) has a texture."""
    return (mesh.uv if isinstance(mesh, arrays.Spooled) else mesh[4]) is not None


def reusable(old, computed):
    """``{(sequence index, frame): (old name, frame)}`` for every frame the library ``old`` stores
    from the same frame files (the same feature key) as ``computed[index]``."""
    if old is None:
        return {}
    names = {record.get("feature_key"): record["name"] for record in old.manifest["sequences"]}
    index = {names[entry.key]: s for s, entry in enumerate(computed) if entry.key in names}
    return {(index[name], frame): (name, frame) for name, frame in old.stored_frames() if name in index}


def _linkable(old, keys, stored):
    """Whether ``old``'s arrays can be kept as they are for the frames ``keys``."""
    return (old is not None and len(stored) == len(old.stored_frames())
            and all(k[0] < len(old.sequences) and stored.get(k) == (old.sequences[k[0]].name, k[1]) for k in keys)
            and len(stored) <= (1 + SPARE_SHARE) * len(keys))


def _next_read(results, missing):
    """The next chunk of frames read; a frame that cannot be read says why it was needed."""
    with _named_reads(missing):
        return next(results)


@contextlib.contextmanager
def _named_reads(missing):
    """A frame that cannot be read says why it was needed: one of ``missing`` frames a library
    did not store before."""
    try:
        yield
    except InputError as error:
        raise InputError(f"{str(error).rstrip('.')}; the library needs {missing} frame(s) it did not "
                         "store before (of motions that changed, or that their loops are closed onto), "
                         "so put the sequence's frame files back where it was built from.") from None


def _growable(old, keys, stored, missing):
    """Whether ``old``'s arrays can be kept as they are, the ``missing`` frames added beside
    them in a part of their own (:func:`tvmedit.engine.store.arrays.parts`): each frame it
    stores is stored by the new library under the same sequence index; it is untextured (a
    part holds no texels); it stores at most :data:`SPARE_SHARE` more frames than the new
    library needs; it has fewer than :data:`MAX_PARTS` parts."""
    if old is None or old.textured or not missing or len(arrays.parts(old.path)) >= MAX_PARTS:
        return False
    names = [seq.name for seq in old.sequences]
    mine = [(names.index(name), frame) for name, frame in old.stored_frames()]
    return (all(stored.get(key) == (names[key[0]], key[1]) for key in mine)
            and len(mine) + len(missing) <= (1 + SPARE_SHARE) * len(keys))


class _Textured(Exception):
    """A frame to add beside a library's arrays has a texture, which a part cannot hold."""


def _grown(tmp, old, missing, pool, run, bar):
    """``old``'s meshes linked into ``tmp`` and the ``missing`` frames read on ``pool`` into a
    part of their own: what a build's :class:`tvmedit.engine.store.arrays.MeshWriter` tells.
    Raises :class:`_Textured`, before it writes that frame, where one has a texture."""
    from types import SimpleNamespace

    kept = layout.link_meshes(old, tmp)
    items = iter(missing)
    with _spools(tmp, pool) as spools, \
            arrays.MeshWriter(tmp, prefix=f"part{len(arrays.parts(old.path))}_") as writer:
        tasks = _read_tasks(missing, spools)
        for meshes, read_s, compute_s in pool.map(_mesh_task, tasks, window=2 * pool.workers + 2):
            run.add_times(read_s, compute_s)
            for mesh in meshes:
                if _textured(mesh):
                    raise _Textured
                seq_index, frame, _, _ = next(items)
                _store(writer, seq_index, frame, mesh)
                bar.update()
            _drop(meshes)
    return SimpleNamespace(frames=kept.frames + writer.frames,
                           bounds=[np.minimum(kept.bounds[0], writer.bounds[0]).tolist(),
                                   np.maximum(kept.bounds[1], writer.bounds[1]).tolist()],
                           max_counts=np.maximum(kept.max_counts, writer.max_counts).tolist())


def _growing(tmp, old, needed, stored, missing, pool, run):
    """:func:`_grown` where :func:`_growable`, else None; None too, its files gone from
    ``tmp`` (unlinked: the links are the old library's own files), where a frame to add has a
    texture, for every frame to be stored anew."""
    import os

    if not _growable(old, [item[:2] for item in needed], stored, missing):
        return None
    bar = run.bar(len(missing), "meshes")
    try:
        with _named_reads(len(missing)):
            return _grown(tmp, old, missing, pool, run, bar)
    except _Textured:
        for name in os.listdir(tmp):
            if layout.mesh_file(name):
                os.unlink(os.path.join(tmp, name))
        return None
    finally:
        bar.close()


def write(tmp, needed, pool, run, old=None, stored=None):
    """Store the ``needed`` frames ``(sequence index, frame, path, orientation)`` in the library
    folder ``tmp``: linked or copied from ``old`` where ``stored`` (:func:`reusable`) has them,
    else read on ``pool``; where ``old``'s can all be kept, the others are added beside them
    (:func:`_growable`), nothing stored rewritten. Returns the
    :class:`tvmedit.engine.store.arrays.MeshWriter` (or what tells the same)."""
    stored = stored or {}
    run.read_frames = 0
    if _linkable(old, [item[:2] for item in needed], stored):
        return layout.link_meshes(old, tmp)
    missing = [item for item in needed if item[:2] not in stored]
    grown = _growing(tmp, old, needed, stored, missing, pool, run)
    if grown is not None:
        run.read_frames = len(missing)
        return grown
    bar = run.bar(len(needed), "meshes")
    read = iter(())
    if stored and not run.old_whole:  # frames taken from old's arrays: their bytes as written, or nothing
        old.verify(layout.MESH_FILES)   # (a build has verified the whole of it already: not read twice)
    # Untextured stored frames are copied in runs of consecutive rows, byte for byte.
    rows = {key: r for r, key in enumerate(old.stored_frames())} if old is not None and not old.textured else {}
    firsts = {first for _, first, _ in arrays.part_rows(old.path)} if rows else set()   # a copied run lies in one part
    pending = []

    def flush():
        if pending:
            writer.copy_frames(old, [r for r, _ in pending], [k for _, k in pending])
            pending.clear()

    try:
        with _spools(tmp, pool) as spools, arrays.MeshWriter(tmp) as writer:
            results = pool.map(_mesh_task, _read_tasks(missing, spools), window=2 * pool.workers + 2)
            meshes = []
            for seq_index, frame, _, _ in needed:
                key = stored.get((seq_index, frame))
                if key in rows:
                    if pending and (pending[-1][0] != rows[key] - 1 or rows[key] in firsts):
                        flush()
                    pending.append((rows[key], (seq_index, frame)))
                elif key is not None:
                    flush()
                    texture = old.frame_texture(key)
                    writer.add(seq_index, frame, *old.frame_mesh(key), *(texture or (None, None)))
                else:
                    flush()
                    mesh = next(read, None)
                    if mesh is None:
                        _drop(meshes)
                        meshes, read_s, compute_s = _next_read(results, len(missing))
                        run.add_times(read_s, compute_s)
                        read = iter(meshes)
                        mesh = next(read)
                    _store(writer, seq_index, frame, mesh)
                bar.update()
            flush()
    finally:
        bar.close()
    run.read_frames = len(missing)
    return writer
