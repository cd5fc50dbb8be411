"""The meshes a library stores (tvmedit.engine.store.meshfiles): kept, copied or read.

Libraries are built from the first frames of the real mocap take 13_30; every run points
``XDG_CACHE_HOME`` at a temporary folder, so no test reads or fills the user's feature cache.
"""

import os
import shutil

import numpy as np
import pytest

from tvmedit import Library, build
from tvmedit.engine.capture.load import open_sequence, read_frame
from tvmedit.engine.store import meshfiles
from tvmedit.engine.store.rebuild import rebuild
from conftest import snippet_inputs as _inputs



# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


@pytest.fixture(scope="module")
def built(snippets_library):
    """The shared library of two sequences (conftest)."""
    return snippets_library


def test_nothing_is_reusable_without_a_library_being_replaced():
    assert meshfiles.reusable(None, []) == {}


def test_a_rebuild_needing_no_new_frame_keeps_the_arrays_as_they_are(built, tmp_path):
    rebuild(built, tmp_path / "again.lib")
    for name in ("positions.npy", "colours.npy", "normals.npy", "faces.npy", "frames.npy", "frame_keys.npy"):
        assert os.path.samefile(built.path / name, tmp_path / "again.lib" / name), name


def test_frames_the_replaced_library_stores_are_copied_others_read(built, take_13_30, tmp_path):
    out = tmp_path / "gym.lib"
    shutil.copytree(built.path, out)
    stored = len(built.stored_frames())
    everything = build(_inputs(take_13_30), out, workers=1, cache=False, keep_frames="all", force=True)
    assert len(everything.stored_frames()) == 120 > stored
    assert everything.report["read_frames"] == 120 - stored
    paths = {name: open_sequence(source).paths for name, source in _inputs(take_13_30)}
    for name, frame in everything.stored_frames()[::7]:
        mesh = read_frame(paths[name][frame])
        positions, colours, faces, _ = everything.frame_mesh((name, frame))
        np.testing.assert_array_equal(positions, mesh.positions)
        np.testing.assert_array_equal(colours, mesh.colours)
        np.testing.assert_array_equal(faces, mesh.faces)
    assert Library.open(built.path).stored_frames() == built.stored_frames()
