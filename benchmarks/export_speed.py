"""How fast an edit leaves in the capture's own format: the scvv card's edit as scvv, obj and glb.

The peer is the PLY export of the same edit (binary PLY with vertex colours, the export
tvmedit had before it wrote the formats captures come in). Each format writes every frame of
the edit with its texture into a fresh folder, as ``export`` does (scvv copies every frame,
the in-between frames' Draco from the build; obj encodes on worker processes, glb in this
thread); the PLY export is timed alternately with it in this process, files in the page
cache, and the best of five rounds of each counts, by wall time (the issue's bar: "at least
as fast per frame as the PLY export of the same edit, on all cores"). Limit: 1x for each.

The card library is built once into ``.cache/bench/card.tvmlib`` (the default build), and
again where it was built before libraries kept their in-between frames' Draco.

    python benchmarks/export_speed.py [--rounds N] [--formats scvv obj glb]
"""

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("TVMEDIT_SHARED", ROOT.parent / "shared"))
CARD = SHARED / "data" / "scvv-card"
LIBRARY = ROOT / ".cache" / "bench" / "card.tvmlib"
LIMITS = {"scvv": 1.0, "obj": 1.0, "glb": 1.0}


def library():
    from tvmedit import Library, build

    if (LIBRARY / "manifest.json").exists() and (LIBRARY / "blend_draco.npy").exists():
        return Library.open(LIBRARY)
    LIBRARY.parent.mkdir(parents=True, exist_ok=True)
    return build([CARD], LIBRARY, progress=False, force=True)


def timed(edit, fmt, folder):
    from tvmedit.engine.graph.export import export_edit

    out = Path(folder) / fmt
    start = time.perf_counter()
    record = export_edit(edit, out, fmt=fmt)
    seconds = time.perf_counter() - start
    shutil.rmtree(out)
    return seconds, len(record["frames"])


def main(rounds, formats):
    if not (CARD / "scvv_animation.json").exists():
        print(f"the scvv capture is not at {CARD}; set TVMEDIT_SHARED to the shared folder")
        return 1
    lib = library()
    edit = lib.edit(list(range(len(lib.nodes))))
    blends = sum(entry.blend is not None for entry in edit.schedule)
    print(f"scvv card: the edit through its {len(lib.nodes)} motions, {len(edit.schedule)} frames "
          f"({blends} in-between), {os.cpu_count()} cores")
    failed = False
    with tempfile.TemporaryDirectory() as folder:
        timed(edit, "ply", folder)   # imports and page cache warm
        for fmt in formats:
            timed(edit, fmt, folder)
            times = {"ply": [], fmt: []}
            for _ in range(rounds):
                for name in ("ply", fmt):
                    times[name].append(timed(edit, name, folder)[0])
            ply, own = min(times["ply"]), min(times[fmt])
            ratio = own / ply
            limit = LIMITS.get(fmt)
            verdict = "" if limit is None else f" (limit {limit:g}x): {'met' if ratio <= limit else 'NOT met'}"
            failed |= limit is not None and ratio > limit
            frames = len(edit.schedule)
            print(f"{fmt}: {own:.2f} s ({frames / own:.0f} frames/s) against ply {ply:.2f} s "
                  f"({frames / ply:.0f} frames/s): {ratio:.2f}x{verdict}")
    return 1 if failed else 0


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--formats", nargs="+", default=["scvv", "obj", "glb"])
    arguments = parser.parse_args()
    sys.exit(main(arguments.rounds, arguments.formats))
