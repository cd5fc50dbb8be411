"""The realtime player: its logic on a fake clock, then a real window under Xvfb pressed with xdotool.

The window tests start their own ``Xvfb`` on a display number it chooses and drive
``python -m tvmedit play`` with real key presses; what the player showed is read back from
its ``--log``. They skip where Xvfb or xdotool is missing (``.ci/run`` installs both).
"""

import json
import os
import select
import shutil
import subprocess
import sys
import time

import networkx as nx
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import ROOT
from tvmedit.engine.errors import NoPath
from tvmedit.engine.graph.search import best_path
from tvmedit.player.source import ArraySource
from tvmedit.player.app import MAX_LAG_S, PlayerApp, motion_keys


def _tiny_source_and_graph():
    """Three textons of one sequence: 0 <-> 1 -> 2, and 2 a dead end; frames are triangles."""
    triangle = np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1]], np.float32)
    frames = {("s", f): (triangle + 0.01 * f, np.full((3, 3), 200, np.uint8), [[0, 1, 2]]) for f in range(12)}
    g = nx.DiGraph()
    for node, (start, end) in enumerate([(0, 3), (4, 7), (8, 11)]):
        g.add_node(node, name=f"s/{node:02d}", sequence="s", start=start, end=end)
    g.add_edge(0, 1, weight=0.2, exit_frame=2, entry_frame=5)
    g.add_edge(1, 0, weight=0.2, exit_frame=5, entry_frame=2)
    g.add_edge(1, 2, weight=0.3, exit_frame=7, entry_frame=8)
    return ArraySource(frames), g


class _Log(list):
    def write(self, text):
        self.append(json.loads(text))

    def flush(self):
        pass


def _app(**options):
    source, graph = _tiny_source_and_graph()
    log = _Log()
    app = PlayerApp(graph, source, [0, 1, 2], 0, fps=10, log=log, print_=lambda text: None, **options)
    return app, log


def _play(app, start, stop, step=0.001):
    """Run the playback clock from ``start`` to ``stop`` as a window would, logging each frame."""
    shown = []
    for now in np.arange(start, stop, step):
        if app.tick(now):
            app.displayed(now)
            shown.append((round(float(now), 3), app.entry.node, app.entry.frame))
    return shown


def test_keys_follow_info_order_and_skip_the_command_letters():
    keys = motion_keys(14)
    assert keys[:10] == list("1234567890")
    assert keys[10:] == ["a", "b", "c", "d"]
    assert not set("qrs") & set(motion_keys(40))


def test_playback_clock_shows_one_frame_per_slot_whatever_the_redraw_rate():
    app, log = _app()
    shown = _play(app, 0.0, 1.0, step=0.0167)          # a 60 Hz display
    times = [t for t, _, _ in shown]
    assert len(shown) == 10
    assert np.allclose(np.diff(times), 0.1, atol=0.0167)
    assert [f for _, _, f in shown] == [0, 1, 2, 3, 0, 1, 2, 3, 0, 1]   # texton 0 loops
    assert [row["frame"] for row in log] == [f for _, _, f in shown]


def test_a_stall_restarts_the_clock_instead_of_rushing():
    app, _ = _app()
    assert app.tick(0.0)
    assert not app.tick(0.05)
    assert app.tick(0.1 + MAX_LAG_S + 0.5)             # one frame after the stall, not six
    assert not app.tick(0.1 + MAX_LAG_S + 0.55)
    assert app.tick(0.1 + MAX_LAG_S + 0.6)


def test_queue_follows_the_playhead_and_backspace_unqueues_the_last():
    app, log = _app()
    app.tick(0.0)
    app.press("2", 0.01)
    app.press("3", 0.02)
    assert app.playhead.queue_list == [1, 2]
    app.press("backspace", 0.03)
    assert app.playhead.queue_list == [1]
    assert app.seconds_to_next_key(0.03) == pytest.approx(0.07 + 0.1 * app.playhead.frames_until_next_key())
    shown = _play(app, 0.05, 1.0)
    # Texton 0 plays to its exit frame 2 through all four frames, then 1 is entered at 5.
    assert [(n, f) for _, n, f in shown[:4]] == [(0, 1), (0, 2), (0, 3), (0, 0)]
    first_of_1 = next(i for i, (_, n, _) in enumerate(shown) if n == 1)
    assert shown[first_of_1 - 1][2] == 2 and shown[first_of_1][2] == 5
    assert log[-1]["queue"] == []


