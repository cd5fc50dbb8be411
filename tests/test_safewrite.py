"""Nothing lost, ever: atomic writes and the ownership rule (tvmedit.engine.safewrite), and every command
that writes, run as a user would against folders and files that are not tvmedit's."""

import json
import shutil
from pathlib import Path

import pytest

from tvmedit.engine import safewrite
from tvmedit.engine.errors import OutputError
from interrupt import reachable_pair, tvmedit


def _pair(library):
    a, b, _ = reachable_pair(library)
    return str(a.id), str(b.id)


def _one_sentence(result):
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith("error: ") and result.stderr.count("\n") == 1, result.stderr
    assert "Traceback" not in result.stderr


def test_a_folder_is_swapped_in_whole_and_marked_with_what_was_written(tmp_path):
    out = tmp_path / "out"
    with safewrite.replacing_folder(out, kind="report") as tmp:
        (tmp / "a.txt").write_text("a")
        (tmp / "sub").mkdir()
        (tmp / "sub" / "b.txt").write_text("b")
    marker = json.loads((out / safewrite.MARKER).read_text())
    assert marker == {"kind": "report", "files": ["a.txt", "sub/b.txt"]}
    assert safewrite.owner(out) == "report"
    with pytest.raises(RuntimeError), safewrite.replacing_folder(out, kind="report") as tmp:
        (tmp / "c.txt").write_text("c")
        raise RuntimeError("disk gone")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert not (out / "c.txt").exists() and (out / "a.txt").read_text() == "a"


def test_an_interrupted_file_write_leaves_the_old_file(tmp_path):
    target = tmp_path / "notes.json"
    target.write_text("{}")
    with pytest.raises(KeyboardInterrupt), safewrite.replacing_file(target) as tmp:
        tmp.write_text('{"half":')
        raise KeyboardInterrupt
    assert target.read_text() == "{}" and sorted(tmp_path.iterdir()) == [target]


def test_force_replaces_only_a_same_kind_output_holding_nothing_else(tmp_path):
    out = tmp_path / "out"
    with safewrite.replacing_folder(out, kind="export") as tmp:
        (tmp / "edit.json").write_text("{}")
    with pytest.raises(OutputError, match="already exists; pass force=True"):
        safewrite.check_target(out, "export")
    safewrite.check_target(out, "export", force=True)
    with pytest.raises(OutputError, match="is a tvmedit export, not a report"):
        safewrite.check_target(out, "report", force=True)
    for k in range(5):
        (out / f"mine{k}.txt").write_text("mine")
    with pytest.raises(OutputError, match=r"holds 5 files, e.g. mine0.txt, mine1.txt, mine2.txt, which "
                                          "tvmedit did not write"):
        safewrite.check_target(out, "export", force=True)
    plain = tmp_path / "plain"
    plain.mkdir()
    (plain / "a.jpg").write_bytes(b"x")
    with pytest.raises(OutputError, match="is not a tvmedit export"):
        safewrite.check_target(plain, "export", force=True)
    with pytest.raises(OutputError, match="is inside the tvmedit export"):
        safewrite.check_target(out / "inner", "report")
    with pytest.raises(OutputError, match="is inside the input"):
        safewrite.check_target(plain / "x", "report", inputs=[plain])


def test_a_file_is_replaced_only_with_force_and_only_of_its_kind(tmp_path):
    notes = tmp_path / "notes.png"
    notes.write_text("my notes")
    with pytest.raises(OutputError, match="already exists; pass force=True"):
        safewrite.check_file_target(notes)
    with pytest.raises(OutputError, match="is not a PNG file"):
        safewrite.check_file_target(notes, force=True)
    png = tmp_path / "real.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(20))
    safewrite.check_file_target(png, force=True)
    video = tmp_path / "keep.mp4"
    video.write_bytes(bytes(4) + b"ftypisom" + bytes(20))
    safewrite.check_file_target(video, force=True)


def test_a_killed_writers_leftovers_are_tidied_and_a_swap_put_back(tmp_path):
    out = tmp_path / "lib"
    dead = 2 ** 22 + 12345  # above the default pid_max: no such process
    (tmp_path / f".lib.tmp-{dead}").mkdir()
    (tmp_path / f".lib.old-{dead}").mkdir()
    (tmp_path / f".lib.old-{dead}" / "manifest.json").write_text("{}")
    safewrite.clean_stale(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lib"]
    assert (out / "manifest.json").exists()


def test_export_into_a_library_is_refused_and_force_keeps_user_files(small_library, tmp_path):
    library = tmp_path / "gym.lib"
    shutil.copytree(small_library, library)
    from tvmedit import Library

    a, b = _pair(Library.open(library))
    result = tvmedit("export", library, a, b, "-o", library / "my_edit", "-q")
    _one_sentence(result)
    assert "inside the tvmedit library" in result.stderr and not (library / "my_edit").exists()

    (library / "my_notes.txt").write_text("mine")
    folder = Path(Library.open(library).sequences[0].paths[0]).parent
    result = tvmedit("build", f"gym={folder}", "-o", library, "--force", "-q", "--workers", "1")
    _one_sentence(result)
    assert "my_notes.txt, which tvmedit did not write" in result.stderr
    assert (library / "my_notes.txt").read_text() == "mine"
    result = tvmedit("build", f"gym={folder}", "-o", folder / "lib", "-q", "--workers", "1")
    _one_sentence(result)
    assert "inside the input" in result.stderr and not (folder / "lib").exists()


def test_render_and_report_never_replace_what_is_not_theirs(small_library, tmp_path):
    from tvmedit import Library

    nodes = Library.open(small_library).nodes
    notes = tmp_path / "notes.png"
    notes.write_text("my notes")
    result = tvmedit("render", small_library, "--node", nodes[0].id, "-o", notes, "--force")
    _one_sentence(result)
    assert "is not a PNG file" in result.stderr and notes.read_text() == "my notes"
    keep = tmp_path / "keep.mp4"
    keep.write_bytes(bytes(4) + b"ftypisom")
    a, b = _pair(Library.open(small_library))
    result = tvmedit("render", small_library, a, b, "-o", keep, "-q")
    _one_sentence(result)
    assert "already exists; pass --force" in result.stderr and keep.read_bytes() == bytes(4) + b"ftypisom"

    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "thesis.tex").write_text("chapter 1")
    result = tvmedit("report", small_library, "-o", folder, "-q", "--force")
    _one_sentence(result)
    assert (folder / "thesis.tex").read_text() == "chapter 1"


def test_an_empty_folder_of_the_users_inside_an_output_is_not_replaced(tmp_path):
    from tvmedit.engine import safewrite
    from tvmedit.engine.errors import OutputError

    out = tmp_path / "report"
    with safewrite.replacing_folder(out, kind="report") as folder:
        (folder / "index.html").write_text("<html>")
        (folder / "figures").mkdir()
        (folder / "figures" / "a.png").write_bytes(b"png")
    safewrite.check_target(out, "report", force=True)          # all of it ours: replaced
    (out / "mine").mkdir()
    with pytest.raises(OutputError, match="holds mine/, which tvmedit did not write"):
        safewrite.check_target(out, "report", force=True)
