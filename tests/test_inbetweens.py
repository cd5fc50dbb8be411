"""The in-between frames of a library (tvmedit.engine.store.inbetweens): made, stored, reused.

Libraries are built from the first frames of the real mocap take 13_30; every run points
``XDG_CACHE_HOME`` at a temporary folder, so no test reads or fills the user's feature cache.
"""

import pytest

from tvmedit import build
from tvmedit.engine.store.inbetweens import loop_frames
from tvmedit.engine.store.rebuild import rebuild
from conftest import snippet_inputs as _inputs



# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


@pytest.fixture(scope="module")
def built(snippets_library):
    """The shared library of two sequences (conftest)."""
    return snippets_library


def test_every_transition_gets_frames_in_steps_smaller_than_its_cut(built):
    runs = built.blend_runs()
    assert set(runs) == set(built.graph.edges) and runs
    for run in runs.values():
        assert run["count"] > 0 and len(run["steps"]) == run["count"] + 1
        assert max(run["steps"]) < run["jump"]
    assert built.natural_step > 0


@pytest.mark.parametrize("count", [0, 3])
def test_a_given_blend_count_gives_every_transition_that_many(take_13_30, tmp_path, count):
    # (no display-rate in-betweens: the transitions' frames are what is counted)
    library = build(_inputs(take_13_30), tmp_path / "lib", workers=1, cache=False, blend_frames=count, smooth=False)
    assert library.params["blend_frames"] == count
    assert {run["count"] for run in library.blend_runs().values()} == {count}


def test_the_frames_loops_are_closed_onto_are_stored(built):
    rooms = {n.id: built.structure(n.sequence).clusters[n.cluster] for n in built.nodes}
    frames = loop_frames(built.graph, built.params["blend_frames"], rooms)
    assert frames <= set(built.stored_frames())


def test_a_rebuild_copies_every_run_that_comes_out_the_same(built, tmp_path):
    report = rebuild(built, tmp_path / "again.lib")
    assert report["blend_made"] == 0
    for name in ("blend_positions.npy", "blend_faces.npy", "blend_frames.npy"):
        assert (tmp_path / "again.lib" / name).read_bytes() == (built.path / name).read_bytes()