def test_shift_key_holds_the_motion_and_the_time_to_next_counts_the_hold():
    plain, _ = _app()
    held, log = _app(hold_seconds=2.0)
    for app in (plain, held):
        app.tick(0.0)
        app.press("2", 0.01, shift=app is held)
        app.press("3", 0.02)
    assert log[-2]["event"] == "queued" and log[-2]["hold"] == 2.0 and held.playhead.queue_list == [1, 2]
    assert "held for 2 s" in held.message_text(0.03)
    # Texton 0 plays 0 1 2 3 0 1 2, then 1 begins at 0.7 s in both; the held one stays 2 s longer.
    shown = {app: _play(app, 0.05, 1.0) for app in (plain, held)}
    assert shown[plain] == shown[held] and shown[held][-3][1] == 1
    assert held.seconds_to_next_key(1.0) == pytest.approx(plain.seconds_to_next_key(1.0) + 2.0)
    assert "(held 1.7 s more)" in held.status_lines(1.0)[-1]
    frames = shown[held] + _play(held, 1.0, 6.0)
    runs = _runs([{"node": n, "frame": f} for _, n, f in frames])
    assert [node for node, _ in runs] == [0, 1, 2]
    assert len(runs[1][1]) == 20 + 7       # the hold, then the rule: all 4 frames, to exit frame 7


def test_an_unreachable_key_is_refused_and_the_queue_keeps_the_others():
    app, log = _app()
    app.tick(0.0)
    app.press("3", 0.01)                               # 0 -> 1 -> 2
    app.press("1", 0.02)                               # 2 is a dead end: refused
    assert app.playhead.queue_list == [2]
    refusal = log[-1]
    assert refusal["event"] == "refused" and refusal["node"] == 0 and refusal["key"] == "1"
    assert "refused" in app.message_text(0.03)
    assert _play(app, 0.05, 0.5)                       # playback goes on


def test_a_key_for_the_motion_playing_or_last_queued_is_ignored_quietly():
    app, log = _app()
    app.tick(0.0)
    app.press("1", 0.01)                               # 0 is playing
    assert app.playhead.queue_list == [] and app.message_text(0.02) is None and not log
    app.press("2", 0.03)
    app.press("2", 0.04)                               # 1 is already last in the queue
    assert app.playhead.queue_list == [1] and app.message_text(0.05) is None
    assert [row["event"] for row in log if "event" in row] == ["queued"]


def test_the_legend_greys_out_what_the_forbidden_motions_cut_off():
    app, _ = _app()
    assert app.legend_dimmed() == set()                # from 0, 1 and 2 are reachable
    app, _ = _app(forbidden=[1])
    assert app.legend_dimmed() == {1, 2}               # 1 is forbidden and 2 lies behind it
    assert app.legend_lines()[:3] == ["[1] 0 s/00", "[2] 1 s/01", "[3] 2 s/02"]


def test_a_forbidden_motion_cannot_be_queued():
    app, log = _app(forbidden=[1])
    app.tick(0.0)
    assert not app.queue(2, 0.01)                      # only path runs through 1
    assert log[-1]["event"] == "refused"
    with pytest.raises(NoPath):
        best_path(app.graph, 0, 2, forbidden=[1])


def test_pause_holds_the_frame_and_resumes_where_it_left_off():
    app, _ = _app()
    app.tick(0.0)
    app.press("space", 0.04)
    assert not _play(app, 0.05, 2.0)
    app.press("space", 2.0)
    assert app.next_frame_at() == pytest.approx(2.06)
    assert app.tick(2.06) and app.entry.frame == 1


def test_camera_keys_orbit_zoom_and_reset():
    app, _ = _app()
    home = app.camera
    app.orbit(30, 10)
    app.press("+", 0.0)
    assert app.camera.azimuth == pytest.approx(home.azimuth + 30)
    assert app.camera.elevation == pytest.approx(home.elevation + 10)
    assert app.camera.distance < home.distance
    app.press("r", 0.0)
    assert app.camera == home
    assert app.press("s", 0.0) == "screenshot" and app.press("q", 0.0) == "quit"


