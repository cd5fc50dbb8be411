"""Find the best paths between key motions and print the edited sequence's schedule.

KEYs are database motions by id or name (see `tvmedit info`), two or more, in order. Between
each neighbouring pair the path whose largest transition cost is smallest is chosen, and
among those the one with the fewest transitions (eq. 15-16). Each texton is shown whole
before leaving it, and transitions happen as early as that allows (section 8).

Lengths, in seconds at the library's frame rate: --durations 4,6.5 makes each leg (from the
start of one key motion to the start of the next) last that long, --at 0,4,10.5 says when each
key motion begins, and --hold KEY=SECONDS keeps a key motion looping that long once it begins.
The planner picks the path and how many extra cycles each texton loops (whole textons, every
frame shown before leaving) so that each leg lasts the time to within one frame, the least
costly such path first (eq. 15), then the fewest transitions (eq. 16), then loops spread
evenly. Where no schedule comes within a frame, the leg lasts the nearest time one makes and a
warning names it, asked and achieved; --strict makes that an error (exit 3). A leg that comes
out a frame short or long does not shift the later key motions: their times are kept. The
last key motion still plays --loops cycles.

--json prints {"legs": [{"from", "to", "path", "cost", "edges", "frames", "asked_s",
"achieved_s"}], "key_starts": [frame each key motion begins at], "fps", "schedule": [{"node",
"sequence", "frame"}, with "blend": [[from, to], i] on in-between frames and [[n, n], i] on
a loop's closing frames], "transitions":
[...]} with node ids as in `tvmedit info --json`; a leg
asked a length also has "goal_frames" and "loops" (extra cycles of each motion on its path).
An unknown motion is refused with the list of known names; an unreachable pair exits with
status 3 and says at which --mu a path would exist.

--wander SECONDS plays a walk in place of key motions: each motion loops about as many cycles
as the capture shows (at most a few seconds), then a transition is drawn, cheap ones likeliest
(--temperature), toward the motions played least, never the one taken the last time the motion
was left. --seed makes it reproducible, --only and --forbid keep it to some motions; a KEY, if
given, is where it starts. Its JSON is the same, one leg per transition.
"""

import json

from . import options

HELP = "best paths between key motions and the frame schedule of the edit"


def add_edit_arguments(parser):
    """LIB, KEY..., --forbid and --loops, shared by path, export and render."""
    parser.add_argument("library", metavar="LIB", help="library directory made by tvmedit build")
    parser.add_argument("keys", metavar="KEY", nargs="*", help="key motions, by id or name, in order")
    options.add_forbid(parser)
    parser.add_argument("--loops", type=options.cycles, default=1, metavar="N",
                        help="cycles of the last key motion (default 1)")
    options.add_timing(parser)
    options.add_wander(parser)


def add_arguments(parser):
    add_edit_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print legs and schedule as JSON")


def open_edit(args):
    """Open the library and compose the edit the arguments describe."""
    from tvmedit.engine.store.library import Library

    options.check_wander(args)
    timing = {} if args.wander else options.check_timing(args)
    library = Library.open(args.library)
    return library, options.edit_of(library, args, timing)


def run(args):
    library, edit = open_edit(args)
    if args.json:
        print(json.dumps(edit.to_json()))
        return 0
    graph = library.graph
    name = lambda node: graph.nodes[node]["name"]  # noqa: E731
    fps = edit.fps
    for leg in edit.legs:
        route = " -> ".join(name(n) for n in leg.path)
        asked = "" if leg.asked is None else f" = {round(leg.frames / fps, 2):g} s, asked {leg.asked:g} s"
        if leg.asked is not None and leg.goal != round(leg.asked * fps):
            asked += f", {round(leg.goal / fps, 2):g} s to keep time"
        what = f"hold {name(leg.source)}" if leg.source == leg.target else f"{name(leg.source)} -> {name(leg.target)}"
        print(f"{what}: {route}  "
              f"(cost {leg.cost:.3f}, {leg.edges} transition{'s' * (leg.edges != 1)}, {leg.frames} frames{asked})")
    print(f"schedule: {len(edit.schedule)} frames ({len(edit.schedule) / fps:.1f} s at {fps:g} fps)")
    runs, previous = [], None
    for entry in edit.schedule:
        # A loop's closing frame ([[n, n], i], tvmedit.engine.inbetween.loops) stands for its texton frame.
        transit = entry.blend is not None and entry.blend[0][0] != entry.blend[0][1]
        if (entry.node, transit) != previous:
            runs.append([entry.node, entry.sequence, [entry.frame], entry.blend if transit else None])
            previous = (entry.node, transit)
        else:
            runs[-1][2].append(entry.frame)
    for node, sequence, frames, blend in runs:
        if blend is None:
            print(f"  {name(node):>16}  {sequence} frames {_ranges(frames)}")
        else:
            print(f"  {'':>16}  {len(frames)} in-between frame{'s' * (len(frames) != 1)} "
                  f"warped from {sequence} frame {frames[0]}")
    return 0


def _ranges(frames):
    """'14-15,10-13' for [14, 15, 10, 11, 12, 13]: consecutive runs of a cyclic play; a run
    repeated, as a looping texton's, is written once with its count (``10-13 (x500)``).

    >>> _ranges([14, 15, 10, 11, 12, 13] + [10, 11, 12, 13] * 3)
    '14-15,10-13 (x4)'
    """
    parts, first = [], frames[0]
    for a, b in zip(frames, frames[1:] + [None]):
        if b != a + 1:
            parts.append(f"{first}-{a}" if a != first else f"{a}")
            first = b
    grouped = []
    for part in parts:
        if grouped and grouped[-1][0] == part:
            grouped[-1][1] += 1
        else:
            grouped.append([part, 1])
    return ",".join(part if count == 1 else f"{part} (x{count})" for part, count in grouped)