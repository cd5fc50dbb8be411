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
    from tvmedit.engine.store import layout

    rebuild(built, tmp_path / "again.lib")
    again = Library.open(tmp_path / "again.lib")
    for name in ("positions.npy", "colours.npy", "normals.npy", "faces.npy", "frames.npy", "frame_keys.npy"):
        assert os.path.samefile(built.path / name, tmp_path / "again.lib" / name), name
    # The linked files' checksums are taken from the old manifest, not read again: each must
    # still be the sum of the bytes there, so that `check` passes and later damage is found.
    sums = again.manifest["checksums"]
    assert sums["positions.npy"] == built.manifest["checksums"]["positions.npy"]
    assert {name: layout.checksum(again.path / name) for name in sums} == sums


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


def test_frames_added_by_a_rebuild_lie_beside_those_kept_and_read_back_as_stored(built, take_13_30, tmp_path,
                                                                                monkeypatch):
    # Every frame the library stores is still needed: its arrays are kept as they are (linked,
    # not rewritten) and the frames it lacks go into a part of their own. A build that keeps no
    # spare frames then copies those it needs from both parts into one.
    from interrupt import tvmedit
    from tvmedit.engine.store import arrays

    out = tmp_path / "grown.lib"
    shutil.copytree(built.path, out)
    kept = {name: os.stat(out / name).st_ino for name in ("positions.npy", "faces.npy", "frames.npy")}
    # Two workers: the frames read come back through spool files (meshfiles._spools).
    grown = build(_inputs(take_13_30), out, workers=2, cache=False, keep_frames="all", force=True)
    assert arrays.parts(grown.path) == ["", "part1_"]
    assert {name: os.stat(out / name).st_ino for name in kept} == kept    # linked, not written again
    paths = {name: open_sequence(source).paths for name, source in _inputs(take_13_30)}
    for name, frame in grown.stored_frames():
        np.testing.assert_array_equal(grown.frame_mesh((name, frame))[0], read_frame(paths[name][frame]).positions)
    assert tvmedit("check", grown.path).returncode == 0
    damaged = tmp_path / "damaged.lib"
    shutil.copytree(grown.path, damaged)
    data = bytearray((damaged / "part1_positions.npy").read_bytes())
    data[len(data) // 2] ^= 0xFF
    (damaged / "part1_positions.npy").write_bytes(bytes(data))
    result = tvmedit("check", damaged)
    assert result.returncode == 2 and "part1_positions.npy does not hold the bytes written" in result.stderr
    monkeypatch.setattr(meshfiles, "SPARE_SHARE", 0.0)
    fewer = build(_inputs(take_13_30), out, workers=1, cache=False, force=True)   # the motions' frames only
    assert arrays.parts(fewer.path) == [""] and len(fewer.stored_frames()) < len(grown.stored_frames())
    assert fewer.report["read_frames"] == 0     # every one copied
    for name, frame in fewer.stored_frames():
        np.testing.assert_array_equal(fewer.frame_mesh((name, frame))[0], read_frame(paths[name][frame]).positions)


def test_textured_frames_to_add_are_stored_anew_and_the_kept_files_left_untouched(built, take_13_30, tmp_path):
    # A part holds no texels: frames to add that come with a texture (here a textured capture
    # added to an untextured library) make every frame stored anew, textured, and the files
    # the old library shares by hard link are never written into.
    from conftest import SHARED
    from tvmedit.engine.capture.readers import texture_for
    from tvmedit.engine.store import arrays

    card = SHARED / "data" / "scvv-card"
    if not card.is_dir():
        pytest.skip(f"the scvv capture is not at {card}")
    frames = tmp_path / "card"
    frames.mkdir()
    for draco in sorted(card.glob("*.draco"))[:16]:
        shutil.copy(draco, frames / draco.name)
        shutil.copy(texture_for(draco), frames / texture_for(draco).name)
    (frames / "sequence.json").write_text('{"fps": 30}')
    out = tmp_path / "lib"
    shutil.copytree(built.path, out)
    shared = tmp_path / "shared_positions.npy"     # the old library's file, as a link keeps it
    os.link(out / "positions.npy", shared)
    before = shared.read_bytes()
    library = build([*_inputs(take_13_30), ("card", str(frames))], out, workers=2, cache=False, keep_frames="all",
                    force=True, smooth=False)     # the meshes, textures and links are what is checked
    assert library.textured and arrays.parts(library.path) == [""]
    assert library.frame_texture(("card", 0)) is not None and library.frame_texture(("gym", 0)) is None
    card_paths = open_sequence(str(frames)).paths
    for frame in (0, 7, 15):    # spooled from the workers with their texture and uv
        (uv, texture), read = library.frame_texture(("card", frame)), read_frame(card_paths[frame])
        assert len(library.frame_mesh(("card", frame))[0]) == len(read.positions)
        np.testing.assert_array_equal(uv, read.uv)
        np.testing.assert_array_equal(texture, read.texture)
    assert not list(library.path.glob(".spool*"))
    assert shared.read_bytes() == before


def test_a_grown_library_without_its_marker_is_still_replaced_with_force(built, take_13_30, tmp_path):
    from tvmedit.engine.safewrite import MARKER
    from tvmedit.engine.store import arrays

    out = tmp_path / "grown.lib"
    shutil.copytree(built.path, out)
    build(_inputs(take_13_30), out, workers=1, cache=False, keep_frames="all", force=True)
    assert arrays.parts(out) == ["", "part1_"]
    (out / MARKER).unlink()     # copied without its dotfiles: a library as built before the marker
    again = build(_inputs(take_13_30), out, workers=1, cache=False, keep_frames="all", force=True)
    assert len(again.stored_frames()) == 120


def test_building_again_over_a_damaged_library_repairs_it(built, take_13_30, tmp_path):
    # The build that `check` advises for a damaged library reads the frames from the capture:
    # it neither links the damaged bytes nor carries their old checksum over.
    from interrupt import tvmedit

    out = tmp_path / "gym.lib"
    shutil.copytree(built.path, out)
    first = Library.open(out).nodes[0]
    Library.open(out).rename(first.id, "warm-up")
    data = bytearray((out / "positions.npy").read_bytes())
    data[len(data) // 2] ^= 0xFF
    (out / "positions.npy").write_bytes(bytes(data))
    damaged = tvmedit("check", out)
    assert damaged.returncode == 2 and "positions.npy does not hold the bytes written" in damaged.stderr
    said = []
    # (no display-rate in-betweens: the meshes are what is repaired and checked)
    again = build(_inputs(take_13_30), out, workers=1, cache=False, force=True, log=said.append, smooth=False)
    assert any("damaged (positions.npy" in line and "nothing is reused" in line for line in said), said
    assert again.nodes[0].name == "warm-up"      # what the user gave is kept
    assert again.report["read_frames"] == len(again.stored_frames())
    assert tvmedit("check", out).returncode == 0
    paths = {name: open_sequence(source).paths for name, source in _inputs(take_13_30)}
    for name, frame in again.stored_frames():
        np.testing.assert_array_equal(again.frame_mesh((name, frame))[0], read_frame(paths[name][frame]).positions)


def test_a_damaged_library_is_not_corrected_and_nothing_is_written(built, tmp_path, monkeypatch):
    # A rebuild takes its features, meshes and in-betweens from the library itself: with
    # damaged bytes it stops and says to build from the capture, leaving no new library.
    from tvmedit.engine.errors import LibraryError

    out = tmp_path / "gym.lib"
    shutil.copytree(built.path, out)
    data = bytearray((out / "features.npy").read_bytes())
    data[-5] ^= 0xFF
    (out / "features.npy").write_bytes(bytes(data))
    with pytest.raises(LibraryError, match="features.npy does not hold the bytes written.*force"):
        rebuild(Library.open(out), tmp_path / "corrected.lib")
    assert not (tmp_path / "corrected.lib").exists()
    # Damaged stored frames: linked as they are, their checksums kept (the new library is
    # found damaged too), or verified before they are copied (refused); never blessed.
    shutil.copy2(built.path / "features.npy", out / "features.npy")
    data = bytearray((out / "positions.npy").read_bytes())
    data[len(data) // 2] ^= 0xFF
    (out / "positions.npy").write_bytes(bytes(data))
    library = Library.open(out)
    for k, corrections in enumerate([None, {"sequences": {"gym": {"drop": [library.nodes[0].name]}}}]):
        # The second keeps no spare frame: the frames it still needs are copied, not linked.
        monkeypatch.setattr(meshfiles, "SPARE_SHARE", 0.0 if k else meshfiles.SPARE_SHARE)
        try:
            rebuild(library, tmp_path / f"corrected-{k}.lib", corrections=corrections)
        except LibraryError as error:
            assert "positions.npy does not hold the bytes written" in str(error)
            assert not (tmp_path / f"corrected-{k}.lib").exists()
        else:
            with pytest.raises(LibraryError, match="positions.npy does not hold the bytes written"):
                Library.open(tmp_path / f"corrected-{k}.lib").verify()
    # Where no hard link can be made (another file system), the frames are copied: refused too.
    monkeypatch.setattr(meshfiles, "SPARE_SHARE", 1.0)

    def no_link(*args):
        raise OSError("cross-device link")

    monkeypatch.setattr(os, "link", no_link)
    with pytest.raises(LibraryError, match="positions.npy does not hold the bytes written"):
        rebuild(library, tmp_path / "copied.lib")
    assert not (tmp_path / "copied.lib").exists()
