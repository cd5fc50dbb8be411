"""In-between frames at transitions (tvmedit.engine.inbetween.blend), built into libraries of real takes: no
displayed step across a transition is larger than natural motion, and every in-between frame
looks like the person; edits, exports and the schedule carry them."""

import json

import numpy as np
import pytest

from conftest import built_library
from tvmedit.engine.inbetween import blend, fit
from tvmedit import Library
from tvmedit.engine.playback import Playhead
from tvmedit.engine.capture.load import read_frame
from tvmedit.cli import main


@pytest.fixture(scope="module")
def libraries(take_13_29, take_13_30, synth_gym):
    """The three takes of the issue, built at default options (blends included), once per
    version of the engine's code."""
    return {name: Library.open(built_library(name, take, smooth=False))
            for name, take in (("13_29", take_13_29), ("13_30", take_13_30), ("gym", synth_gym))}


def _window(library, u, v):
    """The displayed frames from the exit frame to the entry frame of edge ``u -> v``: keys."""
    data = library.graph.edges[u, v]
    a, b = library.nodes[u], library.nodes[v]
    run = [(a.sequence, data["exit_frame"])]
    run += [(a.sequence, data["exit_frame"], ((u, v), i)) for i in range(data.get("blend", 0))]
    return run + [(b.sequence, data["entry_frame"])]


def _all_windows(libraries):
    for name, library in libraries.items():
        for u, v in sorted(library.graph.edges):
            yield name, library, (u, v), [library.frame_mesh(key) for key in _window(library, u, v)]


def test_every_transition_steps_at_most_a_natural_step_and_cuts_did_not(libraries):
    ratios = {}
    for name, library, edge, meshes in _all_windows(libraries):
        natural = library.natural_step
        steps = [blend.chamfer(p[0], q[0]) for p, q in zip(meshes, meshes[1:])]
        assert max(steps) <= 1.25 * natural, (name, edge, [round(s / natural, 2) for s in steps])
        cut = blend.chamfer(meshes[0][0], meshes[-1][0])
        assert library.blend_runs()[edge]["jump"] == pytest.approx(cut, rel=0.02)
        ratios.setdefault(name, []).append(cut / natural)
    # Without blending, real takes pop by two frames' worth of motion (the issue's table).
    assert np.median(ratios["13_29"]) > 1.5 and max(ratios["13_30"]) > 2
    assert max(ratios["gym"]) > 1.25


def test_transitions_join_frames_whose_limbs_lie_alike(libraries):
    # The features of eq. (10) do not see where the arms are, and a forearm before the chest
    # joined to one raised to the face jumps where the run switches from one warp to the other.
    # Each transition is made at a pair of frames all but tied with eq. (10)'s by the features
    # whose poses are nearest, and its fields are fitted matching points by colour (and by
    # position too where that run steps unevenly, the smaller steps kept): no step of any
    # transition moves the points, each matched to the point of the other frame that looks
    # alike, more than 1.25 natural steps by that measure on 13_29 (1.82 at eq. (10)'s own
    # pairs) and on 13_30 (2.35 with fields fitted by position alone, the forearms laid flat on
    # the shirt).
    from tvmedit.engine.features.vectors import distance_matrix
    from tvmedit.engine.graph.motiongraph import entry_range, exit_range
    from tvmedit.engine.inbetween.instants import matched_tail
    from tvmedit.engine.inbetween.pairs import TIE

    for name in ("13_29", "13_30"):
        library = libraries[name]

        def coloured(key):
            return library.frame_mesh(key)[:2]

        natural = np.median([matched_tail(coloured((n.sequence, f)), coloured((n.sequence, f + 1)))
                             for n in library.nodes for f in range(n.start, n.end, 6)])
        worst = {}
        for u, v in sorted(library.graph.edges):
            keys = _window(library, u, v)
            worst[u, v] = max(matched_tail(coloured(a), coloured(b)) for a, b in zip(keys, keys[1:])) / natural
        assert max(worst.values()) <= 1.25, (name, {edge: round(w, 2) for edge, w in worst.items()})
    moved = 0
    for library in libraries.values():    # the frames move; the weights, and what a pair costs, hardly
        for u, v, data in library.graph.edges(data=True):
            a, b = library.nodes[u], library.nodes[v]
            (x0, x1), (e0, e1) = exit_range(a), entry_range(b)
            va = np.asarray(library.features(a.sequence).vectors)[x0:x1 + 1]
            vb = np.asarray(library.features(b.sequence).vectors)[e0:e1 + 1]
            d = distance_matrix(np.concatenate([va, vb]))[:len(va), len(va):]
            assert d[data["exit_frame"] - x0, data["entry_frame"] - e0] <= (1 + TIE) * d.min() + 1e-12
            moved += d[data["exit_frame"] - x0, data["entry_frame"] - e0] > d.min()
    assert moved >= 3


