"""Play a library in a window and steer it with the keyboard.

The first key motion (or the library's first motion) loops until you queue another: keys
1-9, 0, then a, b, ... (q, r and s are commands) queue motions in the order `tvmedit info`
lists them, and the player follows the best path there, finishing each motion texton before
it leaves it (section 8). The legend on screen lists every motion with its key; motions the
forbidden ones cut off are greyed out. A library built with the default --connect auto lets
every motion reach every other, so no other key is ever refused; a key for the motion already
playing, or already last in the queue, is ignored.

  Shift+key        queue the motion held: it loops --hold-seconds (default 3) once it
                   begins, before the path to what is queued next ("next in" counts it)
  Backspace        remove the last queued motion
  Space            pause / resume
  arrows, drag     orbit the camera     scroll, + / -   zoom      R   reset the camera
  S                save a screenshot (tvmedit-screenshot-<n>.png in the current folder)
  Esc, Q           quit

Playback runs at the library's frame rate on its own clock; the window redraws at the
display rate in between, and the body moves at the redraw's rate too: each redraw shows it
at its own instant between the frame on screen and the next, from the display-rate
in-betweens the library holds (--no-smooth shows each stored frame until the next, the
capture as it is; a library built before them plays so, and the player says how to rebuild). With --log every displayed sequence frame is written as one JSON
line, {"t", "node", "sequence", "frame", "queue"} (t in seconds since start, node ids as in
`tvmedit info --json`; an in-between frame also has "blend": [[from, to], i], a frame of
a loop's closing "blend": [[n, n], i]). Lines with an "event" key are not frames: "start" (first line),
"queued" (with "hold" in seconds for Shift+key), "unqueued" and "refused" (with the queue
after the key press), and "stop" (last line, with the redraw rate); skip them to read frames
only.
The first motion played is the first key motion, or the first motion that is not forbidden.
Needs a display: set DISPLAY, or run under xvfb-run; for video files use `tvmedit render`.
"""

import os
import sys
import time

from tvmedit.engine.errors import TvmError

from . import options

HELP = "play a library in a window, queueing key motions from the keyboard"

# The player's times count from here: as close to process start as a command gets.
_CLOCK_ZERO = time.perf_counter()
_WALL_ZERO = time.time()


def add_arguments(parser):
    parser.add_argument("library", metavar="LIB", help="library folder made by tvmedit build")
    parser.add_argument("keys", metavar="KEY", nargs="*",
                        help="key motions (id or name) to queue at the start; the first one plays first")
    options.add_forbid(parser)
    parser.add_argument("--size", metavar="WxH", default="960x720", type=options.size, help="window size (default 960x720)")
    parser.add_argument("--fps", type=float, default=None,
                        help="playback rate, frames per second (default: the library's)")
    parser.add_argument("--log", metavar="FILE.jsonl", default=None,
                        help="write one JSON line per displayed sequence frame")
    parser.add_argument("--seconds", type=options.positive, default=None,
                        help="quit by itself after this many seconds")
    parser.add_argument("--stats", action="store_true", help="print frame and redraw rates on exit")
    parser.add_argument("--hold-seconds", type=options.hold_seconds, default=3.0, metavar="N",
                        help="how long Shift+key holds a motion once it begins (default 3)")
    options.add_shading(parser)
    options.add_smooth(parser)
    options.add_wander(parser, length=False)


def run(args):
    from tvmedit.engine.store.library import Library

    if args.fps is not None and not 0 < args.fps <= 240:
        raise TvmError(f"The playback rate must be above 0 and at most 240 fps, not {args.fps:g}.")
    if args.seconds is not None and args.seconds <= 0:
        raise TvmError(f"--seconds must be positive, not {args.seconds:g}.")
    library = Library.open(args.library)
    graph = library.graph
    keys = [library.node(key).id for key in args.keys]
    forbidden = [library.node(key).id for key in args.forbid]
    for node in keys:
        if node in forbidden:
            raise TvmError(f"Motion {node} is both a key motion and forbidden; drop it from one of them.")
    order = [node.id for node in library.nodes]     # the order of `tvmedit info`
    allowed = [node for node in order if node not in forbidden]
    if not order:
        raise TvmError(f"library {args.library} has no motions; rebuild it from sequences with frames "
                       "(tvmedit build --help).")
    if not allowed:
        raise TvmError("Every motion of the library is forbidden; forbid fewer.")
    if args.shading == "texture" and not library.textured:
        raise TvmError(f"library {args.library} has no textures (its frames were vertex-coloured); "
                       "drop --shading texture.")
    options.check_wander(args, many_keys=True)
    walker = None
    if args.wander:
        walker = library.wander(seed=args.seed, only=args.only, forbid=args.forbid, temperature=args.temperature,
                                start=keys[0] if keys else None).walker()
    start = keys[0] if keys else (walker.first() if walker else allowed[0])
    fps = args.fps or library.sequence(graph.nodes[start]["sequence"]).fps
    from tvmedit.player.app import PlayerApp
    from tvmedit.player.window import Window

    Window.check_display()

    try:
        log = open(args.log, "w", encoding="utf-8") if args.log else None
    except OSError as error:
        raise TvmError(f"cannot write the log {args.log} ({error.strerror}); "
                       "give a path in a folder that exists.") from None
    try:
        app = PlayerApp(graph, library, order, start, fps=fps, forbidden=forbidden,
                        aspect=args.size[0] / args.size[1], log=log, clock_zero=_CLOCK_ZERO,
                        shading=args.shading, hold_seconds=args.hold_seconds, walker=walker,
                        smooth=args.smooth)
        note = options.smooth_note(library, args, float("inf"), fps).strip()
        if note:
            print(note, file=sys.stderr)
        app.write_header(_WALL_ZERO, library=str(args.library))
        for node in keys[1:]:
            app.queue(node, time.perf_counter())
        window = Window(app, size=args.size, title=f"tvmedit - {os.path.basename(os.path.normpath(args.library))}",
                        clock=time.perf_counter)
        try:
            window.run(args.seconds)
        finally:
            # Also when ended by SIGTERM or Ctrl-C, which unwind through here.
            if args.stats and window.elapsed is not None:
                print(f"{app.frames_shown} sequence frames and {window.redraws} redraws in {window.elapsed:.1f} s: "
                      f"{window.redraws / max(window.elapsed, 1e-9):.1f} redraws per second", file=sys.stderr)
    finally:
        if log is not None:
            log.close()
    return 0
