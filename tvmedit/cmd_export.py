"""Export an edit as a new TVM sequence: binary PLY frames with vertex colours and edit.json.

The schedule is the one `tvmedit path` prints for the same arguments. OUT is a new folder
holding frame_00000.ply, ...; edit.json gives for each output frame its source sequence,
frame and file, and for each transition its edge and weight. The folder loads back with
`tvmedit check OUT` and any mesh tool.
"""

HELP = "write an edit as a new TVM sequence (PLY frames + edit.json)"


def add_arguments(parser):
    from .cmd_path import add_edit_arguments

    add_edit_arguments(parser)
    parser.add_argument("-o", "--out", required=True, metavar="DIR", help="folder to create")
    parser.add_argument("--force", action="store_true", help="replace DIR if it exists")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def run(args):
    from tvmedit.engine.graph.export import export_edit

    from .cmd_path import open_edit

    _, edit = open_edit(args)
    record = export_edit(edit, args.out, force=args.force, progress=not args.quiet)
    transitions = len(record["transitions"])
    print(f"wrote {len(record['frames'])} frames and edit.json to {args.out.rstrip('/')}/ "
          f"({transitions} transition{'s' * (transitions != 1)})")
    return 0
