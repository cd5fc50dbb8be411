"""Analyse TVM sequences and write a library: features, structure, database, graph, meshes.

INPUT is a sequence folder of PLY, OBJ, OFF, Draco or glTF/GLB frames or with a sequence
manifest (``scvv_animation.json``), a quoted glob of frame files (one sequence), or a quoted
glob of folders (one sequence each); give as many as you like
(several people, several takes). A sequence is named after its folder; write NAME=INPUT to
name it yourself, e.g. ``tvmedit build walk=capture/A/walk run=capture/A/run -o lib``.

The library is written beside LIB under a temporary name and renamed into place when
complete, so an interrupted build never leaves half a library. Features, the expensive
part, are cached by frame files, bin sizes and frame of reference: rebuilding with other parsing or pruning
parameters reuses them (and says so). --workers and --dask spread the reading of frames
and the blending; the library is the same whichever is used.

--corrections FILE applies corrections by hand on top of the automatic parse (cluster
boundaries and texton starts to add, remove or move, representatives to force, motions to
drop; see ``tvmedit.engine.store.corrections``) and stores them in the library, so a later rebuild with
other parameters applies them again; --no-corrections leaves them out. --keep-frames all
stores every frame, not only the database motions', so that corrections never read a frame
file and the library is inspected, corrected and played without the capture folder (a
larger library).

At every transition of the motion graph the build makes in-between frames that carry the
exit frame smoothly onto the entry frame (a different reconstruction, so otherwise a pop):
as many as keep every displayed step at or below the natural motion between captured frames
(at most 8), or --blend-frames N; --blend-frames 0 keeps the paper's cut.
"""

import argparse
import dataclasses
import math
import re
import sys
from pathlib import Path

from . import options

HELP = "analyse sequences into a library (features, structure, database, graph, meshes)"


def _input(text):
    """``NAME=PATH`` -> (name, path); a path that exists is never split."""
    if "=" in text and not Path(text).exists():
        name, path = text.split("=", 1)
        if name and path:
            return name, path
    return text


def _structure_fields():
    from tvmedit.engine.parse.structure import StructureParams

    return StructureParams, dataclasses.fields(StructureParams)


def _param_help(cls):
    """``{field: description}`` from the numpydoc Parameters/Attributes section of ``cls``."""
    helps, name, indent = {}, None, None
    for line in (cls.__doc__ or "").splitlines():
        match = re.match(r"(\s*)(\w+)\s*:\s*\S", line)
        depth = len(line) - len(line.lstrip())
        if match and (indent is None or depth <= indent):
            name, indent = match.group(2), len(match.group(1))
            helps[name] = []
        elif name and line.strip() and depth > indent:
            helps[name].append(line.strip())
        elif not line.strip() or (indent is not None and depth <= indent):
            name = None if not line.strip() else name
    return {key: " ".join(words).replace("%", "%%") for key, words in helps.items() if words}