def test_a_limb_that_moves_along_the_body_is_carried_by_its_colour():
    # A patch of skin on a shirt, the same surface in both frames, the skin 30 cm further up
    # in the second: by position alone every point already lies on the other surface and
    # nothing moves; matched by colour as well, the skin travels most of the way.
    grid = np.stack(np.meshgrid(np.linspace(0, 1, 60), np.linspace(0, 1, 60)), -1).reshape(-1, 2)
    points = np.column_stack([grid, np.zeros(len(grid))])
    shirt, skin = [40, 90, 170], [224, 172, 140]

    def dressed(low):
        arm = (points[:, 1] >= low) & (points[:, 1] < low + 0.2) & (abs(points[:, 0] - 0.5) < 0.1)
        return np.where(arm[:, None], skin, shirt).astype(np.uint8), arm

    (before, arm), (after, _) = dressed(0.1), dressed(0.4)
    assert abs(fit.align(points, points)[arm, 1].mean()) < 0.03
    assert fit.align(points, points, colours=(before, after))[arm, 1].mean() > 0.15


def test_in_between_frames_look_like_the_person(libraries):
    frames = 0
    for name, library, edge, meshes in _all_windows(libraries):
        (a, *between, b) = meshes
        areas = blend.surface_area(a[0], a[2]), blend.surface_area(b[0], b[2])
        cut = blend.chamfer(a[0], b[0])
        for k, (positions, colours, faces, normals) in enumerate(between):
            t = (k + 1) / (len(between) + 1)
            expected = (1 - t) * areas[0] + t * areas[1]
            assert abs(blend.surface_area(positions, faces) / expected - 1) <= 0.10, (name, edge, k)
            # Colours of the frame it was warped from, which has no black or default-grey vertex.
            source = (a, b)[blend.side(k, len(between))]
            assert np.array_equal(colours, source[1]) and np.array_equal(faces, source[2])
            grey = (colours.min(axis=1) > 120) & (colours.max(axis=1) < 136)
            assert not ((colours.max(axis=1) < 8) | grey).any(), (name, edge, k)
            assert np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-3)
            # Not a double exposure: about half the cut from the nearer source, never the whole.
            nearer = min(blend.chamfer(positions, a[0]), blend.chamfer(positions, b[0]))
            assert nearer <= 0.75 * cut, (name, edge, k, nearer / cut)
            frames += 1
    assert frames >= 40


def _direct_blended_edge(library):
    """An edge with in-between frames that is the best path between its ends."""
    for u, v, data in sorted(library.graph.edges(data=True), key=lambda e: -e[2].get("blend", 0)):
        edit = library.edit([u, v])
        if data.get("blend") and [(t.source, t.target) for t in edit.transitions] == [(u, v)]:
            return u, v, edit
    raise AssertionError("no direct transition with in-between frames")


def test_edits_play_the_in_between_frames_between_exit_and_entry(libraries):
    library = libraries["13_30"]
    u, v, edit = _direct_blended_edge(library)
    count = library.graph.edges[u, v]["blend"]
    transition = edit.transitions[0]
    assert transition.blend == count
    marked = [i for i, entry in enumerate(edit.schedule) if entry.blend is not None and entry.blend[0] == (u, v)]
    assert marked == list(range(transition.index - count, transition.index))
    assert [edit.schedule[i].blend for i in marked] == [((u, v), i) for i in range(count)]
    # Every frame of the first texton is still shown before the run (section 8).
    node = library.nodes[u]
    shown = {e.frame for e in edit.schedule[:marked[0]]}
    assert shown == set(range(node.start, node.end + 1))
    # The realtime player's state machine plays exactly the same frames.
    head = Playhead(library.graph, u)
    head.advance()
    head.queue(v)
    assert [edit.schedule[0]] + [head.advance() for _ in range(len(edit.schedule) - 1)] == edit.schedule
    assert head.transitions == edit.transitions


