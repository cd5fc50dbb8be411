"""The inspector: its timeline as numbers, its actions as Python calls, then a real window under Xvfb.

The window test starts ``python -m tvmedit inspect`` on a copy of the synthetic gym library
in its own Xvfb (the ``xdisplay`` fixture of the player's tests), presses keys with xdotool
and reads back what the user would find: the saved ``corrections.json``, the rebuilt
library and a screenshot.
"""

import json
import os
import shutil
import subprocess
import sys
import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from conftest import ROOT
from tvmedit import Library
from tvmedit.engine.parse.timeline import COLOURS, timeline
from tvmedit.player.inspect import InspectorApp, graph_summary
from test_player_window import KEY_SWEEP, find_window, xdisplay  # noqa: F401 - the session's Xvfb

NAME = "gym"


@pytest.fixture
def library(small_library, tmp_path):
    out = tmp_path / "gym.tvmlib"
    shutil.copytree(small_library, out)
    return Library.open(out)


def _splittable(library):
    """A frame two frames after which a texton start leaves both parts longer than the atom window."""
    texton = max(library.structure(NAME).textons, key=len)
    return texton.start + len(texton) // 2 - 2


def _wait_for_file(path, timeout=30):
    """The JSON in ``path`` once the window has written it."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if path.exists():
            return json.loads(path.read_text())
        time.sleep(0.1)
    raise AssertionError(f"{path} was not written")


def test_the_timeline_lays_out_clusters_representatives_and_marks(library):
    structure = library.structure(NAME)
    line = timeline(NAME, structure, library.parse(NAME), library.nodes)
    assert line.clusters == structure.clusters and len(line.representatives) == len(library.nodes)
    box = (0, 100, 1000, 200)
    shapes = line.shapes(box, playhead=50)
    # one background, one band per cluster, one highlight per motion, a tick per texton,
    # a line per boundary and the playhead
    expected = 1 + len(line.clusters) + len(line.representatives) + len(line.textons) + len(line.boundaries) + 1
    assert shapes.rects.shape == (expected, 4) and len(shapes.curve) == line.frames
    reps = shapes.rects[np.isclose(shapes.colours, COLOURS["representative"]).all(axis=1)]
    first = library.nodes[0]
    assert reps[0][0] == pytest.approx(1000 * first.start / line.frames)
    assert line.frame_at(line.x_of(123, box) + 0.1, box) == 123
    assert shapes.curve[:, 1].min() >= 100 and shapes.curve[:, 1].max() <= 300


def test_every_action_is_a_python_call(library, tmp_path):
    app = InspectorApp(library, tmp_path / "fix.json", print_=lambda text: None)
    frame = _splittable(library)
    app.seek(frame)
    app.press("right")
    app.press("right")
    assert app.frame == frame + 2
    assert app.press("t") == app.press("s") is None
    saved = json.loads((tmp_path / "fix.json").read_text())
    assert saved == {"sequences": {NAME: {"textons": {"add": [frame + 2]}}}}
    assert frame + 2 in app.timeline.texton_starts
    app.press("u")
    assert frame + 2 not in app.timeline.texton_starts and not app.corrections

    start = app.timeline.texton_starts[3]
    app.seek(start + 1)
    app.press("t")                                  # one frame after a start: too short, refused
    assert app.message.startswith("refused") and "atom window" in app.message and not app.corrections
    app.press("m")                                  # the nearest start moves onto the playhead
    assert start + 1 in app.timeline.texton_starts and start not in app.timeline.texton_starts
    boundary = app.timeline.boundaries[0]
    app.seek(boundary + 1)
    app.press("d")                                  # the nearest marker is that boundary
    assert boundary not in app.timeline.boundaries and boundary in app.timeline.removed
    app.seek(0)
    app.press("x")                                  # the first motion is dropped
    assert app.message == f"motion {library.nodes[0].name} dropped"
    summary = app.rebuild()
    assert summary == graph_summary(Library.open(library.path).graph)
    assert summary["motions"] == len(library.nodes) - 2
    assert Library.open(library.path).corrections() == app.corrections


def test_keys_in_a_real_window_edit_rebuild_save_and_show_the_person(xdisplay, library, tmp_path):  # noqa: F811
    frame = _splittable(library)
    clusters = library.structure(NAME).clusters
    far = next(c for c in clusters if not c[0] <= frame + 2 <= c[1] and c[1] - c[0] > 20)
    target = (far[0] + far[1]) // 2
    x = int((target + 0.5) / len(library.sequence(NAME)) * 800)
    fix = tmp_path / "corrections.json"
    env = {**os.environ, "DISPLAY": xdisplay, "PYTHONPATH": str(ROOT)}
    command = [sys.executable, "-m", "tvmedit", "inspect", str(library.path), "--corrections", str(fix),
               "--frame", str(frame), "--seconds", "60", "--size", "800x600"]
    window_app = subprocess.Popen(command, cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True)
    try:
        window = find_window(env, "tvmedit inspect", window_app, lambda: window_app.communicate(timeout=10))
        subprocess.run(["xdotool", "windowfocus", "--sync", window], env=env, check=True, timeout=10)
        for key in ("Right", "Right", "t", "Return", "s", "c"):
            subprocess.run(["xdotool", "key", "--window", window, key], env=env, timeout=10, capture_output=True)
        saved = _wait_for_file(fix)
        # A click on the timeline puts the playhead under the mouse: B then draws a boundary there.
        subprocess.run(["xdotool", "mousemove", "--window", window, str(x), "500", "click", "1"], env=env, timeout=10)
        for key in ("b", "s", "q"):
            subprocess.run(["xdotool", "key", "--window", window, key], env=env, timeout=10, capture_output=True)
        out, err = window_app.communicate(timeout=60)
    finally:
        window_app.kill()
    assert window_app.returncode == 0, err
    assert saved == {"sequences": {NAME: {"textons": {"add": [frame + 2]}}}}, err
    rebuilt = Library.open(library.path)
    assert frame + 2 in rebuilt.structure(NAME).texton_starts and rebuilt.corrections().to_json() == saved
    assert "rebuilt" in err and "reachable pairs" in err
    clicked = json.loads(fix.read_text())["sequences"][NAME]["boundaries"]["add"]
    assert len(clicked) == 1 and abs(clicked[0] - target) <= 1, (clicked, target)

    import imageio.v3 as iio

    shot = [line.split(" saved to ")[-1] for line in out.splitlines() if "screenshot saved to" in line]
    image = iio.imread(tmp_path / shot[0]).astype(np.float64)
    assert image.shape[:2] == (600, 800)
    view, strip = image[:400], image[462:]          # above the timeline (from y 420), and its curve
    background = np.median(view.reshape(-1, 3), axis=0)
    person = np.abs(view - background).sum(axis=2) > 80
    assert 0.01 < person.mean() < 0.5
    for row, colour in ((425, COLOURS["bands"][0]), (445, COLOURS["representative"])):
        assert (np.abs(image[row] - 255 * np.array(colour[:3])).sum(axis=1) < 30).any()
    curve = np.abs(strip - 255 * np.array(COLOURS["curve"][:3])).sum(axis=2) < 60
    assert curve.any(axis=0).mean() > 0.5          # the curve runs across the timeline


def test_a_frame_outside_the_sequence_is_one_sentence(small_library):
    from interrupt import tvmedit

    frames = Library.open(small_library).sequences[0].frames
    result = tvmedit("inspect", small_library, "--frame", frames, env={**os.environ, "DISPLAY": ""})
    assert result.returncode == 2 and result.stderr.count("\n") == 1
    assert f"--frame {frames} is outside sequence" in result.stderr and f"0-{frames - 1}" in result.stderr


def test_a_display_no_server_answers_is_one_sentence_with_what_works_without(small_library):
    from interrupt import tvmedit

    env = {**os.environ, "DISPLAY": ":65000", "PYGLFW_LIBRARY_VARIANT": "x11"}
    env.pop("WAYLAND_DISPLAY", None)
    result = tvmedit("inspect", small_library, env=env)
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert result.stderr.startswith("error: cannot open the display :65000 (X11: Failed to open display :65000)")
    assert "`tvmedit correct` applies a corrections file without one" in result.stderr


def test_a_failed_save_keeps_the_corrections_and_says_why(library, tmp_path):
    app = InspectorApp(library, tmp_path / "fix.json", print_=lambda text: None)
    app.seek(_splittable(library))
    app.press("t")
    kept = app.corrections.copy()
    app.save(tmp_path / "no-such-folder" / "fix.json")
    assert app.message.startswith("not saved") and "press S again" in app.message
    assert app.corrections == kept and kept
    app.save()
    assert json.loads((tmp_path / "fix.json").read_text())


def test_paths_enter_and_s_would_fail_on_are_refused_at_the_start(small_library, tmp_path):
    from interrupt import tvmedit

    result = tvmedit("inspect", small_library, "--corrections", tmp_path / "missing" / "fix.json")
    assert result.returncode == 2 and "cannot save corrections to" in result.stderr
    other = tmp_path / "other.tvmlib"
    shutil.copytree(small_library, other)
    result = tvmedit("inspect", small_library, "--out", other, "--corrections", tmp_path / "fix.json")
    assert result.returncode == 2 and "already exists; pass --force" in result.stderr, result.stderr


#: Keys of the inspector as xdotool names them (q, Escape and C end or leave the window).
KEYS = ["Left", "Right", "Up", "Down", "b", "t", "d", "Delete", "m", "p", "x", "u", "Tab", "Return", "s", "r",
        "Home", "End", "Prior", "Next"]


@KEY_SWEEP
@given(keys=st.lists(st.sampled_from(KEYS), min_size=8, max_size=30))
def test_any_keys_leave_a_whole_library_and_corrections_that_read_back(xdisplay, small_library, tmp_path_factory,  # noqa: F811
                                                                          keys):
    from tvmedit.engine import Corrections

    root = tmp_path_factory.mktemp("keys")
    path = root / "gym.tvmlib"
    shutil.copytree(small_library, path)
    fix = root / "corrections.json"
    env = {**os.environ, "DISPLAY": xdisplay, "PYTHONPATH": str(ROOT)}
    app = subprocess.Popen([sys.executable, "-m", "tvmedit", "inspect", str(path), "--corrections", str(fix),
                            "--seconds", "120", "--size", "640x480"], cwd=root, env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    try:
        window = find_window(env, "tvmedit inspect", app, lambda: app.communicate(timeout=10))
        subprocess.run(["xdotool", "windowfocus", "--sync", window], env=env, check=True, timeout=10)
        for key in [*keys, "q"]:
            subprocess.run(["xdotool", "key", "--window", window, key], env=env, timeout=30, capture_output=True)
        out, err = app.communicate(timeout=120)
    finally:
        app.kill()
    assert app.returncode == 0 and "Traceback" not in err, err
    Library.open(path).verify()          # rebuilt or not, the library is whole
    assert fix.exists() == ("s" in keys), err
    if fix.exists():                     # what S saved reads back as corrections
        Corrections.load(fix)
