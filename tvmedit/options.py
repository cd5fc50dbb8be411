"""Argument types shared by the commands (parsed before any heavy import)."""

import argparse
import math
import re

#: Largest image side a GL context is sure to allocate (GL_MAX_TEXTURE_SIZE is 16384 or more).
MAX_SIZE = 8192


def size(text):
    """``"640x480"`` -> ``(640, 480)``, for --size."""
    try:
        width, height = (int(v) for v in text.lower().split("x"))
        if 0 < width <= MAX_SIZE and 0 < height <= MAX_SIZE:
            return width, height
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"size should be WIDTHxHEIGHT in pixels, like 640x480, each at most "
                                     f"{MAX_SIZE}, not {text!r}")


def camera(text):
    """``"-90,10,0"`` -> ``[-90.0, 10.0, 0.0]``, for --camera AZ,EL,DIST."""
    try:
        values = [float(v) for v in text.split(",")]
        if len(values) == 3 and all(math.isfinite(v) for v in values) and values[2] >= 0:
            return values
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"camera should be AZ,EL,DIST such as -90,10,0, not {text!r}")


def add_forbid(parser):
    """--forbid KEY..., repeatable: ``--forbid a b --forbid c``."""
    parser.add_argument("--forbid", metavar="KEY", nargs="+", action="extend", default=[],
                        help="motions no path may use (repeatable: --forbid a b --forbid c)")


def _number(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def positive(text):
    """A finite number above 0, for --fps."""
    value = _number(text)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"should be a number above 0, not {text!r}")
    return value


def finite(text):
    """Any finite number, for --orbit."""
    value = _number(text)
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"should be a finite number, not {text!r}")
    return value


def cycles(text):
    """A whole number of cycles, 1 or more, for --loops."""
    from tvmedit.engine.checks import MAX_LOOPS

    try:
        value = int(text)
    except ValueError:
        value = 0
    if not 1 <= value <= MAX_LOOPS:
        raise argparse.ArgumentTypeError(f"should be a whole number of cycles from 1 to {MAX_LOOPS}, "
                                         f"not {text!r}")
    return value


def _second(text, what):
    from tvmedit.engine.graph.timing import MAX_SECONDS

    value = _number(text)
    if not (math.isfinite(value) and 0 <= value <= MAX_SECONDS):
        raise argparse.ArgumentTypeError(f"should be {what} in seconds from 0 to {MAX_SECONDS:g}, not {text!r}")
    return value


def hold_seconds(text):
    """Seconds above 0 and at most an hour, for play --hold-seconds."""
    value = _second(text, "the hold")
    if value <= 0:
        raise argparse.ArgumentTypeError(f"should be the hold in seconds above 0, not {text!r}")
    return value


def durations(text):
    """``"4,6.5"`` -> ``[4.0, 6.5]``, for --durations; an empty item (``"4,,6"``) leaves that leg free."""
    return [None if not item.strip() else _second(item, "each leg's length") for item in text.split(",")]


def times(text):
    """``"0,4,10.5"`` -> ``[0.0, 4.0, 10.5]``, for --at."""
    return [_second(item, "each key motion's start") for item in text.split(",")]


def hold(text):
    """``"gym/03=2.5"`` -> ``("gym/03", 2.5)``, for --hold KEY=SECONDS."""
    key, sep, seconds = text.rpartition("=")
    if not sep or not key.strip():
        raise argparse.ArgumentTypeError(f"should be KEY=SECONDS, like gym/03=2.5, not {text!r}")
    return key.strip(), _second(seconds, "the hold")


def add_timing(parser):
    """--durations, --at, --hold and --strict: lengths in seconds (tvmedit.engine.graph.timing), for path, export and render."""
    group = parser.add_argument_group("lengths (seconds at the library's frame rate)")
    lengths = group.add_mutually_exclusive_group()
    lengths.add_argument("--durations", type=durations, metavar="S,S,...",
                         help="how long each leg lasts, from one key motion's start to the next's "
                              "(one a leg; leave one empty, as in 4,,6, to keep it as short as it plays)")
    lengths.add_argument("--at", type=times, metavar="T,T,...",
                         help="when each key motion begins (one a key motion, starting with 0)")
    group.add_argument("--hold", type=hold, action="append", default=[], metavar="KEY=SECONDS",
                       help="keep key motion KEY looping this long once it begins, before the path to "
                            "the next (repeatable; within that leg's time when one is given)")
    group.add_argument("--strict", action="store_true",
                       help="a length no schedule makes within one frame is an error (exit 3), "
                            "not a warning and the nearest length")


def seconds(text):
    """A length in seconds above 0, for --wander."""
    value = _second(text, "the walk's length")
    if value <= 0:
        raise argparse.ArgumentTypeError(f"should be the walk's length in seconds above 0, not {text!r}")
    return value


