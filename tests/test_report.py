"""`tvmedit report` on small built libraries (EGL renders the thumbnails; skipped without it).

The library is a four-motion take of the synthetic actor at 3,000 vertices a frame (about
270 frames, built in seconds); a second library, of its first 100 frames copied to a folder
without ``truth.json``, has no ground truth and only two motions, so no transitions.
"""

import json
import os
import re
import shutil

import imageio.v3 as iio
import networkx as nx
import numpy as np
import pytest

from conftest import synth_take
from tvmedit import build
from tvmedit.engine.errors import TvmError
from tvmedit.engine.lab.evaluate import boundary_scores, load_truth, texton_length_accuracy
from tvmedit.cli import main

pytestmark = pytest.mark.gl

SECTIONS = ["Motion structure", "Motion database", "Motion graph", "Transitions", "Blending"]


@pytest.fixture(scope="module")
def take():
    return synth_take("gym", motions=["walk", "jumping-jacks", "arm-circles", "side-bends"],
                      cycles=4, vertices=3000)


@pytest.fixture(scope="module")
def library(take, tmp_path_factory):
    return build([("gym", str(take))], tmp_path_factory.mktemp("lib") / "gym.lib", workers=2, cache=False,
                 smooth=False)


@pytest.fixture(scope="module")
def library_without_truth(take, tmp_path_factory):
    # Hard links, not symlinks: the library records resolved paths, and a symlink would lead
    # back to the folder that holds truth.json.
    folder = tmp_path_factory.mktemp("frames") / "walk"
    folder.mkdir()
    for path in sorted(take.glob("frame_*.ply"))[:100]:
        try:
            os.link(path, folder / path.name)
        except OSError:
            shutil.copy(path, folder / path.name)
    return build([("walk", str(folder))], folder.parent / "walk.lib", workers=2, cache=False, smooth=False)


def _report(lib, out, capsys, *flags):
    assert main(["report", str(lib.path), "-o", str(out), "-q", *flags]) == 0
    printed = capsys.readouterr().out.strip()
    assert printed == str(out / "index.html")
    return (out / "index.html").read_text(), json.loads((out / "report.json").read_text())


@pytest.fixture(scope="module")
def report(ctx, library, tmp_path_factory):
    from tvmedit.player.report import write_report

    out = tmp_path_factory.mktemp("report") / "gym-report"
    write_report(library, out, progress=False)
    return out, (out / "index.html").read_text(), json.loads((out / "report.json").read_text())


def _images(page):
    """(src, width, height) of every <img> in the page."""
    return [(m.group(1), int(m.group(2)), int(m.group(3)))
            for m in re.finditer(r"<img src='([^']+)' width='(\d+)' height='(\d+)'", page)]


def test_the_cli_prints_the_page_and_draws_pruned_edges_on_request(ctx, library, tmp_path, capsys):
    page, summary = _report(library, tmp_path / "out", capsys, "--show-pruned")
    assert all(f">{title}</h2>" in page for title in SECTIONS)
    assert not list(tmp_path.glob(".out.*"))
    G = library.graph
    pruned = sorted(set(G.graph["unpruned"]) - set(G.edges))
    assert pruned and [tuple(e) for e in summary["graph"]["pruned_drawn"]] == pruned
    assert "pruned edges are drawn dashed" in page
    added = sorted(e for e in G.edges if G.edges[e]["added"])
    assert [tuple(e) for e in summary["graph"]["added"]] == added
    if added:
        assert f"{len(added)} transition" in page and "added back from the complete graph" in page


def test_every_section_is_there_and_every_image_it_names_exists(report):
    out, page, summary = report
    for title in SECTIONS:
        assert f">{title}</h2>" in page
    assert "graph.png" in page and (out / "graph.png").is_file()
    referenced = {src for src, _, _ in _images(page)}
    assert referenced and all((out / src).is_file() for src in referenced)
    assert referenced == set(summary["images"])
    # Self-contained: nothing fetched from anywhere.
    assert not re.search(r"https?://|<script|<link", page)


def test_images_are_pngs_of_the_stated_size_and_not_blank(report):
    out, page, _ = report
    for src, width, height in _images(page):
        data = (out / src).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n", src
        image = iio.imread(data)
        assert image.shape[:2] == (height, width), src
        assert image[..., :3].astype(float).std() > 8.0, f"{src} is nearly uniform"


