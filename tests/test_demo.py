"""`make demo` (tvmedit.demo) over the outputs of an earlier run: it replaces them."""

import numpy as np
import pytest

pytestmark = pytest.mark.gl


def test_the_demo_replaces_the_outputs_of_an_earlier_run(ctx, synth_gym, tmp_path, monkeypatch, capsys):
    import imageio.v2 as iio2
    import imageio.v3 as iio

    from tvmedit import demo
    from tvmedit.engine import safewrite

    monkeypatch.chdir(tmp_path)
    # The demo's take is the suite's gym take (the demo's preset at three cycles a motion and
    # 4,000 vertices, made once for every test): the demo builds, edits, renders and reports
    # on it as on its own.
    folder = tmp_path / "demo"
    folder.mkdir()
    (folder / "gym").symlink_to(synth_gym, target_is_directory=True)
    # What an earlier run left (a second run of the demo was refused before: "demo/out.mp4
    # already exists"): a video, and a report marked as tvmedit's, as a report is.
    iio2.mimwrite(folder / "out.mp4", [np.zeros((32, 32, 3), np.uint8)] * 2, fps=10)
    (folder / "report").mkdir()
    (folder / "report" / "index.html").write_text("an earlier report")
    safewrite.mark(folder / "report", "report")
    demo.main()
    out = capsys.readouterr().out
    assert out.count("done in") == 1
    with iio2.get_reader(folder / "out.mp4") as reader:     # a video, not the earlier bytes
        assert reader.count_frames() > 10 and reader.get_meta_data()["size"] == (640, 480)
    assert "an earlier report" not in (folder / "report" / "index.html").read_text()
    sheets = list(folder.glob("sheet-*.png"))
    assert len(sheets) == 1 and iio.imread(sheets[0]).shape[0] > 100
