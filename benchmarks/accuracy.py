"""Motion-structure accuracy on real motion: one table per take and variant, both methods.

    python benchmarks/accuracy.py [--takes 13_30 13_29] [--variants base seed1 ...]

For every CMU take turned into meshes (``mocap2tvm.py``, generated once into
``.cache/testdata`` exactly as the tests do), and for the synthetic actor's gym preset and every variant of it (another noise seed,
palette, body build, more noise, 30 fps), the sequence is parsed with ``method="energy"``
(default) and ``method="paper"`` and scored with :mod:`engine.evaluate`: cluster-boundary
precision and recall (one-to-one, within 1 s) and texton-length accuracy (median texton
length within 15 % of the true period). The paper method is also shown at its printed
beta = 0.07.
"""

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from conftest import CACHE, mocap_take, synth_take  # noqa: E402  (the tests' generators and cache)

from engine.evaluate import load_truth, score_take  # noqa: E402
from engine.structure import StructureParams  # noqa: E402

VARIANTS = {
    "base": {},
    "seed1": {"seed": 1},
    "palette-b": {"palette": "b"},
    "build0.8": {"build": 0.8},
    "build1.3": {"build": 1.3},
    "noise0.006": {"noise": 0.006},
    "fps30": {"fps": 30},
}
METHODS = {
    "energy": StructureParams(),
    "paper": StructureParams(method="paper"),
    "paper b=.07": StructureParams(method="paper", beta=0.07),
}


def take_folder(take, variant="base"):
    """The cached frames of a CMU take (or ``synth-gym``) in one of :data:`VARIANTS`."""
    return synth_take("gym") if take == "synth-gym" else mocap_take(take, **VARIANTS[variant])


def score(folder, params):
    """(precision, recall, texton accuracy, clusters, seconds) of one parse."""
    result = score_take(folder, params, cache_dir=CACHE.parent / "features")
    return result.precision, result.recall, result.texton_accuracy, result.structure, result.parse_seconds


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--takes", nargs="+", default=["13_30", "13_29", "synth-gym"],
                    help="CMU takes, or synth-gym for the synthetic actor (base variant only)")
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    ap.add_argument("--methods", nargs="+", default=list(METHODS), choices=list(METHODS))
    ap.add_argument("--verbose", action="store_true", help="print detected clusters and periods")
    args = ap.parse_args(argv)
    print(f"{'take':9s} {'variant':11s} {'method':12s} {'prec':>5s} {'recall':>6s} {'texton':>6s} {'clusters':>8s} {'parse s':>7s}")
    worst = {}
    for take in args.takes:
        for name in args.variants:
            if take == "synth-gym" and name != "base":
                continue
            folder = take_folder(take, name)
            for method in args.methods:
                p, r, acc, s, sec = score(folder, METHODS[method])
                print(f"{take:9s} {name:11s} {method:12s} {p:5.2f} {r:6.2f} {acc:6.2f} {len(s.clusters):8d} {sec:7.2f}")
                w = worst.setdefault(method, [1.0, 1.0, 1.0])
                w[0], w[1] = min(w[0], p), min(w[1], r)
                w[2] = min(w[2], acc) if acc == acc else w[2]
                if args.verbose:
                    truth = load_truth(folder)
                    print("      truth   ", [(g["start"], round(h["period_frames"], 1) if h else None)
                                              for g, h in zip(truth["segments"], truth["periods_hint"])])
                    print("      detected", [(c[0], [len(t) for t in s.textons_of(i)]) for i, c in enumerate(s.clusters)])
    for method, (p, r, a) in worst.items():
        print(f"worst over all: {method:12s} precision {p:.2f} recall {r:.2f} texton {a:.2f}")


if __name__ == "__main__":
    main()