def test_one_contact_sheet_per_motion_with_its_numbers(report, library):
    out, page, summary = report
    nodes = library.nodes
    assert [row["id"] for row in summary["nodes"]] == [node.id for node in nodes]
    for node, row in zip(nodes, summary["nodes"]):
        assert (out / row["image"]).is_file()
        assert row["frames"][0] == node.start and row["frames"][-1] == node.end
        assert 6 <= len(row["frames"]) <= 8 or len(row["frames"]) == node.end - node.start + 1
        fps = library.sequence(node.sequence).fps
        n = node.end - node.start + 1
        assert f"{node.name}, frames {node.start}-{node.end} of {node.sequence}, {n} frames ({n / fps:.2f} s)" in page
        assert f"texton distance {node.texton_distance:.4g}, motion intensity {node.intensity:.4g}" in page


def test_the_figure_4_curve_marks_exactly_the_texton_starts(report, library):
    _, _, summary = report
    for row in summary["sequences"]:
        structure = library.structure(row["name"])
        assert row["texton_starts"] == sorted(t.start for t in structure.textons)
        assert row["clusters"] == [list(c) for c in structure.clusters]


def test_precision_and_recall_are_those_of_the_accuracy_benchmark(report, library, take):
    _, page, summary = report
    truth = load_truth(take)
    structure = library.structure("gym")
    # As benchmarks/accuracy.py scores: one second of tolerance at the truth's frame rate.
    precision, recall, _ = boundary_scores(structure.clusters, truth["segments"],
                                           tolerance_frames=round(1.0 * truth["fps"]))
    (row,) = summary["sequences"]
    assert (row["precision"], row["recall"]) == (precision, recall)
    assert f"precision {precision:.3f}, recall {recall:.3f}" in page
    accuracy = texton_length_accuracy(structure, truth)
    assert row["texton_accuracy"] == (accuracy if accuracy == accuracy else None)


def test_transitions_are_listed_by_weight_with_frame_pairs_at_both_ends(report, library):
    out, page, summary = report
    rows = summary["transitions"]
    G = library.graph
    assert len(rows) == G.number_of_edges() > 0
    weights = [row["weight"] for row in rows]
    assert weights == sorted(weights)
    for row in rows:
        edge = G.edges[row["from"], row["to"]]
        assert (row["exit_frame"], row["entry_frame"]) == (edge["exit_frame"], edge["entry_frame"])
    with_pairs = [k for k, row in enumerate(rows) if row["image"]]
    assert 0 in with_pairs and len(rows) - 1 in with_pairs
    assert all((out / rows[k]["image"]).is_file() for k in with_pairs)


def test_a_library_without_truth_reports_without_ground_truth(ctx, library_without_truth, tmp_path, capsys):
    page, summary = _report(library_without_truth, tmp_path / "out", capsys)
    for title in SECTIONS:
        assert f">{title}</h2>" in page
    assert "truth.json" not in page and "precision" not in page
    (row,) = summary["sequences"]
    assert "precision" not in row and "recall" not in row
    structure = library_without_truth.structure("walk")
    assert row["texton_starts"] == sorted(t.start for t in structure.textons)
    for src, width, height in _images(page):
        assert iio.imread(tmp_path / "out" / src).shape[:2] == (height, width)


def test_pruned_edges_are_hidden_unless_asked_for(tmp_path):
    G = nx.DiGraph(mu=0.9, unpruned={(0, 1): 1.0, (1, 0): 2.0, (0, 2): 3.0, (2, 0): 1.0,
                                     (1, 2): 1.0, (2, 1): 3.0})
    for i in range(3):
        G.add_node(i, name=f"m/{i}")
    for i, j in [(0, 1), (1, 2), (2, 0)]:
        G.add_edge(i, j, weight=G.graph["unpruned"][i, j], exit_frame=0, entry_frame=0)
    from tvmedit.player.figures import graph_figure

    hidden = graph_figure(G, tmp_path / "hidden.png")
    shown = graph_figure(G, tmp_path / "shown.png", show_pruned=True)
    assert hidden["edges"] == shown["edges"] == [(0, 1), (1, 2), (2, 0)]
    assert hidden["pruned"] == [] and shown["pruned"] == [(0, 2), (1, 0), (2, 1)]
    a, b = iio.imread(tmp_path / "hidden.png"), iio.imread(tmp_path / "shown.png")
    assert a.shape[:2] == b.shape[:2] == (900, 900)
    assert (a != b).any()


def test_a_failed_report_leaves_nothing_and_other_folders_are_not_replaced(ctx, library, tmp_path):
    from tvmedit.player.report import write_report

    class Broken:
        def __getattr__(self, name):
            return getattr(library, name)

        def frame_mesh(self, key):
            raise RuntimeError("disk gone")

    with pytest.raises(RuntimeError, match="disk gone"):
        write_report(library, tmp_path / "out", progress=False, source=Broken())
    assert list(tmp_path.iterdir()) == []

    other = tmp_path / "photos"
    other.mkdir()
    (other / "a.jpg").write_bytes(b"x")
    with pytest.raises(TvmError, match="is not a tvmedit report"):
        write_report(library, other, progress=False)
    assert [p.name for p in other.iterdir()] == ["a.jpg"]


