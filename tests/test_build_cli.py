"""``tvmedit build``, ``info`` and ``rename`` as a user runs them, on real mocap frames.

Every run points ``XDG_CACHE_HOME`` at a temporary folder, so no test reads or fills the
user's feature cache.
"""

import json
import os
import signal

import jsonschema
import pytest

from tvmedit import Library
from tvmedit.engine.store.library import INFO_SCHEMA
from interrupt import run_signalled
from tvmedit.cli import main


# Short snippets of one take rarely repeat a texton; the database then says so.
pytestmark = [pytest.mark.usefixtures("private_cache"), pytest.mark.filterwarnings("ignore:no motion cluster repeats:UserWarning")]


def _small(take):
    """Frames 0-59 of the take, as a quoted glob."""
    return "gym=" + str(take / "frame_000[0-5]?.ply")


def _library_files(path):
    """Every file of a library but the build time, for comparing two builds."""
    files = {}
    for entry in sorted(os.listdir(path)):
        data = (path / entry).read_bytes()
        if entry == "manifest.json":
            manifest = json.loads(data)
            manifest.pop("created")
            data = json.dumps(manifest, sort_keys=True).encode()
        files[entry] = data
    return files


def test_info_json_follows_the_documented_schema(take_13_30, tmp_path, capsys):
    out = tmp_path / "gym.lib"
    assert main(["build", _small(take_13_30), "-o", str(out), "--workers", "1", "-q"]) == 0
    capsys.readouterr()
    assert main(["info", str(out), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    jsonschema.validate(info, INFO_SCHEMA)
    library = Library.open(out)
    assert [s["name"] for s in info["sequences"]] == ["gym"]
    assert info["sequences"][0]["frames"] == 60
    assert [n["name"] for n in info["nodes"]] == [n.name for n in library.nodes]
    assert len(info["edges"]) == library.graph.number_of_edges()
    for edge in info["edges"]:
        source, target = library.nodes[edge["from"]], library.nodes[edge["to"]]
        assert source.start <= edge["exit_frame"] <= source.end
        assert target.start <= edge["entry_frame"] <= target.end
    clusters = info["sequences"][0]["clusters"]
    assert clusters[0]["start"] == 0 and clusters[-1]["end"] == 59

    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert "gym: 60 frames at 10 fps" in text and library.nodes[0].name in text


def test_build_prints_a_summary_and_refuses_to_overwrite_without_force(take_13_30, tmp_path, capsys):
    out = tmp_path / "gym.lib"
    assert main(["build", _small(take_13_30), "-o", str(out), "--workers", "1"]) == 0
    err = capsys.readouterr().err
    assert f"built {out}: 1 sequence(s), 60 frames," in err and "graph edges" in err
    assert main(["build", _small(take_13_30), "-o", str(out), "--workers", "1"]) == 2
    assert "error: library" in capsys.readouterr().err

    # Other parsing and pruning parameters: the features are reused, and the user is told.
    assert main(["build", _small(take_13_30), "-o", str(out), "--workers", "1", "--force",
                 "--mu", "1.5", "--beta", "0.3"]) == 0
    err = capsys.readouterr().err
    assert "features of gym: reused from the library being replaced (60 frames)" in err
    assert "features reused for 1 of 1 sequence(s)" in err
    assert Library.open(out).params["mu"] == 1.5
    assert Library.open(out).params["structure"]["beta"] == 0.3


def test_serial_worker_and_dask_builds_are_identical(take_13_30, tmp_path):
    libraries = {}
    for label, options in (("serial", ["--workers", "1"]), ("workers", ["--workers", "2"]),
                           ("dask", ["--dask", "local", "--workers", "2"])):
        out = tmp_path / f"{label}.lib"
        assert main(["build", _small(take_13_30), "-o", str(out), "-q", "--no-cache", *options]) == 0
        libraries[label] = _library_files(out)
    assert libraries["workers"] == libraries["serial"]
    assert libraries["dask"] == libraries["serial"]


def _leftovers(folder):
    return sorted(p.name for p in folder.iterdir() if ".tmp-" in p.name or ".old-" in p.name)


def test_an_interrupted_build_leaves_no_library_or_the_previous_one(take_13_30, tmp_path):
    out = tmp_path / "gym.lib"
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "xdg")}
    build = ["build", _small(take_13_30), "-o", out, "--workers", "1", "-q"]

    # Killed outright just after its temporary folder was made.
    result = run_signalled(build, at="tvmedit.engine.store.featurecache:stat_list", signum=signal.SIGKILL, env=env)
    assert result.returncode == -signal.SIGKILL
    assert not out.exists() and len(_leftovers(tmp_path)) == 1

    assert main([str(arg) for arg in build]) == 0
    assert _leftovers(tmp_path) == []  # what the killed build left is cleaned up by the next one
    before = _library_files(out)

    # Killed while the new library was being written (its meshes are the old one's, linked:
    # tvmedit.engine.store.meshfiles).
    result = run_signalled([*build, "--force"], at="tvmedit.engine.store.layout:write_json", after=2,
                           signum=signal.SIGKILL, env=env)
    assert result.returncode == -signal.SIGKILL
    assert _library_files(out) == before
    assert Library.open(out).sequences[0].frames == 60

    # Stopped politely (SIGTERM) at the same point, the build removes its temporary folder itself.
    result = run_signalled([*build, "--force"], at="tvmedit.engine.store.layout:write_json", after=2,
                           signum=signal.SIGTERM, env=env)
    assert result.returncode == 128 + signal.SIGTERM and "Traceback" not in result.stderr
    assert _leftovers(tmp_path) == []
    assert _library_files(out) == before


