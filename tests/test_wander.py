"""The endless walk: every motion plays, none dominates, a seed gives the same walk."""

import collections
import json
import itertools

import networkx as nx
import pytest

from tvmedit.engine.errors import TvmError
from tvmedit.engine.playback.wander import Wander


def graph(edges, lengths=None, once=()):
    """A motion graph of motions ``0..n-1`` whose textons are ``lengths`` frames long (3 each
    by default), each in a sequence of its own, with ``edges`` ``(u, v, weight)``."""
    nodes = sorted({n for u, v, _ in edges for n in (u, v)})
    lengths = lengths or {}
    g = nx.DiGraph()
    for n in nodes:
        g.add_node(n, name=f"m{n}", sequence=f"s{n}", start=0, end=lengths.get(n, 3) - 1,
                   kind="once" if n in once else "cycle")
    for u, v, w in edges:
        g.add_edge(u, v, weight=w, exit_frame=lengths.get(u, 3) - 1, entry_frame=0)
    return g


# A hub: 0 leads to 1, 2 and 3; each leads back to 0 only, 1 also to 2.
HUB = graph([(0, 1, 0.2), (0, 2, 0.5), (0, 3, 0.9), (1, 0, 0.3), (2, 0, 0.3), (3, 0, 0.4), (1, 2, 0.6)])


def shares(edit, nodes):
    counts = collections.Counter(entry.node for entry in edit.schedule)
    even = len(edit.schedule) / len(nodes)
    return {n: counts[n] / even for n in nodes}


def test_the_same_seed_gives_the_same_walk_and_another_seed_another():
    first = [e.to_json() for e in Wander(HUB, seed=7).take(2000).schedule]
    assert first == [e.to_json() for e in Wander(HUB, seed=7).take(2000).schedule]
    assert first != [e.to_json() for e in Wander(HUB, seed=8).take(2000).schedule]


@pytest.mark.parametrize("seed", range(5))
def test_every_motion_plays_and_none_takes_twice_its_share(seed):
    edit = Wander(HUB, seed=seed).take(6000)
    share = shares(edit, HUB.nodes)
    assert min(share.values()) > 0, share
    assert max(share.values()) <= 2.0, share


@pytest.mark.parametrize("seed", range(5))
def test_a_motion_is_not_left_twice_in_a_row_by_the_same_transition(seed):
    edit = Wander(HUB, seed=seed).take(6000)
    last = {}
    for t in edit.transitions:
        if len(list(HUB.successors(t.source))) > 1:
            assert last.get(t.source) != t.target, f"{t.source} -> {t.target} twice in a row"
        last[t.source] = t.target


def test_the_schedule_follows_the_transitions_it_lists():
    edit = Wander(HUB, seed=1).take(500)
    for t in edit.transitions:
        assert edit.schedule[t.index].node == t.target
        assert edit.schedule[t.index - 1].node == t.source
        assert edit.schedule[t.index].frame == t.entry_frame
        assert edit.schedule[t.index - 1].frame == t.exit_frame
    assert len(edit.schedule) == 500


def test_a_walk_is_endless_and_taken_lazily():
    walk = iter(Wander(HUB, seed=2))
    head = list(itertools.islice(walk, 100_000))
    assert len(head) == 100_000
    assert [e.to_json() for e in Wander(HUB, seed=2).take(300).schedule] == [e.to_json() for e in head[:300]]


def test_only_and_forbid_keep_the_walk_to_the_motions_allowed():
    ring = graph([(0, 1, 0.1), (1, 2, 0.1), (2, 0, 0.1), (1, 0, 0.1), (0, 3, 0.1), (3, 0, 0.1)])
    played = {e.node for e in Wander(ring, seed=0, only=["m0", "m1", "m2"]).take(3000).schedule}
    assert played == {0, 1, 2}
    played = {e.node for e in Wander(ring, seed=0, forbid=["m3"]).take(3000).schedule}
    assert played == {0, 1, 2}


def test_motions_that_cannot_reach_each_other_are_refused_by_name():
    ring = graph([(0, 1, 0.1), (1, 2, 0.1), (2, 0, 0.1), (0, 3, 0.1), (3, 0, 0.1)])
    with pytest.raises(TvmError, match=r"\(1\) 'm0', 'm3'; \(2\) 'm1'"):
        Wander(ring, only=["m0", "m1", "m3"])


def test_one_allowed_motion_plays_on_for_ever():
    edit = Wander(HUB, seed=0, only=["m2"]).take(30)
    assert [e.frame for e in edit.schedule] == [0, 1, 2] * 10
    assert edit.transitions == []


def test_a_one_shot_motion_plays_once_per_visit():
    g = graph([(0, 1, 0.1), (1, 0, 0.1)], lengths={0: 3, 1: 8}, once={1})
    edit = Wander(g, seed=0, start="m0").take(400)
    visits = [[e.frame for e in group] for node, group in itertools.groupby(edit.schedule, key=lambda e: e.node)
              if node == 1][:-1]
    assert len(visits) > 5 and all(frames == list(range(8)) for frames in visits)


