"""Fresh HDM05 takes: made to check a parser step once, never part of the development suite.

    python benchmarks/fresh.py [--batch step21 ...] [--set rhythm_ratio=0 ...] [--errors]

Each batch was made when a step came in and scored once before the step was tried on it, so
it stands for a new take of people the parser was developed on; the figures the README and
``docs/parsing.md`` quote for fresh takes come from here. Scored as the development suite is
(``benchmarks/accuracy.py``): cluster-start precision and recall within 1 s, texton-length
accuracy within 15 %, in the body's axes unless ``TVMEDIT_DEV_FRAME`` says otherwise.
"""

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import devsuite  # noqa: E402

from engine.evaluate import pool, score  # noqa: E402
from engine.structure import StructureParams, parse  # noqa: E402

#: (actor, plan, order seed, mocap2tvm options) of each batch, as devsuite.HDM_SOURCES.
BATCHES = {
    "step18": [
        ("bd", "squat1Reps:5,hopBothLegs1hops:6,grabHighR:4,elbowToKnee1RepsLelbowStart:5,"
               "rotateArmsBothBackward1Reps:4", 21, {"seed": 21, "palette": "a"}),
        ("dg", "kickLFront1Reps:4,depositFloorR:4,hopBothLegs1hops:7,squat1Reps:6,sneak2StepsLStart:3", 22,
         {"seed": 22, "build": 1.15}),
        ("bk", "elbowToKnee1RepsLelbowStart:5,squat1Reps:5,grabHighR:4,throwBasketball:3,hopBothLegs1hops:7", 23,
         {"seed": 23, "palette": "b"}),
    ],
    "step21": [
        ("dg", "rotateArmsBothBackward1Reps:2,squat1Reps:5,kickLFront1Reps:4,elbowToKnee1RepsLelbowStart:5,"
               "hopBothLegs1hops:6", 31, {"seed": 31, "palette": "c"}),
        ("bd", "grabHighR:4,kickLFront1Reps:5,squat1Reps:5,depositFloorR:4,rotateArmsBothBackward1Reps:4", 32,
         {"seed": 32, "build": 0.9}),
        ("bk", "hopBothLegs1hops:7,kickLFront1Reps:5,elbowToKnee1RepsLelbowStart:5,rotateArmsBothBackward1Reps:3,"
               "squat1Reps:6", 33, {"seed": 33, "palette": "a", "build": 1.05}),
        ("dg", "squat1Reps:6,depositFloorR:4,elbowToKnee1RepsLelbowStart:5,grabHighR:4,kickLFront1Reps:4", 34,
         {"seed": 34, "build": 1.2}),
    ],
}


def takes(batch):
    """The batch's takes (devsuite.Take, group "fresh")."""
    return [devsuite.hdm_take(*source, group="fresh") for source in BATCHES[batch]]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--batch", nargs="+", default=list(BATCHES), choices=list(BATCHES))
    ap.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE",
                    help="parser parameters other than the defaults, e.g. rhythm_ratio=0")
    ap.add_argument("--errors", action="store_true", help="print each take's missed and false starts")
    args = ap.parse_args(argv)
    params = StructureParams(**{k: float(v) for k, v in (s.split("=", 1) for s in args.set)})
    import accuracy
    for batch in args.batch:
        results = []
        for take in takes(batch):
            result = score(parse(take.vectors, take.fps, params, theta=take.theta), take.truth, take.fps)
            results.append(result)
            print(accuracy.line(f"{batch} {take.name}", result.precision, result.recall, result.texton_accuracy))
            if args.errors:
                result.structure = parse(take.vectors, take.fps, params, theta=take.theta)
                print(accuracy.errors(take, result) or "    no error")
        print(accuracy.line(f"{batch} pooled", *pool(results)))


if __name__ == "__main__":
    main()