def test_path_json_and_export_mark_the_in_between_frames(libraries, tmp_path, capsys):
    library = libraries["13_30"]
    u, v, _ = _direct_blended_edge(library)
    assert main(["path", str(library.path), str(u), str(v), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    marked = [entry for entry in data["schedule"] if "blend" in entry]
    between = [entry for entry in marked if entry["blend"][0] == [u, v]]
    assert between and data["transitions"][0]["blend_frames"] == len(between)
    # The others close a loop (tvmedit.engine.inbetween.loops): frames of the motion, marked [[n, n], i].
    assert all(e["blend"][0] == [e["node"], e["node"]] for e in marked if e not in between)

    assert main(["export", str(library.path), str(u), str(v), "-o", str(tmp_path / "out"), "-q"]) == 0
    record = json.loads((tmp_path / "out" / "edit.json").read_text())
    blended = [frame for frame in record["frames"] if "blend" in frame]
    assert [frame["blend"] for frame in blended] == [entry["blend"] for entry in marked]
    for frame in blended:
        mesh = read_frame(tmp_path / "out" / frame["file"])
        key = (frame["sequence"], frame["frame"], (tuple(frame["blend"][0]), frame["blend"][1]))
        positions, colours, faces, _ = library.frame_mesh(key)
        assert np.allclose(mesh.positions, positions) and np.array_equal(mesh.colours, colours)
        assert np.array_equal(mesh.faces, faces)


def test_blend_frames_option_fixes_the_count_and_zero_keeps_the_cut(take_13_30, tmp_path, capsys):
    out = tmp_path / "lib.tvmlib"
    first_100 = str(take_13_30 / "frame_000[0-9]?.ply")
    # (no display-rate in-betweens in either build: the transitions' frames are what is checked)
    assert main(["build", first_100, "-o", str(out), "-q", "--workers", "2", "--blend-frames", "0", "--no-smooth"]) == 0
    library = Library.open(out)
    assert all(run["count"] == 0 for run in library.blend_runs().values())
    assert not any("blend" in data for _, _, data in library.graph.edges(data=True))
    # The paper's cut is made where eq. (10) says, at the nearest pair by the features.
    from tvmedit.engine.graph.motiongraph import transitions

    vectors = {seq: library.features(seq).vectors for seq in {n.sequence for n in library.nodes}}
    frames = transitions(library.nodes, vectors)[1]
    assert all((data["exit_frame"], data["entry_frame"]) == frames[u, v]
               for u, v, data in library.graph.edges(data=True))
    assert library.info()["natural_step"] > 0

    assert main(["build", first_100, "-o", str(out), "--force", "--workers", "2",
                 "--blend-frames", "2", "--no-smooth"]) == 0
    err = capsys.readouterr().err
    assert "reused from the library being replaced" in err and "in-between" in err
    library = Library.open(out)
    assert {run["count"] for run in library.blend_runs().values()} == {2}
    assert library.params["blend_frames"] == 2


def test_a_blend_count_out_of_range_is_one_sentence(take_13_30, tmp_path, capsys):
    assert main(["build", str(take_13_30), "-o", str(tmp_path / "x.tvmlib"), "--blend-frames", "9"]) == 2
    err = capsys.readouterr().err
    assert "--blend-frames 9 is out of range" in err and "at most 8" in err
    assert not (tmp_path / "x.tvmlib").exists()


def test_a_correction_keeps_the_natural_step_and_copies_every_run_it_keeps(libraries, tmp_path):
    # Dropping a motion would move the natural step (the median over the textons left), and
    # with it the runs that cannot reach it; a correction keeps the library's, so it makes
    # only the runs of transitions that are new, and copies the others frame for frame.
    library = libraries["gym"]
    corrected = library.correct({"sequences": {"gym": {"drop": [library.nodes[-1].name]}}},
                                tmp_path / "corrected.tvmlib")
    assert corrected.natural_step == library.natural_step
    ends = lambda r: (tuple(r["exit"]), tuple(r["entry"]))  # noqa: E731
    old = {ends(r): r for r in library.blend_data()["edges"] + library.blend_data()["wraps"]}
    new = corrected.blend_data()["edges"] + corrected.blend_data()["wraps"]
    kept = [r for r in new if ends(r) in old]
    assert corrected.report["blend_made"] == len(new) - len(kept) < len(new)
    for r in kept:
        was = old[ends(r)]
        assert r["count"] == was["count"]
        for k in range(r["count"]):
            assert (corrected.blend_row(r["first"] + k)[0] == library.blend_row(was["first"] + k)[0]).all()
