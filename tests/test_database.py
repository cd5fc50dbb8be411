"""Motion database, eq. (9), on hand-built structures whose representatives are known."""

from types import SimpleNamespace

import pytest

from tvmedit.engine.graph.database import Node, build_database, select_textons


def texton(start, end, cluster, distance):
    return SimpleNamespace(start=start, end=end, cluster=cluster, distance=distance)


def test_representative_has_minimal_texton_distance_per_cluster():
    # Cluster 0 holds three textons (0.5, 0.2, 0.4): the middle one wins, not the first or
    # last. Cluster 1 holds two (0.3, 0.1): the later one wins.
    textons = [texton(0, 9, 0, 0.5), texton(10, 19, 0, 0.2), texton(20, 29, 0, 0.4),
               texton(30, 35, 1, 0.3), texton(36, 41, 1, 0.1)]
    chosen = select_textons(textons)
    assert [(t.start, t.end, t.cluster) for t in chosen] == [(10, 19, 0), (36, 41, 1)]


def test_tie_goes_to_the_earliest_texton():
    textons = [texton(0, 9, 0, 0.2), texton(10, 19, 0, 0.2)]
    assert select_textons(textons)[0].start == 0


def test_several_sequences_keep_their_own_names_and_ranges():
    walk = [texton(0, 9, 0, 0.3), texton(10, 19, 0, 0.1),
            texton(20, 25, 1, 0.4), texton(26, 31, 1, 0.6)]
    run = [texton(0, 5, 0, 0.2), texton(6, 11, 0, 0.05)]
    nodes = build_database({"walk": (walk, [(0, 19), (20, 31)]), "run": (run, [(0, 11)])})
    assert nodes == [
        Node(0, "walk/01", "walk", 10, 19, 0, 0.1),
        Node(1, "walk/02", "walk", 20, 25, 1, 0.4),
        Node(2, "run/01", "run", 6, 11, 0, 0.05),
    ]
    assert all(node.intensity is None for node in nodes)


def test_ids_follow_sequence_order_then_start_frame():
    # Textons listed out of order still give ids by start frame within the sequence.
    b = [texton(20, 29, 1, 0.1), texton(30, 39, 1, 0.1),
         texton(0, 9, 0, 0.1), texton(10, 19, 0, 0.1)]
    a = [texton(0, 4, 0, 0.1), texton(5, 9, 0, 0.1)]
    nodes = build_database({"b": (b, [(0, 19), (20, 39)]), "a": (a, [(0, 9)])})
    assert [(n.id, n.name, n.start) for n in nodes] == [
        (0, "b/01", 0), (1, "b/02", 20), (2, "a/01", 0)]


def test_single_texton_cluster_becomes_a_one_shot_of_the_whole_cluster():
    # Cluster 1 is a stretch the parser saw once: no evidence it can be looped, so it is
    # played through once, all of it.
    textons = [texton(0, 9, 0, 0.3), texton(10, 19, 0, 0.2), texton(20, 24, 1, 0.0)]
    nodes = build_database({"gym": (textons, [(0, 19), (20, 26)])})
    assert [(n.start, n.end, n.cluster, n.kind) for n in nodes] == [(10, 19, 0, "cycle"), (20, 26, 1, "once")]
    assert not nodes[0].once and nodes[1].once


def test_single_texton_of_a_cluster_that_runs_on_is_kept():
    # A slow exercise: one whole 10-frame cycle fits once aligned, but its cluster runs 16
    # frames (1.6 cycles), so the motion is seen going on; a 14-frame cluster (1.4) is not,
    # and is played once instead.
    textons = [texton(0, 9, 0, 0.3), texton(10, 19, 0, 0.2),
               texton(23, 32, 1, 0.1), texton(40, 49, 2, 0.1)]
    nodes = build_database({"gym": (textons, [(0, 19), (20, 35), (36, 49)])})
    assert [(n.start, n.cluster, n.kind) for n in nodes] == [(10, 0, "cycle"), (23, 1, "cycle"), (36, 2, "once")]


def test_a_take_that_is_not_an_exercise_gives_one_shots():
    # A talking head: clusters without any texton. Each is a motion played once; its d_T is
    # the parse's atom distance from its first frame to its last.
    structure = SimpleNamespace(textons=[], clusters=[(0, 29), (30, 49)],
                                curve=[0.01 * k for k in range(30)] + [0.02 * k for k in range(20)])
    nodes = build_database({"talk": structure})
    assert [(n.name, n.start, n.end, n.kind) for n in nodes] == [
        ("talk/01", 0, 29, "once"), ("talk/02", 30, 49, "once")]
    assert [round(n.texton_distance, 6) for n in nodes] == [0.29, 0.38]


def test_motions_are_numbered_in_time_order_whatever_their_kind():
    seq = [texton(20, 24, 1, 0.1), texton(25, 29, 1, 0.2)]
    nodes = build_database({"a": (seq, [(0, 19), (20, 29)])})
    assert [(n.name, n.kind) for n in nodes] == [("a/01", "once"), ("a/02", "cycle")]


def test_no_textons_gives_an_empty_database():
    assert build_database({"a": ([], [])}) == []


def test_structure_object_is_accepted_in_place_of_the_pair():
    structure = SimpleNamespace(textons=[texton(0, 4, 0, 0.2), texton(5, 9, 0, 0.1)],
                                clusters=[(0, 9)])
    assert [(n.start, n.end) for n in build_database({"s": structure})] == [(5, 9)]


def test_texton_naming_a_missing_cluster_is_refused():
    with pytest.raises(ValueError, match="cluster 3"):
        build_database({"s": ([texton(0, 4, 3, 0.2)], [(0, 9)])})
