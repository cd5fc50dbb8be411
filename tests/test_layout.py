"""The library's on-disk format (tvmedit.engine.store.layout): written once, read back, checked.

Libraries are built from the first frames of the real mocap take 13_30; every run points
``XDG_CACHE_HOME`` at a temporary folder, so no test reads or fills the user's feature cache.
"""

import dataclasses
import json
import shutil

import networkx as nx
import numpy as np
import pytest

from tvmedit import Library, LibraryError, build
from tvmedit.engine.store import layout
from conftest import snippet_inputs as _inputs



# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


@pytest.fixture(scope="module")
def built(snippets_library):
    """The shared library of two sequences (conftest), by its path."""
    return snippets_library.path


@dataclasses.dataclass
class _Point:
    x: int
    y: float


def test_json_files_hold_numpy_values_tuples_and_dataclasses(tmp_path):
    data = {"n": np.int64(3), "w": np.float32(0.5), "a": np.arange(3), "t": (1, 2), "p": _Point(1, 2.0)}
    layout.write_json(tmp_path / "x.json", data)
    assert (tmp_path / "x.json").read_text() == '{"n":3,"w":0.5,"a":[0,1,2],"t":[1,2],"p":{"x":1,"y":2.0}}'
    assert layout.read_json(tmp_path, "x.json")["p"] == {"x": 1, "y": 2.0}
    with pytest.raises(TypeError, match="cannot store set in JSON"):
        layout.write_json(tmp_path / "y.json", {"s": {1}})


def test_a_json_file_that_is_not_json_names_the_library_and_the_rebuild(tmp_path):
    (tmp_path / "graph.json").write_text("{not json")
    with pytest.raises(LibraryError, match=r"cannot be read \(JSONDecodeError: .*rebuild it with"):
        layout.read_graph(tmp_path)


def test_the_manifest_records_the_size_of_every_checked_file(tmp_path):
    (tmp_path / "features.npy").write_bytes(b"x" * 7)
    (tmp_path / "holiday.jpg").write_bytes(b"y" * 3)
    layout.write_manifest(tmp_path, {"format": layout.FORMAT})
    assert layout.read_manifest(tmp_path)["files"] == {"features.npy": 7}
    (tmp_path / "features.npy").write_bytes(b"x" * 6)
    with pytest.raises(LibraryError, match="features.npy has 6 bytes where 7 were written"):
        layout.read_manifest(tmp_path)


def test_a_folder_left_by_an_interrupted_build_is_named(tmp_path):
    (tmp_path / ".gym.lib.old-1234").mkdir()
    with pytest.raises(LibraryError, match=r"an interrupted build left the previous one at .*gym.lib.old-1234; "
                                           r"rename it back to gym.lib\.$"):
        layout.read_manifest(tmp_path / "gym.lib")


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
    library = build([(a, first), ("stray", str(stray)), (b, second)], tmp_path / "three.lib", workers=2,
                    cache=False, blend_frames=0, smooth=False)
    alone = build([(b, second)], tmp_path / "alone.lib", workers=2, cache=False, blend_frames=0, smooth=False)
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


@pytest.mark.parametrize("names, words", [
    ([1, 2], r"must hold a JSON object of motion names such as \{\"3\": \"squats\"\}, not \[1, 2\]"),
    ({"0": 7}, r"maps '0' to 7, but it must map motion ids to one-line names"),
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