@pytest.fixture(scope="session")
def xdisplay():
    """``:N`` of an Xvfb started for this session (1024x768x24); DISPLAY for subprocesses."""
    missing = [tool for tool in ("Xvfb", "xdotool") if shutil.which(tool) is None]
    if missing:
        pytest.skip(f"{' and '.join(missing)} not installed (apt-get install xvfb xdotool)")
    # Xvfb chooses a free display number itself and writes it to -displayfd once it is ready,
    # so that test processes starting servers at the same moment never pick the same one.
    # It resets whenever its last client leaves and refuses connections meanwhile: the player
    # tries a refused display again (player.window.Window._init_glfw). -noreset would keep
    # one test's leftovers for the next: the inspector's sweep then quit at once.
    read, write = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "1024x768x24", "-nolisten", "tcp"],
                              pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    number = b""
    deadline = time.monotonic() + 30
    while not number.endswith(b"\n") and time.monotonic() < deadline:
        ready, _, _ = select.select([read], [], [], 0.1)
        if ready:
            chunk = os.read(read, 16)
            if not chunk:
                break
            number += chunk
    os.close(read)
    if not number.strip().isdigit():
        server.kill()
        server.wait()
        pytest.fail("Xvfb did not start (no display number on -displayfd within 30 s)")
    yield f":{number.strip().decode()}"
    server.terminate()
    server.wait(timeout=10)


def _rows(log_path):
    if not log_path.exists():
        return []
    return [json.loads(line) for line in log_path.read_text().splitlines() if line.endswith("}")]


def _frames(rows):
    return [row for row in rows if "event" not in row]


def _wait_for(predicate, log_path, timeout):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate(_rows(log_path)):
            return True
        time.sleep(0.05)
    return False


def _plan(graph):
    """Start S, then key motions A and B (B reachable from A), C to queue and take back, and
    U, a motion that the player must refuse after B."""
    reach = {node: nx.descendants(graph, node) for node in graph}
    for s in sorted(graph, key=lambda n: -len(reach[n])):
        for a in sorted(reach[s] - {s}):
            for b in sorted(reach[a] - {a, s}):
                others = sorted(reach[b] - {b})
                unreachable = sorted(set(graph) - reach[b] - {b})
                if others and unreachable:
                    return s, a, b, others[0], unreachable[0]
    pytest.skip("the test library has no motion unreachable from a two-step path")


def _runs(frames):
    """Consecutive frames of one node: [(node, [frame, ...]), ...]."""
    runs = []
    for row in frames:
        if runs and runs[-1][0] == row["node"]:
            runs[-1][1].append(row["frame"])
        else:
            runs.append((row["node"], [row["frame"]]))
    return runs


def find_window(env, name, process, finish):
    """The X window id of ``process``'s window titled ``name``, looked for until it shows or the
    process ends: on a loaded machine a window may take longer than xdotool's own wait."""
    deadline, found, searched = time.monotonic() + 45, [], None
    while not found and time.monotonic() < deadline and process.poll() is None:
        searched = subprocess.run(["xdotool", "search", "--name", name], env=env, capture_output=True, text=True,
                                  timeout=20)
        found = searched.stdout.split() or time.sleep(0.2) or []
    assert found, f"no window {name!r}; xdotool: {searched and searched.stderr!r}; process: {finish()}"
    return found[0]


