"""Blended transitions: the pop ratio of every transition, blended and not, and what blending costs.

    .venv/bin/python benchmarks/blend_quality.py [--takes gym 13_29 13_30] [--workers 2]

Each take is built at default options (in-between frames as many as needed, ``tvmedit.engine.inbetween.blend``).
For every edge of the motion graph it prints the *pop ratio*: the largest step across the
transition window, from the exit frame to the entry frame, divided by the library's natural
step (median step between consecutive texton frames). A step is the symmetric mean Chamfer
distance between consecutive displayed frames (all vertices). "cut" is the paper's jump from
exit frame to entry frame (``--blend-frames 0``); "blended" plays the in-between frames
between them. The bar: blended <= 1.25 on every edge.

Then every looping motion's wrap from its texton's last frame to its first (``tvmedit.engine.inbetween.loops``),
as captured and closed, over the capture's own step across that phase.

Then the cost, on one core (CPU time of ``tvmedit.engine.inbetween.blend.blend`` for one transition, reading
aside): per transition of 13_29 (17,000-vertex frames, limit 2 s), how it grows with the
vertex count (every k-th vertex of the same two frames) and with the number of in-between
frames (fixed counts).
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

from tvmedit import engine # noqa: E402
from tvmedit.engine.inbetween import blend, fit  # noqa: E402

LIMIT_RATIO = 1.25
LIMIT_SECONDS = 2.0


def take(name):
    """The test suite's take folders (generated once into .cache/testdata)."""
    import conftest

    return conftest.synth_take("gym") if name == "gym" else conftest.mocap_take(name)


def window(library, u, v):
    data = library.graph.edges[u, v]
    a, b = library.nodes[u], library.nodes[v]
    keys = [(a.sequence, data["exit_frame"])]
    keys += [(a.sequence, data["exit_frame"], ((u, v), i)) for i in range(data.get("blend", 0))]
    return [library.frame_mesh(k) for k in keys + [(b.sequence, data["entry_frame"])]]


def pop_ratios(library):
    """``[(edge, in-between frames, cut ratio, blended ratio)]`` for every graph edge."""
    rows = []
    natural = library.natural_step
    for u, v in sorted(library.graph.edges):
        meshes = window(library, u, v)
        steps = [blend.chamfer(p[0], q[0]) for p, q in zip(meshes, meshes[1:])]
        cut = blend.chamfer(meshes[0][0], meshes[-1][0])
        rows.append(((u, v), len(meshes) - 2, cut / natural, max(steps) / natural))
    return rows


def quality(names, workers, folder):
    libraries, ok = {}, True
    for name in names:
        t0 = time.perf_counter()
        library = engine.build([(name, take(name))], Path(folder) / f"{name}.tvmlib", workers=workers, force=True)
        libraries[name] = library
        report = library.report
        print(f"{name}: natural step {library.natural_step * 1000:.1f} mm; {report['edges']} transitions, "
              f"{report['blend_frames']} in-between frames; build {time.perf_counter() - t0:.1f} s "
              f"(blends stage {report['stages'].get('blends', 0):.1f} s on {workers} workers)")
        rows = pop_ratios(library)
        for (u, v), count, cut, blended in rows:
            print(f"   {u:>3} -> {v:<3} {count} frames   cut {cut:4.2f}   blended {blended:4.2f}")
        cuts, blends = [r[2] for r in rows], [r[3] for r in rows]
        met = max(blends) <= LIMIT_RATIO
        ok &= met
        print(f"   pop ratio: cut median {np.median(cuts):.2f} max {max(cuts):.2f}; blended median "
              f"{np.median(blends):.2f} max {max(blends):.2f} (limit {LIMIT_RATIO}: {'met' if met else 'NOT MET'})")
        loops(library)
    return libraries, ok


def loops(library):
    """Every cyclic motion's wrap (tvmedit.engine.inbetween.loops): its largest step over the capture's own step
    there (and the natural step), as captured and with the loop closed."""
    from tvmedit.engine.inbetween.loops import pace, window as closing_window

    rows = []
    for node in library.nodes:
        if node.kind == "once":
            continue
        data = library.graph.nodes[node.id]
        k, at = data.get("wrap", 0), data.get("wrap_at", "end")
        mesh = lambda f: library.source_mesh((node.sequence, f))  # noqa: E731
        goal = max(library.natural_step, pace(mesh, node.start, node.end, at))
        warped = closing_window(node.start, node.end, at, k)[0]
        keys = [(node.sequence, f, ((node.id, node.id), i)) for i, f in enumerate(warped)]
        keys = ([(node.sequence, node.end - k)] + keys + [(node.sequence, node.start)] if at == "end"
                else [(node.sequence, node.end)] + keys + [(node.sequence, node.start + k)])
        points = [library.frame_mesh(key)[0] for key in keys]
        closed = max(blend.chamfer(p, q) for p, q in zip(points, points[1:]))
        wrap = blend.chamfer(mesh(node.end)[0], mesh(node.start)[0])
        rows.append((wrap / goal, closed / goal))
        print(f"   loop {node.name:<10} {k} frame(s) at its {at:<5}  wrap {wrap / goal:4.2f}  closed "
              f"{closed / goal:4.2f}  (of the capture's own step there, {goal / library.natural_step:.2f} natural)")
    if rows:
        print(f"   loops: wrap max {max(r[0] for r in rows):.2f}, closed max {max(r[1] for r in rows):.2f}; "
              f"{sum(r[1] < r[0] for r in rows)} of {len(rows)} closed")


def ends(library, u, v):
    data = library.graph.edges[u, v]
    a, b = library.nodes[u], library.nodes[v]
    return [tuple(np.asarray(x) for x in library.frame_mesh(key)[:3])
            for key in ((a.sequence, data["exit_frame"]), (b.sequence, data["entry_frame"]))]


def cpu(fn, *args, **kwargs):
    t0 = time.process_time()
    result = fn(*args, **kwargs)
    return time.process_time() - t0, result


def cost(library):
    natural = library.natural_step
    times = []
    for u, v in sorted(library.graph.edges):
        seconds, run = cpu(blend.blend, *ends(library, u, v), natural)
        times.append((seconds, len(run)))
    worst = max(t for t, _ in times)
    print(f"one transition, one core, {library.max_counts()[0]:,} vertices at most: mean "
          f"{np.mean([t for t, _ in times]):.2f} s, max {worst:.2f} s over {len(times)} transitions "
          f"(limit {LIMIT_SECONDS:g} s: {'met' if worst <= LIMIT_SECONDS else 'NOT MET'})")
    u, v = max(library.graph.edges, key=lambda e: library.blend_runs()[e]["jump"])
    a, b = ends(library, u, v)
    line = []
    for stride in (4, 2, 1):
        sub = [(m[0][::stride], m[1][::stride], m[2]) for m in (a, b)]
        seconds, _ = cpu(lambda: (fit.align(sub[0][0], sub[1][0]), fit.align(sub[1][0], sub[0][0])))
        line.append(f"{len(sub[0][0]):,} vertices {seconds:.2f} s")
    print("   the two fields by vertices: " + ", ".join(line))
    line = []
    for count in (1, 2, 4, 8):
        seconds, _ = cpu(blend.blend, a, b, natural, count)
        line.append(f"{count} frames {seconds:.2f} s")
    print("   a whole transition by in-between frames: " + ", ".join(line))
    return worst <= LIMIT_SECONDS


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--takes", nargs="+", default=["gym", "13_29", "13_30"])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        libraries, ok = quality(args.takes, args.workers, folder)
        ok &= cost(libraries.get("13_29") or next(iter(libraries.values())))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
