"""Analysis speed: features plus structure parsing of a 2,000-frame, ~17,000-vertex sequence.

    python benchmarks/analysis_speed.py [--frames 2000]

The sequence is CMU 13_29 at 60 fps turned into meshes by ``mocap2tvm.py`` (generated once
into ``.cache/speed``). File reading is excluded: all vertex arrays are loaded first, then
the histograms of every frame (eq. (1)-(4); and, as a build makes them for a person who
stays on their spot, about each frame's own centre for the turn veto) and ``parse`` (eq.
(5)-(8), default method) are timed, in wall and CPU seconds (CPU time shows when other work
on the machine slowed a run).
Frames are read in the frame features are computed in (the body's own by default), as a
build reads them.
The limit is 2 s for 2,000 frames. Linear growth is shown by timing the first 250 frames the
same way: the per-frame cost should stay about the same.

Then the same on two cores as a build computes them: every frame's stored rows
(``features.stored_rows``, what a build's worker keeps of each frame it reads) on two worker
processes forked with the frames already in memory, in chunks as a build sends them, and
the parse in this process (limit 1.0 s, the issue's bar).
"""

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

from tvmedit.engine.features import BinSizes, FeatureAccumulator, stored_rows  # noqa: E402
from tvmedit.engine.parallel import Workers  # noqa: E402
from tvmedit.engine.capture.load import frame_paths, iter_frames, open_sequence  # noqa: E402
from tvmedit.engine.parse.structure import parse  # noqa: E402

SHARED = Path(os.environ.get("TVMEDIT_SHARED", ROOT.parent / "shared"))
FPS = 60


def data(frames):
    out = ROOT / ".cache" / "speed" / f"13_29-{FPS}fps-{frames}"
    if not (out / "truth.json").exists():
        subprocess.run([sys.executable, str(SHARED / "tools" / "mocap2tvm.py"),
                        str(SHARED / "data" / "mocap6" / "13_29.amc"), "--fps", str(FPS),
                        "--end", str(frames), "--workers", "2", "--overwrite", "--out", str(out)],
                       check=True, stdout=subprocess.DEVNULL)
    return out


def analyse(positions):
    """Wall and CPU seconds, ``{"features": (wall, cpu), "parse": (wall, cpu)}``, for (N, 3) arrays."""
    w0, c0 = time.perf_counter(), time.process_time()
    acc = FeatureAccumulator(BinSizes(), centred=True)   # as the builder: the actor stays put
    for p in positions:
        acc.add(p)
    features = acc.result()
    w1, c1 = time.perf_counter(), time.process_time()
    parse(features.vectors, FPS, theta=features.theta_columns, centred=features.centred)
    w2, c2 = time.perf_counter(), time.process_time()
    return {"features": (w1 - w0, c1 - c0), "parse": (w2 - w1, c2 - c1)}


#: The frames, read once before the workers are forked, which see them without a copy.
_FRAMES = []
#: Frames a worker's task holds, as a build's (``builder.FEATURE_CHUNK``).
CHUNK = 32
LIMIT_TWO_CORES = 1.0


def _rows_task(task):
    start, stop, origin = task
    return [stored_rows(p, origin) for p in _FRAMES[start:stop]]


def analyse_on_workers(pool):
    """Wall seconds ``(features, parse)`` with the stored rows made on ``pool``'s processes."""
    w0 = time.perf_counter()
    acc = FeatureAccumulator(BinSizes(), origin=_FRAMES[0].mean(axis=0, dtype=np.float64), centred=True)
    tasks = [(k, min(k + CHUNK, len(_FRAMES)), acc.origin) for k in range(0, len(_FRAMES), CHUNK)]
    for rows in pool.map(_rows_task, tasks):
        for own, centred in rows:
            acc.add_histograms(*own, centred=centred)
    features = acc.result()
    w1 = time.perf_counter()
    parse(features.vectors, FPS, theta=features.theta_columns, centred=features.centred)
    return w1 - w0, time.perf_counter() - w1


def total(run, k=0):
    """Features plus parse: k = 0 wall seconds, k = 1 CPU seconds."""
    return run["features"][k] + run["parse"][k]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3, help="best of this many runs")
    args = ap.parse_args(argv)
    folder = data(args.frames)
    # In the frame features are computed in, as a build does (the body's own by default).
    orientation = open_sequence(str(folder)).orientation.for_features()
    positions = [frame.positions for _, frame in iter_frames(frame_paths(str(folder)), orientation=orientation)]
    mean_vertices = sum(len(p) for p in positions) / len(positions)
    print(f"{len(positions)} frames at {FPS} fps, {mean_vertices:,.0f} vertices a frame (files already read); "
          f"best of {args.repeat}, wall (CPU) seconds")
    rows = {}
    for n in (250, len(positions)):
        best = min((analyse(positions[:n]) for _ in range(args.repeat)), key=total)
        rows[n] = best
        f, p = best["features"], best["parse"]
        print(f"{n:5d} frames: features {f[0]:.2f} ({f[1]:.2f}) s + parse {p[0]:.2f} ({p[1]:.2f}) s "
              f"= {total(best):.2f} ({total(best, 1):.2f}) s; {n / total(best):,.0f} frames/s; "
              f"features {1000 * f[0] / n:.2f} ({1000 * f[1] / n:.2f}) ms/frame")
    small, large = rows[250], rows[len(positions)]
    ratio = (total(large) / len(positions)) / (total(small) / 250)
    print(f"per-frame cost {len(positions)} vs 250 frames: {ratio:.2f}x (1.0 = linear)")
    scaled = total(large) * 2000 / len(positions)
    print(f"limit 2.00 s for 2,000 frames: {scaled:.2f} s, {scaled / 2.0:.2f} of the limit "
          f"({'within' if scaled <= 2.0 else 'OVER'}); CPU {total(large, 1) * 2000 / len(positions):.2f} s")
    _FRAMES[:] = positions
    with Workers(2) as pool:
        pool.start()    # forked now: the workers hold the frames already
        best = min((analyse_on_workers(pool) for _ in range(args.repeat)), key=sum)
    two = sum(best) * 2000 / len(positions)
    print(f"on two cores, as a build computes them: features {best[0]:.2f} s + parse {best[1]:.2f} s = "
          f"{sum(best):.2f} s; limit {LIMIT_TWO_CORES:.2f} s for 2,000 frames: {two:.2f} s "
          f"({'within' if two <= LIMIT_TWO_CORES else 'OVER'})")


if __name__ == "__main__":
    main()
