"""The report of a built library (``tvmedit report``): one HTML page with the paper's figures.

What a build found, in the order of the paper:

* **Motion structure** (section 4), per sequence: the atom distance d_A(t, t_first) from the
  first atom of the current texton, with the texton starts as black points (Figure 4) and the
  motion clusters as alternating bands. Where a ``truth.json`` sits beside the sequence's
  frames, its segments are drawn as a labelled band under the detected clusters and the
  boundary precision and recall of the clusters are printed (Figure 5's measure), computed
  by ``tvmedit.engine.lab.evaluate.score``, the scorer of the tests and of ``benchmarks/accuracy.py``.
  A sequence corrected by hand (``tvmedit.engine.store.corrections``) shows the automatic parse's clusters
  in a strip above the corrected ones, boundaries drawn by hand as orange lines and those
  removed by hand as dotted red ones, and its corrections under the figure. Each detected
  boundary's confidence (:mod:`tvmedit.engine.parse.confidence`) is written above it; those under
  ``LOOK_BELOW`` (0.1), the ones to look at first, are red with a dashed red line.
* **Motion database** (section 5, eq. (9)): one contact sheet of evenly spaced frames per
  node, captioned with its length, texton distance d_T (eq. (6)) and motion intensity
  (eq. (11)), as Figure 6 shows selected textons.
* **Motion graph** (section 6, Figure 7): nodes on a circle with a rendered frame each, kept
  edges labelled with their weight (eq. (12)); edges pruned by eq. (14) are hidden, or drawn
  faint with ``show_pruned``.
* **Transitions**: every kept edge with its transition frames (eq. (10)), cheapest first, and
  the two frames side by side for the cheapest and the costliest.
* **Blending** (:mod:`tvmedit.engine.inbetween.blend`), per transition: a filmstrip of the frames around it as
  an edit plays them, with the in-between frames and with the paper's cut, and the step curve
  (Chamfer distance between consecutive displayed frames) with the natural step marked; and
  per loop the build closed (:mod:`tvmedit.engine.inbetween.loops`), the frames around its wrap as it plays and
  as captured.

The page is self-contained: ``index.html`` with PNG files beside it, referenced relatively,
no script and no external style. ``report.json`` holds the same numbers (the texton starts
each curve marks, precision, recall) for scripts and tests. Everything is written into a
temporary folder next to the target and renamed at the end, so a failure leaves nothing
half-written.

Matplotlib is an optional dependency (``pip install 'tvmedit[report]'``) and is imported
only when a figure is drawn; figures draw with Agg, so no display is needed.
"""

import html
import json
import math
import sys
from pathlib import Path

import numpy as np

from ..engine import safewrite
from ..engine.parse.confidence import LOOK_BELOW
from ..engine.errors import TvmError
from ..engine.lab.evaluate import TOLERANCE_S, score
from ..engine.parse.structure import StructureParams, followed_heading, vetoed_turns
from .figures import (CURVE_SIZE, GRAPH_SIZE, STEP_SIZE, atom_distance_figure, fmt_number, graph_figure,
                      require_matplotlib, start_end, step_figure)

#: Frames per node contact sheet (evenly spaced over the texton, first and last included).
SHEET_FRAMES = 8

#: Cheapest and costliest transitions shown as frame pairs (each end of the sorted table).
PAIRS_EACH_END = 3

STRIP_TILE = (90, 120)
SHEET_TILE = (120, 160)
THUMB_SIZE = (84, 112)
PAIR_TILE = (150, 200)



def _connect_sentence(connect):
    """What connecting the graph did, in a sentence (tvmedit.engine.graph.connect), or nothing."""
    if not connect or connect["mode"] == "off":
        return "The graph is the paper's: nothing was added to connect it (built with --connect off). "
    if not connect["added"]:
        return "Every motion reaches every other through the kept transitions alone. "
    n = connect["added"]
    return (f"{n} transition{'s were' if n != 1 else ' was'} added back from the complete graph so "
            f"that every motion reaches every other (dashed, red labels); the largest added weight, "
            f"{connect['largest_weight']:.3g}, is the least that connects the graph. ")