def test_rename_and_its_errors(take_13_30, tmp_path, capsys):
    out = tmp_path / "gym.lib"
    assert main(["build", _small(take_13_30), "-o", str(out), "--workers", "1", "-q", "--no-smooth"]) == 0
    first = Library.open(out).nodes[0]
    assert main(["rename", str(out), str(first.id), "warm-up"]) == 0
    assert f"is now 'warm-up' (was '{first.name}')" in capsys.readouterr().out
    assert Library.open(out).node("warm-up").id == first.id
    assert main(["rename", str(out), "no-such-motion", "x"]) == 2
    assert "error: there is no motion 'no-such-motion'" in capsys.readouterr().err
    assert main(["info", str(tmp_path / "missing.lib")]) == 2
    assert "error: no library at" in capsys.readouterr().err


def test_bad_input_is_one_sentence(tmp_path, capsys):
    assert main(["build", str(tmp_path / "nowhere"), "-o", str(tmp_path / "lib"), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: sequence folder") and err.count("\n") == 1
    assert not (tmp_path / "lib").exists()



def test_an_infinite_mu_is_refused_in_one_sentence(take_13_30, tmp_path, capsys):
    out = tmp_path / "lib"
    assert main(["build", _small(take_13_30), "-o", str(out), "--mu", "inf", "-q"]) == 2
    err = capsys.readouterr().err
    assert err == "error: --mu inf is out of range: it must be a finite number above 0 (the default is 0.9).\n"
    assert not out.exists()


def test_build_reports_a_file_left_out_and_refuses_a_bad_sequence_name(take_13_30, tmp_path, capsys):
    import glob
    import shutil

    walk = tmp_path / "walk"
    walk.mkdir()
    for path in sorted(glob.glob(str(take_13_30 / "frame_000[0-3]?.ply"))):
        shutil.copy2(path, walk)
    (walk / "frame_00040.stl").write_bytes(b"solid x\nendsolid x\n")
    (walk / "notes.md").write_text("take 3")
    assert main(["build", str(walk), "-o", str(tmp_path / "walk.tvmlib"), "--workers", "1", "-q"]) == 0
    err = capsys.readouterr().err
    assert "warning: " in err and "left out 1 file(s) with an unsupported extension (frame_00040.stl)" in err
    assert "notes.md" not in err
    assert Library.open(tmp_path / "walk.tvmlib").sequences[0].frames == 40

    (walk / "sequence.json").write_text(json.dumps({"name": 7}))
    assert main(["build", str(walk), "-o", str(tmp_path / "named.tvmlib"), "--workers", "1", "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "sequence name 7" in err and err.count("\n") == 1
    assert not (tmp_path / "named.tvmlib").exists()


def test_keep_frames_all_stores_every_frame_and_info_says_so(take_13_30, tmp_path, capsys):
    out = tmp_path / "all.lib"
    assert main(["build", _small(take_13_30), "-o", str(out), "--workers", "1", "-q", "--keep-frames", "all",
                 "--no-smooth"]) == 0
    library = Library.open(out)
    assert library.params["keep_frames"] == "all"
    assert sorted(library.stored_frames()) == [("gym", f) for f in range(60)]
    capsys.readouterr()
    assert main(["info", str(out)]) == 0
    assert "stored: 60 frames" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exit_:
        main(["build", _small(take_13_30), "-o", str(tmp_path / "x.lib"), "--keep-frames", "some"])
    assert exit_.value.code == 2 and "invalid choice: 'some'" in capsys.readouterr().err


def test_every_parse_option_of_build_says_what_it_does():
    import dataclasses

    from tvmedit.cli import _parser
    from tvmedit.engine.parse.params import StructureParams

    parser = _parser(["build"])
    build = next(a for a in parser._subparsers._group_actions[0].choices.values() if a.prog.endswith(" build"))
    helps = {a.dest: a.help or "" for a in build._actions}
    for field in dataclasses.fields(StructureParams):
        if field.name in ("method", "window_taps"):
            continue
        words = helps[f"structure_{field.name}"].split(" (default")[0]
        assert len(words.split()) >= 4, (field.name, helps[f"structure_{field.name}"])
