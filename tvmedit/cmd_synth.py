"""Make a synthetic time-varying mesh take with a procedural actor, as a capture studio would.

Each frame of the actor (an implicit body posed by exercises, and by one-off movements,
putting something on the floor and reaching up, whose repetitions each go somewhere else) is
reconstructed on its own with marching cubes, so vertex count and connectivity change every
frame. The folder gets binary PLY frames frame_00000.ply, ..., sequence.json (their frame
rate, which `tvmedit build` reads) and truth.json (labels, segments, true periods), which is
written last: a folder without it is incomplete.

presets:
  walk   about 100 frames of walking on the spot at 10 fps (like the paper's Walk)
  gym    walk, run, jumping-jacks, arm-circles, squats, side-bends in one take,
         about 650 frames at 10 fps (like the paper's BroadGym)

example:
  tvmedit synth --preset gym --out data/gym
  tvmedit synth --motions squats,side-bends --cycles 3 --vertices 8000 --out /tmp/two
  tvmedit synth --motions squats,jumping-jacks --rest 1.5 --out /tmp/pausing
  tvmedit synth --motions pick-up,reach-up,squats --out /tmp/one-offs
  tvmedit synth --motions box,toe-touch,twist --out /tmp/alternating
  tvmedit synth --motions knee-raises,kick,hop --rest 0.5 --out /tmp/kicks
  tvmedit synth --motions side-reach,toe-touch-both,up-down --out /tmp/mocap6
  tvmedit synth --motions jumping-jacks,side-bends --turns 90 --out /tmp/turning
"""

import time

HELP = "make a synthetic TVM take with a procedural actor (walk, gym)"


def add_arguments(parser):
    from tvmedit.engine.lab.synth import MOTIONS, PRESETS

    parser.add_argument("--preset", choices=sorted(PRESETS), default="gym",
                        help="take to make (default: gym)")
    parser.add_argument("--motions", metavar="A,B,...",
                        help="motions in order, replacing the preset's: " + ", ".join(MOTIONS))
    parser.add_argument("--cycles", type=int, metavar="N",
                        help="cycles of every motion (default: about 10 s of each)")
    parser.add_argument("--rest", type=float, default=0.0, metavar="S",
                        help="pause after each cycle for up to S seconds, at random, as people pause "
                             "between repetitions (default: 0, no pauses)")
    parser.add_argument("--turns", type=float, default=0.0, metavar="DEG",
                        help="turn to face another way every 5-10 s, by DEG/2 to DEG degrees to either "
                             "side, as people turn between repetitions (default: 0, facing -y)")
    parser.add_argument("--fps", type=float, default=10, help="frames per second (default: 10)")
    parser.add_argument("--vertices", type=int, default=16000, metavar="N",
                        help="target vertices per frame; sets the grid resolution (default: 16000)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    parser.add_argument("--out", metavar="DIR", help="output folder (default: ./PRESET)")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="processes (default: all cores); the files do not depend on it")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace the frames of a non-empty output folder")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")


def run(args):
    from tvmedit.engine.lab.synth import generate

    motions = None if args.motions is None else [m.strip() for m in args.motions.split(",") if m.strip()]
    fps = int(args.fps) if float(args.fps).is_integer() else args.fps
    start = time.perf_counter()
    truth = generate(args.out or args.preset, preset=args.preset, motions=motions, cycles=args.cycles,
                     fps=fps, vertices=args.vertices, seed=args.seed, workers=args.workers,
                     overwrite=args.overwrite, progress=not args.quiet, rest=args.rest, turns=args.turns)
    if not args.quiet:
        counts = truth["vertex_counts"]
        segments = ", ".join(f"{s['label']} {s['start']}-{s['end']}" for s in truth["segments"])
        print(f"{truth['frames']} frames, vertices per frame {min(counts)}..{max(counts)} "
              f"(mean {sum(counts) / len(counts):.0f}), segments: {segments}; "
              f"{time.perf_counter() - start:.1f} s")
    return 0
