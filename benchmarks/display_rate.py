"""Display-rate in-betweens: how far the body moves between two frames shown, at 60 fps and at the capture's rate.

    .venv/bin/python benchmarks/display_rate.py [--takes gym 13_29 13_30] [--fps 60] [--libraries LIB ...]

Each take is built at default options (display-rate in-betweens included,
``tvmedit.engine.inbetween.instants``), and once more with ``smooth=False`` for what they cost
(build time and library size against the same build without them; limits 1.5x and 1.4x).

Both are first builds: an empty folder, every frame read, no feature cache (a build reuses
what the library it replaces holds, and a cached one reads nothing). A step is measured as
the body sees it: point-to-surface distances, both ways, between two consecutive displayed
surfaces (``instants.step_measures``, every 8th vertex), their mean and
their 99th percentile (the few hundred vertices of a hand or forearm that a mean hides). The
*natural step* is the median over consecutive texton frames of each figure at the capture's rate.

- **At 60 fps**, an edit through every motion of the take (``Library.edit``), every output
  frame the surface the player shows (``export --fps 60`` writes the same): the largest step
  in the middle of textons, across transitions and across wraps, over the natural step, and
  over the larger of the natural step and the captured step it divides, by mean (bar 0.35x;
  a perfect in-between of a 10 fps capture is 1/6) and by 99th percentile (bar 0.5x). The
  second is the bar: where the capture itself moves three natural steps in one frame (a fast
  arm), a sixth of that step is half a natural step, whatever the in-betweens.
- **At the capture's rate**, every database motion's wrap (its last frame shown to its first,
  through the frames that close its loop) and every transition's run: the largest step over
  the natural one (bars: transitions 1.25x by the 99th percentile; wraps 1.25x by both
  figures, each step over the larger of the natural step and the capture's own at its phase,
  in the texton or the repetition its closing is warped onto, as fast as the motion moves
  there, among the frames the build looked at: ``tvmedit.engine.inbetween.loops.paces`` and
  ``reach``). The raw figures over the natural step are
  printed beside them. Transitions and wraps are measured a second way too, each point
  matched to the nearest point of the other surface that looks alike (``instants.matched_tail``,
  against the same figure for natural steps, same bar): a forearm that jumps from the chest
  to the air still lies near some surface in both frames, and only this figure sees it.
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from tvmedit import Library, engine  # noqa: E402
from tvmedit.engine.inbetween.instants import matched_tail, moved, shown, step_measures  # noqa: E402
from tvmedit.engine.inbetween.loops import paces, reach  # noqa: E402

STRIDE = 8
BARS = {"mean60": 0.35, "p99_60": 0.5, "wrap": 1.25, "transition_p99": 1.25, "size": 1.4, "build": 1.5}


def take(name):
    """The test suite's take folders (generated once into .cache/testdata)."""
    import conftest

    return conftest.synth_take("gym") if name == "gym" else conftest.mocap_take(name)


def measure(a, b):
    return step_measures((a[0], a[1]), (b[0], b[1]), stride=STRIDE)


