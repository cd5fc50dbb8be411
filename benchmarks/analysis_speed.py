"""Analysis speed: features plus structure parsing of a 2,000-frame, ~17,000-vertex sequence.

    python benchmarks/analysis_speed.py [--frames 2000]

The sequence is CMU 13_29 at 60 fps turned into meshes by ``mocap2tvm.py`` (generated once
into ``.cache/speed``). File reading is excluded: all vertex arrays are loaded first, then
the histograms of every frame (eq. (1)-(4)) and ``parse`` (eq. (5)-(8), default method) are
timed. The limit is 2 s for 2,000 frames. Linear growth is shown by timing the first 250
frames the same way: the per-frame cost should stay about the same.
"""

import argparse
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from engine.features import BinSizes, FeatureAccumulator  # noqa: E402
from engine.load import frame_paths, iter_frames  # noqa: E402
from engine.structure import parse  # noqa: E402

SHARED = ROOT.parent / "shared"
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
    """(feature seconds, parse seconds) for a list of (N, 3) arrays."""
    t0 = time.perf_counter()
    acc = FeatureAccumulator(BinSizes())
    for p in positions:
        acc.add(p)
    features = acc.result()
    t1 = time.perf_counter()
    parse(features.vectors, FPS, theta=features.theta_columns)
    return t1 - t0, time.perf_counter() - t1


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3, help="best of this many runs")
    args = ap.parse_args(argv)
    folder = data(args.frames)
    positions = [frame.positions for _, frame in iter_frames(frame_paths(str(folder)))]
    mean_vertices = sum(len(p) for p in positions) / len(positions)
    print(f"{len(positions)} frames at {FPS} fps, {mean_vertices:,.0f} vertices a frame (files already read)")
    rows = {}
    for n in (250, len(positions)):
        best = min((analyse(positions[:n]) for _ in range(args.repeat)), key=sum)
        rows[n] = best
        total = sum(best)
        print(f"{n:5d} frames: features {best[0]:.2f} s + parse {best[1]:.2f} s = {total:.2f} s "
              f"({n / total:,.0f} frames/s, {1000 * total / n:.2f} ms/frame)")
    small, large = rows[250], rows[len(positions)]
    ratio = (sum(large) / len(positions)) / (sum(small) / 250)
    print(f"per-frame cost {len(positions)} vs 250 frames: {ratio:.2f}x (1.0 = linear)")
    print(f"limit 2.00 s for 2,000 frames: {sum(large) * 2000 / len(positions):.2f} s "
          f"({'within' if sum(large) * 2000 / len(positions) <= 2.0 else 'OVER'})")


if __name__ == "__main__":
    main()
