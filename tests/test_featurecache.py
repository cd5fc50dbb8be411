"""The feature cache (tvmedit.engine.store.featurecache): kept by what features depend on.

Every test points ``XDG_CACHE_HOME`` at a temporary folder, so no test reads or fills the
user's feature cache.
"""

import os
import shutil

import numpy as np
import pytest

from tvmedit import build
from tvmedit.engine.capture.load import open_sequence
from tvmedit.engine.errors import InputError
from tvmedit.engine.features import BinSizes, Features
from tvmedit.engine.store import featurecache
from tvmedit.engine.store.featurecache import cache_dir
from conftest import snippet_inputs as _inputs



# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


def test_rebuild_with_other_parameters_reuses_cached_features(take_13_30, tmp_path):
    out, messages = tmp_path / "lib", []
    first = build(_inputs(take_13_30)[:1], out, workers=1, blend_frames=0, smooth=False)
    assert first.report["reused"] == {}
    assert list((cache_dir() / "features").glob("*.npz"))

    first.rename(first.nodes[0].id, "warm-up")
    second = build(_inputs(take_13_30)[:1], out, workers=1, mu=2.0, force=True, log=messages.append,
                   blend_frames=0, smooth=False)
    assert second.report["reused"] == {"gym": "library"}
    assert any("features of gym: reused" in m for m in messages)
    # Only the pruning changed, so the renamed texton is still a motion and keeps its name.
    assert second.nodes[0].name == "warm-up" and second.graph.nodes[0]["name"] == "warm-up"
    assert "kept 1 motion name(s) given in the library being replaced" in messages
    np.testing.assert_array_equal(second.features("gym").vectors, first.features("gym").vectors)
    assert second.mu == 2.0 and second.graph.number_of_edges() >= first.graph.number_of_edges()

    elsewhere = build(_inputs(take_13_30)[:1], tmp_path / "other", workers=1, blend_frames=0, smooth=False)
    assert elsewhere.report["reused"] == {"gym": "cache"}

    coarse = build(_inputs(take_13_30)[:1], out, workers=1, bins=BinSizes(r=0.04), force=True,
                   blend_frames=0, smooth=False)
    assert coarse.report["reused"] == {}

    frames = tmp_path / "frames"
    frames.mkdir()
    for path in open_sequence(_inputs(take_13_30)[0][1]).paths:
        shutil.copy2(path, frames / path.name)
    build([("gym", frames)], tmp_path / "copied", workers=1, blend_frames=0, smooth=False)
    touched = sorted(frames.iterdir())[5]
    os.utime(touched, ns=(touched.stat().st_atime_ns, touched.stat().st_mtime_ns + 10**9))
    again = build([("gym", frames)], tmp_path / "copied", workers=1, force=True, blend_frames=0, smooth=False)
    assert again.report["reused"] == {}


def _features(frames, centred):
    rng = np.random.default_rng(0)
    bins = BinSizes()
    parts = [rng.random((frames, k)).astype(np.float32) for k in (5, 4, 3)]
    inner = Features(*[p / 2 for p in parts], np.zeros(3), bins) if centred else None
    return Features(*parts, np.array([0.5, 0.0, 1.0]), bins, inner)


@pytest.mark.parametrize("centred", [False, True])
def test_features_written_to_the_cache_read_back_the_same(tmp_path, centred):
    features, meta = _features(6, centred), {"files": ["a.ply"], "skipped": []}
    featurecache.write("k1", features, meta, folder=tmp_path)
    again, meta_again = featurecache.read("k1", BinSizes(), folder=tmp_path)
    assert meta_again == meta
    for name in ("r", "theta", "phi", "origin"):
        np.testing.assert_array_equal(getattr(again, name), getattr(features, name))
    assert (again.centred is None) == (not centred)
    if centred:
        np.testing.assert_array_equal(again.centred.vectors, features.centred.vectors)


def test_a_missing_or_damaged_cache_entry_reads_as_absent(tmp_path):
    assert featurecache.read("nothing", BinSizes(), folder=tmp_path) is None
    (tmp_path / "k2.npz").write_bytes(b"not a zip file")
    assert featurecache.read("k2", BinSizes(), folder=tmp_path) is None


def test_the_cache_key_changes_with_the_files_and_the_bins(tmp_path):
    frame = tmp_path / "frame_0000.ply"
    frame.write_bytes(b"ply")
    stats = featurecache.stat_list([frame])
    assert stats == [[str(frame.resolve()), 3, frame.stat().st_mtime_ns]]
    key = featurecache.key(stats, BinSizes())
    assert key == featurecache.key(stats, BinSizes()) and len(key) == 20
    assert key != featurecache.key(stats, BinSizes(r=0.04))
    assert key != featurecache.key(stats, BinSizes(), skip_bad_frames=True)
    frame.write_bytes(b"ply!")
    assert key != featurecache.key(featurecache.stat_list([frame]), BinSizes())


def test_a_frame_file_that_is_gone_is_named_in_one_sentence(tmp_path):
    with pytest.raises(InputError, match=r"frame .*gone.ply cannot be read \(No such file or directory\); "
                                         r"check the input\.$"):
        featurecache.stat_list([tmp_path / "gone.ply"])


def test_the_cache_lives_under_xdg_cache_home(tmp_path):
    assert cache_dir() == tmp_path / "xdg" / "tvmedit"
