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

#: Frames per node contact sheet (evenly spaced over the texton, first and last included).
SHEET_FRAMES = 8

#: Cheapest and costliest transitions shown as frame pairs (each end of the sorted table).
PAIRS_EACH_END = 3

CURVE_SIZE = (960, 300)
STEP_SIZE = (420, 200)
STRIP_TILE = (90, 120)
GRAPH_SIZE = (900, 900)
SHEET_TILE = (120, 160)
THUMB_SIZE = (84, 112)
PAIR_TILE = (150, 200)

_INSTALL = "matplotlib is needed for reports; install it with: pip install 'tvmedit[report]'"
_BAND_COLOURS = ("#dfe9f5", "#f5e9d9")


def require_matplotlib():
    """The ``matplotlib`` module, or a TvmError saying how to install it."""
    try:
        import matplotlib
    except ImportError:
        raise TvmError(_INSTALL) from None
    return matplotlib


def _figure(size):
    # A bare Figure draws with Agg and touches no pyplot state, so a report made from a
    # notebook or a GUI program leaves its backend and its open figures alone. 100 dpi and
    # no tight bounding box make the PNG exactly ``size`` pixels.
    require_matplotlib()
    from matplotlib.figure import Figure

    return Figure(figsize=(size[0] / 100, size[1] / 100), dpi=100)


def _save(fig, out_png):
    fig.savefig(out_png, dpi=100, facecolor="white")