def write_report(library, out, show_pruned=False, progress=True, source=None, force=False):
    """Write the report of ``library`` into folder ``out`` and return the path of its index.html.

    Parameters
    ----------
    library : engine.Library
        An opened library (``sequences``, ``structure(name)``, ``nodes``, ``graph``).
    out : str or Path
        Folder to create; an existing report there is replaced only with ``force`` and only
        if it holds nothing but what tvmedit wrote; any other existing folder is refused.
    show_pruned : bool
        Draw the pruned edges faintly in the motion graph.
    progress : bool
        Print one line per step on stderr.
    source : MeshSource, optional
        Where rendered frames come from; the library itself by default.
    force : bool
        Replace a previous report at ``out``.
    """
    require_matplotlib()
    out = Path(out)
    inputs = library.sources() if hasattr(library, "sources") else ()
    safewrite.check_target(out, "report", force, inputs=inputs, legacy=_legacy_report)
    say = _say if progress else (lambda *a: None)
    recheck = lambda target: safewrite.check_target(target, "report", force, legacy=_legacy_report)  # noqa: E731
    with safewrite.replacing_folder(out, recheck=recheck, kind="report") as temporary:
        page = _Report(library, source if source is not None else library, temporary, say)
        html_text, summary = page.build(show_pruned)
        (temporary / "index.html").write_text(html_text, encoding="utf-8")
        (temporary / "report.json").write_text(json.dumps(summary, indent=1, allow_nan=False), encoding="utf-8")
    return out / "index.html"


def _legacy_report(path):
    """A report written before the ownership marker: report.json, index.html and PNG figures."""
    if not (path / "report.json").is_file():
        return None
    return [p.name for p in path.iterdir()
            if p.name not in ("report.json", "index.html") and p.suffix != ".png"]


def _say(message):
    print(message, file=sys.stderr, flush=True)