def add_wander(parser, length=True):
    """--wander [SECONDS], --seed, --only and --temperature: a walk over the library
    (:mod:`tvmedit.engine.playback.wander`) in place of key motions."""
    group = parser.add_argument_group("wandering (a walk that plays itself, in place of key motions)")
    if length:
        group.add_argument("--wander", type=seconds, metavar="SECONDS",
                           help="play a walk this long over the library's motions, each chosen at random, cheap "
                                "transitions likeliest, none repeated back to back; a KEY, if given, is where "
                                "it starts")
    else:
        group.add_argument("--wander", action="store_true",
                           help="when nothing is queued, walk on to motions chosen at random (cheap transitions "
                                "likeliest) instead of looping the current one; a key pressed is played, then "
                                "the walk goes on")
    group.add_argument("--seed", type=int, default=None, metavar="N", help="seed of the walk: the same seed, the same walk")
    group.add_argument("--only", metavar="KEY", nargs="+", action="extend", default=None,
                       help="the motions the walk may play (default: all but --forbid)")
    group.add_argument("--temperature", type=positive, default=1.0, metavar="T",
                       help="how freely the walk takes costly transitions, as a multiple of the median "
                            "transition weight (default 1; smaller keeps to the cheapest)")


def check_wander(args, many_keys=False):
    """With --wander: at most one KEY (where it starts; any number with ``many_keys``, as the
    player queues them) and no lengths; without, no walk options."""
    from tvmedit.engine.errors import TvmError

    if not args.wander:
        for flag, value in (("--seed", args.seed), ("--only", args.only)):
            if value is not None:
                raise TvmError(f"{flag} shapes a walk: add --wander, or leave {flag} out.")
        return
    if len(args.keys) > 1 and not many_keys:
        raise TvmError(f"a walk chooses its own motions: give at most one KEY with --wander, where it starts "
                       f"(got {len(args.keys)}).")
    for flag, value in (("--durations", getattr(args, "durations", None)), ("--at", getattr(args, "at", None)),
                        ("--hold", getattr(args, "hold", None))):
        if value:
            raise TvmError(f"{flag} times key motions; a walk has none: use --wander SECONDS for its length.")


def edit_of(library, args, timing):
    """The edit the arguments describe: a walk with --wander, else the key motions' edit."""
    if args.wander:
        return library.wander(args.wander, seed=args.seed, only=args.only, forbid=args.forbid,
                              temperature=args.temperature, start=args.keys[0] if args.keys else None)
    if len(args.keys) < 2:
        from tvmedit.engine.errors import TvmError

        raise TvmError(f"an edit goes through two or more key motions (got {len(args.keys)}): name them, "
                       f"or give --wander SECONDS for a walk that chooses its own.")
    return library.edit(args.keys, forbid=args.forbid, loops=args.loops, **timing)


def check_timing(args):
    """The counts of --durations and --at and the keys of --hold, against the KEYs given."""
    from tvmedit.engine.errors import TvmError

    legs = len(args.keys) - 1
    if legs < 1:
        return {}  # the engine says an edit needs two key motions
    for option, values, needed, unit in (("--durations", args.durations, legs, "one for each leg"),
                                         ("--at", args.at, len(args.keys), "one for each key motion")):
        if values is not None and len(values) != needed:
            raise TvmError(f"{option} has {len(values)} value{'s' * (len(values) != 1)}, but "
                           f"{len(args.keys)} key motions need {needed}, {unit}.")
    if args.at is not None and args.at[0] != 0:
        raise TvmError(f"--at starts at {args.at[0]:g}, but the first key motion begins at 0; start the list with 0.")
    for i in range(1, len(args.at or ())):
        if args.at[i] < args.at[i - 1]:
            raise TvmError(f"--at goes back in time: key motion {i + 1} at {args.at[i]:g} s comes before "
                           f"key motion {i} at {args.at[i - 1]:g} s; give the times in order.")
    for key, _ in args.hold:
        if key not in args.keys:
            raise TvmError(f"--hold {key}=... names a motion that is not among the key motions "
                           f"({', '.join(args.keys)}); hold one of them, written as among the KEYs.")
    return dict(durations=args.durations, at=args.at, holds=dict(args.hold) or None, strict=args.strict)


def up_axis(text):
    """``+x`` ... ``-z`` (a bare ``y`` means ``+y``), for --up and --front."""
    key = text.strip().lower()
    key = key if key[:1] in "+-" else "+" + key
    if key not in ("+x", "-x", "+y", "-y", "+z", "-z"):
        raise argparse.ArgumentTypeError(f"should be one of +x, -x, +y, -y, +z, -z, not {text!r}")
    return key


def add_frame_of_reference(parser):
    """--up, --front, --units, --mirror/--no-mirror (the capture's frame, where detection is not wanted) and
    --body-frame/--no-body-frame (features in the body's own axes, the default)."""
    group = parser.add_argument_group("frame of reference (default: detected; tvmedit check says how)")
    group.add_argument("--up", type=up_axis, default=None, metavar="AXIS",
                       help="the capture's up axis: +x, -x, +y, -y, +z or -z")
    group.add_argument("--front", type=up_axis, default=None, metavar="AXIS",
                       help="the way the subject faces, across up (+x, -x, +y, -y, +z or -z), for a render "
                            "that shows a back; default: a depth camera's subject faces it, else the up "
                            "axis's convention (+z for Y up, -y for Z up)")
    group.add_argument("--units", choices=("m", "cm", "mm"), default=None,
                       help="the capture's length unit")
    group.add_argument("--mirror", action=argparse.BooleanOptionalAction, default=None,
                       help="swap left and right, for a capture stored as a mirror image (text reads backwards); default: no")
    group.add_argument("--body-frame", action=argparse.BooleanOptionalAction, default=True,
                       help="compute features in the body's own axes (its principal axes over the take), so a "
                            "take parses the same however it is turned (default); --no-body-frame: in the "
                            "capture's axes once put upright")


