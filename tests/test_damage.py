"""A library knows its own bytes: damage on disk is found by `check LIB`, and stops export and
render with nothing written (checksums in the manifest, beside the frames; each frame within its bounds)."""

import json
import shutil

import pytest

from interrupt import tvmedit
from tvmedit import Library


def _damaged(library, tmp_path, name, keep_checksums=True):
    """A copy of ``library`` with 200 bytes of ``name`` flipped, its size kept."""
    copy = tmp_path / "damaged.tvmlib"
    shutil.copytree(library, copy)
    data = bytearray((copy / name).read_bytes())
    middle = len(data) // 2
    for k in range(200):
        data[middle + 7 * k] ^= 0xFF
    (copy / name).write_bytes(bytes(data))
    if not keep_checksums:  # a library as built before checksums
        manifest = json.loads((copy / "manifest.json").read_text())
        manifest.pop("checksums")
        (copy / "manifest.json").write_text(json.dumps(manifest))
    return copy


def test_check_lib_passes_a_library_as_built(small_library):
    result = tvmedit("check", small_library)
    assert result.returncode == 0 and "hold the bytes written" in result.stdout, result.stderr


@pytest.mark.parametrize("name", ["positions.npy", "features.npy", "instant_fields.npy"])
def test_same_size_damage_to_any_array_is_named_by_check(small_library, tmp_path, name):
    copy = _damaged(small_library, tmp_path, name)
    result = tvmedit("check", copy)
    assert result.returncode == 2 and f"{name} does not hold the bytes written" in result.stderr, result.stderr
    assert "Traceback" not in result.stderr


@pytest.mark.parametrize("name", ["colours.npy", "positions.npy"])
@pytest.mark.parametrize("command", ["export", "render"])
def test_damage_stops_export_and_render_and_leaves_nothing(small_library, tmp_path, command, name):
    # The checksums run beside the frames: damage a frame read meets first (positions off
    # their bounds) is named by them all the same, and nothing is left at the output.
    copy = _damaged(small_library, tmp_path, name)
    out = tmp_path / ("edit" if command == "export" else "edit.mp4")
    result = tvmedit(command, copy, "0", "1", "-o", out, "-q")
    assert result.returncode == 2 and f"{name} does not hold the bytes written" in result.stderr, result.stderr
    assert not out.exists() and list(tmp_path.iterdir()) == [copy]


def test_without_checksums_a_vertex_off_its_bounds_is_still_caught(small_library, tmp_path):
    copy = _damaged(small_library, tmp_path, "positions.npy", keep_checksums=False)
    library = Library.open(copy)
    frames = library.stored_frames()
    with pytest.raises(Exception, match="outside the bounds the build recorded"):
        for key in frames:
            library.frame_mesh(key)
    result = tvmedit("check", copy)
    assert result.returncode == 2 and "outside the bounds" in result.stderr and "Traceback" not in result.stderr


def test_damage_met_before_the_frames_is_named_by_the_checksums(small_library, tmp_path):
    # At 30 fps an export reads the display fields' table before it starts writing: a damaged
    # one is named as such, not as an array that does not match.
    copy = _damaged(small_library, tmp_path, "instant_pairs.npy")
    out = tmp_path / "edit"
    result = tvmedit("export", copy, "0", "1", "--fps", "30", "-o", out, "-q")
    assert result.returncode == 2 and "instant_pairs.npy does not hold the bytes written" in result.stderr, \
        result.stderr
    assert not out.exists() and "Traceback" not in result.stderr


def test_an_export_forks_its_workers_before_any_thread_of_it_runs(small_library, tmp_path):
    # Worker processes forked beside a running thread inherit its locks held; the checksums'
    # thread must start after them.
    import os
    import threading

    from tvmedit.engine.graph.export import POOL_FROM

    library = Library.open(small_library)
    edit = library.edit(list(range(len(library.nodes))))
    assert len(edit.schedule) >= POOL_FROM    # OBJ on worker processes
    before = set(threading.enumerate())
    seen = []
    os.register_at_fork(before=lambda: seen.append(set(threading.enumerate()) - before) if watching else None)
    watching = True
    try:
        from tvmedit.engine.graph.export import export_edit

        export_edit(edit, tmp_path / "obj", fmt="obj")
    finally:
        watching = False
    assert seen and all(not extra for extra in seen), [sorted(t.name for t in extra) for extra in seen]


def test_a_stopped_check_reads_no_further_and_reports_nothing(small_library):
    import threading

    from tvmedit.engine.store import layout

    stop = threading.Event()
    stop.set()
    library = Library.open(small_library)
    assert layout.checksum(small_library / "positions.npy", stop) is None
    assert layout.verify(small_library, library.manifest, None, stop) == []
