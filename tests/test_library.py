"""The library through the Python API: build, reopen, compare with the analysis in memory.

Inputs are the first frames of the real mocap take 13_30 (selected by glob), so a build
takes seconds; the feature cache always lives in a temporary ``XDG_CACHE_HOME``.
"""

import argparse
import json
import shutil

import networkx as nx
import numpy as np
import pytest

import tvmedit

from tvmedit import Library, LibraryError, UnknownMotion
from tvmedit.engine.store.inbetweens import loop_frames
from tvmedit.engine.capture.normals import vertex_normals
from tvmedit.engine.graph.database import build_database
from tvmedit.engine.errors import TvmError
from tvmedit.engine.features import BinSizes, FeatureAccumulator
from tvmedit.engine.graph.motiongraph import build_graph, nodes_of
from tvmedit.engine.capture.load import open_sequence, read_frame
from tvmedit.options import as_flags
from conftest import snippet_inputs as _inputs



# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


@pytest.fixture(scope="module")
def built(snippets_library):
    """The shared library of two sequences (conftest), by its path."""
    return snippets_library.path


def _in_memory(take):
    """The whole analysis in memory, the obvious way, to compare a library with."""
    from tvmedit.engine.parse.structure import StructureParams, parse

    sequences = [open_sequence(source, name=name) for name, source in _inputs(take)]
    features = {}
    for sequence in sequences:
        # The subject stays on its spot: the histograms about each frame's own centre too.
        acc = FeatureAccumulator(BinSizes(), centred=True)
        in_body_axes = sequence.orientation.for_features()   # features in the body's own frame
        for path in sequence.paths:
            acc.add(read_frame(path, in_body_axes).positions)
        features[sequence.name] = acc.result()
    width = max(f.r.shape[1] for f in features.values())
    vectors = {name: f.pad_r(width).vectors for name, f in features.items()}
    # As the builder does: with the azimuth columns, which tell a half period from a whole one,
    # and the centred rows, which the turn veto reads.
    structures = {s.name: parse(vectors[s.name], s.fps, StructureParams(),
                                theta=features[s.name].pad_r(width).theta_columns,
                                centred=features[s.name].centred) for s in sequences}
    graph = build_graph(build_database(structures), vectors)
    return sequences, features, vectors, structures, graph


def _plain(data):
    return json.loads(json.dumps(data))


def test_reopened_library_matches_the_analysis_in_memory(built, take_13_30):
    sequences, features, vectors, structures, graph = _in_memory(take_13_30)
    library = Library.open(built)

    assert [s.name for s in library.sequences] == ["gym", "gym2"]
    for sequence in sequences:
        stored = library.sequence(sequence.name)
        assert stored.frames == len(sequence.paths) == 60
        assert stored.fps == sequence.fps
        assert stored.paths == [str(p.resolve()) for p in sequence.paths]
        f = library.features(sequence.name)
        assert isinstance(f.r.base, np.memmap) or isinstance(f.r, np.memmap)
        np.testing.assert_array_equal(f.vectors, vectors[sequence.name])
        np.testing.assert_array_equal(f.centred.vectors, features[sequence.name].centred.vectors)
        np.testing.assert_array_equal(f.origin, features[sequence.name].origin)
        assert _plain(library.structure(sequence.name).to_json()) == _plain(structures[sequence.name].to_json())

    assert library.nodes == nodes_of(graph)
    # Transitions are made where the poses are nearest among eq. (10)'s near ties (the stored
    # frames' poses: tvmedit.engine.inbetween.pairs); the weights are eq. (12)'s as they were.
    from tvmedit.engine.store.inbetweens import join

    join(graph, nodes_of(graph), vectors, lambda keys: [library.frame_mesh(key)[:2] for key in keys],
         {s.name: s.fps for s in sequences})
    # The stored graph adds only how many in-between frames each transition has (tvmedit.engine.inbetween.blend).
    plain = [(i, j, {k: v for k, v in d.items() if k != "blend"}) for i, j, d in library.graph.edges(data=True)]
    assert sorted(plain) == sorted(graph.edges(data=True))
    assert library.graph.graph["unpruned"] == graph.graph["unpruned"]
    assert library.graph.graph["transitions"] == graph.graph["transitions"]

    # Exactly the texton frames of the database are stored, and the neighbouring repetitions'
    # frames their loops are closed onto (tvmedit.engine.inbetween.loops), each as it was read.
    by_name = {s.name: s for s in sequences}
    wanted = {(n.sequence, f) for n in library.nodes for f in range(n.start, n.end + 1)}
    rooms = {n.id: library.structure(n.sequence).clusters[n.cluster] for n in library.nodes}
    wanted |= loop_frames(library.graph, library.params["blend_frames"], rooms)
    assert set(library.stored_frames()) == wanted
    low, high = np.full(3, np.inf), np.full(3, -np.inf)
    most = [0, 0]
    for name, k in sorted(wanted):
        frame = read_frame(by_name[name].paths[k])
        positions, colours, faces, normals = library.frame_mesh((name, k))
        np.testing.assert_array_equal(positions, frame.positions)
        np.testing.assert_array_equal(colours, frame.colours)
        np.testing.assert_array_equal(faces, frame.faces)
        np.testing.assert_array_equal(normals, vertex_normals(frame.positions, frame.faces))
        assert (positions.dtype, colours.dtype, faces.dtype, normals.dtype) == (
            np.float32, np.uint8, np.uint32, np.float32)
        low, high = np.minimum(low, positions.min(0)), np.maximum(high, positions.max(0))
        most = [max(most[0], len(positions)), max(most[1], len(faces))]
    assert library.bounds() == (tuple(low.tolist()), tuple(high.tolist()))
    assert library.max_counts() == tuple(most)


