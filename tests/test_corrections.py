"""Corrections by hand (tvmedit.engine.store.corrections): a wrong parse made right, and only what changed redone.

On real motion (CMU 13_30 turned into meshes): a true boundary removed and a spurious one
added through ``corrections.json`` give exactly the corrected clusters, the same database
and graph as a build from scratch given those clusters, and the rebuild reads no frame file
but those of the motions the library never stored. Every run points ``XDG_CACHE_HOME`` at
a temporary folder, so no test reads or fills the user's feature cache.
"""

import json
import os
import shutil

import jsonschema
import numpy as np
import pytest

from tvmedit import engine
from tvmedit import Library
from tvmedit.engine.inbetween.blend import chamfer
from tvmedit.engine.store.inbetweens import loop_frames
from tvmedit.engine.store.corrections import CorrectionError, Corrections, apply_structure
from tvmedit.engine.graph.database import build_database
from tvmedit.engine.graph.motiongraph import build_graph
from tvmedit.engine.store.library import INFO_SCHEMA
from tvmedit.engine.parse.structure import Structure, StructureParams, parser_view, texton_curve, textons_for
from tvmedit.engine.inbetween.loops import window
from tvmedit.cli import main

NAME = "t30"


pytestmark = pytest.mark.usefixtures("private_cache")


@pytest.fixture(scope="module")
def take(take_13_30, tmp_path_factory):
    """The take's frames linked into a folder of the test's own, which tests may move away."""
    folder = tmp_path_factory.mktemp("frames") / NAME
    folder.mkdir()
    for entry in take_13_30.iterdir():
        try:
            os.link(entry, folder / entry.name)
        except OSError:
            shutil.copy2(entry, folder / entry.name)
    return folder


@pytest.fixture(scope="module")
def base(take, tmp_path_factory):
    """The automatic library of the take (tests write their corrections elsewhere)."""
    out = tmp_path_factory.mktemp("lib") / "t30.tvmlib"
    return engine.build([take], out, workers=2, cache=False, smooth=False)


def _truth(take):
    return [s["start"] for s in json.loads((take / "truth.json").read_text())["segments"]][1:]


def _expected(library, clusters):
    """Structure, database and graph of a build from scratch given ``clusters``."""
    f = library.features(NAME)
    params = StructureParams(**{**library.params["structure"],
                                "window_taps": tuple(library.params["structure"]["window_taps"])})
    fps = library.sequence(NAME).fps
    textons = textons_for(f.vectors, clusters, fps, params, theta=f.theta_columns)
    structure = Structure(clusters, textons, texton_curve(f.vectors, clusters, textons, fps, params, f.theta_columns), fps)
    nodes = build_database({NAME: structure})
    return structure, nodes, build_graph(nodes, {NAME: f.vectors}, mu=library.mu)


def _edges(graph):
    return {(i, j): (round(d["weight"], 9), d["exit_frame"], d["entry_frame"]) for i, j, d in graph.edges(data=True)}


def _joined(graph, nodes, library):
    """``graph`` with its transitions made where a build makes them (the pair of frames whose
    poses are nearest among eq. (10)'s near ties, tvmedit.engine.inbetween.pairs), the poses
    read from ``library``'s stored frames."""
    from tvmedit.engine.store.inbetweens import join

    join(graph, nodes, {NAME: library.features(NAME).vectors},
         lambda keys: [library.frame_mesh(key)[:2] for key in keys], {NAME: library.sequence(NAME).fps})
    return graph


def _away(take, keep=()):
    """Move the frame folder away, leaving only the files of frames ``keep``; returns a restorer."""
    aside = take.with_name(take.name + ".aside")
    take.rename(aside)
    take.mkdir()
    files = sorted(p for p in aside.iterdir() if p.suffix == ".ply")
    for frame in keep:
        os.link(files[frame], take / files[frame].name)

    def restore():
        shutil.rmtree(take)
        aside.rename(take)
    return restore


def _boundary_fix(library, take):
    """A true boundary of ``library``'s parse to remove, a spurious one to add in the middle of
    its longest cluster (checked: no true boundary within a second), and the clusters they give."""
    auto = [s for s, _ in library.structure(NAME).clusters]
    truth = _truth(take)
    true = next(b for b in auto[1:] if min(abs(b - t) for t in truth) <= 10)
    longest = max(library.structure(NAME).clusters, key=lambda c: c[1] - c[0])
    spurious = (longest[0] + longest[1]) // 2
    assert min(abs(spurious - t) for t in truth) > 10
    starts = sorted(set(auto) - {true} | {spurious})
    return true, spurious, [(s, e - 1) for s, e in zip(starts, starts[1:] + [len(library.sequence(NAME))])]