def natural(library, pairs=30, matched=False):
    """Median mean and 99th percentile of the steps between consecutive texton frames; with
    ``matched``, the median of their colour-matched 99th percentiles (``matched_tail``)."""
    steps = [(node.sequence, f) for node in library.nodes for f in range(node.start, node.end)]
    steps = steps[::max(1, len(steps) // pairs)]
    if matched:
        return float(np.median([matched_tail(_coloured(library, (s, f)), _coloured(library, (s, f + 1)),
                                             stride=STRIDE) for s, f in steps]))
    figures = [measure(_mesh(library, (s, f)), _mesh(library, (s, f + 1))) for s, f in steps]
    return float(np.median([m for m, _ in figures])), float(np.median([p for _, p in figures]))


#: Which of a mesh's arrays goes with its positions: colours to match points by, faces for surfaces.
COLOURS, FACES = 1, 2


def _pair(mesh, which):
    """``(positions, mesh[which])`` of ``(positions, colours, faces, ...)`` as arrays."""
    return np.asarray(mesh[0]), np.asarray(mesh[which])


def _coloured(library, key):
    return _pair(library.frame_mesh(key), COLOURS)


def _mesh(library, key):
    return _pair(library.frame_mesh(key), FACES)


def kind(a, b):
    """middle, transition or wrap: the kind of the schedule step from entry ``a`` to ``b``."""
    if a.node != b.node or (b.blend is not None and b.blend[0][0] != b.blend[0][1]):
        return "transition"
    if (b.blend is not None) or (a.blend is not None) or b.frame < a.frame:
        return "wrap"
    return "middle"


def display(library, edit, fps, nat):
    """Per kind, the largest 60 fps step's (mean, p99), and its largest ratio to the larger of
    the captured step it divides and the natural step ``nat`` (a fast motion's captured step is
    several natural ones, and a sixth of it is the most an in-between can do)."""
    schedule = edit.schedule
    capture = library.sequence(schedule[0].sequence).fps
    worst = {}
    field_of = lambda i: library.instant_field(schedule[i].key, schedule[i + 1].key)  # noqa: E731
    frames = list(shown(len(schedule), capture, fps, field_of))
    surfaces = []
    for index, s, field in frames:
        positions, faces = _mesh(library, schedule[index].key)
        surfaces.append((index, moved(positions, field, s) if field is not None else positions, faces))
    captured = {}
    missing = 0
    for (i, p, f), (j, q, g) in zip(surfaces, surfaces[1:]):
        k = kind(schedule[i], schedule[min(i + 1, len(schedule) - 1)])
        if i not in captured and i + 1 < len(schedule):
            captured[i] = measure(_mesh(library, schedule[i].key), _mesh(library, schedule[i + 1].key))
            missing += library.instant_field(schedule[i].key, schedule[i + 1].key) is None
        m, p99 = measure((p, f), (q, g))
        whole = captured.get(i, (m, p99))
        row = worst.setdefault(k, [0.0, 0.0, 0.0, 0.0, None])
        row[0], row[1] = max(row[0], m), max(row[1], p99)
        ratio = max(m / max(whole[0], nat[0]), p99 / max(whole[1], nat[1]))
        if ratio > max(row[2], row[3]):
            row[4] = (i, schedule[i].key, schedule[min(i + 1, len(schedule) - 1)].key)
        row[2], row[3] = max(row[2], m / max(whole[0], nat[0])), max(row[3], p99 / max(whole[1], nat[1]))
    return worst, missing, len(frames)


def wraps(library, nat):
    """Every database motion's wrap at the capture's rate: ``{name: (largest step (mean, p99),
    largest step over the larger of the natural step and the capture's own at its phase (mean,
    p99), the same by the p99 of points matched by colour)}``, over the steps of the path
    through its closing frames (or the wrap itself); ``nat`` is the natural (mean, p99,
    matched p99).
    The capture's own step at a step's phase is the larger of the texton's and the
    neighbouring repetition's there (``tvmedit.engine.inbetween.loops.paces``): a fast motion
    steps more than the natural step, and more at some phases than at others."""
    out = {}
    closings = {tuple(w["texton"]): w for w in library.blend_data().get("wraps", [])}
    for node in library.nodes:
        w = closings.get((node.sequence, node.start, node.end))
        count, at = (w["count"], w["at"]) if w else (0, "end")
        # The capture's steps are those of the frames the build looked at (the texton alone
        # where no closing was tried).
        first, last = (w["reach"] if "reach" in w else reach(node.start, node.end, at, w.get("limit", 0))) if w \
            else (node.start, node.end)
        if count:
            keys = ([(node.sequence, node.end - count)] if at == "end" else [(node.sequence, node.end)])
            keys += [(node.sequence, 0, ((node.id, node.id), k)) for k in range(count)]
            keys += [(node.sequence, node.start)] if at == "end" else [(node.sequence, node.start + count)]
        else:
            keys = [(node.sequence, node.end), (node.sequence, node.start)]
        figures = [measure(_mesh(library, a), _mesh(library, b)) for a, b in zip(keys, keys[1:])]
        matched = [matched_tail(_coloured(library, a), _coloured(library, b), stride=STRIDE)
                   for a, b in zip(keys, keys[1:])]

        source = lambda frame, which=FACES: _pair(library.source_mesh((node.sequence, frame)), which)  # noqa: E731
        within = lambda f: first <= f <= last  # noqa: E731
        own = paces(lambda f, g: measure(source(f), source(g)), node.start, node.end, at, count, within)
        pair = lambda f, g: (matched_tail(source(f, COLOURS), source(g, COLOURS), stride=STRIDE),) * 2  # noqa: E731
        own_matched = [tail for tail, _ in paces(pair, node.start, node.end, at, count, within)]
        ratios = [(m / max(nat[0], om), p / max(nat[1], op)) for (m, p), (om, op) in zip(figures, own)]
        out[node.name] = ((max(m for m, _ in figures), max(p for _, p in figures)),
                          (max(r for r, _ in ratios), max(r for _, r in ratios)),
                          max(m / max(nat[2], om) for m, om in zip(matched, own_matched)))
    return out


def transitions(library):
    """The largest captured-rate step's 99th percentile of every edge's run, point to surface
    and colour-matched (``matched_tail``: a limb that jumps along a surface, which the first
    misses): ``{(u, v): (p99, matched p99)}``."""
    out = {}
    for u, v in sorted(library.graph.edges):
        data = library.graph.edges[u, v]
        a, b = library.nodes[u], library.nodes[v]
        keys = [(a.sequence, data["exit_frame"])]
        keys += [(a.sequence, data["exit_frame"], ((u, v), i)) for i in range(data.get("blend", 0))]
        keys += [(b.sequence, data["entry_frame"])]
        pairs = list(zip(keys, keys[1:]))
        out[(u, v)] = (max(measure(_mesh(library, p), _mesh(library, q))[1] for p, q in pairs),
                       max(matched_tail(_coloured(library, p), _coloured(library, q), stride=STRIDE) for p, q in pairs))
    return out


def size(path, names=None):
    return sum(f.stat().st_size for f in Path(path).iterdir() if names is None or f.name in names)


def report(name, library, fps, cost=None):
    ok = True
    nat_mean, nat_p99 = natural(library)
    keys = [node.id for node in library.nodes]
    edit = library.edit(keys if len(keys) >= 3 else keys + keys[:1])
    worst, missing, count = display(library, edit, fps, (nat_mean, nat_p99))
    print(f"{name}: natural step {nat_mean * 1000:.1f} mm mean, {nat_p99 * 1000:.1f} mm p99 (point to surface); "
          f"edit through {len(keys)} motions, {count} frames at {fps:g} fps, {missing} steps without a field")
    for k, (m, p, rm, rp, where) in sorted(worst.items()):
        good = rm <= BARS["mean60"] and rp <= BARS["p99_60"]
        ok &= good
        print(f"  {fps:g} fps {k:10s} largest step {m / nat_mean:.2f}x natural by mean, {p / nat_p99:.2f}x by p99; "
              f"over the larger of the captured step it divides and the natural step {rm:.2f}x by mean "
              f"(bar {BARS['mean60']}), {rp:.2f}x by p99 (bar {BARS['p99_60']}) {'ok' if good else 'OVER'}; "
              f"worst at schedule frame {where[0]}, {where[1]} -> {where[2]}")
    nat_matched = natural(library, matched=True)
    for motion, ((m, p), (rm, rp), rc) in wraps(library, (nat_mean, nat_p99, nat_matched)).items():
        good = rm <= BARS["wrap"] and rp <= BARS["wrap"]
        ok &= good and rc <= BARS["wrap"]
        print(f"  wrap of {motion:12s} {m / nat_mean:.2f}x natural by mean, {p / nat_p99:.2f}x by p99; each step over "
              f"the larger of the natural step and the capture's own at its phase {rm:.2f}x, {rp:.2f}x "
              f"(bar {BARS['wrap']}) {'ok' if good else 'OVER'}; by p99 of points matched by colour {rc:.2f}x "
              f"{'ok' if rc <= BARS['wrap'] else 'OVER'}")
    runs = transitions(library)
    most = max(p for p, _ in runs.values()) / nat_p99 if runs else 0.0
    ok &= most <= BARS["transition_p99"]
    print(f"  transitions: largest step {most:.2f}x natural by p99 over {len(runs)} runs "
          f"(bar {BARS['transition_p99']}) {'ok' if most <= BARS['transition_p99'] else 'OVER'}")
    names = {node.id: node.name for node in library.nodes}
    over = {f"{names[u]}->{names[v]}": m / nat_matched for (u, v), (_, m) in runs.items()
            if m / nat_matched > BARS["transition_p99"]}
    most = max(m for _, m in runs.values()) / nat_matched if runs else 0.0
    ok &= not over
    print(f"  transitions, points matched by colour (a limb that jumps along a surface): largest step {most:.2f}x "
          f"natural ({nat_matched * 1000:.1f} mm) by p99 (bar {BARS['transition_p99']}) {'OVER' if over else 'ok'}"
          + (f"; over it: {', '.join(f'{k} {r:.2f}x' for k, r in sorted(over.items()))}" if over else ""))
    if cost is not None:
        (t_on, t_off), path = cost
        grown = size(path) / (size(path) - size(path, {"instant_fields.npy", "instant_pairs.npy"}))
        ok &= grown <= BARS["size"] and t_on / t_off <= BARS["build"]
        print(f"  library {size(path) / 1e6:.0f} MB, {grown:.2f}x without the in-betweens (bar {BARS['size']}); "
              f"build {t_on:.1f} s against {t_off:.1f} s without them, {t_on / t_off:.2f}x (bar {BARS['build']})")
    return ok


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--takes", nargs="*", default=["gym", "13_29", "13_30"])
    parser.add_argument("--libraries", nargs="*", default=[], help="measure these built libraries too")
    parser.add_argument("--fps", type=float, default=60.0)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    ok = True
    with tempfile.TemporaryDirectory() as folder:
        for name in args.takes:
            times = []
            for smooth in (False, True):   # a first build: frames read, nothing reused or cached
                path = Path(folder) / f"{name}-{'smooth' if smooth else 'plain'}.tvmlib"
                t0 = time.perf_counter()
                engine.build([(name, take(name))], path, workers=args.workers, force=True, smooth=smooth,
                             cache=False)
                times.append(time.perf_counter() - t0)
            ok &= report(name, Library.open(path), args.fps, ((times[1], times[0]), path))
    for path in args.libraries:
        ok &= report(Path(path).name, Library.open(path), args.fps)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
