"""How fast tvmedit reads a real textured capture: the scvv card, 193 Draco frames with a JPG each.

The peer is the least any reader must do with the same files: a bare loop that decodes each
Draco mesh with DracoPy (points, faces, texture coordinates as arrays) and each JPG with
Pillow. tvmedit's read is the whole of it as ``check`` and ``build`` do it: open the sequence
(manifest, timing, the frame of reference detected from a dozen frames), then read every
frame with its checks, its vertex colours averaged from the texture (``texture_colours``), the
texture image, and the map into Z up. Both run in this process with the files in the page
cache, alternately, and the best of five rounds counts, by CPU time of this process (on a
shared machine other processes' load shows in wall time; both are printed). Limit: 2x the
bare loop.

    python benchmarks/read_speed.py [--rounds N]
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("TVMEDIT_SHARED", ROOT.parent / "shared"))
CARD = SHARED / "data" / "scvv-card"
LIMIT = 2.0


def bare(frames):
    import DracoPy
    from PIL import Image

    for frame in frames:
        mesh = DracoPy.decode((CARD / frame["mesh_path"]).read_bytes())
        np.asarray(mesh.points), np.asarray(mesh.faces), np.asarray(mesh.tex_coord)
        with Image.open(CARD / frame["texture_path"]) as image:
            np.asarray(image.convert("RGB"))


def tvmedit():
    from tvmedit.engine.capture.load import iter_frames, open_sequence

    sequence = open_sequence(CARD)
    vertices = 0
    for _, frame in iter_frames(sequence.captured, orientation=sequence.orientation):
        vertices += len(frame.positions)
    return vertices


def main(rounds):
    if not (CARD / "scvv_animation.json").exists():
        print(f"the scvv capture is not at {CARD}; set TVMEDIT_SHARED to the shared folder")
        return 1
    frames = json.loads((CARD / "scvv_animation.json").read_text())["frames"]
    bare(frames[:5])
    tvmedit()  # warm the page cache and the imports
    wall = {"bare": [], "tvmedit": []}
    cpu = {"bare": [], "tvmedit": []}
    for _ in range(rounds):
        w0, c0 = time.perf_counter(), time.process_time()
        bare(frames)
        w1, c1 = time.perf_counter(), time.process_time()
        vertices = tvmedit()
        w2, c2 = time.perf_counter(), time.process_time()
        wall["bare"].append(w1 - w0)
        wall["tvmedit"].append(w2 - w1)
        cpu["bare"].append(c1 - c0)
        cpu["tvmedit"].append(c2 - c1)
    b, t = min(cpu["bare"]), min(cpu["tvmedit"])
    wb, wt = min(wall["bare"]), min(wall["tvmedit"])
    print(f"scvv card: {len(frames)} Draco frames + JPG textures, {vertices / len(frames):,.0f} vertices a frame")
    print(f"bare DracoPy + Pillow decoding: {b:.2f} s CPU ({len(frames) / b:.0f} frames/s), {wb:.2f} s wall")
    print(f"tvmedit (open, detect the frame, read, check, colour from textures, map): {t:.2f} s CPU "
          f"({len(frames) / t:.0f} frames/s), {wt:.2f} s wall")
    print(f"by wall time {wt / wb:.2f}x")
    ratio = t / b
    print(f"by CPU time {ratio:.2f}x (limit {LIMIT:g}x): {'met' if ratio <= LIMIT else 'NOT met'}")
    return 0 if ratio <= LIMIT else 1


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    sys.exit(main(parser.parse_args().rounds))