#: Options of other commands that engine advice may name (``rebuild with mu=2``).
_OTHER = {"mu": "--mu", "skip_bad_frames": "--skip-bad-frames", "fps": "--fps", "force": "--force",
          "workers": "--workers", "dask": "--dask", "min_cluster": "--min-cluster",
          "novelty_threshold": "--novelty-threshold"}


def as_flags(message, parser=None):
    """An engine message with the Python it speaks (``force=True``, ``mu=2``, ``min_cluster``,
    ``build(...)``) said as the command line's options and commands.

    The engine names parameters as ``name=value`` or, in advice, by name; where the command
    (``parser``), or another command the advice is about, has an option of that name
    (``--force``, ``--mu``, ``--min-cluster``), the option is given instead.

    >>> p = argparse.ArgumentParser()
    >>> _ = p.add_argument("--force", action="store_true"); _ = p.add_argument("--mu", type=float)
    >>> as_flags("library x already exists; pass force=True to replace it, or mu=2.5.", p)
    'library x already exists; pass --force to replace it, or --mu 2.5.'
    >>> as_flags("x is damaged; rebuild it with build(inputs, 'x', force=True).", p)
    'x is damaged; rebuild it with `tvmedit build INPUT... -o x --force`.'
    >>> as_flags("try a shorter min_cluster or a lower novelty_threshold.")
    'try a shorter --min-cluster or a lower --novelty-threshold.'
    >>> _ = p.add_argument("--no-corrections", action="store_true")
    >>> as_flags("build with corrections=False to drop them.", p)
    'build with --no-corrections to drop them.'
    """
    if not message:
        return message
    options = {name: (option, name in ("force", "skip_bad_frames")) for name, option in _OTHER.items()}
    for action in (parser._actions if parser is not None else ()):
        if action.option_strings:
            option = action.option_strings[-1]
            for name in (action.dest, option.lstrip("-").replace("-", "_")):
                options[name] = (option, action.nargs == 0)

    def flag(match):
        name, value = match.group(1), match.group(2)
        if value == "False" and f"no_{name}" in options:  # corrections=False is --no-corrections
            return options[f"no_{name}"][0]
        found = options.get(name)
        if found is None:
            return match.group(0)
        option, switch = found
        pair = re.fullmatch(r"\((\d+), (\d+)\)", value)
        if pair:  # size=(640, 480) is --size 640x480
            return f"{option} {pair.group(1)}x{pair.group(2)}"
        return option if switch and value == "True" else f"{option} {value}"

    message = re.sub(r"\bbuild\((inputs|\[.*?\]), '(.+?)'(, force=True)?\)", _build_command, message)
    message = re.sub(r"\b([a-z][a-z_]*)=(\(\d+, \d+\)|\S+?)(?=[,;.:)]*(?:\s|$))", flag, message)
    # Parameters named in advice ("a shorter min_cluster"): snake_case words that are options.
    return re.sub(r"(?<![-=\w])([a-z]+(?:_[a-z]+)+)\b(?!=)",
                  lambda m: options[m.group(1)][0] if m.group(1) in options else m.group(0), message)


def _build_command(match):
    """``build(['a'], 'lib', force=True)`` (see ``tvmedit.engine.errors.build_call``) as a command."""
    sources = "INPUT..." if match.group(1) == "inputs" else " ".join(re.findall(r"'(.*?)'", match.group(1)))
    force = " --force" if match.group(3) else ""
    return f"`tvmedit build {sources} -o {match.group(2)}{force}`"


def add_shading(parser):
    """--shading auto|texture|colour, for render and play."""
    parser.add_argument("--shading", choices=("auto", "texture", "colour"), default="auto",
                        help="draw each frame's texture (texture) or its vertex colours (colour); "
                             "default auto: the texture where the capture has one")


def add_smooth(parser):
    """--smooth / --no-smooth, for play, render and export."""
    parser.add_argument("--smooth", action=argparse.BooleanOptionalAction, default=True,
                        help="show the body between stored frames at the display's rate, from the library's "
                             "display-rate in-betweens (default); --no-smooth shows the capture as it is")


def smooth_note(library, args, fps, capture_fps):
    """One line for a library without display-rate in-betweens asked to show more frames a
    second than it stores: what it shows, and how to rebuild it; '' otherwise."""
    if not args.smooth or library.smooth or not capture_fps or fps <= capture_fps:
        return ""
    return (f"\nnote: {library.path} has no display-rate in-betweens (built before them, or with --no-smooth), "
            f"so each stored frame is held; rebuild it for smooth motion: tvmedit build ... -o {library.path} --force")
