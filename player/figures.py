"""The report's figures: the atom distance curve (Figure 4), the motion graph (Figure 7) and
a transition's step curve, each drawn with matplotlib's Agg into a PNG of an exact size.

Matplotlib is an optional dependency (``pip install 'tvmedit[report]'``), imported only when a
figure is drawn; a bare ``Figure`` touches no pyplot state, so no display is needed and a
caller's own figures are left alone. Each function returns what it really drew, read back
from the plotted artists, so tests check the picture rather than its inputs.
"""

import math

import numpy as np

from ..engine.errors import TvmError
from ..engine.parse.confidence import LOOK_BELOW

CURVE_SIZE = (960, 300)
STEP_SIZE = (420, 200)
GRAPH_SIZE = (900, 900)

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
    starts = sorted(int(start_end(t)[0]) for t in textons)
    clusters = [tuple(int(v) for v in start_end(c)) for c in clusters]
    strips = 1 + (truth_segments is not None) + (automatic is not None)
    fig = _figure(size)
    grid = fig.add_gridspec(1 + strips, 1, height_ratios=[6] + [1] * strips, hspace=0.08,
                            left=0.07, right=0.99 if heading is None else 0.94,
                            top=0.9 if title else 0.96, bottom=0.16)
    ax = fig.add_subplot(grid[0])
    markers = _curve(ax, curve, starts, clusters, automatic)
    shown = _turn_marks(ax, turns)
    unsure = _confidence_marks(ax, clusters, confidence)
    ax.set_ylabel("atom distance")
    ax.tick_params(labelbottom=False)
    handles = ax.get_legend_handles_labels()[0]
    if heading is not None:
        handles.append(_heading_line(ax, heading))
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.8)
    if title:
        ax.set_title(title, fontsize=10, pad=12 if confidence else 6)   # above the confidences
    _strips(fig, grid, ax, clusters, automatic, truth_segments)
    unit = f"frame ({fps:g} fps)" if fps else "frame"
    fig.axes[-1].set_xlabel(unit)
    _save(fig, out_png)
    # What the figure really marks, read back from the plotted line (not the input).
    return {"texton_starts": [int(x) for x in markers.get_xdata()], "turns": shown, "unsure": unsure,
            "size": list(size)}


def _curve(ax, curve, starts, clusters, automatic):
    """The cluster bands, the curve, its texton starts (returned) and the boundaries moved by hand."""
    for k, (s, e) in enumerate(clusters):
        ax.axvspan(s - 0.5, e + 0.5, color=_BAND_COLOURS[k % 2], lw=0)
    t = np.arange(len(curve))
    ax.plot(t, curve, color="#3060a0", lw=1.2, label="d_A(t, t_first)")
    ys = [curve[s] if 0 <= s < len(curve) and np.isfinite(curve[s]) else 0.0 for s in starts]
    (markers,) = ax.plot(starts, ys, "o", color="black", ms=4, label="texton start")
    if automatic is not None:
        now, then = {s for s, _ in clusters[1:]}, {int(start_end(c)[0]) for c in automatic[1:]}
        for frames, style in ((now - then, dict(color=ADDED_COLOUR_BOUNDARY, lw=1.6)),
                              (then - now, dict(color=ADDED_COLOUR, lw=1.2, ls=":"))):
            for b in sorted(frames):
                ax.axvline(b - 0.5, **style)
    ax.set_xlim(-0.5, max(len(curve), 1) - 0.5)
    return markers


def _turn_marks(ax, turns):
    """Purple triangles along the top where the parser read a turn; their frames as drawn."""
    shown = []
    if turns:
        (mark,) = ax.plot(sorted(int(t) for t in turns), [0.97] * len(turns), "v", color=TURN_COLOUR, ms=7,
                          transform=ax.get_xaxis_transform(), clip_on=False, label="turn, no boundary")
        shown = [int(x) for x in mark.get_xdata()]
    return shown


def _confidence_marks(ax, clusters, confidence):
    """Each boundary's confidence written above it; the least sure dashed in red (returned)."""
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
    return unsure


def _heading_line(ax, heading):
    """The heading followed, on an axis of its own at the right; returns its line for the legend."""
    turn = ax.twinx()
    (line,) = turn.plot(np.arange(len(heading)), heading, color="#909090", lw=1.0, ls="--",
                        label="heading followed (deg)")
    low, high = float(np.min(heading)), float(np.max(heading))
    turn.set_ylim(min(low, -10.0) - 5, max(high, 10.0) + 5)
    turn.set_ylabel("heading (deg)", fontsize=8, color="#707070")
    turn.tick_params(labelsize=7, colors="#707070")
    return line


def _strips(fig, grid, ax, clusters, automatic, truth_segments):
    """The labelled strips under the curve: automatic (where corrected), detected or corrected, truth."""
    rows = [("corrected" if automatic is not None else "detected",
             [(s, e, f"C{k}") for k, (s, e) in enumerate(clusters)])]
    if automatic is not None:
        rows.insert(0, ("automatic", [(*map(int, start_end(c)), f"C{k}") for k, c in enumerate(automatic)]))
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
    from matplotlib.patches import FancyArrowPatch

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
        ax.text(*mid, fmt_number(w), fontsize=7, ha="center", va="center", zorder=4,
                color=ADDED_COLOUR if edge in added else "black",
                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": frame, "lw": 1.0 if edge in added else 0.6})
    for n in nodes:
        _node(ax, graph, n, positions[n], thumbnails, radius)
    if weights:
        _colour_bar(fig, low, high, cmap)
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


def _node(ax, graph, n, position, thumbnails, radius):
    """One node: its thumbnail (or a disc) and its label outside the circle."""
    from matplotlib.offsetbox import AnnotationBbox, OffsetImage
    from matplotlib.patches import Circle

    x, y = position
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


def _colour_bar(fig, low, high, cmap):
    """The scale of edge colours, eq. (12)'s weight, at the bottom right."""
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    scale = ScalarMappable(Normalize(low, low + (high - low) / 0.85 if high > low else low + 1), cmap)
    bar = fig.colorbar(scale, cax=fig.add_axes([0.72, 0.04, 0.25, 0.012]), orientation="horizontal")
    bar.set_label("weight, eq. (12)", fontsize=8)
    bar.ax.xaxis.set_label_position("top")
    bar.ax.tick_params(labelsize=7)


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


def fmt_number(value):
    """Three significant digits, or "inf"."""
    return f"{value:.3g}" if math.isfinite(value) else "inf"


def start_end(item):
    """``(start, end)`` of a texton, a cluster, a dict or a pair."""
    if hasattr(item, "start"):
        return item.start, item.end
    if isinstance(item, dict):
        return item["start"], item["end"]
    return item[0], item[1]


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
