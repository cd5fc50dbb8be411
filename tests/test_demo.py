"""`make demo` (tvmedit.demo) run twice in one folder: the second run replaces its own outputs."""

import pytest

pytestmark = pytest.mark.gl


def test_the_demo_runs_again_over_its_own_outputs(ctx, synth_gym, tmp_path, monkeypatch, capsys):
    from tvmedit import demo

    monkeypatch.chdir(tmp_path)
    # The demo's take is the suite's gym take (the demo's preset at three cycles a motion and
    # 4,000 vertices, made once for every test): the demo builds, edits, renders and reports
    # on it as on its own; both runs take 18 s, against 59 s on the demo's full take.
    (tmp_path / "demo").mkdir()
    (tmp_path / "demo" / "gym").symlink_to(synth_gym, target_is_directory=True)
    demo.main()
    first = (tmp_path / "demo" / "out.mp4").stat().st_mtime_ns
    demo.main()      # refused before: "demo/out.mp4 already exists"
    out = capsys.readouterr().out
    assert (tmp_path / "demo" / "out.mp4").stat().st_mtime_ns > first
    assert (tmp_path / "demo" / "report" / "index.html").exists()
    assert out.count("done in") == 2
