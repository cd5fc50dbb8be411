"""Load a TVM sequence and report what tvmedit sees in it, before you build.

INPUT is a folder of PLY, OBJ or OFF frames (ordered by the last number in each file
name) or a quoted glob such as 'capture/*.ply'. Every frame is loaded and checked: a frame
that is not a mesh, is truncated, has no vertices, or has NaN/inf coordinates stops the
check with one sentence naming the file, unless --skip-bad-frames is given.
"""

HELP = "load a TVM sequence and report frames, vertices and colours"


def add_arguments(parser):
    parser.add_argument("input", metavar="INPUT", help="sequence folder or quoted glob of frame files")
    parser.add_argument("--fps", type=float, default=None,
                        help="frame rate (default: sequence.json beside the frames, else 10)")
    parser.add_argument("--skip-bad-frames", action="store_true",
                        help="leave out frames that cannot be loaded, with a warning that lists them")


def run(args):
    import numpy as np

    from engine.load import iter_frames, open_sequence, warn_skipped

    sequence = open_sequence(args.input, fps=args.fps)
    counts, faces, coloured = [], [], 0
    skipped = []
    for _, frame in iter_frames(sequence.paths, args.skip_bad_frames, skipped):
        counts.append(len(frame.positions))
        faces.append(len(frame.faces))
        coloured += int(len(np.unique(frame.colours[:64], axis=0)) > 1)
    warn_skipped(skipped)
    if not counts:
        from engine.errors import InputError
        raise InputError(f"no usable frames in {args.input}: all {len(sequence.paths)} were bad.")
    counts = np.array(counts)
    print(f"{sequence.name}: {len(counts)} frames at {sequence.fps:g} fps "
          f"({len(counts) / sequence.fps:.1f} s)")
    print(f"vertices per frame: {counts.min()}..{counts.max()} (mean {counts.mean():.0f}); "
          f"triangles: {min(faces)}..{max(faces)}")
    print(f"vertex colours: {'yes' if coloured else 'none (neutral grey)'}; "
          f"topology varies: {'yes' if len(set(counts.tolist())) > 1 else 'no'}")
    return 0
