"""The playhead: an edit played one frame at a time while key motions are queued.

Every test compares with what :func:`compose` plans for the same key motions (section 8's
play length rule, the best paths of eq. (15)-(16)), on tiny hand-made graphs.
"""

import random

import pytest

from tvmedit.engine.errors import NoPath
from tvmedit.engine.graph.compose import ScheduleEntry, compose
from tvmedit.engine.graph.motiongraph import build_graph
from tvmedit.engine.graph.timing import Timing
from tvmedit.engine.playback import Playhead

from test_compose import frames, random_texton_graph, texton_graph, three_textons
from test_oneshot import _features as one_shot_features, _nodes as one_shot_nodes
from test_timing import random_graph


def play(head, count):
    return [(entry.node, entry.frame) for entry in (head.advance() for _ in range(count))]


def test_playhead_plays_what_compose_plans():
    rng = random.Random(21)
    compared = 0
    for _ in range(300):
        g = random_texton_graph(rng, rng.randrange(3, 7))
        keys = [rng.randrange(len(g)) for _ in range(rng.randrange(2, 6))]
        try:
            edit = compose(g, keys, loops=2)
        except NoPath:
            continue
        head = Playhead(g, keys[0])
        for key in keys[1:]:
            head.queue(key)
        assert play(head, len(edit.schedule)) == frames(edit)
        assert head.transitions == edit.transitions
        assert head.queue_list == [] and head.current_node == keys[-1]
        compared += 1
    assert compared > 100


def test_keys_queued_while_playing_match_compose():
    # Queuing each key only once the previous one has begun gives the same schedule.
    g = texton_graph({0: (0, 2), 1: (10, 15), 2: (30, 32), 3: (40, 41)},
                     {(0, 1): (1.0, 2, 14), (1, 2): (2.0, 12, 30), (2, 3): (0.5, 31, 40),
                      (3, 0): (1.0, 40, 1)})
    edit = compose(g, [0, 2, 3, 0])
    head = Playhead(g, 0)
    played = play(head, 1)
    for key in (2, 3, 0):
        head.queue(key)
        played += play(head, head.frames_until_next_key() + 1)
        assert head.current_node == key and head.queue_list == []
    played += play(head, len(edit.schedule) - len(played))
    assert played == frames(edit)


def test_frames_until_next_key_counts_down_to_its_first_frame():
    g = three_textons(exit_b=12)
    head = Playhead(g, 0)
    assert head.frames_until_next_key() is None
    head.queue(2)
    assert head.frames_until_next_key() == 3 + 11
    for left in range(14, 0, -1):
        assert head.frames_until_next_key() == left
        head.advance()
    assert head.frames_until_next_key() == 0 and head.queue_list == [2]
    assert head.advance() == ScheduleEntry(2, "seq2", 30)
    assert head.queue_list == [] and head.frames_until_next_key() is None


def test_current_texton_finishes_first_when_queued_late():
    # Texton 1 (10-15) rests and loops; queued after 8 frames, it leaves at its exit 11:
    # frames 10..15, 10, 11 already shown and the last was 11, so the next frame is the target's.
    g = texton_graph({1: (10, 15), 2: (30, 32)}, {(1, 2): (1.0, 11, 31)})
    head = Playhead(g, 1)
    assert play(head, 8)[-2:] == [(1, 10), (1, 11)]
    head.queue(2)
    assert head.frames_until_next_key() == 0
    assert play(head, 2) == [(2, 31), (2, 32)]
    # Queued after 9 frames (last shown 12), it plays on to 11 once more.
    head = Playhead(g, 1)
    play(head, 9)
    head.queue(2)
    assert head.frames_until_next_key() == 5
    assert play(head, 6) == [(1, 13), (1, 14), (1, 15), (1, 10), (1, 11), (2, 31)]


def test_unreachable_queue_is_refused_and_unqueue_restores_looping():
    g = texton_graph({0: (0, 1), 1: (2, 3), 2: (4, 5)}, {(0, 1): (1.0, 1, 2)})
    head = Playhead(g, 0)
    head.queue(1)
    with pytest.raises(NoPath):
        head.queue(2)
    assert head.queue_list == [1]
    assert head.unqueue_last() == 1 and head.queue_list == [] and head.unqueue_last() is None
    assert play(head, 5) == [(0, 0), (0, 1), (0, 0), (0, 1), (0, 0)]


def test_unqueue_inside_a_path_keeps_the_current_texton():
    g = three_textons(exit_b=12)
    head = Playhead(g, 0)
    head.queue(2)
    play(head, 4)
    assert head.current_node == 1
    assert head.unqueue_last() == 2
    assert play(head, 8) == [(1, f) for f in (15, 10, 11, 12, 13, 14, 15, 10)]
    # Re-planning starts from the texton now playing.
    assert head.queue(2) == [1, 2]
    assert head.frames_until_next_key() == 2


def test_queuing_the_motion_already_planned_is_an_empty_leg():
    g = three_textons(exit_b=12)
    head = Playhead(g, 0)
    assert head.queue("m0") == [0] and head.queue_list == []
    head.queue(2)
    assert head.queue(2) == [2] and head.queue_list == [2]


def test_the_player_holds_a_motion_as_compose_does():
    rng = random.Random(3)
    compared = 0
    while compared < 40:
        g = random_graph(rng)
        if len(g) < 3:
            continue
        a, b, c = rng.sample(sorted(g.nodes), 3)
        hold = rng.randint(1, 25)
        try:
            keys, timing = Timing.request(g, [a, b, c], fps=1, durations=[None, None], holds={b: hold})
            edit = compose(g, keys, timing=timing)
        except (NoPath, ValueError):
            continue
        head = Playhead(g, a)
        head.queue(b, hold=hold)
        head.queue(c)
        assert [head.advance() for _ in edit.schedule] == edit.schedule
        compared += 1


def test_a_one_shot_rests_by_replaying_and_plays_as_compose():
    G = build_graph(one_shot_nodes(), {"take": one_shot_features()}, mu=10.0)
    head = Playhead(G, 1)
    first = [head.advance().frame for _ in range(25)]
    assert first == list(range(10, 30)) + list(range(10, 15))  # rests: plays again from the start
    head = Playhead(G, 1)
    head.queue(0)
    planned = [e.frame for e in compose(G, [1, 0]).schedule]
    assert [head.advance().frame for _ in range(len(planned))] == planned


def test_peek_shows_the_frame_advance_plays_next_through_queues_and_walks(small_library):
    """The player draws the body on its way to :meth:`Playhead.peek`; a wrong peek would show
    it moving toward one frame and then jump to another."""
    from tvmedit import Library

    library = Library.open(small_library)
    walker = library.wander(seed=4).walker()
    for head in (Playhead(library.graph, 0), Playhead(library.graph, walker.first(), walker=walker)):
        nodes, rng = sorted(library.graph.nodes), random.Random(1)
        for k in range(1500):
            if k % 170 == 60:
                head.queue(rng.choice(nodes), hold=rng.choice([0, 7]))
            peeked = head.peek()
            assert head.advance() == peeked, k
