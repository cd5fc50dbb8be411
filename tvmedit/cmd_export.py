"""Export an edit as a new TVM sequence, in the format the capture came in, with edit.json.

The schedule is the one `tvmedit path` prints for the same arguments. OUT is a new folder
holding one file (or a mesh and its texture) per output frame, frame_00000.* on, and
edit.json: for each output frame its source sequence, frame and file, and for each
transition its edge and weight. The folder loads back with `tvmedit check OUT` and any mesh
tool.

--format picks what the frames are: ply (binary PLY with vertex colours, tvmedit's axes),
scvv (Draco + a JPG texture per frame + scvv_animation.json, as depth-camera apps export, in
the capture's own coordinates), obj (OBJ + MTL + texture per frame) or glb (a binary
glTF per frame with its texture, Y up). The default is the format the library's first
sequence came in, so a textured capture's edit stays textured. Draco keeps positions to
0.12 mm on a 2 m body and JPG textures at quality 92; a texture that is the capture's own
image (in-between frames move a captured frame) is copied as it came. An edit reorders frames, so a
capture's sound track is not carried over.

--fps N writes N frames a second of the edit, its timing kept: each output frame is the
surface the player shows at that instant, between two stored frames (the library's
display-rate in-betweens; --no-smooth holds each stored frame instead), and edit.json says
for each which schedule frame it shows (schedule_index), and between two, the next one
(next) and how far along (at, 0 to 1).
"""

from . import options

HELP = "write an edit as a new TVM sequence (frames in the capture's format + edit.json)"


def add_arguments(parser):
    from .cmd_path import add_edit_arguments

    add_edit_arguments(parser)
    parser.add_argument("-o", "--out", required=True, metavar="DIR", help="folder to create")
    parser.add_argument("--format", choices=("ply", "scvv", "obj", "glb"), default=None,
                        help="frame format (default: the one the library's first sequence came in)")
    parser.add_argument("--fps", type=options.positive, default=None, metavar="N",
                        help="frames a second to write, the edit's timing kept (default: the library's)")
    options.add_smooth(parser)
    parser.add_argument("--force", action="store_true", help="replace DIR if it exists")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def run(args):
    from tvmedit.engine.graph.export import export_edit, has_sound

    from .cmd_path import open_edit

    library, edit = open_edit(args)
    record = export_edit(edit, args.out, force=args.force, progress=not args.quiet, fmt=args.format,
                         fps=args.fps, smooth=args.smooth)
    transitions = len(record["transitions"])
    fmt = record.get("format", "ply")
    print(f"wrote {len(record['frames'])} frames ({fmt}) and edit.json to {args.out.rstrip('/')}/ "
          f"({transitions} transition{'s' * (transitions != 1)})"
          + (options.smooth_note(library, args, args.fps, record.get("capture_fps")) if args.fps else ""))
    if has_sound(library):
        print("note: the capture's sound track is not in the export: the edit reorders its frames.")
    return 0
