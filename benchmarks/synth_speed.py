"""Seconds per frame of the synthetic actor on one core, against the 0.3 s limit.

Reconstructs and writes frames spread evenly over the gym preset (all six motions) at the
default 16,000 vertices, in this process only, and prints the figure the README quotes.

    .venv/bin/python benchmarks/synth_speed.py [--frames 36] [--vertices 16000]
"""

import argparse
import tempfile
import time

import numpy as np

from tvmedit.engine.lab import synth

LIMIT_S = 0.3


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=36)
    parser.add_argument("--vertices", type=int, default=16000)
    args = parser.parse_args()
    poses, labels, _, _ = synth.plan("gym")
    picks = np.linspace(0, len(poses) - 1, args.frames).round().astype(int)
    voxel = synth.voxel_size(args.vertices)
    counts = []
    with tempfile.TemporaryDirectory() as folder:
        synth._frame_job((folder, 0, poses[0], voxel, 0))       # imports and warms up
        start = time.perf_counter()
        for k in picks:
            counts.append(synth._frame_job((folder, int(k), poses[k], voxel, 0))[1])
        seconds = (time.perf_counter() - start) / len(picks)
    print(f"synth: {seconds:.3f} s per frame on one core ({len(picks)} gym frames, "
          f"{min(counts)}..{max(counts)} vertices, mean {np.mean(counts):.0f}, PLY written)")
    print(f"ratio to the {LIMIT_S} s limit: {seconds / LIMIT_S:.2f}")


if __name__ == "__main__":
    main()
