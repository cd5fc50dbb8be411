"""Display-rate in-betweens: a surface at every instant, in the library, the renderer, render,
export and the player (:mod:`tvmedit.engine.inbetween.instants`)."""

import json
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from conftest import built_library, synth_take
from tvmedit import Library
from tvmedit.engine.inbetween.instants import instants, moved, step_measures, surface_distances
from tvmedit.player.camera import Camera
from tvmedit.player.renderer import Renderer
from tvmedit.player.app import PlayerApp


@pytest.fixture(scope="module")
def library(small_library):
    return Library.open(small_library)


def _edit(library):
    return library.edit([node.id for node in library.nodes][:4])


def _mesh(library, key):
    positions, _, faces, _ = library.frame_mesh(key)
    return np.asarray(positions), np.asarray(faces)


def test_every_step_shown_moves_but_where_the_capture_stands_still(library):
    """A step gets a field unless the fit would not bring the frame nearer the next one (the
    body barely moves there); those are few, and small."""
    natural = np.median([step_measures(_mesh(library, (n.sequence, f)), _mesh(library, (n.sequence, f + 1)), 4)[0]
                         for n in library.nodes for f in range(n.start, n.end, 4)])
    assert library.smooth
    steps = held = 0
    for edit in (_edit(library), library.wander(40, seed=2)):
        schedule = edit.schedule
        for a, b in zip(schedule, schedule[1:]):
            field = library.instant_field(a.key, b.key)
            steps += 1
            if field is None:
                held += 1
                captured = step_measures(_mesh(library, a.key), _mesh(library, b.key), 4)[0]
                assert captured < natural, f"the step {a.key} -> {b.key} moves {captured / natural:.2f} natural steps"
            else:
                assert field.shape == (len(library.frame_mesh(a.key)[0]), 3) and field.dtype == np.float16
    assert held <= 0.1 * steps, (held, steps)


def test_a_field_carries_a_frame_onto_the_next_frames_surface(library):
    schedule = _edit(library).schedule
    for a, b in list(zip(schedule, schedule[1:]))[::7]:
        start, end = _mesh(library, a.key), _mesh(library, b.key)
        captured = surface_distances(start[0], *end).mean()
        arrived = surface_distances(moved(start[0], library.instant_field(a.key, b.key), 1.0), *end).mean()
        assert arrived < 0.35 * captured + 0.002, (a.key, b.key, captured, arrived)


def test_at_sixty_fps_no_step_is_more_than_half_the_capture_step(library):
    """Every step of an edit written at 60 fps from a 10 fps library, middles, transitions and
    wraps, against the larger of the natural step and the captured step it divides."""
    schedule = _edit(library).schedule[28:44]   # a texton, a run of in-between frames, the next
    natural = np.median([step_measures(_mesh(library, a.key), _mesh(library, b.key), stride=4)
                         for a, b in zip(schedule, schedule[1:])], axis=0)
    surfaces = []
    for index, s in instants(len(schedule), 10, 60):
        positions, faces = _mesh(library, schedule[index].key)
        if s and index + 1 < len(schedule):
            positions = moved(positions, library.instant_field(schedule[index].key, schedule[index + 1].key), s)
        surfaces.append((index, positions, faces))
    for (i, p, f), (_, q, g) in zip(surfaces, surfaces[1:]):
        whole = step_measures(_mesh(library, schedule[i].key), _mesh(library, schedule[min(i + 1, len(schedule) - 1)].key),
                              stride=4)
        step = step_measures((p, f), (q, g), stride=4)
        assert step[0] <= 0.5 * max(whole[0], natural[0]), (i, step, whole)
        assert step[1] <= 0.6 * max(whole[1], natural[1]), (i, step, whole)


def test_the_shader_draws_the_surface_the_field_moves_to(ctx, library):
    """Drawn with ``instant=(field, 1)``, a frame looks like the frame moved on the CPU."""
    schedule = _edit(library).schedule
    a, b = schedule[3], schedule[4]
    mesh = library.frame_mesh(a.key)
    field = np.asarray(library.instant_field(a.key, b.key))
    camera = Camera.framing(library.bounds(), 4 / 3)
    renderer = Renderer(ctx, (320, 240), antialias="none", max_counts=library.max_counts())
    try:
        renderer.draw(mesh, camera, instant=(field * 8, 1.0))   # far enough to see
        shader = renderer.read().astype(int)
        renderer.draw((moved(mesh[0], field * 8, 1.0), *mesh[1:]), camera)
        cpu = renderer.read().astype(int)
        renderer.draw(mesh, camera)
        still = renderer.read().astype(int)
    finally:
        renderer.release()
    assert np.abs(shader - cpu).mean() < 0.5
    assert np.abs(still - cpu).mean() > 2.0


def test_render_at_30_fps_keeps_the_timing_and_moves_between_stored_frames(library, tmp_path):
    from tvmedit import player

    edit = library.edit([0, 1])
    out = player.render(edit, tmp_path / "smooth", size=(160, 120), fps=30, progress=False)
    frames = sorted(out.glob("frame_*.png"))
    assert len(frames) == 3 * len(edit.schedule)
    held = player.render(edit, tmp_path / "held", size=(160, 120), fps=30, progress=False, smooth=False)
    import imageio.v3 as iio

    smooth = [iio.imread(f).astype(int) for f in sorted(out.glob("frame_*.png"))[:9]]
    still = [iio.imread(f).astype(int) for f in sorted(held.glob("frame_*.png"))[:9]]
    # each stored frame shown until the instant nearest the next one
    assert all(np.abs(still[k] - still[3 * int(k / 3 + 0.5)]).max() == 0 for k in range(7))
    assert all(np.abs(smooth[k] - smooth[k - 1]).mean() > 0 for k in (1, 2, 4, 5))  # the body moves within
    assert np.abs(smooth[0] - still[0]).max() == 0                                   # stored frames as stored