def test_a_visit_plays_at_least_one_whole_cycle():
    for seed in range(3):
        edit = Wander(HUB, seed=seed, cycles={n: 1.0 for n in HUB}).take(3000)
        for node, group in itertools.groupby(edit.schedule[:edit.transitions[-1].index], key=lambda e: e.node):
            assert len(list(group)) >= 3


def test_a_bad_temperature_or_start_is_refused_with_a_sentence():
    with pytest.raises(TvmError, match="temperature"):
        Wander(HUB, temperature=0)
    with pytest.raises(TvmError, match="cannot start at 'm3'"):
        Wander(HUB, start="m3", forbid=["m3"])


# --- on a built library, from Python and the command line -----------------------------------

def test_a_ten_minute_walk_of_the_demo_plays_every_motion_evenly(small_library):
    from tvmedit import Library
    from tvmedit.engine.playback.wander import library_walk

    library = Library.open(small_library)
    assert library.wander(30, seed=1).to_json() == library_walk(library, 30, seed=1).to_json()
    assert next(iter(library.wander(seed=1))) == library.wander(30, seed=1).schedule[0]   # endless, lazy
    for seed in range(5):
        edit = library_walk(library, 600, seed=seed)
        assert len(edit.schedule) == round(600 * edit.fps)
        share = shares(edit, library.graph.nodes)
        assert min(share.values()) > 0 and max(share.values()) <= 2.0, (seed, share)


def test_path_wander_json_is_the_same_for_a_seed_and_differs_across(small_library):
    from interrupt import tvmedit

    runs = [tvmedit("path", small_library, "--wander", "120", "--seed", str(seed), "--json") for seed in (3, 3, 4)]
    assert all(run.returncode == 0 for run in runs), runs[0].stderr
    assert runs[0].stdout == runs[1].stdout != runs[2].stdout
    data = json.loads(runs[0].stdout)
    assert len(data["schedule"]) == round(120 * data["fps"])
    assert {"node", "sequence", "frame"} <= set(data["schedule"][0])
    assert all({"from", "to"} <= set(t) and t["from"] != t["to"] for t in data["transitions"])


def test_export_wander_writes_the_same_edit_json_for_a_seed(small_library, tmp_path):
    from interrupt import tvmedit

    for out in ("a", "b"):
        result = tvmedit("export", small_library, "--wander", "5", "--seed", "1", "-o", tmp_path / out, "-q")
        assert result.returncode == 0, result.stderr
    assert (tmp_path / "a" / "edit.json").read_bytes() == (tmp_path / "b" / "edit.json").read_bytes()
    assert len(list((tmp_path / "a").glob("frame_*.ply"))) == 50


@pytest.mark.parametrize("args, says", [
    (["--wander", "10", "gym/01", "gym/02"], "at most one KEY"),
    (["--seed", "3", "gym/01", "gym/02"], "add --wander"),
    (["--wander", "10", "--durations", "3"], "--durations times key motions"),
    ([], "or give --wander SECONDS"),
])
def test_walk_options_out_of_place_are_refused_in_one_sentence(small_library, args, says):
    from interrupt import tvmedit

    result = tvmedit("path", small_library, *args)
    assert result.returncode == 2 and says in result.stderr and "Traceback" not in result.stderr, result.stderr


# --- the realtime playhead walking --------------------------------------------------------------

def test_the_playhead_walks_on_when_nothing_is_queued():
    from tvmedit.engine.playback import Playhead

    head = Playhead(HUB, 0, walker=Wander(HUB, seed=4).walker())
    nodes = [head.advance().node for _ in range(600)]
    assert set(nodes) == set(HUB.nodes) and head.wandering
    for t in head.transitions:                       # every step is one of the graph's edges
        assert HUB.has_edge(t.source, t.target)


def test_a_key_queued_mid_walk_is_played_then_the_walk_goes_on():
    from tvmedit.engine.playback import Playhead

    head = Playhead(HUB, 1, walker=Wander(HUB, seed=5).walker())
    for _ in range(20):
        head.advance()
    head.queue("m3", hold=6)
    assert head.queue_list == [3] and head.queue_holds == [6] and not head.wandering
    frames = [head.advance() for _ in range(300)]
    reached = next(i for i, e in enumerate(frames) if e.node == 3)
    assert head.queue_list == [] and head.wandering
    assert len({e.node for e in frames[reached:]}) >= 3    # the walk went on from there


def test_the_playhead_says_when_a_motion_is_only_passed_through():
    from tvmedit.engine.playback import Playhead

    head = Playhead(HUB, 1)
    head.advance()
    head.queue("m3")                                  # 1 -> 0 -> 3: 0 is on the way
    seen = set()
    for _ in range(40):
        entry = head.advance()
        if entry.node == 0 and entry.blend is None:
            seen.add(head.passing_through)
    assert seen == {True}
