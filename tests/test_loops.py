"""A looping motion does not pop where its texton wraps from its last frame to its first
(tvmedit.engine.inbetween.loops), on real takes and the synthetic gym, in edits, the player's playhead and exports."""

import numpy as np
import pytest

from conftest import built_library
from tvmedit.engine.inbetween import blend
from tvmedit import Library
from tvmedit.engine.playback import Playhead
from tvmedit.engine.inbetween.loops import closing, paces, reach, window


@pytest.fixture(scope="module")
def libraries(take_13_29, take_13_30, synth_gym):
    """The three takes, built at default options, once per version of the engine's code."""
    return {name: Library.open(built_library(name, take, smooth=False))
            for name, take in (("13_29", take_13_29), ("13_30", take_13_30), ("gym", synth_gym))}


def _loop(library, node):
    """Keys of the frames a looping motion shows around its wrap, with its closing frames in
    place of the captured ones they warp, and the captured frames those are."""
    n, data = library.nodes[node], library.graph.nodes[node]
    k, at = data.get("wrap", 0), data.get("wrap_at", "end")
    warped = window(n.start, n.end, at, k)[0]
    closed = [(n.sequence, f, ((node, node), i)) for i, f in enumerate(warped)]
    if at == "end":
        return [(n.sequence, n.end - k)] + closed + [(n.sequence, n.start)], warped, k
    return [(n.sequence, n.end)] + closed + [(n.sequence, n.start + k)], warped, k


def _reach(library, node):
    """Where ``node``'s loop is closed and the frames its closing looked at
    (:func:`tvmedit.engine.inbetween.loops.reach`; the texton alone where none was tried)."""
    tried = {tuple(w["texton"]): w for w in library.blend_data().get("wraps", [])}
    w = tried.get((node.sequence, node.start, node.end))
    if w is None:
        return "end", (node.start, node.end)
    return w["at"], tuple(w["reach"]) if "reach" in w else reach(node.start, node.end, w["at"], w.get("limit", 0))


def test_every_loop_wraps_within_a_natural_step_where_the_cut_did_not(libraries):
    raw, closed = {}, 0
    for name, library in libraries.items():
        natural = library.natural_step
        for node in library.nodes:
            if node.kind == "once":
                continue
            keys, warped, k = _loop(library, node.id)
            meshes = [library.frame_mesh(key)[0] for key in keys]
            steps = [blend.chamfer(a, b) for a, b in zip(meshes, meshes[1:])]
            # A pop is a step beyond natural motion, and beyond what the capture itself steps
            # at the same phase (a fast motion steps more in every frame, more at some phases).
            # The capture's steps are those of the frames the build looked at (loops.reach).
            at, (first, last) = _reach(library, node)

            def goals(count, seq=node.sequence, start=node.start, end=node.end, at=at, first=first, last=last):
                def step(f, g):
                    return blend.chamfer(library.source_mesh((seq, f))[0], library.source_mesh((seq, g))[0]), 0.0

                own = paces(step, start, end, at, count, lambda f: first <= f <= last)
                return [max(natural, m) for m, _ in own]

            goal = goals(k)
            wrap = blend.chamfer(library.frame_mesh((node.sequence, node.end))[0],
                                 library.frame_mesh((node.sequence, node.start))[0])
            # Closed, the loop's largest step is smaller than the wrap's was, and each step within
            # 1.25 of the capture's pace at its phase unless the wrap was already beyond it.
            assert all(s <= max(1.25 * g, wrap) for s, g in zip(steps, goal)), (
                name, node.name, k, [round(s / g, 2) for s, g in zip(steps, goal)])
            assert k == 0 or max(steps) < 0.98 * wrap, (name, node.name, k, wrap / goal[0])
            raw.setdefault(name, []).append(wrap / goals(0)[0])
            closed += k > 0
            for i, frame in enumerate(warped):   # each is a captured frame of the texton, moved
                positions, colours, faces, _ = library.frame_mesh(keys[1 + i])
                captured = library.frame_mesh((node.sequence, frame))
                assert np.array_equal(colours, captured[1]) and np.array_equal(faces, captured[2])
                area = blend.surface_area(positions, faces) / blend.surface_area(captured[0], captured[2])
                assert abs(area - 1) <= 0.10, (name, node.name, i)
                # Moved toward the neighbouring repetition, but still its own pose: less than the
                # wrap's jump away from the captured frame.
                assert blend.chamfer(positions, captured[0]) < wrap, (name, node.name, i)
    # Without the closing frames a wrap of a real take pops by nearly twice that.
    assert max(max(r) for r in raw.values()) > 1.5 and closed >= 3


def _closed_motions(libraries):
    """Every (library, motion) whose loop is closed, at either end, in the real takes."""
    found = [(library, n) for library in (libraries["13_29"], libraries["13_30"]) for n in library.nodes
             if library.graph.nodes[n.id].get("wrap")]
    assert {library.graph.nodes[n.id]["wrap_at"] for library, n in found} == {"end", "start"}
    return found


def test_each_wrap_is_held_to_the_captured_step_it_replaces(libraries):
    # The wrap from a texton's last frame to its first stands where the capture stepped from
    # the last frame to the next: where the cluster holds that frame, the build looked at it
    # and the library stores it, so its pace counts (13_30's motion 01 is a fast wrap that
    # steps no more than the capture does there, 2.0 natural steps).
    across = 0
    for library in libraries.values():
        stored = set(library.stored_frames())
        for w in library.blend_data()["wraps"]:
            seq, start, end = w["texton"]
            first, last = w["reach"]
            assert all((seq, f) in stored for f in range(first, last + 1))
            across += last == end + 1 if w["at"] == "end" else first == start - 1
    assert across >= 3