def test_removing_and_adding_boundaries_gives_exactly_those_clusters(base, take, tmp_path):
    true, spurious, clusters = _boundary_fix(base, take)
    fix = tmp_path / "corrections.json"
    fix.write_text(json.dumps({"sequences": {NAME: {"boundaries": {"remove": [true], "add": [spurious]}}}}))

    structure, nodes, graph = _expected(base, clusters)
    stored = set(base.stored_frames())
    rooms = {n.id: clusters[n.cluster] for n in nodes}   # loops are closed onto the next repetition
    closing = {f for _, f in loop_frames(graph, base.params["blend_frames"], rooms)}
    new_frames = sorted(({f for n in nodes for f in range(n.start, n.end + 1)} | closing) - {f for _, f in stored})

    # Only the files of frames the library never stored are left: reading any other one
    # (features, the frame of reference, a stored mesh) would fail.
    restore = _away(take, keep=new_frames)
    try:
        fixed = base.correct(fix, tmp_path / "fixed.tvmlib")
    finally:
        restore()

    assert fixed.structure(NAME).clusters == clusters
    assert fixed.report["read_frames"] == len(new_frames)
    assert [(t.start, t.end) for t in fixed.structure(NAME).textons] == [(t.start, t.end) for t in structure.textons]
    assert [(n.name, n.start, n.end, n.kind) for n in fixed.nodes] == [(n.name, n.start, n.end, n.kind) for n in nodes]
    assert _edges(fixed.graph) == _edges(_joined(graph, nodes, fixed))
    assert fixed.parse(NAME).clusters == base.structure(NAME).clusters      # the automatic parse is kept
    assert fixed.corrections() == Corrections.load(fix)
    for node in fixed.nodes:                                                # every motion plays
        assert len(fixed.frame_mesh((NAME, node.end))[0]) > 1000
    _check_closings(fixed)
    for key in set(fixed.stored_frames()) & stored:                         # copied frames are the same
        assert all((a == b).all() for a, b in zip(fixed.frame_mesh(key), base.frame_mesh(key)))

    # The same corrections in a build from scratch give the same database and graph.
    scratch = tmp_path / "scratch.tvmlib"
    assert main(["build", f"{NAME}={take}", "-o", str(scratch), "--corrections", str(fix), "--no-cache",
                 "--workers", "2", "-q", "--no-smooth"]) == 0     # as the base library: no display steps
    again = Library.open(scratch)
    assert [(n.start, n.end, n.kind) for n in again.nodes] == [(n.start, n.end, n.kind) for n in fixed.nodes]
    assert _edges(again.graph) == _edges(fixed.graph)
    # A correction keeps the capture's natural step, so the transitions it did not change keep
    # their in-between frames as they were; a build from scratch measures it on its own motions.
    assert fixed.natural_step == base.natural_step
    assert again.natural_step == pytest.approx(base.natural_step, rel=0.1)
    ends = lambda e: (tuple(e["exit"]), tuple(e["entry"]))  # noqa: E731
    before = {ends(e): e for e in base.blend_data()["edges"] + base.blend_data()["wraps"]}
    runs = fixed.blend_data()["edges"] + fixed.blend_data()["wraps"]
    kept = [e for e in runs if ends(e) in before]
    assert kept and fixed.report["blend_made"] == len(runs) - len(kept)
    for e in kept:
        was = before[ends(e)]
        assert (e["count"], e["steps"]) == (was["count"], was["steps"])
        for k in range(e["count"]):
            assert (fixed.blend_row(e["first"] + k)[0] == base.blend_row(was["first"] + k)[0]).all()