#: Random key sequences sent to a real window (the player's, the inspector's): the same two on
#: every run, or TVMEDIT_HOSTILE_EXAMPLES / 20 new ones, to hunt.
KEY_SWEEP = settings(max_examples=int(os.environ.get("TVMEDIT_HOSTILE_EXAMPLES", "0")) // 20 or 2, deadline=None,
                     derandomize="TVMEDIT_HOSTILE_EXAMPLES" not in os.environ, database=None,
                     suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


class _Window:
    """``tvmedit play ARGS`` in a real window under Xvfb, driven with xdotool keys."""

    def __init__(self, display, args, tmp_path):
        self.env = {**os.environ, "DISPLAY": display, "PYTHONPATH": str(ROOT)}
        self.log_path = tmp_path / "play.jsonl"
        self.player = subprocess.Popen([sys.executable, "-m", "tvmedit", "play", *map(str, args),
                                        "--log", str(self.log_path)], cwd=tmp_path, env=self.env,
                                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def __enter__(self):
        self.window = find_window(self.env, "tvmedit", self.player, self._finish)
        subprocess.run(["xdotool", "windowfocus", "--sync", self.window], env=self.env, check=True, timeout=10)
        assert _wait_for(lambda rows: _frames(rows), self.log_path, 20), "no frame was shown"
        return self

    def __exit__(self, *exc):
        self._finish()

    def _finish(self):
        if self.player.poll() is None:
            self.player.kill()
        return self.player.communicate()

    def press(self, *keys):
        for key in keys:
            sent = subprocess.run(["xdotool", "key", "--window", self.window, key], env=self.env, timeout=10,
                                  capture_output=True, text=True)
            assert sent.returncode == 0, f"xdotool: {sent.stderr}; player: {self._finish()}"
            time.sleep(0.15)

    def quit(self):
        """Press Q; returns (stdout, stderr) once the player has quit by itself."""
        # The player may close its window between xdotool's key press and release, which
        # xdotool reports as an error: what counts is that the player quits.
        subprocess.run(["xdotool", "key", "--window", self.window, "q"], env=self.env, capture_output=True,
                       timeout=10)
        out, err = self.player.communicate(timeout=20)
        assert self.player.returncode == 0, err
        return out, err

    def rows(self):
        return _rows(self.log_path)


def test_keys_pressed_in_a_real_window_queue_motions_along_best_paths(xdisplay, paper_library, tmp_path):
    # The paper's graph (--connect off) still cuts motions off: refusals are checked on it.
    from tvmedit.engine.store.library import Library

    library = Library.open(paper_library)
    graph = library.graph
    order = [node.id for node in library.nodes]
    key_of = dict(zip(order, motion_keys(len(order))))
    s, a, b, c, u = _plan(graph)
    forbid = next((n for n in order if n not in (s, a, b, c, u) and n not in best_path(graph, s, a)
                   and n not in best_path(graph, a, b)), None)
    args = [paper_library, s, "--seconds", "40", "--size", "640x480"]
    if forbid is not None:
        args += ["--forbid", forbid]
    with _Window(xdisplay, args, tmp_path) as window:
        window.press(key_of[a], key_of[b], key_of[c], "BackSpace", key_of[u])
        if forbid is not None:
            window.press(key_of[forbid])
        window.press("s")
        # Q quits once B has been reached and shown for a second.
        assert _wait_for(lambda rows: any(r.get("node") == b and not r["queue"] for r in _frames(rows)),
                         window.log_path, 30), "the second key motion was never reached"
        time.sleep(1.0)
        out, err = window.quit()

    rows = window.rows()
    frames = _frames(rows)
    assert rows[0]["event"] == "start" and rows[-1]["event"] == "stop"
    assert rows[-1]["t"] < 40, "Q did not quit the player"

    # Key motions are reached in order, through the best paths.
    runs = _runs(frames)
    nodes = [node for node, _ in runs]
    expected = best_path(graph, s, a, forbidden=[forbid] if forbid is not None else [])
    expected += best_path(graph, a, b, forbidden=[forbid] if forbid is not None else [])[1:]
    assert nodes == expected
    _check_textons_and_transitions(graph, runs)
    _check_queue(rows, frames, a, b, c)
    _check_refusals(rows, frames, err, key_of, [u] + ([forbid] if forbid is not None else []))
    _check_screenshot(out, tmp_path)


def _check_textons_and_transitions(graph, runs):
    # Every texton is shown completely, in its cyclic order, before it is left; each
    # transition leaves and enters at the frames the graph gives.
    for k, (node, shown) in enumerate(runs[:-1]):
        start, end = graph.nodes[node]["start"], graph.nodes[node]["end"]
        length = end - start + 1
        assert set(shown) == set(range(start, end + 1)), f"texton {node} not shown completely"
        assert all(start + (f - start + 1) % length == g for f, g in zip(shown, shown[1:]))
        target, entered = runs[k + 1][0], runs[k + 1][1][0]
        edge = graph.edges[node, target]
        assert (shown[-1], entered) == (edge["exit_frame"], edge["entry_frame"])


def _check_queue(rows, frames, a, b, c):
    # Backspace took back C: the queue held it, then lost it, and C was never reached as a key.
    events = [(row["event"], row["node"], tuple(row["queue"])) for row in rows
              if row.get("event") in ("queued", "unqueued")]
    assert events == [("queued", a, (a,)), ("queued", b, (a, b)), ("queued", c, (a, b, c)), ("unqueued", c, (a, b))]
    taken_back = next(row["t"] for row in rows if row.get("event") == "unqueued")
    queues = [tuple(row["queue"]) for row in frames if row["t"] > taken_back]
    assert queues and all(c not in q for q in queues)
    assert (a, b) in queues or (b,) in queues


def _check_refusals(rows, frames, err, key_of, refused_nodes):
    # The unreachable (and the forbidden) key motions were refused, and playback went on.
    refused = [row for row in rows if row.get("event") == "refused"]
    assert [row["node"] for row in refused] == refused_nodes
    assert all(row["key"] == key_of[row["node"]] and "path" in row["message"] for row in refused)
    assert "No path" in err or "no path" in err
    after = [row["t"] for row in frames if row["t"] > refused[-1]["t"]]
    assert len(after) >= 10 and max(np.diff(after)) < 0.5


def _check_screenshot(out, tmp_path):
    # S saved a screenshot of the actor: many pixels differ from the background.
    saved = [line.split(" saved to ")[-1] for line in out.splitlines() if "screenshot saved to" in line]
    assert saved, out
    import imageio.v3 as iio

    image = iio.imread(tmp_path / saved[0]).astype(np.float64)
    assert image.shape[:2] == (480, 640) and image.std() > 10
    background = np.median(image.reshape(-1, 3), axis=0)
    foreground = np.abs(image - background).sum(axis=2) > 60
    assert foreground.mean() > 0.01


def _play_command(*args, env=None):
    return subprocess.run([sys.executable, "-m", "tvmedit", "play", *map(str, args)], capture_output=True,
                          text=True, timeout=60, env=env, cwd=ROOT)


def test_bad_arguments_and_a_missing_display_are_one_sentence(small_library, tmp_path):
    missing = _play_command(tmp_path / "nowhere")
    assert missing.returncode != 0 and missing.stderr.count("\n") == 1 and "no library" in missing.stderr
    unknown = _play_command(small_library, "no-such-motion")
    assert unknown.returncode != 0 and unknown.stderr.count("\n") == 1 and "no-such-motion" in unknown.stderr
    env = {key: value for key, value in os.environ.items() if key not in ("DISPLAY", "WAYLAND_DISPLAY")}
    headless = _play_command(small_library, env=env)
    assert headless.returncode != 0 and headless.stderr.strip() == (
        "error: no display: set DISPLAY or run under xvfb-run; for files use tvmedit render.")
    # A display that no server answers: glfw's own reason is in the one sentence.
    nobody = _play_command(small_library, env={**env, "DISPLAY": ":65000", "PYGLFW_LIBRARY_VARIANT": "x11"})
    assert nobody.returncode != 0 and nobody.stderr.count("\n") == 1 and "Traceback" not in nobody.stderr
    assert nobody.stderr.startswith("error: cannot open the display :65000 (X11: Failed to open display :65000)")


def test_an_unwritable_log_is_one_sentence(small_library, tmp_path):
    env = {**os.environ, "DISPLAY": os.environ.get("DISPLAY", ":0")}
    result = _play_command(small_library, "--log", tmp_path / "no" / "such" / "log.jsonl", "--seconds", "1", env=env)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr.startswith("error: cannot write the log") and result.stderr.count("\n") == 1


def test_without_keys_the_player_starts_on_the_first_motion_not_forbidden(xdisplay, small_library, tmp_path):
    from tvmedit import Library

    order = [node.id for node in Library.open(small_library).nodes]
    log = tmp_path / "play.jsonl"
    # --seconds counts from the command's start: on a busy 2-core machine the imports and the
    # first window took over 2 s, and the player quit before drawing a frame.
    result = _play_command(small_library, "--forbid", str(order[0]), "--log", log, "--seconds", "6",
                           env={**os.environ, "DISPLAY": xdisplay})
    assert result.returncode == 0, result.stderr
    frames = _frames(_rows(log))
    assert frames and {row["node"] for row in frames} == {order[1]}


def test_pressing_every_motion_key_in_turn_plays_them_all_with_no_refusal(xdisplay, small_library, tmp_path):
    """Issue 12's bar: on the demo library (connected by default) no key is refused."""
    from tvmedit import Library

    order = [node.id for node in Library.open(small_library).nodes]
    with _Window(xdisplay, [small_library, "--seconds", "60", "--size", "320x240", "--fps", "40"],
                 tmp_path) as window:
        window.press(*motion_keys(len(order)))         # the first is the motion playing: ignored
        assert _wait_for(lambda rows: any(r.get("node") == order[-1] and not r["queue"] for r in _frames(rows)),
                         window.log_path, 40), "the last motion was never reached"
        _, err = window.quit()
    rows = window.rows()
    assert not [row for row in rows if row.get("event") == "refused"], err
    assert [row["node"] for row in rows if row.get("event") == "queued"] == order[1:]
    reached = iter(node for node, _ in _runs(_frames(rows)))
    assert all(any(node == key for node in reached) for key in order)       # in this order
    # In-between frames (tvmedit.engine.inbetween.blend) are logged as such, between the two motions of their edge.
    frames = _frames(rows)
    plain = [k for k, row in enumerate(frames) if "blend" not in row]
    for k, row in enumerate(frames):
        if "blend" in row:
            before = max(i for i in plain if i < k)
            after = min(i for i in plain if i > k)
            assert row["blend"][0] == [frames[before]["node"], frames[after]["node"]], row


def test_shift_key_in_a_real_window_holds_the_motion(xdisplay, small_library, tmp_path):
    from tvmedit import Library

    library = Library.open(small_library)
    order = [node.id for node in library.nodes]
    keys = motion_keys(len(order))
    with _Window(xdisplay, [small_library, "--seconds", "60", "--size", "320x240", "--fps", "40",
                            "--hold-seconds", "1.5"], tmp_path) as window:
        window.press(f"shift+{keys[1]}", keys[2])
        assert _wait_for(lambda rows: any(r.get("node") == order[2] and not r["queue"] for r in _frames(rows)),
                         window.log_path, 40), "the motion queued after the held one was never reached"
        window.quit()
    rows = window.rows()
    queued = [row for row in rows if row.get("event") == "queued"]
    assert [(row["node"], row.get("hold")) for row in queued] == [(order[1], 1.5), (order[2], None)]
    held = next(frames for node, frames in _runs(_frames(rows)) if node == order[1])
    texton = library.node(order[1])
    assert len(held) >= 60 + texton.end - texton.start + 1    # 1.5 s at 40 fps, then the whole texton


def test_stats_are_printed_when_the_player_is_ended_by_sigterm(xdisplay, small_library, tmp_path):
    with _Window(xdisplay, [small_library, "--stats", "--size", "320x240"], tmp_path) as window:
        time.sleep(1.0)
        window.player.terminate()
        out, err = window.player.communicate(timeout=20)
    assert "redraws per second" in err, err
    assert window.rows()[-1].get("event") == "stop"


def test_wandering_plays_motions_by_itself_and_honours_a_key(xdisplay, small_library, tmp_path):
    from tvmedit import Library

    library = Library.open(small_library)
    order = [node.id for node in library.nodes]
    keys = motion_keys(len(order))
    args = [small_library, "--wander", "--seed", "2", "--seconds", "60", "--size", "320x240", "--fps", "40"]
    with _Window(xdisplay, args, tmp_path) as window:
        assert _wait_for(lambda rows: len({r["node"] for r in _frames(rows)}) >= 3, window.log_path, 30), \
            "the walk did not move on by itself"
        shown = {r["node"] for r in _frames(window.rows())}
        key = next(k for k, n in zip(keys, order) if n not in shown)
        window.press(key)
        target = order[keys.index(key)]
        assert _wait_for(lambda rows: any(r.get("node") == target for r in _frames(rows)), window.log_path, 30), \
            "the key pressed mid-walk was never reached"
        # and the walk goes on from there, to another motion
        assert _wait_for(lambda rows: _runs(_frames(rows))[-1][0] != target
                         and any(n == target for n, _ in _runs(_frames(rows))), window.log_path, 30), \
            "the walk did not resume after the key motion"
        window.quit()
    runs = _runs(_frames(window.rows()))
    assert all(a != b for (a, _), (b, _) in zip(runs, runs[1:]))   # no motion twice back to back


#: Keys a user may press in the player, as xdotool names them (Q ends the window).
PLAYER_KEYS = ["1", "2", "3", "4", "5", "6", "shift+1", "shift+3", "space", "BackSpace", "plus", "minus", "r",
               "Left", "Right", "Up", "Down", "s", "7", "z"]


@KEY_SWEEP
@given(keys=st.lists(st.sampled_from(PLAYER_KEYS), min_size=8, max_size=30))
def test_any_keys_in_the_player_leave_it_playing_until_q(xdisplay, small_library, tmp_path_factory, keys):
    tmp_path = tmp_path_factory.mktemp("player-keys")
    with _Window(xdisplay, [small_library, "--seconds", "60", "--size", "320x240"], tmp_path) as window:
        window.press(*keys)
        before = len(_frames(window.rows()))
        time.sleep(0.5)
        if keys.count("space") % 2 == 0:        # not left paused
            assert len(_frames(window.rows())) > before, "the player stopped drawing"
        _, err = window.quit()
    assert "Traceback" not in err, err
    assert window.rows()[-1].get("event") == "stop", window.rows()[-1]
