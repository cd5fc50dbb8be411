"""The library through the Python API: build, reopen, compare with the analysis in memory.

Inputs are the first frames of the real mocap take 13_30 (selected by glob), so a build
takes seconds; the feature cache always lives in a temporary ``XDG_CACHE_HOME``.
"""

import argparse
import json
import os
import shutil
import sys

import networkx as nx
import numpy as np
import pytest

from tvmedit import Library, LibraryError, UnknownMotion, build
from tvmedit.engine.store.inbetweens import loop_frames
from tvmedit.engine.store.builder import expand_inputs
from tvmedit.engine.store.featurecache import cache_dir
from tvmedit.engine.capture.normals import vertex_normals
from tvmedit.engine.graph.database import build_database
from tvmedit.engine.errors import InputError, OutputError, ParameterError, TvmError
from tvmedit.engine.features import BinSizes, FeatureAccumulator
from tvmedit.engine.graph.motiongraph import build_graph, nodes_of
from tvmedit.engine.capture.load import open_sequence, read_frame
from tvmedit.engine.store.parallel import Workers
from tvmedit.options import as_flags


def _inputs(take):
    """Two sequences cut from one take: frames 0-59 and 100-159."""
    return [("gym", str(take / "frame_000[0-5]?.ply")), ("gym2", str(take / "frame_001[0-5]?.ply"))]


# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")


@pytest.fixture(autouse=True)
def _cache_home(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))


@pytest.fixture(scope="module")
def built(take_13_30, tmp_path_factory):
    """A library of two sequences, built serially without the cache."""
    out = tmp_path_factory.mktemp("lib") / "gym.lib"
    build(_inputs(take_13_30), out, workers=1, cache=False)
    return out


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


def test_centred_rows_of_sequences_that_stay_stand_beside_one_that_strays(take_13_30, tmp_path):
    # Three sequences, the middle one moving 3 cm a frame (its origin follows: no centred
    # rows). Each keeps its own rows and r width whatever its neighbours, and parses as the
    # library says; a library from before centred features (no features_centred.npy) opens and parses.
    import trimesh

    from tvmedit.engine.parse.structure import StructureParams, parse

    stray = tmp_path / "stray"
    stray.mkdir()
    for k, path in enumerate(sorted(take_13_30.glob("frame_000[0-5]?.ply"))):
        mesh = trimesh.load(path, process=False)
        mesh.vertices = mesh.vertices + np.array([0.03 * k, 0.0, 0.0])
        mesh.export(stray / path.name)
    (a, first), (b, second) = _inputs(take_13_30)
    library = build([(a, first), ("stray", str(stray)), (b, second)], tmp_path / "three.lib", workers=2, cache=False)
    alone = build([(b, second)], tmp_path / "alone.lib", workers=2, cache=False)
    records = {r["name"]: r for r in library.manifest["sequences"]}
    assert "centred_rows" not in records["stray"] and library.features("stray").centred is None
    assert records[a]["centred_rows"] == [0, 60] and records[b]["centred_rows"] == [60, 120]
    np.testing.assert_array_equal(library.features(b).centred.vectors, alone.features(b).centred.vectors)
    for name in (a, "stray", b):
        f = library.features(name)
        params = StructureParams.recorded(library.parse(name).params)
        again = parse(f.vectors, library.sequence(name).fps, params, theta=f.theta_columns, centred=f.centred)
        assert again.clusters == library.parse(name).clusters
    old = tmp_path / "old.lib"
    shutil.copytree(tmp_path / "three.lib", old)
    (old / "features_centred.npy").unlink()
    manifest = json.loads((old / "manifest.json").read_text())
    del manifest["files"]["features_centred.npy"]
    for record in manifest["sequences"]:
        record.pop("centred_rows", None)
        record.pop("centred_r_bins", None)
    (old / "manifest.json").write_text(json.dumps(manifest))
    opened = Library.open(old)
    assert opened.features(b).centred is None
    np.testing.assert_array_equal(opened.features(b).vectors, library.features(b).vectors)
    assert opened.structure(b).clusters == library.structure(b).clusters


def test_graphml_loads_back_with_the_same_edges(built):
    library = Library.open(built)
    exported = nx.read_graphml(built / "graph.graphml", node_type=int)
    assert sorted(exported.edges) == sorted(library.graph.edges)
    for i, j, data in library.graph.edges(data=True):
        assert exported.edges[i, j]["weight"] == pytest.approx(data["weight"])
        assert exported.edges[i, j]["exit_frame"] == data["exit_frame"]
    assert {i: d["name"] for i, d in exported.nodes(data=True)} == {n.id: n.name for n in library.nodes}


def test_mesh_arrays_are_flat_memory_mapped_and_read_only_when_used(built):
    library = Library.open(built)
    assert "_arrays" not in library.__dict__  # opening reads no mesh array
    for name in ("positions", "colours", "normals", "faces", "frames", "frame_keys", "features"):
        array = np.load(built / f"{name}.npy", mmap_mode="r")
        assert isinstance(array, np.memmap)
    frames = np.load(built / "frames.npy")
    assert frames.shape == (len(library.stored_frames()), 4)
    blends = sum(run["count"] for run in library.blend_runs().values())
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


