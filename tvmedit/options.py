"""Argument types shared by the commands (parsed before any heavy import)."""

import argparse
import math

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
    from engine.params import MAX_LOOPS

    try:
        value = int(text)
    except ValueError:
        value = 0
    if not 1 <= value <= MAX_LOOPS:
        raise argparse.ArgumentTypeError(f"should be a whole number of cycles from 1 to {MAX_LOOPS}, "
                                         f"not {text!r}")
    return value


def up_axis(text):
    """``+x`` ... ``-z`` (a bare ``y`` means ``+y``), for --up."""
    key = text.strip().lower()
    key = key if key[:1] in "+-" else "+" + key
    if key not in ("+x", "-x", "+y", "-y", "+z", "-z"):
        raise argparse.ArgumentTypeError(f"should be one of +x, -x, +y, -y, +z, -z, not {text!r}")
    return key


def add_frame_of_reference(parser):
    """--up, --units and --mirror/--no-mirror: the capture's frame, where detection is not wanted."""
    group = parser.add_argument_group("frame of reference (default: detected; tvmedit check says how)")
    group.add_argument("--up", type=up_axis, default=None, metavar="AXIS",
                       help="the capture's up axis: +x, -x, +y, -y, +z or -z")
    group.add_argument("--units", choices=("m", "cm", "mm"), default=None,
                       help="the capture's length unit")
    group.add_argument("--mirror", action=argparse.BooleanOptionalAction, default=None,
                       help="swap left and right, for a capture stored as a mirror image (text reads backwards); default: no")


def as_flags(text):
    """An engine message with the structure parameters it names written as build flags
    (``min_cluster`` -> ``--min-cluster``)."""
    if not text:
        return text
    for name in ("min_cluster", "novelty_threshold"):
        text = text.replace(name, "--" + name.replace("_", "-"))
    return text


def add_shading(parser):
    """--shading auto|texture|colour, for render and play."""
    parser.add_argument("--shading", choices=("auto", "texture", "colour"), default="auto",
                        help="draw each frame's texture (texture) or its vertex colours (colour); "
                             "default auto: the texture where the capture has one")