def test_without_matplotlib_one_sentence_says_what_to_install(monkeypatch):
    import sys

    from tvmedit.player.figures import require_matplotlib

    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(TvmError, match=r"pip install 'tvmedit\[report\]'"):
        require_matplotlib()


def test_plotting_returns_the_markers_it_draws(tmp_path):
    from tvmedit.player.figures import atom_distance_figure

    curve = np.abs(np.sin(np.arange(60) * np.pi / 10))
    plotted = atom_distance_figure(curve, [(20, 29), (0, 9), (10, 19)], [(0, 29), (30, 59)],
                                   tmp_path / "c.png", size=(400, 200))
    assert plotted["texton_starts"] == [0, 10, 20]
    assert iio.imread(tmp_path / "c.png").shape[:2] == (200, 400)


def test_the_least_sure_boundaries_are_marked_red(tmp_path):
    # Three boundaries, one of them under LOOK_BELOW (0.097: written 0.097, not 0.10): only that
    # one gets the red dashed line, down the curve's axes at its frame; a boundary of unknown
    # confidence (None) gets neither line nor figure.
    from tvmedit.player.figures import UNSURE_COLOUR, atom_distance_figure

    curve = np.abs(np.sin(np.arange(80) * np.pi / 10))
    clusters = [(0, 19), (20, 39), (40, 59), (60, 79)]
    rgb = np.array([int(UNSURE_COLOUR[i:i + 2], 16) for i in (1, 3, 5)])
    red = []
    for confidence in ([1.0, 0.6, 0.3, 0.5], [1.0, 0.6, 0.097, None]):
        plotted = atom_distance_figure(curve, [(0, 9)], clusters, tmp_path / "u.png", size=(960, 300),
                                       confidence=confidence)
        image = iio.imread(tmp_path / "u.png")[..., :3].astype(int)
        red.append((plotted["unsure"], np.abs(image - rgb).max(axis=-1) <= 40))   # not the removed lines
    assert red[0][0] == [] and not red[0][1].any()
    assert red[1][0] == [40]
    rows, cols = np.nonzero(red[1][1])
    # at frame 40 of 80, about the middle of the figure, and the dashes down most of the curve's
    # axes (about 200 of the 300 rows): distinct rows in a narrow band of columns
    middle = int(np.median(cols))
    assert 0.4 * 960 < middle < 0.6 * 960, middle
    band = np.unique(rows[np.abs(cols - middle) <= 2])
    assert len(band) > 100 and band.max() - band.min() > 150, (len(band), band.min(), band.max())


def test_turns_the_parser_cut_no_boundary_at_are_marked_and_named(report, tmp_path):
    # The synthetic actor never turns: nothing is marked, and the page says nothing of turns.
    _, page, summary = report
    assert summary["sequences"][0]["turns_s"] == []
    assert "turning at" not in page
    # Turns are drawn as purple triangles along the top, where the parser read them.
    from tvmedit.player.figures import TURN_COLOUR, atom_distance_figure
    from tvmedit.player.report import _turns_paragraph

    # On a curve of any scale (here 0-50) they sit at the top, at the turns' frames (the
    # legend's own triangle, upper right, is left out of the count).
    curve = 50 * np.abs(np.sin(np.arange(60) * np.pi / 10))
    purple, rgb = [], np.array([int(TURN_COLOUR[i:i + 2], 16) for i in (1, 3, 5)])
    for turns in (None, [10, 30]):
        plotted = atom_distance_figure(curve, [(0, 9)], [(0, 59)], tmp_path / "t.png", size=(400, 200), turns=turns)
        image = iio.imread(tmp_path / "t.png")[..., :3].astype(int)
        mask = np.abs(image - rgb).max(axis=-1) <= 24
        mask[:, 250:] = False
        purple.append(mask)
    assert plotted["turns"] == [10, 30]
    rows, cols = np.nonzero(purple[1])
    assert not purple[0].any() and len(rows) > 40 and rows.max() < 0.2 * 200, (len(rows), rows.max())
    left, right = cols[cols < cols.mean()], cols[cols >= cols.mean()]   # one triangle each side
    assert 70 < left.mean() < 115 and 190 < right.mean() < 240, (left.mean(), right.mean())
    row = {}
    text = _turns_paragraph([60, 151], 10.0, row)
    assert row["turns_s"] == [6.0, 15.1] and "6.0 s, 15.1 s" in text and "tvmedit correct" in text