def test_truncated_missing_or_foreign_files_are_named_with_the_rebuild(built, tmp_path):
    copy = tmp_path / "copy.lib"
    shutil.copytree(built, copy)
    with open(copy / "positions.npy", "r+b") as handle:
        handle.truncate(1000)
    with pytest.raises(LibraryError, match=r"positions.npy has 1000 bytes .*\(truncated .* force=True"):
        Library.open(copy)
    with pytest.raises(ValueError):  # what a reader without the size check would meet
        np.load(copy / "positions.npy", mmap_mode="r")

    shutil.rmtree(copy)
    shutil.copytree(built, copy)
    (copy / "faces.npy").unlink()
    with pytest.raises(LibraryError, match="incomplete: faces.npy is missing; rebuild it with"):
        Library.open(copy)

    shutil.rmtree(copy)
    shutil.copytree(built, copy)
    manifest = json.loads((copy / "manifest.json").read_text())
    manifest["format"] = 0
    (copy / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(LibraryError, match=r"format version 0 but this tvmedit reads version 2; "
                                           r"rebuild it with build\(inputs, '.*', force=True\)"):
        Library.open(copy)

    with pytest.raises(LibraryError, match="no library at"):
        Library.open(tmp_path / "nothing")


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


def test_rebuild_with_other_parameters_reuses_cached_features(take_13_30, tmp_path):
    out, messages = tmp_path / "lib", []
    first = build(_inputs(take_13_30)[:1], out, workers=1)
    assert first.report["reused"] == {}
    assert list((cache_dir() / "features").glob("*.npz"))

    first.rename(first.nodes[0].id, "warm-up")
    second = build(_inputs(take_13_30)[:1], out, workers=1, mu=2.0, force=True, log=messages.append)
    assert second.report["reused"] == {"gym": "library"}
    assert any("features of gym: reused" in m for m in messages)
    # Only the pruning changed, so the renamed texton is still a motion and keeps its name.
    assert second.nodes[0].name == "warm-up" and second.graph.nodes[0]["name"] == "warm-up"
    assert "kept 1 motion name(s) given in the library being replaced" in messages
    np.testing.assert_array_equal(second.features("gym").vectors, first.features("gym").vectors)
    assert second.mu == 2.0 and second.graph.number_of_edges() >= first.graph.number_of_edges()

    elsewhere = build(_inputs(take_13_30)[:1], tmp_path / "other", workers=1)
    assert elsewhere.report["reused"] == {"gym": "cache"}

    coarse = build(_inputs(take_13_30)[:1], out, workers=1, bins=BinSizes(r=0.04), force=True)
    assert coarse.report["reused"] == {}

    frames = tmp_path / "frames"
    frames.mkdir()
    for path in open_sequence(_inputs(take_13_30)[0][1]).paths:
        shutil.copy2(path, frames / path.name)
    build([("gym", frames)], tmp_path / "copied", workers=1)
    touched = sorted(frames.iterdir())[5]
    os.utime(touched, ns=(touched.stat().st_atime_ns, touched.stat().st_mtime_ns + 10**9))
    again = build([("gym", frames)], tmp_path / "copied", workers=1, force=True)
    assert again.report["reused"] == {}


def test_existing_libraries_and_other_folders_are_not_overwritten(built, tmp_path, take_13_30):
    with pytest.raises(OutputError, match="already exists; pass force=True to replace it"):
        build(_inputs(take_13_30), built, workers=1)
    folder = tmp_path / "photos"
    folder.mkdir()
    (folder / "holiday.jpg").write_bytes(b"...")
    with pytest.raises(OutputError, match="exists and is not a tvmedit library"):
        build(_inputs(take_13_30), folder, workers=1, force=True)
    assert (folder / "holiday.jpg").exists()


def test_bad_frames_stop_the_build_or_are_skipped_and_recorded(take_13_30, tmp_path):
    frames = tmp_path / "frames"
    frames.mkdir()
    for path in open_sequence(_inputs(take_13_30)[0][1]).paths[:40]:
        shutil.copy2(path, frames / path.name)
    bad = sorted(frames.iterdir())[7]
    bad.write_bytes(bad.read_bytes()[:5000])
    with pytest.raises(InputError, match=f"frame {bad} is not a readable mesh"):
        build([frames], tmp_path / "lib", workers=1)
    assert not (tmp_path / "lib").exists() and not list(tmp_path.glob(".lib.tmp-*"))

    library = build([frames], tmp_path / "lib", workers=1, skip_bad_frames=True)
    assert library.sequences[0].frames == 39
    skipped = library.manifest["sequences"][0]["skipped"]
    assert [os.path.basename(path) for path, _ in skipped] == [bad.name]


def test_inputs_name_sequences_and_duplicate_names_are_refused(take_13_30, tmp_path):
    for name in ("a", "b"):
        (tmp_path / "takes" / name).mkdir(parents=True)
    assert [os.path.basename(s) for _, s in expand_inputs([str(tmp_path / "takes" / "*")])] == ["a", "b"]
    with pytest.raises(InputError, match="both named 'gym'"):
        build([("gym", _inputs(take_13_30)[0][1]), ("gym", _inputs(take_13_30)[1][1])],
              tmp_path / "lib", workers=1)


def test_vertex_normals_are_area_weighted_unit_vectors():
    p = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    # A big face in the xy plane and a small one in the xz plane share vertex 0.
    # Twice their areas: 1 along +z, 0.1 along -y.
    p[3, 2] = 0.1
    n = vertex_normals(p, np.array([[0, 1, 2], [0, 1, 3]]))
    np.testing.assert_allclose(n[0], np.array([0, -0.1, 1]) / np.sqrt(1.01), rtol=1e-6)
    np.testing.assert_allclose(n[2], [0, 0, 1])
    np.testing.assert_allclose(n[3], [0, -1, 0])


def test_dask_missing_is_one_sentence(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(TvmError, match=r"pip install 'tvmedit\[dask\]'"):
        with Workers(2, dask="local") as pool:
            list(pool.map(abs, [1]))


@pytest.mark.parametrize("address", ["nonsense", "tcp://host:port", "ftp://host:8786"])
def test_a_malformed_dask_address_is_one_sentence(address):
    pytest.importorskip("distributed")
    with pytest.raises(TvmError, match=f"dask={address} is not a scheduler address .*; give one "
                                       r"such as tcp://host:8786, or local to start one here\.$"):
        with Workers(2, dask=address) as pool:
            list(pool.map(abs, [1]))


def test_a_synthetic_walk_builds_into_a_library_named_after_its_folder(synth_walk, tmp_path):
    library = build([synth_walk], tmp_path / "walk.lib", workers=2, cache=False)
    assert [s.name for s in library.sequences] == [synth_walk.name]
    assert library.sequences[0].structure.clusters[0][0] == 0
    assert library.nodes, "a walk of nine cycles gives at least one motion"
    node = library.nodes[0]
    for frame in range(node.start, node.end + 1):
        positions, colours, faces, normals = library.frame_mesh((node.sequence, frame))
        assert len(positions) > 10000 and faces.max() < len(positions)
        lengths = np.linalg.norm(normals, axis=1)
        assert np.mean(np.abs(lengths - 1) < 1e-5) > 0.999  # closed surfaces: every vertex has a normal
    (low, high) = library.bounds()
    assert 1.5 < high[2] - low[2] < 2.0  # the actor is about 1.70 m tall


def test_force_replaces_only_a_tvmedit_library(built, tmp_path, take_13_30, monkeypatch):
    folder = tmp_path / "webapp"
    folder.mkdir()
    (folder / "manifest.json").write_text(json.dumps({"name": "my web app", "icons": []}))
    (folder / "index.html").write_text("<p>hello</p>")
    with pytest.raises(OutputError, match="exists and is not a tvmedit library"):
        build(_inputs(take_13_30), folder, workers=1, force=True)
    assert (folder / "index.html").exists() and json.loads((folder / "manifest.json").read_text())["icons"] == []

    copy = tmp_path / "copy.lib"
    shutil.copytree(built, copy)
    monkeypatch.chdir(copy)
    with pytest.raises(OutputError, match="is the current folder or holds it"):
        build(_inputs(take_13_30), ".", workers=1, force=True)
    (copy / "sub").mkdir()
    monkeypatch.chdir(copy / "sub")
    with pytest.raises(OutputError, match="is the current folder or holds it"):
        build(_inputs(take_13_30), copy, workers=1, force=True)
    assert Library.open(copy).manifest == Library.open(built).manifest


@pytest.mark.parametrize("mu", [float("inf"), float("nan"), -1.0, 0.0, "abc"])
def test_mu_must_be_finite_and_positive(take_13_30, tmp_path, mu):
    with pytest.raises(ParameterError, match=r"mu=.* is out of range: it must be a finite number above 0 \(the default is 0.9\)\.$"):
        build(_inputs(take_13_30), tmp_path / "lib", workers=1, mu=mu)
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("names, words", [
    ([1, 2], r"must hold a JSON object of motion names such as \{\"3\": \"squats\"\}, not \[1, 2\]"),
    ({"0": 7}, r"maps '0' to 7, but it must map motion ids to names"),
    ({"first": "walk"}, r"maps 'first' to 'walk'"),
    ({"0": "12"}, r"maps '0' to '12'"),
    ({"0": "same", "1": "same"}, r"gives motions 0 and 1 the same name 'same'"),
])
def test_a_hand_edited_names_json_is_checked(built, tmp_path, names, words):
    copy = tmp_path / "copy.lib"
    shutil.copytree(built, copy)
    (copy / "names.json").write_text(json.dumps(names))
    with pytest.raises(LibraryError, match=f"names.json {words}.*; fix it or delete it"):
        Library.open(copy)


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