def _check_closings(library):
    """Every loop-closing frame (tvmedit.engine.inbetween.loops) stands for its texton frame: nearer it than the
    texton's wrap jumps, or on the way from it to the frame it is warped onto (its distances
    to the two add up to little more than theirs). A closing shown for a frame far from its
    own would be neither (one reused for the next frame may pass). Nearer than the jump alone
    is not enough where a texton's end lies near its start and its last frames are warped hard."""
    for node in library.nodes:
        data = library.graph.nodes[node.id]
        warped, onto = window(node.start, node.end, data.get("wrap_at", "end"), data.get("wrap", 0))
        jump = chamfer(library.frame_mesh((NAME, node.end))[0], library.frame_mesh((NAME, node.start))[0])
        for i, (frame, target) in enumerate(zip(warped, onto)):
            closed = library.frame_mesh((NAME, frame, ((node.id, node.id), i)))[0]
            own, there = library.frame_mesh((NAME, frame))[0], library.frame_mesh((NAME, target))[0]
            way = chamfer(closed, own) + chamfer(closed, there)
            assert chamfer(closed, own) < jump or way <= 1.25 * chamfer(own, there), (node.name, frame)


@pytest.fixture(scope="module")
def base_all(take, tmp_path_factory):
    """The take's library with every frame stored (``keep_frames="all"``)."""
    out = tmp_path_factory.mktemp("lib") / "t30-all.tvmlib"
    return engine.build([take], out, workers=2, cache=False, keep_frames="all", smooth=False)


def test_a_library_keeping_every_frame_is_corrected_without_its_capture(base_all, take, tmp_path):
    true, spurious, clusters = _boundary_fix(base_all, take)
    structure, nodes, graph = _expected(base_all, clusters)
    assert len(base_all.stored_frames()) == len(base_all.sequence(NAME))
    assert base_all.params["keep_frames"] == "all"

    restore = _away(take)                                # no frame file at all
    try:
        fixed = base_all.correct({"sequences": {NAME: {"boundaries": {"remove": [true], "add": [spurious]}}}},
                                 tmp_path / "fixed.tvmlib")
        shown = fixed.source_mesh((NAME, 3))             # inspect's view of any frame
    finally:
        restore()
    assert fixed.report["read_frames"] == 0
    assert fixed.structure(NAME).clusters == clusters
    assert [(n.start, n.end, n.kind) for n in fixed.nodes] == [(n.start, n.end, n.kind) for n in nodes]
    assert _edges(fixed.graph) == _edges(_joined(graph, nodes, fixed))
    assert fixed.params["keep_frames"] == "all" and len(fixed.stored_frames()) == len(base_all.stored_frames())
    assert (shown[0] == base_all.frame_mesh((NAME, 3))[0]).all()
    for node in fixed.nodes:                             # every motion plays, frames as captured
        assert (fixed.frame_mesh((NAME, node.end))[0] == base_all.frame_mesh((NAME, node.end))[0]).all()
    _check_closings(fixed)


def test_a_correction_of_stored_motions_only_reads_no_frame_file_at_all(base, take, tmp_path):
    restore = _away(take)
    try:
        fixed = base.correct({"sequences": {NAME: {"drop": [base.nodes[1].name]}}}, tmp_path / "d.tvmlib")
    finally:
        restore()
    assert fixed.report["read_frames"] == 0
    assert [n.name for n in fixed.nodes] == [n.name for n in base.nodes if n.id != 1]
    # The features about each frame's own centre (the subject stays on its spot) go along, so
    # that a later rebuild's parse reads turns as the first did.
    centred = base.features(NAME).centred, fixed.features(NAME).centred
    assert centred[0] is not None and np.array_equal(centred[0].vectors, centred[1].vectors)
    for node in fixed.nodes:
        assert (fixed.frame_mesh((NAME, node.start))[0] == base.frame_mesh((NAME, node.start))[0]).all()


def test_a_correction_needing_frames_that_are_gone_is_one_sentence(base, take, tmp_path, capsys):
    auto = base.structure(NAME).clusters
    fix = tmp_path / "c.json"
    fix.write_text(json.dumps({"sequences": {NAME: {"boundaries": {"remove": [auto[1][0]]}}}}))
    restore = _away(take)
    try:
        capsys.readouterr()
        assert main(["correct", str(base.path), str(fix), "-o", str(tmp_path / "x")]) == 2
    finally:
        restore()
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: frame ") and "put the sequence's frame files back" in err and "\n" not in err
    assert not (tmp_path / "x").exists()