def test_a_take_where_the_actor_turns_names_the_turns_on_its_page(ctx, tmp_path):
    # A real take of the synthetic actor turning to face another way now and then (tvmedit
    # synth --turns 90), built and reported: the page and report.json name the turns the
    # parser read, within a second of where the actor turned, and the parse holds the three exercises.
    from tvmedit.engine.lab import synth
    from tvmedit.player.report import write_report

    take = synth_take("gym", motions=["jumping-jacks", "side-bends", "squats"], turns=90.0, vertices=4000, seed=3)
    truth = json.loads((take / "truth.json").read_text())
    heading = np.degrees(synth.turn_headings(truth["frames"], truth["fps"], 90.0, seed=3))
    turning = np.flatnonzero(np.abs(np.diff(heading)) > 1e-6) / truth["fps"]
    lib = build([("turning", str(take))], tmp_path / "t.lib", workers=2, cache=False, smooth=False)
    write_report(lib, tmp_path / "rep", progress=False)
    row = json.loads((tmp_path / "rep" / "report.json").read_text())["sequences"][0]
    assert row["turns_s"] and all(np.abs(turning - t).min() <= 1.0 for t in row["turns_s"]), (row["turns_s"], turning)
    # The parse holds the three exercises, none split at a turn, the change into side bends
    # right. The change into squats, which start from an upright pose as the side bends' own,
    # is placed about 1.2 s late (the novelty weighs the pace twice).
    starts = [cs / truth["fps"] for cs, _ in row["clusters"]]
    true = [seg["start"] / truth["fps"] for seg in truth["segments"]]
    assert len(starts) == 3 and abs(starts[1] - true[1]) <= 1.0 and abs(starts[2] - true[2]) <= 1.5, (starts, true)
    page = (tmp_path / "rep" / "index.html").read_text()
    assert "turning at " + ", ".join(f"{t:.1f} s" for t in row["turns_s"]) in page


def test_an_actor_turning_right_round_on_its_spot_is_read_as_turning(tmp_path):
    # The actor stays where it started (the features' origin stays at the first frame's
    # centre) and turns by 90-180 degrees every 5-10 s. About that origin a turn of a body
    # standing a little off it changes even the heading-free rows, and without the histograms
    # about each frame's own centre two turns became false boundaries (precision 0.5).
    from tvmedit.engine.lab import synth
    from tvmedit.player.report import write_report

    take = synth_take("gym", motions=["walk", "jumping-jacks", "box", "side-bends"], cycles=[10, 8, 8, 4],
                      turns=180.0, vertices=4000, seed=61)
    truth = json.loads((take / "truth.json").read_text())
    heading = np.degrees(synth.turn_headings(truth["frames"], truth["fps"], 180.0, seed=61))
    turning = np.flatnonzero(np.abs(np.diff(heading)) > 1e-6) / truth["fps"]
    lib = build([("spin", str(take))], tmp_path / "s.lib", workers=2, cache=False, smooth=False)
    assert lib.features("spin").centred is not None and len(lib.features("spin").centred) == truth["frames"]
    write_report(lib, tmp_path / "rep", progress=False)
    row = json.loads((tmp_path / "rep" / "report.json").read_text())["sequences"][0]
    assert (row["precision"], row["recall"]) == (1.0, 1.0), row
    assert len(row["turns_s"]) >= 2, row["turns_s"]
    assert all(np.abs(turning - t).min() <= 1.0 for t in row["turns_s"]), (row["turns_s"], turning)


def test_the_heading_the_parser_followed_is_shown_beside_the_curve(report, tmp_path):
    # The synthetic actor stands facing one way: the page says no turn was followed.
    _, page, summary = report
    assert summary["sequences"][0]["heading_deg"] == [0.0, 0.0]
    assert "followed no turn" in page
    # A turning take's heading is drawn on an axis of its own, in grey, beside the curve.
    from tvmedit.player.figures import atom_distance_figure

    curve = np.abs(np.sin(np.arange(60) * np.pi / 10))
    grey = []
    for heading in (None, np.linspace(0.0, 30.0, 60)):
        atom_distance_figure(curve, [(0, 9)], [(0, 59)], tmp_path / "h.png", size=(400, 200), heading=heading)
        image = iio.imread(tmp_path / "h.png")[..., :3].astype(int)
        grey.append((np.abs(image - 0x90).max(axis=-1) <= 8).sum())   # the dashed line's #909090
    assert grey[1] > grey[0] + 100, grey
