"""`make demo` (tvmedit.demo) run twice in one folder: the second run replaces its own outputs."""

import pytest

pytestmark = pytest.mark.gl


def test_the_demo_runs_again_over_its_own_outputs(ctx, tmp_path, monkeypatch, capsys):
    from tvmedit import demo

    monkeypatch.chdir(tmp_path)
    demo.main()
    first = (tmp_path / "demo" / "out.mp4").stat().st_mtime_ns
    demo.main()      # refused before: "demo/out.mp4 already exists"
    out = capsys.readouterr().out
    assert (tmp_path / "demo" / "out.mp4").stat().st_mtime_ns > first
    assert (tmp_path / "demo" / "report" / "index.html").exists()
    assert out.count("done in") == 2
