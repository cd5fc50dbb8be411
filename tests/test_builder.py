"""Building a library (tvmedit.engine.store.builder): inputs named, bad frames and folders refused.

Inputs are the first frames of the real mocap take 13_30 (selected by glob), so a build
takes seconds; the feature cache always lives in a temporary ``XDG_CACHE_HOME``.
"""

import json
import os
import shutil

import numpy as np
import pytest

from tvmedit import Library, build
from tvmedit.engine.capture.load import open_sequence
from tvmedit.engine.errors import InputError, OutputError
from tvmedit.engine.capture.load import expand_inputs
from conftest import snippet_inputs as _inputs



# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


@pytest.fixture(scope="module")
def built(snippets_library):
    """The shared library of two sequences (conftest), by its path."""
    return snippets_library.path


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


def test_a_synthetic_walk_builds_into_a_library_named_after_its_folder(synth_walk, tmp_path):
    library = build([synth_walk], tmp_path / "walk.lib", workers=2, cache=False, smooth=False)
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


def test_a_stage_with_nothing_to_do_shows_no_progress_bar(capsys):
    # A bar of no steps ("blends: 0run") stayed in logs of builds without transitions or loops.
    from tvmedit.engine.store.builder import _Run

    run = _Run(progress=True, log=None)
    for total in (0, 3):
        bar = run.bar(total, "blends", unit="run")
        bar.update(total)
        bar.close()
    err = capsys.readouterr().err
    assert err.startswith("\rblends:") and "0run" not in err