def test_export_at_60_fps_writes_the_surfaces_and_says_where_each_lies(small_library, tmp_path):
    out = tmp_path / "ex"
    run = subprocess.run([sys.executable, "-m", "tvmedit", "export", str(small_library), "0", "1",
                          "-o", str(out), "--fps", "60", "-q"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    record = json.loads((out / "edit.json").read_text())
    library = Library.open(small_library)
    schedule = library.edit([0, 1]).schedule
    assert record["fps"] == 60 and record["capture_fps"] == 10 and len(record["frames"]) == 6 * len(schedule)
    frame = record["frames"][9]
    assert frame["schedule_index"] == 1 and frame["at"] == 0.5 and frame["next"]["frame"] == schedule[2].frame
    written = trimesh.load(out / frame["file"], process=False)
    expected = moved(library.frame_mesh(schedule[1].key)[0],
                     library.instant_field(schedule[1].key, schedule[2].key), 0.5)
    assert np.abs(np.asarray(written.vertices) - expected).max() < 1e-5
    check = subprocess.run([sys.executable, "-m", "tvmedit", "check", str(out)], capture_output=True, text=True)
    assert check.returncode == 0 and "60 fps" in check.stdout, check.stdout + check.stderr


def test_a_library_without_them_plays_as_captured_and_says_how_to_rebuild(tmp_path):
    path = built_library("walk", synth_take("walk", vertices=3000), smooth=False)
    library = Library.open(path)
    assert not library.smooth
    edit = library.wander(3, seed=0)
    assert library.instant_field(edit.schedule[0].key, edit.schedule[1].key) is None
    run = subprocess.run([sys.executable, "-m", "tvmedit", "render", str(path), "0", "--wander", "3",
                          "-o", str(tmp_path / "v"), "--fps", "30", "--size", "64x48", "-q"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "no display-rate in-betweens" in run.stdout and "rebuild" in run.stdout
    assert len(list((tmp_path / "v").glob("frame_*.png"))) == 90


def test_the_player_places_the_body_by_the_redraw_clock(library):
    graph = library.graph
    app = PlayerApp(graph, library, sorted(graph.nodes), 0, fps=10)
    assert app.tick(0.0)
    app.displayed(0.0)
    field, s = app.instant(0.05)
    assert abs(s - 0.5) < 1e-6 and field.shape == (len(app.mesh()[0]), 3)
    assert app.instant(0.0)[1] == 0.0 and app.instant(0.5)[1] < 1.0
    app.toggle_pause(0.03)
    assert abs(app.instant(5.0)[1] - 0.3) < 1e-6          # paused: the body stays where it was
    app.toggle_pause(5.0)
    assert abs(app.instant(5.01)[1] - 0.4) < 1e-6         # and goes on from there
    plain = PlayerApp(graph, library, sorted(graph.nodes), 0, fps=10, smooth=False)
    plain.tick(0.0)
    plain.displayed(0.0)
    assert plain.instant(0.05) is None


def test_a_rebuild_copies_the_fields_of_the_steps_it_did_not_change(small_library, tmp_path):
    import shutil

    copy = tmp_path / "copy.tvmlib"
    shutil.copytree(small_library, copy)
    before = Library.open(copy)
    node = before.nodes[-1]
    after = before.correct({"sequences": {node.sequence: {"drop": [node.name]}}})
    report = after.report
    # Only the steps of runs made anew are fitted; those of runs copied, in-between frames and
    # all, are copied with them.
    from tvmedit.engine.inbetween.blend import MAX_FRAMES

    assert report["display_made"] <= report["blend_made"] * (MAX_FRAMES + 1) < report["display_steps"], report
    others = [n for n in after.nodes if n.start != node.start]
    a = others[0]
    assert np.array_equal(np.asarray(after.instant_field((a.sequence, a.start), (a.sequence, a.start + 1))),
                          np.asarray(Library.open(small_library).instant_field((a.sequence, a.start),
                                                                               (a.sequence, a.start + 1))))


def test_a_take_captured_at_display_rate_gets_no_fields(synth_gym, tmp_path):
    """At 60 fps a captured step lasts a redraw: a field would move the body within it, at six
    times a 10 fps take's cost. The same frames at 10 fps get theirs."""
    from tvmedit import engine

    take = synth_gym
    fast = engine.build([("gym", take)], tmp_path / "fast.tvmlib", fps=60, workers=2, cache=False, blend_frames=0)
    assert fast.smooth and fast.report["display_steps"] == 0 and fast.report["display_made"] == 0
    node = fast.nodes[0]
    assert fast.instant_field((node.sequence, node.start), (node.sequence, node.start + 1)) is None
    slow = engine.build([("gym", take)], tmp_path / "slow.tvmlib", fps=10, workers=2, cache=False, blend_frames=0)
    assert slow.report["display_made"] > 0


def test_sequences_named_like_a_run_get_their_fields(synth_gym, tmp_path):
    """Mesh ids are matched by what they show, and a run is told from a frame by a tag, not by
    the sequence's name: a take named "edge" builds and rebuilds like any other."""
    from tvmedit import engine

    take = synth_gym
    library = engine.build([("edge", take)], tmp_path / "edge.tvmlib", workers=2, cache=False, blend_frames=0)
    assert library.report["display_made"] > 0
    node = library.nodes[-1]
    again = library.correct({"sequences": {"edge": {"drop": [node.name]}}})
    assert again.report["display_made"] == 0 and again.smooth
