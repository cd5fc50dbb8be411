"""How fast a correction by hand is applied: ``Library.correct`` on 2,000-frame libraries.

Inputs, each built once with its features cached:

* ``gym``: the synthetic actor's gym at 10 fps with 22 cycles of each exercise, 2,040 frames
  of about 16,000 vertices (the paper's BroadGym scale: about 2,000 frames at 10 fps),
  generated once into ``.cache/bench``;
* ``13_29``: CMU 13_29 at 60 fps, 2,296 frames of about 17,000 vertices (the take
  ``build_speed.py`` generates), whose textons are six times as many frames.

Corrections as a user makes them in ``tvmedit inspect``: a true cluster boundary removed and
a spurious one added in the middle of the longest cluster (the clusters they change get their
textons found anew; the frames of the new motions are read from their files in a library
built with ``--keep-frames motions``, the default, which never stored them, and taken from
the library itself with ``--keep-frames all``), and a correction of stored motions only (a
texton start moved, a motion dropped: no frame file is read). The transitions the
correction changes get their in-between frames made anew; the others, and the natural
step's measured frame pairs, are taken from the library. Each is timed from opening the
library to the new library opened (best of three, a fresh output each time), against the
limit of 1 s and against a build into a new folder with the features cached (which reads
every stored frame again), for both ``--keep-frames`` choices.

    python benchmarks/correct_speed.py
"""

import json
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
GYM = ROOT / ".cache" / "bench" / "gym-2000"
LIMIT_S = 1.0


def gym_data():
    """The 2,040-frame synthetic take, generated on first use (about a minute on two cores)."""
    if not (GYM / "truth.json").exists():
        from tvmedit.engine.lab import synth

        print(f"generating {GYM} (once) ...", flush=True)
        synth.generate(GYM, preset="gym", cycles=22, fps=10, vertices=16000, workers=2, progress=False,
                       overwrite=True)
    return GYM


def timed(fn, rounds=3):
    best, result = float("inf"), None
    for k in range(rounds):
        t0 = time.perf_counter()
        result = fn(k)
        best = min(best, time.perf_counter() - t0)
    return best, result


def corrections_for(library, data):
    """The two corrections: boundaries (a true one removed, a spurious one added), and stored
    motions only (a texton start away from the representative moved, the last motion dropped)."""
    structure = library.structure("take")
    truth = [s["start"] for s in json.loads((data / "truth.json").read_text())["segments"]][1:]
    starts = [s for s, _ in structure.clusters[1:]]
    true = min(starts, key=lambda b: min(abs(b - t) for t in truth))
    longest = max(structure.clusters, key=lambda c: c[1] - c[0])
    boundaries = {"remove": [true], "add": [(longest[0] + longest[1]) // 2]}
    cluster = max(range(len(structure.clusters)), key=lambda k: len(structure.textons_of(k)))
    node = next(n for n in library.nodes if n.cluster == cluster)
    far = [t for t in structure.textons_of(cluster) if t.start > node.end + 1 or t.end < node.start - 1]
    stored = {"textons": {"move": [[far[-1].start, far[-1].start + 1]]}, "drop": [library.nodes[-1].name]}
    return [("a true boundary removed, a spurious one added", {"sequences": {"take": {"boundaries": boundaries}}}),
            ("a texton start moved, a motion dropped", {"sequences": {"take": stored}})]


def measure(name, data, fps, tmp, keep):
    from tvmedit import Library, build

    path = tmp / f"{name}-{keep}.tvmlib"
    build([("take", data)], path, fps=fps, workers=2, keep_frames=keep)   # fills the feature cache
    # The peer: a build of the same take into a new folder, features from the cache, every
    # stored frame read (what a correction would cost without a library to take meshes from).
    rebuild_s, _ = timed(lambda k: build([("take", data)], tmp / f"{name}-{keep}-scratch", fps=fps, workers=2,
                                         keep_frames=keep), 1)
    library = Library.open(path)
    rows = []
    for label, corrections in corrections_for(library, data):
        seconds, result = timed(lambda k: Library.open(path).correct(corrections, tmp / f"{name}-{keep}-{k}",
                                                                     force=True))
        rows.append((label, seconds, result.report))
    frames = sum(len(s) for s in library.sequences)
    print(f"  {name}, --keep-frames {keep}: {frames} frames at {fps:g} fps, "
          f"{library.manifest['counts']['stored_frames']} stored; "
          f"a build with features cached, into a new folder {rebuild_s:.1f} s")
    for label, seconds, report in rows:
        stages = ", ".join(f"{k} {v:.2f} s" for k, v in report["stages"].items())
        verdict = "ok" if seconds <= LIMIT_S else "OVER"
        print(f"    {label}: {seconds:.2f} s (limit {LIMIT_S:g} s: {verdict}; {rebuild_s / seconds:.0f}x faster "
              f"than that build), {report['read_frames']} frame files read; {report['clusters']} clusters, "
              f"{report['nodes']} motions, {report['edges']} edges, {report['blend_made']} transitions "
              f"blended anew; {stages}", flush=True)
    for folder in tmp.glob(f"{name}-{keep}*"):
        shutil.rmtree(folder, ignore_errors=True)


def main():
    warnings.simplefilter("ignore")
    from build_speed import DATA, ensure_data

    gym_data()
    ensure_data()
    print("correct_speed: open a library, apply corrections by hand, derive it again, open the result")
    with tempfile.TemporaryDirectory(dir=ROOT / ".cache" / "bench") as tmp:
        for keep in ("motions", "all"):
            measure("gym", GYM, 10, Path(tmp), keep)
            measure("13_29", DATA, 60, Path(tmp), keep)


if __name__ == "__main__":
    main()