def test_corrections_survive_a_rebuild_with_other_parameters(base, take, tmp_path, capsys):
    out = tmp_path / "lib.tvmlib"
    shutil.copytree(base.path, out)
    auto = base.structure(NAME).clusters
    fix = tmp_path / "c.json"
    c = Corrections()
    c.remove_boundary(NAME, auto[1][0])
    c.save(fix)
    assert main(["correct", str(out), str(fix)]) == 0
    # Other parameters of the graph and of the in-between frames (none: the clusters are what
    # is checked, and a rebuild without in-betweens takes a third of the time).
    fast = ["--blend-frames", "0", "--no-smooth"]
    assert main(["build", f"{NAME}={take}", "-o", str(out), "--force", "--mu", "0.8", "-q", "--workers", "1",
                 *fast]) == 0
    rebuilt = Library.open(out)
    assert rebuilt.mu == 0.8 and len(rebuilt.structure(NAME).clusters) == len(auto) - 1
    capsys.readouterr()
    assert main(["info", str(out)]) == 0
    assert f"corrected by hand: boundaries -{auto[1][0]}" in capsys.readouterr().out
    assert main(["info", str(out), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    jsonschema.validate(info, INFO_SCHEMA)
    assert info["sequences"][0]["corrections"] == c.to_json()["sequences"][NAME]
    assert main(["build", f"{NAME}={take}", "-o", str(out), "--force", "--no-corrections", "-q", *fast]) == 0
    assert Library.open(out).structure(NAME).clusters == auto and not Library.open(out).corrections()


def test_texton_starts_representatives_and_drops(base):
    parse = base.parse(NAME)
    features = base.features(NAME)
    vectors, theta = features.vectors, features.theta_columns
    cluster = max(range(len(parse.clusters)), key=lambda k: len(parse.textons_of(k)))
    first, second, third = parse.textons_of(cluster)[:3]
    c = Corrections()
    c.move_texton(NAME, second.start, second.start + 1)
    c.remove_texton(NAME, third.start)              # joins the third texton to the second
    c.add_texton(NAME, third.start + 1)             # and splits it again one frame later
    fixed = apply_structure(parse, vectors, c.of(NAME), theta=theta, name=NAME)   # as the builder calls it
    spans = [(t.start, t.end) for t in fixed.textons_of(cluster)]
    assert spans[:3] == [(first.start, second.start), (second.start + 1, third.start), (third.start + 1, third.end)]
    assert len(fixed.textons) == len(parse.textons)
    from tvmedit.engine.parse.atoms import atom_window
    from tvmedit.engine.parse.confidence import texton_confidence

    edited = fixed.textons_of(cluster)[1]                 # its confidence is measured anew
    # on the view the parser measured every texton on (azimuth smoothed)
    view = parser_view(vectors, StructureParams(), theta, parse.fps)
    assert edited.confidence == texton_confidence(view, edited.start, edited.end, atom_window(parse.fps))
    c.remove_texton(NAME, third.start + 1)          # undoing an added start leaves no entry
    assert c.of(NAME).textons["add"] == []

    c = Corrections()
    c.represent(NAME, second.start + 2)
    c.drop(NAME, base.nodes[0].name)
    fixed = base.correct(c, base.path.with_name("rep.tvmlib"))
    assert fixed.nodes[0].name == base.nodes[1].name and len(fixed.nodes) == len(base.nodes) - 1
    forced = next(n for n in fixed.nodes if n.cluster == cluster)
    assert (forced.start, forced.end) == (second.start, second.end)


@pytest.mark.parametrize("entry, words", [
    ({"boundaries": {"add": [5000]}}, "boundaries.add[0] = 5000 lies outside the sequence"),
    ({"textons": {"add": [None]}}, "textons.add[0] must be a frame number"),
    ({"drop": ["t30/99"]}, "drop[0] = 't30/99' names no motion"),
    ({"representatives": [0]}, "representatives[0] = 0 lies in no texton"),
    ({"boundaries": {"add": [60, 62]}}, "boundaries make cluster 60-61 2 frames long, shorter than the 5-frame atom"),
])
def test_an_invalid_correction_is_one_sentence_naming_the_entry(base, tmp_path, capsys, entry, words):
    fix = tmp_path / "bad.json"
    fix.write_text(json.dumps({"sequences": {NAME: entry}}))
    capsys.readouterr()
    assert main(["correct", str(base.path), str(fix), "-o", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ") and words in err and str(fix) in err and "\n" not in err
    assert not (tmp_path / "x").exists()


def test_a_texton_shorter_than_the_atom_window_is_refused(base):
    texton = base.parse(NAME).textons[0]
    c = Corrections()
    c.add_texton(NAME, texton.start + 2)
    with pytest.raises(CorrectionError, match=r"textons.add\[0\] = .* shorter than the 5-frame atom window"):
        base.correct(c, base.path.with_name("short.tvmlib"))


def test_dropping_every_motion_is_refused(base, tmp_path):
    # An empty library is never of use, and replacing one with it would lose its stored meshes.
    c = Corrections()
    for node in base.nodes:
        c.drop(NAME, node.name)
    with pytest.raises(CorrectionError, match=r"drop leaves the library no motion; keep at least one"):
        base.correct(c, tmp_path / "empty.tvmlib")
    assert not (tmp_path / "empty.tvmlib").exists()


def test_the_report_shows_corrected_boundaries_and_the_parse_before(base, tmp_path):
    auto = base.structure(NAME).clusters
    c = Corrections()
    c.remove_boundary(NAME, auto[1][0])
    fixed = base.correct(c, tmp_path / "fixed.tvmlib")
    assert main(["report", str(fixed.path), "-o", str(tmp_path / "report")]) == 0
    row = json.loads((tmp_path / "report" / "report.json").read_text())["sequences"][0]
    assert row["corrections"] == c.to_json()["sequences"][NAME]
    assert row["automatic_clusters"] == [list(x) for x in auto] and len(row["clusters"]) == len(auto) - 1
    page = (tmp_path / "report" / "index.html").read_text()
    assert "Corrected by hand" in page and f"{auto[0][0]}-{auto[0][1]} {auto[1][0]}-{auto[1][1]}" in page


def test_kept_corrections_that_no_longer_fit_say_how_to_drop_them(base, take, tmp_path, capsys):
    out = tmp_path / "lib.tvmlib"
    shutil.copytree(base.path, out)
    frames = len(base.sequence(NAME))
    c = Corrections()
    c.add_boundary(NAME, frames - 20)
    Library.open(out).correct(c)
    shorter = f"{NAME}=" + str(take / "frame_000[0-9]?.ply")          # the first 100 frames only
    capsys.readouterr()
    assert main(["build", shorter, "-o", str(out), "--force", "-q", "--workers", "1", "--fps", "10"]) == 2
    err = capsys.readouterr().err
    assert "no longer fit" in err and "--no-corrections" in err and err.count("\n") == 1
    assert main(["build", shorter, "-o", str(out), "--force", "-q", "--workers", "1", "--fps", "10",
                 "--no-corrections"]) == 0


def test_any_corrections_give_a_sound_parse_or_one_sentence(small_library):
    """Random corrections of the gym library: a parse that covers the sequence with textons
    inside their clusters and a database inside them, or a CorrectionError naming the entry."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from tvmedit.engine.store.corrections import apply_database, apply_structures

    library = Library.open(small_library)
    name = library.sequences[0].name
    frames = len(library.sequence(name))
    vectors = {name: library.features(name).vectors}
    parses = {name: library.parse(name)}
    frame = st.integers(-3, frames + 3)
    pair = st.lists(frame, min_size=2, max_size=2)
    ops = st.fixed_dictionaries({}, optional={"add": st.lists(frame, max_size=3), "remove": st.lists(frame, max_size=3),
                                              "move": st.lists(pair, max_size=2)})
    entry = st.fixed_dictionaries({}, optional={
        "boundaries": ops, "textons": ops, "representatives": st.lists(frame, max_size=2),
        "drop": st.lists(st.sampled_from([n.name for n in library.nodes] + [f"{name}/99"]), max_size=2)})

    @settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
    @given(entry)
    def check(data):
        try:
            c = Corrections.from_json({"sequences": {name: data}}, "c.json")
            c.check_sequences({name: frames})
            structures = apply_structures(parses, vectors, c)
            nodes = apply_database(build_database(structures), structures, c)
        except CorrectionError as error:
            assert str(error).startswith("c.json, sequence") and str(error).endswith(".") and "\n" not in str(error)
            return
        s = structures[name]
        assert s.clusters[0][0] == 0 and s.clusters[-1][1] == frames - 1
        assert all(a[1] + 1 == b[0] for a, b in zip(s.clusters, s.clusters[1:]))
        assert all(s.clusters[t.cluster][0] <= t.start <= t.end <= s.clusters[t.cluster][1] for t in s.textons)
        assert [n.id for n in nodes] == list(range(len(nodes)))
        assert all(s.clusters[n.cluster][0] <= n.start <= n.end <= s.clusters[n.cluster][1] for n in nodes)

    check()
