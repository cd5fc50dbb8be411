"""Argument types shared by the commands (parsed before any heavy import)."""

import argparse


def size(text):
    """``"640x480"`` -> ``(640, 480)``, for --size."""
    try:
        width, height = (int(v) for v in text.lower().split("x"))
        if width > 0 and height > 0:
            return width, height
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"size should be WIDTHxHEIGHT in pixels, like 640x480, not {text!r}")


def camera(text):
    """``"-90,10,0"`` -> ``[-90.0, 10.0, 0.0]``, for --camera AZ,EL,DIST."""
    try:
        values = [float(v) for v in text.split(",")]
        if len(values) == 3:
            return values
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"camera should be AZ,EL,DIST such as -90,10,0, not {text!r}")


def add_forbid(parser):
    """--forbid KEY..., repeatable: ``--forbid a b --forbid c``."""
    parser.add_argument("--forbid", metavar="KEY", nargs="+", action="extend", default=[],
                        help="motions no path may use (repeatable: --forbid a b --forbid c)")
