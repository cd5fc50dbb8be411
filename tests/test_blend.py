"""In-between frames at transitions (engine.blend), on real takes: they look like the person
and no displayed step across a transition is larger than natural motion."""

import numpy as np
import pytest

import engine
from engine import blend


def _library(tmp_path_factory, name, take):
    return engine.build([(name, take)], tmp_path_factory.mktemp(name) / "lib.tvmlib", workers=2, cache=False)


@pytest.fixture(scope="module")
def lib_13_29(tmp_path_factory, take_13_29):
    return _library(tmp_path_factory, "13_29", take_13_29)


@pytest.fixture(scope="module")
def lib_gym(tmp_path_factory, synth_gym):
    return _library(tmp_path_factory, "gym", synth_gym)


def _natural(library):
    steps = [blend.texton_steps([library.frame_mesh((n.sequence, f))[0] for f in range(n.start, n.end + 1)])
             for n in library.nodes]
    return blend.natural_step(steps)


def _ends(library, u, v):
    """The exit frame of ``u`` and the entry frame of ``v`` on edge ``u -> v``."""
    data = library.graph.edges[u, v]
    a, b = library.nodes[u], library.nodes[v]
    return (library.frame_mesh((a.sequence, data["exit_frame"]))[:3],
            library.frame_mesh((b.sequence, data["entry_frame"]))[:3])


def _largest_jumps(library, count):
    jumps = [(blend.chamfer(*(end[0] for end in _ends(library, u, v))), u, v) for u, v in library.graph.edges]
    return sorted(jumps, reverse=True)[:count]


@pytest.fixture(scope="module")
def runs(lib_13_29, lib_gym):
    """The blended runs of the three costliest transitions of 13_29 and the costliest of gym."""
    made = []
    for library, count in ((lib_13_29, 3), (lib_gym, 1)):
        natural = _natural(library)
        for jump, u, v in _largest_jumps(library, count):
            ends = _ends(library, u, v)
            made.append((library.path.parent.name, natural, ends, blend.blend(*ends, natural)))
    return made


def test_costly_transitions_are_pops_without_blending(runs):
    # What the blending is for: these cuts jump more than two frames' worth of motion.
    assert all(run.jump > 1.5 * natural for _, natural, _, run in runs)


def test_no_step_across_a_blended_transition_exceeds_natural_motion(runs):
    for name, natural, _, run in runs:
        assert 1 <= len(run) <= blend.MAX_FRAMES
        assert len(run.steps) == len(run) + 1
        assert max(run.steps) <= 1.25 * natural, (name, [s / natural for s in run.steps])


def test_in_between_frames_keep_the_area_of_a_person(runs):
    for name, _, (a, b), run in runs:
        ends = blend.surface_area(a[0], a[2]), blend.surface_area(b[0], b[2])
        for k, frame in enumerate(run.frames):
            t = (k + 1) / (len(run) + 1)
            expected = (1 - t) * ends[0] + t * ends[1]
            assert abs(blend.surface_area(frame[0], frame[2]) / expected - 1) <= 0.10, (name, k)


def test_in_between_frames_wear_the_person_s_colours(runs):
    for name, _, ends, run in runs:
        for k, (positions, colours, faces, normals, side) in enumerate(run.frames):
            source = ends[side]
            assert side == blend.side(k, len(run))
            assert np.array_equal(colours, source[1]) and np.array_equal(faces, source[2])
            grey_or_black = (colours.max(axis=1) < 8) | ((colours.min(axis=1) > 120) & (colours.max(axis=1) < 136))
            assert not grey_or_black.any(), name
            assert positions.dtype == np.float32 and np.isfinite(positions).all()
            assert np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-3)


def test_in_between_frames_are_not_double_exposures(runs):
    for name, _, (a, b), run in runs:
        for k, frame in enumerate(run.frames):
            nearer = min(blend.chamfer(frame[0], a[0]), blend.chamfer(frame[0], b[0]))
            # Half-way, the frame lies about half the cut from either source; a ghost of both
            # lies the whole cut away from each.
            assert nearer <= 0.6 * run.jump, (name, k, nearer / run.jump)


def test_zero_frames_keeps_the_paper_s_cut(lib_13_29):
    jump, u, v = _largest_jumps(lib_13_29, 1)[0]
    run = blend.blend(*_ends(lib_13_29, u, v), natural=0.02, count=0)
    assert len(run) == 0 and run.steps == [pytest.approx(jump)]