def test_an_edit_shows_the_closing_frames_only_in_cycles_that_wrap(libraries):
    for library, node in _closed_motions(libraries):
        _check_edit(library, node)


def _check_edit(library, node):
    other = next(n for n in library.nodes if n.id != node.id and n.kind != "once")
    edit = library.edit([node.id, other.id, node.id], loops=3)
    k = library.graph.nodes[node.id]["wrap"]
    plain = library.graph.copy()
    for n in plain.nodes:
        plain.nodes[n].pop("wrap", None), plain.nodes[n].pop("wrap_at", None)
    from tvmedit.engine.graph.compose import compose

    bare = compose(plain, [node.id, other.id, node.id], loops=3)
    assert len(edit.schedule) == len(bare.schedule)            # lengths and timing are unchanged
    marks = [e.blend[1] for e in edit.schedule if e.blend is not None and e.blend[0] == (node.id, node.id)]
    # Whole windows, but for the last visit's: the edit ends there, and the player rests in
    # that motion, going on through its window.
    assert marks and marks == (list(range(k)) * len(marks))[:len(marks)]
    # Each closing run stands for the window's captured frames and is followed by the texton's
    # first frame; every other entry is the edit's as it was.
    for i, (e, was) in enumerate(zip(edit.schedule, bare.schedule)):
        u = e.blend[0][0] if e.blend is not None and e.blend[0][0] == e.blend[0][1] else None
        if u is None:
            assert e == was
            continue
        n, data = library.nodes[u], library.graph.nodes[u]
        assert (e.node, e.frame) == (was.node, was.frame) == (u, window(n.start, n.end, data["wrap_at"],
                                                                        data["wrap"])[0][e.blend[1]])
        if e.blend[1] == data["wrap"] - 1 and data["wrap_at"] == "end" and i + 1 < len(edit.schedule):
            assert (edit.schedule[i + 1].node, edit.schedule[i + 1].frame) == (u, n.start)
        if e.blend[1] == 0 and data["wrap_at"] == "start":
            assert (edit.schedule[i - 1].node, edit.schedule[i - 1].frame) == (u, n.end)
    # The player's playhead shows the same frames.
    head = Playhead(library.graph, node.id)
    shown = [head.advance()]
    head.queue(other.id)
    head.queue(node.id)
    shown += [head.advance() for _ in range(len(edit.schedule) - 1)]
    assert shown == edit.schedule


def test_closing_marks_only_whole_windows_next_to_a_wrap():
    # Entered inside the window: that first partial window is shown as captured.
    assert closing([12, 13, 10, 11, 12, 13, 10], 10, 13, 2) == [None, None, None, None, 0, 1, None]
    # Left at the window's first frame: nothing is closed.
    assert closing([10, 11, 12], 10, 13, 2) == [None, None, None]
    assert closing([10, 11, 12, 13], 10, 13, 0) == [None] * 4
    # At the start: only after a wrap, and only where the whole window is played.
    assert closing([10, 11, 12, 13, 10, 11], 10, 13, 2, "start") == [None, None, None, None, 0, 1]
    assert closing([12, 13, 10], 10, 13, 2, "start") == [None, None, None]


def test_a_library_without_blending_closes_no_loop(take_13_30, tmp_path):
    library = Library.open(built_library("13_30", take_13_30, blend_frames=0, smooth=False))
    assert not library.blend_data()["wraps"]
    assert not any(count for _, count in library.graph.nodes(data="wrap"))


def test_the_report_shows_each_closed_loop_as_it_plays_and_as_captured(ctx, libraries, tmp_path):
    import imageio.v3 as iio

    from tvmedit.player.report import write_report

    library = libraries["13_30"]
    out = tmp_path / "report"
    write_report(library, out, progress=False)
    page = (out / "index.html").read_text()
    closed = [n for n in library.nodes if library.graph.nodes[n.id].get("wrap")]
    assert "<h3>Loops</h3>" in page and closed
    for node in closed:
        assert f"{node.name}: {library.graph.nodes[node.id]['wrap']} frame(s) warped" in page
        for png in (f"loop-{node.id:03d}.png", f"loop-{node.id:03d}-cut.png"):
            assert f"src='{png}'" in page
            image = iio.imread(out / png)
            assert image[..., :3].astype(float).std() > 8.0, png


def test_an_edit_played_for_ever_closes_its_loop_as_the_playhead_does():
    # The last motion entered at the first frame of its closing window (at its start): the
    # first cycle cannot close it (no wrap before it), every later one does.
    import networkx as nx

    from tvmedit.engine.graph.compose import compose

    g = nx.DiGraph()
    g.add_node(0, name="walk", sequence="a", start=10, end=15)
    g.add_node(1, name="run", sequence="b", start=30, end=38, wrap=2, wrap_at="start")
    g.add_edge(0, 1, weight=0.5, exit_frame=12, entry_frame=30)
    edit = compose(g, ["walk", "run"], loops=None)
    head = Playhead(g, "walk")
    played = [head.advance()]
    head.queue("run")
    played += [head.advance() for _ in range(len(edit.schedule) + 3 * 9 - 1)]
    forever = edit.frames()
    assert [next(forever) for _ in played] == played
    assert sum(e.blend == ((1, 1), 0) for e in played) == 3