def test_mesh_arrays_are_flat_memory_mapped_and_read_only_when_used(built):
    library = Library.open(built)
    assert "_arrays" not in library.__dict__  # opening reads no mesh array
    for name in ("positions", "colours", "normals", "faces", "frames", "frame_keys", "features"):
        array = np.load(built / f"{name}.npy", mmap_mode="r")
        assert isinstance(array, np.memmap)
    frames = np.load(built / "frames.npy")
    assert frames.shape == (len(library.stored_frames()), 4)
    blends = sum(run["count"] for run in library.blend_runs().values())
    blends += sum(wrap["count"] for wrap in library.blend_data().get("wraps", []))  # loop closings
    assert np.load(built / "blend_frames.npy").shape == (blends, 4)
    assert (frames[1:, 0] == frames[:-1, 0] + frames[:-1, 1]).all()
    positions = library.frame_mesh(library.stored_frames()[0])[0]
    assert isinstance(positions, np.memmap) and not positions.flags.writeable


def test_a_frame_outside_the_database_is_refused_in_one_sentence(built):
    library = Library.open(built)
    node = library.nodes[0]
    assert (node.sequence, node.start) in library.stored_frames()
    outside = next(f for f in range(60) if ("gym", f) not in library.stored_frames())
    with pytest.raises(LibraryError, match=f"frame {outside} of gym is not stored"):
        library.frame_mesh(("gym", outside))
    with pytest.raises(LibraryError, match="no sequence 'walk'; it has gym, gym2"):
        library.frame_mesh(("walk", 0))


def test_rename_by_id_or_name_persists_and_names_stay_unique(built, tmp_path):
    copy = tmp_path / "copy.lib"
    shutil.copytree(built, copy)
    library = Library.open(copy)
    first, second = library.nodes[0], library.nodes[1]
    assert library.rename(first.id, "swing").name == "swing"
    assert library.rename("swing", "swing arms").id == first.id
    assert library.node("swing arms") == library.nodes[0]
    assert library.graph.nodes[first.id]["name"] == "swing arms"
    with pytest.raises(TvmError, match="already taken"):
        library.rename(second.name, "swing arms")
    with pytest.raises(TvmError, match="non-digit"):
        library.rename(second.id, "12")
    with pytest.raises(UnknownMotion, match="no motion 'swing'"):
        library.node("swing")

    reopened = Library.open(copy)
    assert reopened.node(first.id).name == "swing arms"
    assert reopened.graph.nodes[first.id]["name"] == "swing arms"
    assert [n.name for n in reopened.nodes[1:]] == [n.name for n in library.nodes[1:]]
    exported = nx.read_graphml(copy / "graph.graphml", node_type=int)
    assert exported.nodes[first.id]["name"] == "swing arms"
    assert Library.open(built).nodes[0].name == first.name  # the original is untouched


def test_edit_plays_only_stored_frames(built):
    library = Library.open(built)
    edges = sorted(library.graph.edges)
    if not edges:
        pytest.skip("this small library's pruned graph has no edge")
    source, target = edges[0]
    edit = library.edit([source, target], loops=1)
    assert edit.library is library
    assert edit.schedule and all((e.sequence, e.frame) in library.stored_frames() for e in edit.schedule)


def test_vertex_normals_are_area_weighted_unit_vectors():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    # A big face in the xy plane and a small one in the xz plane share vertex 0.
    # Twice their areas: 1 along +z, 0.1 along -y.
    p[3, 2] = 0.1
    n = vertex_normals(p, np.array([[0, 1, 2], [0, 1, 3]]))
    np.testing.assert_allclose(n[0], np.array([0, -0.1, 1]) / np.sqrt(1.01), rtol=1e-6)
    np.testing.assert_allclose(n[2], [0, 0, 1])
    np.testing.assert_allclose(n[3], [0, -1, 0])


def test_a_sequence_folder_is_told_how_to_become_a_library(take_13_30, tmp_path, monkeypatch):
    from tvmedit.cli import main

    walk = tmp_path / "walk"
    walk.mkdir()
    for path in open_sequence(_inputs(take_13_30)[0][1]).paths[:40]:
        shutil.copy2(path, walk / path.name)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(LibraryError) as caught:
        Library.open("walk")
    assert str(caught.value).endswith("build a library from it with build(['walk'], 'walk.tvmlib').")
    message = as_flags(str(caught.value), argparse.ArgumentParser())  # what the command line says
    assert message.startswith("walk is a sequence folder (frame files, no manifest.json), not a library")
    assert message.endswith("build a library from it with `tvmedit build walk -o walk.tvmlib`.")
    suggested = message.split("`")[1].split()[1:]
    assert main([*suggested, "--workers", "1", "-q"]) == 0
    assert Library.open("walk.tvmlib").sequences[0].name == "walk"
    with pytest.raises(LibraryError, match="is not a tvmedit library .*give a library folder"):
        Library.open(tmp_path / "xdg")


@pytest.mark.parametrize("call, says", [
    (lambda lib: type(lib).open(123), "opened from its folder's path"),
    (lambda lib: lib.edit(None), "at least two key motions"),
    (lambda lib: lib.graph_at(mu=-1), "mu=-1 is out of range"),
    (lambda lib: tvmedit.build("walk", "walk.tvmlib"), "should be a list of sequence folders"),
    (lambda lib: tvmedit.build([("walk", 5)], "walk.tvmlib"), "is not a sequence folder or a (name, folder) pair"),
])
def test_the_python_api_answers_wrong_types_in_one_sentence(small_library, call, says):
    # Read one character at a time, build("walk") looked for folders "w", "a", "l", "k".
    with pytest.raises(tvmedit.TvmError) as caught:
        call(Library.open(small_library))
    assert says in str(caught.value) and "\n" not in str(caught.value)
