"""How the default bin sizes were chosen: parse accuracy over a grid of r and angle bin sizes.

    python benchmarks/bin_sizes.py [--takes 13_30 13_29 synth-gym] [--variants base build0.8]

For each bin size pair, features are recomputed (cached per bin size in .cache/features),
every take is parsed at the default parameters, and the worst precision, recall and
texton-length accuracy over the takes is printed, with the histogram width (values per
frame) that the distance works on.
"""

import argparse
import math
from pathlib import Path

ROOT = Path(__file__).resolve().parent

from accuracy import CACHE, VARIANTS, take_folder  # noqa: E402

from tvmedit.engine.lab.evaluate import score_take  # noqa: E402
from tvmedit.engine.features import BinSizes  # noqa: E402

R_SIZES = (0.01, 0.02, 0.04, 0.08)
ANGLE_SIZES = (2.5, 5.0, 10.0, 20.0)


def scores(folder, bins):
    result = score_take(folder, bins=bins, cache_dir=CACHE.parent / "features")
    return result.precision, result.recall, result.texton_accuracy, result.feature_columns


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--takes", nargs="+", default=["13_30", "13_29", "synth-gym"])
    ap.add_argument("--variants", nargs="+", default=["base", "build0.8"], choices=list(VARIANTS))
    args = ap.parse_args(argv)
    folders = [take_folder(take, variant) for take in args.takes for variant in args.variants
               if not (take == "synth-gym" and variant != "base")]
    print(f"worst over {len(folders)} takes: precision / recall / texton accuracy; width = values per frame")
    print(f"{'r bin':>7} {'angle bin':>9}   {'prec':>5} {'recall':>6} {'texton':>6} {'width':>6}")
    for r_size in R_SIZES:
        for angle in ANGLE_SIZES:
            bins = BinSizes(r=r_size, theta=math.radians(angle), phi=math.radians(angle))
            rows = [scores(folder, bins) for folder in folders]
            default = " (default)" if bins == BinSizes() else ""
            print(f"{r_size * 100:5.0f} cm {angle:7.1f} deg   {min(x[0] for x in rows):5.2f} "
                  f"{min(x[1] for x in rows):6.2f} {min(x[2] for x in rows):6.2f} "
                  f"{max(x[3] for x in rows):6d}{default}", flush=True)


if __name__ == "__main__":
    main()
