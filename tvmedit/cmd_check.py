"""Load a TVM sequence and report what tvmedit sees in it, before you build.

INPUT is a folder of frame files (PLY, OBJ, OFF, Draco, glTF/GLB; ordered by the last number
in each file name), a folder with a sequence manifest (``scvv_animation.json`` or
``scvv.json``), or a quoted glob such as 'capture/*.ply'. Every frame is loaded and checked:
a frame that is not a mesh, is truncated, has no vertices, or has NaN/inf coordinates stops
the check with one sentence naming the file, unless --skip-bad-frames is given.

It prints the format, the frames and their timing, vertices and triangles, colours and
textures, and the frame of reference: the up axis, the units, the way the subject faces and
whether the capture is mirrored, each with the reason it was chosen (--up, --units, --front,
--mirror override them; --front names the axis to face the camera where a render shows a back), and
the axes features are computed in: the body's own, found from its shape, by default
(--no-body-frame: the capture's, once put upright).

INPUT may also be a library (LIB, made by tvmedit build): every file of it is then checked
against the checksums the build recorded, and every stored frame against the bounds it
recorded, so that damage on disk is found before an edit is written from it.
"""

from . import options

HELP = ("load a TVM sequence and report format, frames, timing, vertices, textures, up axis and units; "
        "or verify a library")


def add_arguments(parser):
    parser.add_argument("input", metavar="INPUT",
                        help="sequence folder, manifest, or quoted glob of frame files; or a library to verify")
    parser.add_argument("--fps", type=float, default=None,
                        help="frame rate (default: sequence.json beside the frames, else the manifest's "
                             "frame times, else 10); a capture with frame times is resampled to it")
    parser.add_argument("--skip-bad-frames", action="store_true",
                        help="leave out frames that cannot be loaded, with a warning that lists them")
    options.add_frame_of_reference(parser)


def _timing(sequence, usable):
    """Lines about the frame rate and, for a capture with its own frame times, their spread."""
    import numpy as np

    if sequence.times is None:
        from tvmedit.engine.capture.load import rate_assumed

        assumed = rate_assumed(sequence)
        return [f"{sequence.name}: {usable} frames at {sequence.fps:g} fps ({usable / sequence.fps:.1f} s)"
                + (f"; the rate is {sequence.rate_from}'s" if sequence.rate_from == "sequence.json" else "")
                + (f"; the rate is the one its {sequence.rate_from} states (--fps overrides it)"
                   if sequence.rate_from.startswith(("folder name", "uvol manifest")) else "")] \
            + ([f"note: {assumed}"] if assumed else [])
    steps = np.diff(sequence.times) * 1000
    captured = len(sequence.captured)
    shown = len(set(map(str, sequence.paths)))
    held = len(sequence.paths) - shown
    regular = steps.max() - steps.min() <= 0.1 * np.median(steps)
    return [f"{sequence.name}: {captured} frames over {sequence.times[-1]:.2f} s, "
            f"{steps.min():.1f}-{steps.max():.1f} ms apart (median {np.median(steps):.1f} ms: "
            f"{1000 / np.median(steps):.1f} fps; {'regular' if regular else 'variable'})",
            f"analysed at {sequence.fps:g} fps: {len(sequence.paths)} frames "
            f"({held} held over a gap, {captured - shown} dropped)"]


def _check_library(path):
    """Verify a library's files and frames; prints what was checked."""
    from tvmedit.engine.store.library import Library

    library = Library.open(path)
    verified = library.verify()
    frames = library.stored_frames()
    for key in frames:
        library.frame_mesh(key)
    blends = int(library.manifest["counts"].get("blend_frames", 0))
    for row in range(blends):
        library.blend_row(row)
    if not verified:
        print(f"library {path}: built before checksums, so only its sizes and frame bounds were checked; "
              f"rebuild it to check every byte")
    print(f"library {path}: {verified} files hold the bytes written; {len(frames)} stored frames and "
          f"{blends} in-between frames lie within the recorded bounds")
    return 0


def run(args):
    import numpy as np
    from pathlib import Path

    from tvmedit.engine.capture.load import iter_frames, open_sequence, warn_skipped

    if (Path(args.input) / "manifest.json").is_file():
        return _check_library(args.input)

    sequence = open_sequence(args.input, fps=args.fps, up=args.up, units=args.units, mirror=args.mirror, front=args.front,
                             body_frame=args.body_frame)
    counts, faces, coloured, textured, sizes = [], [], 0, 0, set()
    skipped = []
    paths = sequence.captured or sequence.paths
    for _, frame in iter_frames(paths, args.skip_bad_frames, skipped, sequence.orientation):
        counts.append(len(frame.positions))
        faces.append(len(frame.faces))
        coloured += int(len(np.unique(frame.colours[:64], axis=0)) > 1)
        if frame.texture is not None:
            textured += 1
            sizes.add(f"{frame.texture.shape[1]}x{frame.texture.shape[0]}")
    warn_skipped(skipped)
    if not counts:
        from tvmedit.engine.errors import InputError
        raise InputError(f"no usable frames in {args.input}: all {len(paths)} were bad.")
    counts = np.array(counts)
    if sequence.manifest is not None:
        print(f"format: {sequence.format} sequence ({sequence.manifest.name}) of {_formats(paths)} frames")
    else:
        print(f"format: {_formats(paths)} frames")
    for line in _timing(sequence, len(counts)):
        print(line)
    print(f"vertices per frame: {counts.min()}..{counts.max()} (mean {counts.mean():.0f}); "
          f"triangles: {min(faces)}..{max(faces)}")
    if textured:
        print(f"textures: {textured} of {len(counts)} frames ({', '.join(sorted(sizes))}); "
              "vertex colours sampled from them; render and play draw the textures")
    else:
        print("textures: none")
    print(f"vertex colours: {'yes' if coloured else 'none (neutral grey)'}; "
          f"topology varies: {'yes' if len(set(counts.tolist())) > 1 else 'no'}")
    for line in sequence.orientation.describe():
        print(line)
    return 0


def _formats(paths):
    from tvmedit.engine.capture.readers import reader_for

    names = sorted({(reader_for(p) or ("?",))[0] for p in paths})
    return "/".join(names)