def add_arguments(parser):
    from tvmedit.engine.features import BinSizes
    from tvmedit.engine.graph.motiongraph import MU
    from tvmedit.engine.store.settings import KEEP_FRAMES

    parser.add_argument("inputs", nargs="+", metavar="INPUT", type=_input,
                        help="sequence folder, quoted glob, or NAME=INPUT")
    parser.add_argument("-o", "--out", required=True, metavar="LIB", help="library directory to write")
    parser.add_argument("--force", action="store_true", help="replace LIB if it exists")
    parser.add_argument("--fps", type=float, default=None,
                        help="frame rate of every sequence (default: sequence.json beside the frames, else 10)")
    parser.add_argument("--skip-bad-frames", action="store_true",
                        help="leave out frames that cannot be loaded instead of stopping")
    fixes = parser.add_mutually_exclusive_group()
    fixes.add_argument("--corrections", metavar="FILE", default=None,
                       help="corrections.json to apply on top of the parse (default: those stored "
                            "in the library being replaced, if any)")
    fixes.add_argument("--no-corrections", action="store_true",
                       help="build from the automatic parse alone, dropping stored corrections")
    options.add_frame_of_reference(parser)

    bins = BinSizes()
    group = parser.add_argument_group("features (section 3)")
    group.add_argument("--bin-r", type=float, default=bins.r, metavar="M",
                       help="radial bin size in metres (default: %(default)g)")
    group.add_argument("--bin-theta", type=float, default=math.degrees(bins.theta), metavar="DEG",
                       help="azimuth bin size in degrees (default: %(default)g)")
    group.add_argument("--bin-phi", type=float, default=math.degrees(bins.phi), metavar="DEG",
                       help="polar bin size in degrees (default: %(default)g)")

    cls, fields = _structure_fields()
    defaults, helps = cls(), _param_help(cls)
    group = parser.add_argument_group("structure parsing (section 4)")
    for field in fields:
        # A default of None follows other parameters (the novelty threshold follows whether its
        # rows are whitened): it stays None here, and the engine decides.
        default = None if field.default is None else getattr(defaults, field.name)
        flag = "--" + field.name.replace("_", "-")
        text = helps.get(field.name, field.name.replace("_", " "))
        kwargs = {"dest": f"structure_{field.name}", "default": default, "metavar": field.name.upper()}
        if isinstance(default, bool):
            kwargs["action"] = argparse.BooleanOptionalAction
        elif isinstance(default, (list, tuple)):
            kwargs.update(nargs="+", type=type(default[0]) if default else float)
        elif default is None:
            kwargs["type"] = float
        else:
            kwargs["type"] = type(default)
        group.add_argument(flag, help=text if default is None else f"{text} (default: %(default)s)", **kwargs)

    group = parser.add_argument_group("motion graph (section 6)")
    group.add_argument("--connect", choices=("auto", "off"), default="auto",
                       help="auto (default): add back the fewest, lightest transitions of the complete graph "
                            "so that every motion reaches every other; off: keep the paper's pruned graph")
    group.add_argument("--mu", type=float, default=MU,
                       help="pruning parameter of eq. (14); larger keeps more edges (default: %(default)g)")

    group.add_argument("--blend-frames", type=int, default=None, metavar="N",
                       help="in-between frames at every transition, 0-8, warped from the exit frame "
                            "onto the entry frame; 0 keeps the paper's cut (default: as many as keep "
                            "every step at or below the natural step between captured frames)")

    group.add_argument("--smooth", action=argparse.BooleanOptionalAction, default=True,
                       help="make the display-rate in-betweens (default): the body moves at the display's rate")

    group.add_argument("--keep-frames", choices=KEEP_FRAMES, default="motions",
                       help="motions (default): store the frames of the database motions only; all: store "
                            "every frame, a larger library whose corrections by hand (tvmedit correct, "
                            "inspect) never read a frame file, with or without the capture folder")

    group = parser.add_argument_group("speed")
    group.add_argument("--workers", type=int, default=None, metavar="N",
                       help="local worker processes reading frames (default: all cores; 1: none)")
    group.add_argument("--dask", default=None, metavar="ADDRESS",
                       help="spread the work over a dask.distributed scheduler at ADDRESS "
                            "(frame files must be on a shared file system), or 'local' to start one here")
    group.add_argument("--no-cache", action="store_true",
                       help="neither read nor write the feature cache in $XDG_CACHE_HOME/tvmedit")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bars and no summary")


def run(args):
    from tvmedit.engine.store.library import build
    from tvmedit.engine.features import BinSizes

    def say(message):
        # -q silences progress and the summary, never a warning (skipped frames, no motions).
        if not args.quiet or message.startswith("warning") or "skipped" in message:
            print(options.as_flags(message, args._parser), file=sys.stderr)

    from tvmedit.engine.features import MAX_ANGLE_BINS
    from tvmedit.engine.checks import number

    # Angles are degrees here and radians in the engine, so they are checked here, in degrees.
    number("bin_r", args.bin_r, above=0)
    for name, span in (("bin_theta", 360), ("bin_phi", 180)):
        number(name, getattr(args, name), at_least=span / MAX_ANGLE_BINS, at_most=span,
               hint=f" degrees (at most {MAX_ANGLE_BINS} bins over {span} degrees)")
    bins = BinSizes(r=args.bin_r, theta=math.radians(args.bin_theta), phi=math.radians(args.bin_phi))
    cls, fields = _structure_fields()
    defaults = cls()
    structure = {}
    for field in fields:
        value = getattr(args, f"structure_{field.name}")
        structure[field.name] = tuple(value) if isinstance(getattr(defaults, field.name), tuple) else value
    library = build(args.inputs, args.out, fps=args.fps, bins=bins, structure=structure, mu=args.mu,
                    connect=args.connect, skip_bad_frames=args.skip_bad_frames, progress=not args.quiet,
                    workers=args.workers, dask=args.dask, force=args.force,
                    cache=not args.no_cache, log=say, up=args.up, units=args.units, mirror=args.mirror, front=args.front,
                    body_frame=args.body_frame,
                    corrections=False if args.no_corrections else args.corrections,
                    blend_frames=args.blend_frames, keep_frames=args.keep_frames, smooth=args.smooth)
    if args.quiet:
        return 0
    report = library.report
    reused = report["reused"]
    say(f"built {library.path}: {report['sequences']} sequence(s), {report['frames']} frames, "
        f"{report['clusters']} clusters, {report['nodes']} database motions, "
        f"{report['edges']} graph edges"
        + (f" ({report['added']} added so every motion reaches every other)" if report.get("added") else "")
        + f", {report['stored_frames']} frames stored (+{report['blend_frames']} in-between"
        + (f", {report['display_steps']} steps smoothed" if report.get("display_steps") else "") + "), "
        f"in {report['seconds']:.1f} s ({report['workers']})"
        + (f"; features reused for {len(reused)} of {report['sequences']} sequence(s)" if reused else "")
        + (f"; corrections by hand applied to {', '.join(report['corrected'])}" if report["corrected"] else ""))
    return 0
