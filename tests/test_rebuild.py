"""Deriving a library again (tvmedit.engine.store.rebuild): from what it stores, no frame read.

Libraries are built from the first frames of the real mocap take 13_30; every run points
``XDG_CACHE_HOME`` at a temporary folder, so no test reads or fills the user's feature cache.
"""

import json

import numpy as np
import pytest

from tvmedit.engine.errors import OutputError
from tvmedit.engine.store.rebuild import rebuild



# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


@pytest.fixture(scope="module")
def built(snippets_library):
    """The shared library of two sequences (conftest)."""
    return snippets_library


def _edges(library):
    return sorted(library.graph.edges(data="weight"))


def test_a_rebuild_without_corrections_gives_the_same_library(built, tmp_path):
    again = tmp_path / "again.lib"
    report = rebuild(built, again)
    assert report["read_frames"] == 0 and report["corrected"] == []
    opened = type(built).open(again)
    assert opened.nodes == built.nodes and _edges(opened) == _edges(built)
    assert opened.stored_frames() == built.stored_frames() and opened.params == built.params
    for sequence in built.sequences:
        np.testing.assert_array_equal(opened.features(sequence.name).vectors, built.features(sequence.name).vectors)
        assert opened.structure(sequence.name).to_json() == built.structure(sequence.name).to_json()
    assert json.loads((again / "blends.json").read_text()) == built.blend_data()


def test_a_rebuild_with_another_mu_prunes_the_graph_anew(built, tmp_path):
    rebuild(built, tmp_path / "mu.lib", mu=2.0)
    opened = type(built).open(tmp_path / "mu.lib")
    assert opened.mu == 2.0 and built.mu == 0.9
    assert set(built.graph.edges) <= set(opened.graph.edges)


def test_a_rebuild_over_another_existing_folder_needs_force(built, tmp_path):
    rebuild(built, tmp_path / "copy.lib")
    with pytest.raises(OutputError, match="already exists; pass force=True to replace it"):
        rebuild(built, tmp_path / "copy.lib")
    rebuild(built, tmp_path / "copy.lib", force=True)