class _Report:
    """Builds the page section by section, writing figures into ``folder`` as it goes."""

    def __init__(self, library, source, folder, say):
        self.library = library
        self.source = source
        self.folder = folder
        self.say = say
        self.fps = {seq.name: float(seq.fps) for seq in library.sequences}

    def build(self, show_pruned):
        graph = self.library.graph
        nodes = sorted(self.library.nodes, key=lambda n: n.id)
        summary = {"sequences": [], "nodes": [], "graph": {}, "transitions": []}
        sections = [
            self.structure_section(summary),
            self.database_section(nodes, summary),
            self.graph_section(graph, nodes, show_pruned, summary),
            self.transitions_section(graph, nodes, summary),
            self.blending_section(graph, nodes, summary),
        ]
        summary["images"] = sorted(p.name for p in self.folder.glob("*.png"))
        title = (f"Library {self.library.path}: {len(self.library.sequences)} sequences, "
                 f"{len(nodes)} motions, {graph.number_of_edges()} transitions")
        return _page(title, sections), summary

    def structure_section(self, summary):
        parts = ["<h2 id='structure'>Motion structure</h2>",
                 "<p>Atom distance d<sub>A</sub>(t, t<sub>first</sub>) from the first atom of the "
                 "current texton (Figure 4); black points mark texton starts, bands the motion "
                 "clusters.</p>"]
        corrections = self.library.corrections().to_json()["sequences"]
        for k, seq in enumerate(self.library.sequences):
            self.say(f"report: structure of {seq.name}")
            structure = self.library.structure(seq.name)
            truth = _truth_beside(seq)
            scored = score(structure, truth, seq.fps) if truth else None
            png = f"structure-{k:02d}.png"
            fixes = corrections.get(seq.name)
            automatic = self.library.parse(seq.name).clusters if fixes else None
            features = self.library.features(seq.name)
            params = StructureParams.recorded(structure.params)
            heading = followed_heading(features.vectors, params, features.theta_columns, seq.fps)
            turns = vetoed_turns(features.vectors, params, features.theta_columns, seq.fps, features.centred)
            if fixes:
                # A boundary drawn by hand at a turn: the parser's veto is no longer the news.
                near = params.min_cluster * seq.fps
                turns = [t for t in turns if all(abs(t - cs) > near for cs, _ in structure.clusters[1:])]
            plotted = atom_distance_figure(structure.curve, structure.textons, structure.clusters,
                                           self.folder / png,
                                           truth_segments=scored.segments if scored else None,
                                           fps=seq.fps, title=seq.name, automatic=automatic, heading=heading,
                                           turns=turns, confidence=structure.boundary_confidence)
            row = {"name": seq.name, "image": png, "texton_starts": plotted["texton_starts"],
                   "clusters": [list(map(int, c)) for c in structure.clusters],
                   "textons": len(structure.textons)}
            if fixes:
                row.update(corrections=fixes, automatic_clusters=[list(map(int, c)) for c in automatic])
            facts = (f"{len(structure.clusters)} clusters, {len(structure.textons)} textons, "
                     f"{len(structure.curve)} frames at {seq.fps:g} fps")
            parts.append(f"<h3>{_e(seq.name)}</h3><p>{_e(facts)}</p>"
                         f"<img src='{png}' width='{CURVE_SIZE[0]}' height='{CURVE_SIZE[1]}' "
                         f"alt='atom distance of {_e(seq.name)}'>")
            if fixes:
                parts.append(_corrections_paragraph(fixes, automatic, structure.clusters))
            parts.append(_confidence_paragraph(structure, row))
            parts.append(_heading_paragraph(heading, row))
            parts.append(_turns_paragraph(plotted["turns"], seq.fps, row))
            if scored is not None:
                parts.append(self._score_paragraph(seq, structure, scored, row))
            summary["sequences"].append(row)
        return "\n".join(parts)

    def _score_paragraph(self, seq, structure, scored, row):
        """The scores against truth.json (tvmedit.engine.lab.evaluate.score), for the page and report.json."""
        self.say(f"report: {seq.name}: cluster boundaries against truth.json: precision "
                 f"{scored.precision:.3f}, recall {scored.recall:.3f}")
        accuracy = ""
        if math.isfinite(scored.texton_accuracy):
            accuracy = (f"; texton-length accuracy {scored.texton_accuracy:.3f} (median texton "
                        "length within 15 % of the true period)")
        row.update(precision=scored.precision, recall=scored.recall,
                   tolerance_frames=scored.tolerance_frames, truth_segments=len(scored.segments),
                   texton_accuracy=scored.texton_accuracy if math.isfinite(scored.texton_accuracy) else None)
        return (f"<p class='score'>Cluster boundaries against truth.json "
                f"(tolerance {scored.tolerance_frames} frames, {TOLERANCE_S:g} s): precision "
                f"{scored.precision:.3f}, recall {scored.recall:.3f} ({len(scored.matches)} matched "
                f"of {len(_inner(structure.clusters))} detected and {len(_inner(scored.segments))} "
                f"true boundaries){accuracy}</p>")

    def database_section(self, nodes, summary):
        from .headless import contact_sheet, spread_frames

        parts = ["<h2 id='database'>Motion database</h2>",
                 "<p>The representative texton of each cluster, eq. (9): the one with the smallest "
                 "texton distance d<sub>T</sub> (Figure 6). A cluster that does not repeat is a "
                 "one-shot motion, played through once from its first frame and left from its "
                 "last part.</p>"]
        if not nodes:
            parts.append("<p>The database holds no motions.</p>")
        for node in nodes:
            self.say(f"report: contact sheet of {node.name}")
            frames = spread_frames(node.start, node.end, SHEET_FRAMES)
            png = f"node-{node.id:03d}.png"
            contact_sheet(self.source, [(node.sequence, f) for f in frames], self.folder / png,
                          columns=len(frames), tile=SHEET_TILE,
                          labels=[f"{f}" for f in frames])
            n_frames = node.end - node.start + 1
            seconds = n_frames / self.fps[node.sequence]
            intensity = node.intensity if node.intensity is not None else float("nan")
            caption = (f"{node.id}: {node.name}, frames {node.start}-{node.end} of {node.sequence}, "
                       f"{n_frames} frames ({seconds:.2f} s), texton distance "
                       f"{node.texton_distance:.4g}, motion intensity {intensity:.4g}"
                       + ("; a one-shot motion, played once" if getattr(node, "kind", "cycle") == "once" else ""))
            parts.append(f"<figure><img src='{png}' width='{SHEET_TILE[0] * len(frames)}' "
                         f"height='{SHEET_TILE[1]}' alt='{_e(node.name)}'>"
                         f"<figcaption>{_e(caption)}</figcaption></figure>")
            summary["nodes"].append({"id": node.id, "name": node.name, "image": png,
                                     "frames": frames, "n_frames": n_frames, "seconds": seconds,
                                     "texton_distance": node.texton_distance,
                                     "intensity": node.intensity, "kind": getattr(node, "kind", "cycle")})
        return "\n".join(parts)

    def graph_section(self, graph, nodes, show_pruned, summary):
        from .headless import render_frame

        self.say("report: motion graph")
        thumbnails = {}
        # Thumbnails shrink to fit side by side on the circle; below a readable size, discs.
        circumference = math.pi * min(GRAPH_SIZE) / 1.4
        scale = min(1.0, circumference / (1.3 * max(len(nodes), 1) * math.hypot(*THUMB_SIZE)))
        size = (round(THUMB_SIZE[0] * scale), round(THUMB_SIZE[1] * scale))
        for node in nodes if size[1] >= 40 else []:
            key = (node.sequence, (node.start + node.end) // 2)
            thumbnails[node.id] = render_frame(self.source, key, camera=self._framing(key, size),
                                               size=size)
        drawn = graph_figure(graph, self.folder / "graph.png", thumbnails=thumbnails,
                             show_pruned=show_pruned)
        unpruned = graph.graph.get("unpruned", {})
        summary["graph"] = {"image": "graph.png", "edges": [list(e) for e in drawn["edges"]],
                            "pruned_drawn": [list(e) for e in drawn["pruned"]],
                            "pruned": len(unpruned) - graph.number_of_edges() if unpruned else 0,
                            "mu": graph.graph.get("mu"), "added": [list(e) for e in drawn["added"]],
                            "connect": graph.graph.get("connect")}
        hidden = "drawn dashed in grey" if show_pruned else "hidden (show them with --show-pruned)"
        kept = graph.number_of_edges() - len(drawn["added"])
        return ("<h2 id='graph'>Motion graph</h2>"
                f"<p>{graph.number_of_nodes()} motions, {kept} transitions kept by "
                f"pruning, eq. (14); edge labels are weights, eq. (12); pruned edges are {hidden}. "
                f"{_connect_sentence(graph.graph.get('connect'))}"
                "Each node shows the middle frame of its texton (Figure 7).</p>"
                f"<img src='graph.png' width='{GRAPH_SIZE[0]}' height='{GRAPH_SIZE[1]}' "
                "alt='motion graph'>")

    def transitions_section(self, graph, nodes, summary):
        from .headless import contact_sheet

        names = {node.id: node.name for node in nodes}
        sequence_of = {node.id: node.sequence for node in nodes}
        edges = sorted(graph.edges(data=True), key=lambda e: (e[2]["weight"], e[0], e[1]))
        shown = set(range(min(PAIRS_EACH_END, len(edges))))
        shown |= set(range(max(0, len(edges) - PAIRS_EACH_END), len(edges)))
        rows = []
        for rank, (i, j, data) in enumerate(edges):
            pair = ""
            if rank in shown:
                self.say(f"report: transition {names[i]} -> {names[j]}")
                png = f"transition-{i:03d}-{j:03d}.png"
                keys = [(sequence_of[i], data["exit_frame"]), (sequence_of[j], data["entry_frame"])]
                contact_sheet(self.source, keys, self.folder / png, columns=2, tile=PAIR_TILE,
                              labels=[f"exit {data['exit_frame']}", f"entry {data['entry_frame']}"])
                pair = (f"<img src='{png}' width='{2 * PAIR_TILE[0]}' height='{PAIR_TILE[1]}' "
                        f"alt='{_e(names[i])} to {_e(names[j])}'>")
            rows.append(f"<tr><td>{rank + 1}</td><td>{_e(names[i])}</td><td>{_e(names[j])}</td>"
                        f"<td class='num'>{fmt_number(data['weight'])}</td>"
                        f"<td class='num'>{data['exit_frame']}</td><td class='num'>{data['entry_frame']}</td>"
                        f"<td>{pair}</td></tr>")
            summary["transitions"].append({"from": i, "to": j, "weight": data["weight"],
                                           "exit_frame": data["exit_frame"],
                                           "entry_frame": data["entry_frame"],
                                           "image": png if pair else None})
        if not rows:
            return "<h2 id='transitions'>Transitions</h2><p>The motion graph has no transitions.</p>"
        return ("<h2 id='transitions'>Transitions</h2>"
                "<p>Every kept edge, cheapest first: weight, eq. (12), and the transition frames "
                f"t<sub>i</sub>* (exit, in the source motion's sequence) and t<sub>j</sub>* (entry, in "
                f"the target's), eq. (10). The {PAIRS_EACH_END} cheapest and costliest show the two "
                "frames side by side.</p>"
                "<table><tr><th>#</th><th>from</th><th>to</th><th>weight</th><th>exit frame</th>"
                "<th>entry frame</th><th>exit | entry</th></tr>" + "\n".join(rows) + "</table>")

    def blending_section(self, graph, nodes, summary):
        from .headless import contact_sheet

        natural = getattr(self.library, "natural_step", 0.0)
        runs = self.library.blend_runs() if hasattr(self.library, "blend_runs") else {}
        summary["blending"] = {"natural_step": natural, "transitions": []}
        parts = ["<h2 id='blending'>Blending</h2>",
                 f"<p>Each transition as an edit plays it: the frame before the exit frame, the exit "
                 f"frame, the in-between frames the build made (marked <i>b</i>), the entry frame and "
                 f"the one after; below, the paper's cut. The curve shows the Chamfer distance between "
                 f"consecutive displayed frames (vertex positions) with and without the in-between "
                 f"frames; the dashed line is the natural step, the median step between consecutive "
                 f"texton frames ({natural * 1000:.1f} mm).</p>"]
        by_id = {node.id: node for node in nodes}
        for i, j, data in sorted(graph.edges(data=True)):
            if (i, j) not in runs:
                continue
            self.say(f"report: blending {by_id[i].name} -> {by_id[j].name}")
            window = _blend_window(by_id[i], by_id[j], data)
            stem = f"blend-{i:03d}-{j:03d}"
            row = {"from": i, "to": j, **runs[i, j], "images": [f"{stem}.png", f"{stem}-cut.png",
                                                                f"{stem}-steps.png"]}
            sizes = [(STRIP_TILE[0] * len(window["blended"]), STRIP_TILE[1]),
                     (STRIP_TILE[0] * len(window["cut"]), STRIP_TILE[1]), STEP_SIZE]
            for keys, png in ((window["blended"], row["images"][0]), (window["cut"], row["images"][1])):
                contact_sheet(self.source, [k for k, _ in keys], self.folder / png, columns=len(keys),
                              tile=STRIP_TILE, labels=[label for _, label in keys])
            row.update(_window_steps(self.source, window, runs[i, j]))
            step_figure(row, natural, self.folder / row["images"][2])
            summary["blending"]["transitions"].append(row)
            worst = max(row["blended_steps"]) / natural if natural else float("nan")
            cut = max(row["cut_steps"]) / natural if natural else float("nan")
            parts.append(f"<h3>{_e(by_id[i].name)} &rarr; {_e(by_id[j].name)}</h3>"
                         f"<p>{runs[i, j]['count']} in-between frame(s); largest step "
                         f"{worst:.2f} natural steps (cut: {cut:.2f})</p>"
                         + "".join(f"<img src='{png}' width='{w}' height='{h}' alt='{png}'><br>"
                                   for png, (w, h) in zip(row["images"], sizes)))
        if not summary["blending"]["transitions"]:
            parts.append("<p>This library holds no transitions to blend.</p>")
        return "\n".join(parts + self._loops_part(nodes, natural, summary))

    def _loops_part(self, nodes, natural, summary):
        """Each loop the build closed (:mod:`tvmedit.engine.inbetween.loops`): its wrap as captured and closed."""
        from .headless import contact_sheet

        data = self.library.blend_data() if hasattr(self.library, "blend_data") else {}
        wraps = [w for w in data.get("wraps", []) if w["count"]]
        summary["blending"]["loops"] = wraps
        if not wraps:
            return []
        by_id = {node.id: node for node in nodes}
        parts = ["<h3>Loops</h3><p>Where a motion's texton wraps from its last frame to its first "
                 "further than the capture itself steps there, the build warps the frames next to the "
                 "wrap onto the neighbouring repetition's (marked <i>w</i>); above, the loop as it plays, "
                 "below, as captured.</p>"]
        for wrap in wraps:
            node = by_id[wrap["from"]]
            keys = _loop_window(node, wrap["count"], wrap.get("at", "end"))
            for row, png in ((keys["closed"], f"loop-{node.id:03d}.png"), (keys["captured"], f"loop-{node.id:03d}-cut.png")):
                contact_sheet(self.source, [k for k, _ in row], self.folder / png, columns=len(row),
                              tile=STRIP_TILE, labels=[label for _, label in row])
            worst = max(wrap["steps"]) / natural if natural else float("nan")
            parts.append(f"<p>{_e(node.name)}: {wrap['count']} frame(s) warped at its {wrap.get('at', 'end')}; "
                         f"largest step {worst:.2f} natural steps (the wrap as captured: "
                         f"{wrap['jump'] / natural if natural else float('nan'):.2f})</p>"
                         + "".join(f"<img src='{png}' width='{STRIP_TILE[0] * len(keys['closed'])}' "
                                   f"height='{STRIP_TILE[1]}' alt='{png}'><br>"
                                   for png in (f"loop-{node.id:03d}.png", f"loop-{node.id:03d}-cut.png")))
        return parts

    def _framing(self, key, size):
        from .camera import Camera

        positions = self.source.frame_mesh(key)[0]
        return Camera.framing((positions.min(axis=0), positions.max(axis=0)), size[0] / size[1])


def _blend_window(source, target, data):
    """Keys and labels of the frames around edge ``source -> target``, with and without blending."""
    def step(node, frame, by):
        return node.start + (frame - node.start + by) % (node.end - node.start + 1)

    x, e = data["exit_frame"], data["entry_frame"]
    before = [((source.sequence, step(source, x, -1)), f"{step(source, x, -1)}"), ((source.sequence, x), f"exit {x}")]
    after = [((target.sequence, e), f"entry {e}"), ((target.sequence, step(target, e, 1)), f"{step(target, e, 1)}")]
    edge = (source.id, target.id)
    between = [((source.sequence, x, (edge, k)), f"b{k + 1}") for k in range(data.get("blend", 0))]
    return {"blended": before + between + after, "cut": before + after}


def _loop_window(node, count, at):
    """Keys and labels of the frames around a texton's wrap, with its closing frames and without."""
    from ..engine.inbetween.loops import window

    warped = window(node.start, node.end, at, count)[0]
    closing = [((node.sequence, f, ((node.id, node.id), k)), f"w{f}") for k, f in enumerate(warped)]
    plain = [((node.sequence, f), f"{f}") for f in warped]
    if at == "end":
        before, after = [node.end - count], [node.start, node.start + 1]
    else:
        before, after = [node.end - 1, node.end], [node.start + count]
    before = [((node.sequence, f), f"{f}") for f in before]
    after = [((node.sequence, f), f"{f}") for f in after]
    return {"closed": before + closing + after, "captured": before + plain + after}


def _window_steps(source, window, run):
    """Steps across the window (metres): the texton steps at either end are measured here."""
    from ..engine.inbetween.blend import chamfer

    mesh = lambda key: np.asarray(source.frame_mesh(key)[0])  # noqa: E731
    (first, _), (exit_key, _), (entry_key, _), (last, _) = window["cut"]
    before = chamfer(mesh(first), mesh(exit_key), stride=4)
    after = chamfer(mesh(entry_key), mesh(last), stride=4)
    steps = run["steps"] if run["count"] else [run["jump"]]
    return {"blended_steps": [before, *steps, after], "cut_steps": [before, run["jump"], after]}


def _corrections_paragraph(fixes, automatic, clusters):
    """What was corrected by hand, before and after (the figure's top two strips)."""
    def spans(ranges):
        return " ".join(f"{s}-{e}" for s, e in ranges)

    listed = _e(json.dumps(fixes, separators=(", ", ": ")))
    return (f"<p class='corrections'>Corrected by hand (<code>corrections.json</code>: {listed}): "
            f"clusters {_e(spans(automatic))} as parsed, {_e(spans(clusters))} as corrected. In the "
            "figure, orange lines mark boundaries drawn by hand and dotted red ones boundaries "
            "removed by hand.</p>")


def _truth_beside(sequence):
    """The ``truth.json`` in the sequence's source folder, or None."""
    folder = _sequence_folder(sequence)
    if folder is None or not (folder / "truth.json").is_file():
        return None
    try:
        return json.loads((folder / "truth.json").read_text())
    except (OSError, ValueError) as error:
        raise TvmError(f"{folder / 'truth.json'} cannot be read as JSON ({error})") from None


def _sequence_folder(sequence):
    return Path(sequence.paths[0]).parent if sequence.paths else None


def _inner(ranges):
    return [r for r in ranges if int(start_end(r)[0]) != 0]


def _e(text):
    return html.escape(str(text), quote=True)


_STYLE = """
body { font-family: sans-serif; margin: 2em auto; max-width: 1000px; color: #202020; }
h2 { border-bottom: 1px solid #c0c0c0; padding-bottom: 0.2em; margin-top: 2em; }
figure { margin: 1em 0; }
figcaption { font-size: 0.9em; color: #404040; }
img { max-width: 100%; height: auto; }
table { border-collapse: collapse; font-size: 0.9em; }
td, th { border: 1px solid #d0d0d0; padding: 0.2em 0.5em; vertical-align: middle; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
p.score { font-weight: bold; }
"""


def _page(title, sections):
    nav = " | ".join(f"<a href='#{a}'>{t}</a>" for a, t in [
        ("structure", "Motion structure"), ("database", "Motion database"),
        ("graph", "Motion graph"), ("transitions", "Transitions"), ("blending", "Blending")])
    return ("<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
            f"<title>tvmedit report</title><style>{_STYLE}</style></head><body>"
            f"<h1>tvmedit report</h1><p>{_e(title)}</p><p>{nav}</p>\n" + "\n".join(sections) + "\n</body></html>\n")


def _heading_paragraph(heading, row):
    """Which way the parser read the person facing (tvmedit.engine.parse.heading), for the page and report.json."""
    if heading is None:
        row.update(heading_deg=None)
        return "<p class='heading'>The parser read the azimuth histograms as they stand (no heading followed).</p>"
    low, high = float(np.min(heading)), float(np.max(heading))
    row.update(heading_deg=[round(low, 1), round(high, 1)])
    if high - low == 0:
        text = ("The parser followed no turn: the person kept facing one way (within the 5 degree "
                "steps a second it follows)")
    else:
        text = (f"The parser followed the person turning between {low:+.0f} and {high:+.0f} degrees "
                f"(dashed grey, right axis) and read every frame turned back by it; where the line "
                f"moves with no turn in the capture, look there first")
    return f"<p class='heading'>{_e(text)}.</p>"


def _turns_paragraph(turns, fps, row):
    """Where the parser read a turn and cut no boundary (the turn veto), for the page and report.json."""
    row.update(turns_s=[round(t / fps, 2) for t in turns])
    if not turns:
        return ""
    at = ", ".join(f"{t / fps:.1f} s" for t in turns)
    return (f"<p class='turns'>{_e(f'The parser read the person turning at {at} (purple triangles) and cut no boundary there')}: "
            "if the motion changes there too, add the boundary by hand (<code>tvmedit correct</code>).</p>")


def _confidence_paragraph(structure, row):
    """How sure the parse is of each boundary and of its least sure textons (tvmedit.engine.parse.confidence)."""
    bounds = [(int(c[0]), float(v)) for c, v in zip(structure.clusters[1:], structure.boundary_confidence[1:])]
    known = [t for t in structure.textons if t.confidence is not None]
    textons = sorted((float(t.confidence), int(t.start), int(t.end)) for t in known)[:3]
    row.update(boundary_confidence=[v for _, v in bounds],
               texton_confidence=[None if t.confidence is None else float(t.confidence) for t in structure.textons])
    if not bounds and not textons:
        return ""
    text = f"Confidence (0-1, low first deserves a look; boundaries under {LOOK_BELOW:g} are red in the figure): "
    text += ("boundaries " + ", ".join(f"frame {f} {v:.2f}" for f, v in bounds)) if bounds else "no boundaries"
    if textons:
        text += "; least sure textons " + ", ".join(f"{a}-{b} {v:.2f}" for v, a, b in textons)
    return f"<p class='confidence'>{_e(text)}.</p>"