def atom_distance_figure(curve, textons, clusters, out_png, truth_segments=None, fps=None,
                         title="", size=CURVE_SIZE, automatic=None, heading=None, turns=None, confidence=None):
    """Figure 4 for one sequence: d_A(t, t_first) with texton starts and cluster bands.

    Parameters
    ----------
    curve : (T,) array_like
        d_A(t, t_first) for every frame t (NaN where undefined, e.g. near the ends).
    textons : list of (start, end) or objects with ``.start`` and ``.end``
        The sequence's textons; each start is marked with a black point on the curve.
    clusters : list of (start, end)
        Motion clusters, inclusive; drawn as alternating bands behind the curve and as a
        numbered strip under it.
    truth_segments : list of dicts with "start", "end" (inclusive) and "label", optional
        True segments (``truth.json``), drawn as a labelled strip under the clusters.
    fps : float, optional
        Named in the x-axis label.
    size : (width, height) of the PNG in pixels
    automatic : list of (start, end), optional
        The automatic parse's clusters where ``clusters`` were corrected by hand: drawn as a
        strip of their own, with the boundaries added by hand marked by orange lines and
        those removed by hand by dotted red ones.
    heading : (T,) array_like, optional
        The person's heading as the parser followed it, degrees
        (:func:`tvmedit.engine.parse.structure.followed_heading`): a grey line on its own axis, right.
    turns : list of int, optional
        Frames where the parser read the person turning and cut no boundary
        (:func:`tvmedit.engine.parse.structure.vetoed_turns`): purple triangles along the top.
    confidence : list of float or None, optional
        Each cluster's boundary confidence (:attr:`tvmedit.engine.parse.structure.Structure.boundary_confidence`;
        the first cluster's is not drawn, nor a None; a boundary drawn by hand has 1.0,
        :mod:`tvmedit.engine.store.corrections`): written above each boundary, and those under
        :data:`tvmedit.engine.parse.confidence.LOOK_BELOW`, the ones to look at first, in bright red with a
        dashed bright red line (boundaries removed by hand are dotted, in a darker red).

    Returns
    -------
    dict
        ``texton_starts``: the x positions (frames) of the markers as plotted, in order;
        ``turns``: those of the turn markers; ``unsure``: the boundaries drawn as least sure
        (frames); ``size``: the PNG's (width, height).
    """
    curve = np.asarray(curve, dtype=np.float64)
    starts = sorted(int(_start_end(t)[0]) for t in textons)
    clusters = [tuple(int(v) for v in _start_end(c)) for c in clusters]
    strips = 1 + (truth_segments is not None) + (automatic is not None)
    fig = _figure(size)
    grid = fig.add_gridspec(1 + strips, 1, height_ratios=[6] + [1] * strips, hspace=0.08,
                            left=0.07, right=0.99 if heading is None else 0.94,
                            top=0.9 if title else 0.96, bottom=0.16)
    ax = fig.add_subplot(grid[0])
    for k, (s, e) in enumerate(clusters):
        ax.axvspan(s - 0.5, e + 0.5, color=_BAND_COLOURS[k % 2], lw=0)
    t = np.arange(len(curve))
    ax.plot(t, curve, color="#3060a0", lw=1.2, label="d_A(t, t_first)")
    ys = [curve[s] if 0 <= s < len(curve) and np.isfinite(curve[s]) else 0.0 for s in starts]
    (markers,) = ax.plot(starts, ys, "o", color="black", ms=4, label="texton start")
    if automatic is not None:
        now, then = {s for s, _ in clusters[1:]}, {int(_start_end(c)[0]) for c in automatic[1:]}
        for frames, style in ((now - then, dict(color=ADDED_COLOUR_BOUNDARY, lw=1.6)),
                              (then - now, dict(color=ADDED_COLOUR, lw=1.2, ls=":"))):
            for b in sorted(frames):
                ax.axvline(b - 0.5, **style)
    ax.set_xlim(-0.5, max(len(curve), 1) - 0.5)
    shown = []
    if turns:
        (mark,) = ax.plot(sorted(int(t) for t in turns), [0.97] * len(turns), "v", color=TURN_COLOUR, ms=7,
                          transform=ax.get_xaxis_transform(), clip_on=False, label="turn, no boundary")
        shown = [int(x) for x in mark.get_xdata()]
    unsure = []
    for (b, _), c in zip(clusters[1:], (confidence or [])[1:]):
        if c is None:
            continue
        low = c < LOOK_BELOW
        # Written with a third digit where two would round it up to the mark (0.097, not 0.10).
        text = f"{c:.3f}" if low and round(c, 2) >= LOOK_BELOW else f"{c:.2f}"
        ax.text(b - 0.5, 1.0, text, transform=ax.get_xaxis_transform(), ha="center", va="bottom",
                fontsize=7, color=UNSURE_COLOUR if low else "#606060", fontweight="bold" if low else "normal")
        if low:
            line = ax.axvline(b - 0.5, color=UNSURE_COLOUR, lw=1.2, ls="--",
                              label=f"least sure boundary (confidence < {LOOK_BELOW:g})" if not unsure else None)
            unsure.append(int(round(line.get_xdata()[0] + 0.5)))
    ax.set_ylabel("atom distance")
    ax.tick_params(labelbottom=False)
    handles = ax.get_legend_handles_labels()[0]
    if heading is not None:
        turn = ax.twinx()
        (line,) = turn.plot(np.arange(len(heading)), heading, color="#909090", lw=1.0, ls="--",
                            label="heading followed (deg)")
        low, high = float(np.min(heading)), float(np.max(heading))
        turn.set_ylim(min(low, -10.0) - 5, max(high, 10.0) + 5)
        turn.set_ylabel("heading (deg)", fontsize=8, color="#707070")
        turn.tick_params(labelsize=7, colors="#707070")
        handles.append(line)
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.8)
    if title:
        ax.set_title(title, fontsize=10, pad=12 if confidence else 6)   # above the confidences
    rows = [("corrected" if automatic is not None else "detected",
             [(s, e, f"C{k}") for k, (s, e) in enumerate(clusters)])]
    if automatic is not None:
        rows.insert(0, ("automatic", [(*map(int, _start_end(c)), f"C{k}") for k, c in enumerate(automatic)]))
    if truth_segments is not None:
        rows.append(("truth", [(int(g["start"]), int(g["end"]), str(g.get("label", "")))
                               for g in truth_segments]))
    for r, (name, spans) in enumerate(rows):
        strip = fig.add_subplot(grid[1 + r], sharex=ax)
        for k, (s, e, label) in enumerate(spans):
            strip.axvspan(s - 0.5, e + 0.5, color=_BAND_COLOURS[k % 2], ec="#808080", lw=0.5)
            strip.text((s + e) / 2, 0.5, label, ha="center", va="center", fontsize=7, clip_on=True)
        strip.set_yticks([0.5], [name], fontsize=8)
        strip.set_ylim(0, 1)
        strip.tick_params(labelbottom=r == len(rows) - 1)
    unit = f"frame ({fps:g} fps)" if fps else "frame"
    fig.axes[-1].set_xlabel(unit)
    _save(fig, out_png)
    # What the figure really marks, read back from the plotted line (not the input).
    return {"texton_starts": [int(x) for x in markers.get_xdata()], "turns": shown, "unsure": unsure,
            "size": list(size)}


#: Where along its arc an edge's weight is written (0: at the source, 1: at the target).
LABEL_AT = 0.35

#: Label colour of the edges added to connect the graph (and of boundaries removed by hand).
ADDED_COLOUR = "#c0262d"

