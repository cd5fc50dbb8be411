"""Find the best paths between key motions and print the edited sequence's schedule.

KEYs are database motions by id or name (see `tvmedit info`), two or more, in order. Between
each neighbouring pair the path whose largest transition cost is smallest is chosen, and
among those the one with the fewest transitions (eq. 15-16). Each texton is shown whole
before leaving it, and transitions happen as early as that allows (section 8).

--json prints {"legs": [{"from", "to", "path", "cost", "edges", "frames"}], "schedule":
[{"node", "sequence", "frame"}], "transitions": [...]} with node ids as in `tvmedit info
--json`. An unknown motion is refused with the list of known names; an unreachable pair
exits with status 3 and says at which --mu a path would exist.
"""

import json

from . import options

HELP = "best paths between key motions and the frame schedule of the edit"


def add_edit_arguments(parser):
    """LIB, KEY..., --forbid and --loops, shared by path, export and render."""
    parser.add_argument("library", metavar="LIB", help="library directory made by tvmedit build")
    parser.add_argument("keys", metavar="KEY", nargs="+", help="key motions, by id or name, in order")
    options.add_forbid(parser)
    parser.add_argument("--loops", type=options.cycles, default=1, metavar="N",
                        help="cycles of the last key motion (default 1)")


def add_arguments(parser):
    add_edit_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print legs and schedule as JSON")


def open_edit(args):
    """Open the library and compose the edit the arguments describe."""
    from engine.library import Library

    library = Library.open(args.library)
    return library, library.edit(args.keys, forbid=args.forbid, loops=args.loops)


def run(args):
    library, edit = open_edit(args)
    if args.json:
        print(json.dumps(edit.to_json()))
        return 0
    graph = library.graph
    name = lambda node: graph.nodes[node]["name"]  # noqa: E731
    fps = library.sequence(edit.schedule[0].sequence).fps
    for leg in edit.legs:
        route = " -> ".join(name(n) for n in leg.path)
        print(f"{name(leg.source)} -> {name(leg.target)}: {route}  "
              f"(cost {leg.cost:.3f}, {leg.edges} transition{'s' * (leg.edges != 1)}, {leg.frames} frames)")
    print(f"schedule: {len(edit.schedule)} frames ({len(edit.schedule) / fps:.1f} s at {fps:g} fps)")
    runs, previous = [], None
    for entry in edit.schedule:
        if entry.node != previous:
            runs.append([entry.node, entry.sequence, [entry.frame]])
            previous = entry.node
        else:
            runs[-1][2].append(entry.frame)
    for node, sequence, frames in runs:
        print(f"  {name(node):>16}  {sequence} frames {_ranges(frames)}")
    return 0


def _ranges(frames):
    """'14-15,10-13' for [14, 15, 10, 11, 12, 13]: consecutive runs of a cyclic play."""
    parts, first = [], frames[0]
    for a, b in zip(frames, frames[1:] + [None]):
        if b != a + 1:
            parts.append(f"{first}-{a}" if a != first else f"{a}")
            first = b
    return ",".join(parts)