#: Where the parser read a turn and cut no boundary (structure figure).
TURN_COLOUR = "#8a3ab9"
#: Colour of the boundaries whose confidence is under tvmedit.engine.parse.confidence.LOOK_BELOW (dashed):
#: a brighter red than ADDED_COLOUR's dotted lines of boundaries removed by hand.
UNSURE_COLOUR = "#ff1a1a"
#: Colour of the cluster boundaries added or moved by hand.
ADDED_COLOUR_BOUNDARY = "#e07010"


def graph_figure(graph, out_png, thumbnails=None, show_pruned=False, size=GRAPH_SIZE):
    """Figure 7: the motion graph with weights on the edges and a rendered frame per node.

    Parameters
    ----------
    graph : networkx.DiGraph
        As ``tvmedit.engine.graph.motiongraph.graph_from`` makes it: node attribute ``name``, edge attribute
        ``weight``, and ``graph.graph["unpruned"]`` ({(i, j): weight}) for the pruned edges.
    thumbnails : dict of node -> (H, W, 3) uint8, optional
        Drawn at the node's place; nodes without one are drawn as discs.
    show_pruned : bool
        Draw the edges that pruning removed, faint and dashed, without labels.
    size : (width, height) of the PNG in pixels

    Returns
    -------
    dict
        ``positions``: {node: (x, y)} in the unit square; ``edges``: kept edges drawn;
        ``pruned``: pruned edges drawn (empty unless ``show_pruned``); ``added``: edges
        put back to connect the graph (``added`` edge attribute), drawn dashed with red
        labels; ``size``.
    """
    from matplotlib.offsetbox import AnnotationBbox, OffsetImage
    from matplotlib.patches import Circle, FancyArrowPatch

    nodes = sorted(graph.nodes)
    positions = _circle(nodes)
    thumbnails = thumbnails or {}
    fig = _figure(size)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_xlim(-0.2, 1.2)
    ax.set_ylim(-0.2, 1.2)
    ax.set_aspect("equal")
    ax.axis("off")
    # Node radius in data units (the axes span 1.4 units): a little over half a thumbnail's
    # diagonal, so arrows end outside it, or a fixed disc.
    thumb_px = max((math.hypot(*im.shape[:2]) for im in thumbnails.values()), default=0)
    radius = max(0.03, 0.5 * thumb_px * 1.4 / min(size))
    kept = sorted(graph.edges)
    pruned = []
    if show_pruned:
        pruned = sorted(e for e in graph.graph.get("unpruned", {}) if not graph.has_edge(*e)
                        and e[0] in graph and e[1] in graph)
    weights = [graph.edges[e]["weight"] for e in kept]
    cmap = require_matplotlib().colormaps["viridis"]
    low, high = (min(weights), max(weights)) if weights else (0.0, 1.0)
    for edge in pruned:
        _arrow(ax, FancyArrowPatch, positions, edge, radius, color="#b0b0b0", lw=0.7, ls="--",
               alpha=0.6, zorder=1)
    added = [e for e in kept if graph.edges[e].get("added")]
    for edge, w in zip(kept, weights):
        colour = cmap(0.85 * (w - low) / (high - low) if high > low else 0.0)
        # Edges put back to connect the graph (tvmedit.engine.graph.connect): dashed, labelled in red.
        extra = {"ls": (0, (4, 2))} if edge in added else {}
        mid = _arrow(ax, FancyArrowPatch, positions, edge, radius, color=colour, lw=1.4, zorder=2, **extra)
        frame = ADDED_COLOUR if edge in added else colour
        ax.text(*mid, _fmt(w), fontsize=7, ha="center", va="center", zorder=4,
                color=ADDED_COLOUR if edge in added else "black",
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": frame, "lw": 1.0 if edge in added else 0.6})
    for n in nodes:
        x, y = positions[n]
        if n in thumbnails:
            # Matplotlib scales images by dpi / 72; undo it so one pixel stays one pixel.
            image = OffsetImage(thumbnails[n], zoom=72 / 100)
            ax.add_artist(AnnotationBbox(image, (x, y), frameon=True, pad=0.1, zorder=3))
        else:
            ax.add_patch(Circle((x, y), radius * 0.5, color="#3060a0", zorder=3))
        label = str(graph.nodes[n].get("name", n))
        dx, dy = x - 0.5, y - 0.5
        norm = math.hypot(dx, dy) or 1.0
        ax.text(x + dx / norm * (radius + 0.02), y + dy / norm * (radius + 0.02), f"{n}: {label}",
                fontsize=8, ha="center", va="center", zorder=5,
                bbox={"boxstyle": "round,pad=0.2", "fc": "#fff8e0", "ec": "none", "alpha": 0.9})
    if weights:
        from matplotlib.cm import ScalarMappable
        from matplotlib.colors import Normalize

        scale = ScalarMappable(Normalize(low, low + (high - low) / 0.85 if high > low else low + 1), cmap)
        bar = fig.colorbar(scale, cax=fig.add_axes([0.72, 0.04, 0.25, 0.012]), orientation="horizontal")
        bar.set_label("weight, eq. (12)", fontsize=8)
        bar.ax.xaxis.set_label_position("top")
        bar.ax.tick_params(labelsize=7)
    mu = graph.graph.get("mu")
    note = f"{len(kept) - len(added)} transitions kept" + (f" (mu = {mu:g})" if mu is not None else "")
    if added:
        note += f", {len(added)} added to connect (dashed, red labels)"
    if show_pruned:
        note += f", {len(pruned)} pruned (dashed)"
    ax.text(0.01, 0.01, note, transform=ax.transAxes, fontsize=8, color="#404040")
    _save(fig, out_png)
    return {"positions": {n: tuple(positions[n]) for n in nodes}, "edges": kept,
            "pruned": pruned, "added": added, "size": list(size)}


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


def _circle(nodes):
    # A circle keeps every node visible and every chord distinct, which a dense graph of a
    # few dozen nodes needs more than a force layout's clusters; first node at the top.
    n = len(nodes)
    if n == 1:
        return {nodes[0]: (0.5, 0.5)}
    return {node: (0.5 + 0.5 * math.sin(2 * math.pi * k / n), 0.5 + 0.5 * math.cos(2 * math.pi * k / n))
            for k, node in enumerate(nodes)}


def _arrow(ax, arrow_class, positions, edge, radius, **style):
    # Both directions of a pair bend to their own side (arc3 bends to the right of travel),
    # so i -> j and j -> i are two arcs with a label each; returns the label position.
    (x1, y1), (x2, y2) = positions[edge[0]], positions[edge[1]]
    # Stop at the thumbnail's edge: shorten the chord by the node radius at both ends.
    length = math.hypot(x2 - x1, y2 - y1) or 1.0
    ux, uy = (x2 - x1) / length * radius, (y2 - y1) / length * radius
    x1, y1, x2, y2 = x1 + ux, y1 + uy, x2 - ux, y2 - uy
    rad = 0.15
    patch = arrow_class((x1, y1), (x2, y2), connectionstyle=f"arc3,rad={rad}", arrowstyle="-|>",
                        mutation_scale=18, shrinkA=0, shrinkB=0, **style)
    ax.add_patch(patch)
    # The label sits a third of the way along the quadratic Bezier that arc3 draws (control
    # point: chord midpoint + rad * (dy, -dx)), nearer the source, so the labels of i -> j and
    # j -> i stay apart even where the two arcs run close.
    t = LABEL_AT
    cx, cy = (x1 + x2) / 2 + rad * (y2 - y1), (y1 + y2) / 2 - rad * (x2 - x1)
    return ((1 - t) ** 2 * x1 + 2 * t * (1 - t) * cx + t ** 2 * x2,
            (1 - t) ** 2 * y1 + 2 * t * (1 - t) * cy + t ** 2 * y2)


def _fmt(value):
    return f"{value:.3g}" if math.isfinite(value) else "inf"


def _start_end(item):
    if hasattr(item, "start"):
        return item.start, item.end
    if isinstance(item, dict):
        return item["start"], item["end"]
    return item[0], item[1]


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
                        f"<td class='num'>{_fmt(data['weight'])}</td>"
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


def step_figure(row, natural, out_png, size=STEP_SIZE):
    """The step curve of one transition: Chamfer per displayed frame, blended and cut, in mm."""
    fig = _figure(size)
    ax = fig.add_axes([0.13, 0.24, 0.84, 0.68])
    blended = np.array(row["blended_steps"]) * 1000
    n = len(blended)
    ax.plot(np.arange(1, n + 1), blended, "o-", color="#1f77b4", label="blended")
    # The cut is one step where the blended run takes n - 2: drawn across the same span.
    ax.plot([1, (n + 1) / 2, n], np.array(row["cut_steps"]) * 1000, "s--", color="#d62728", label="cut")
    if natural:
        ax.axhline(natural * 1000, color="black", linestyle=":", label="natural step")
    ax.set_xlabel("displayed step across the transition")
    ax.set_ylabel("Chamfer (mm)")
    ax.set_ylim(bottom=0)
    ax.legend(loc="upper right", fontsize=7)
    _save(fig, out_png)


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
    return [r for r in ranges if int(_start_end(r)[0]) != 0]


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
