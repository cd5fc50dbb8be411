"""Render an edit headless (EGL, no display needed) to video, GIF or PNG frames, or a texton's contact sheet.

The schedule is the one `tvmedit path` prints for the same KEYs. OUT's suffix picks the
output: .mp4 (H.264), .gif, or no suffix for a folder of PNG frames. With --node, OUT is a
contact sheet PNG of that motion's texton (what you look at when choosing key motions).

The camera frames the person automatically; --camera AZ,EL,DIST sets azimuth and elevation
in degrees and distance in metres (0 keeps the automatic distance), --orbit turns it
slowly during playback. With --node, --size is the size of each tile and --orbit, --fps,
--loops and the lengths do not apply. A sheet shows at most 24 tiles of 160x120, 8 a row; of
a textured capture at most 12 tiles of 640x480, 4 a row, large enough to read print on a
held card. A longer motion (a one-shot stretch of a real capture) is shown by frames spread
evenly over it, each labelled with its frame number.

--durations, --at and --hold set how long the legs last, as for `tvmedit path`; the video
lasts as long as that schedule plays. --fps N writes N frames a second of it (MP4 at 30 or 60
from a 10 fps capture): each output frame shows the body at its own instant, between two
stored frames, from the display-rate in-betweens the library holds (--no-smooth holds each
stored frame instead, the capture as it is; a library built before them does so too).
"""

import dataclasses


from . import options

HELP = "render an edit to MP4/GIF/PNG frames, or a motion's contact sheet"


def add_arguments(parser):
    parser.add_argument("library", metavar="LIB", help="library directory made by tvmedit build")
    parser.add_argument("keys", metavar="KEY", nargs="*", help="key motions, by id or name, in order")
    parser.add_argument("-o", "--out", required=True, metavar="OUT",
                        help="OUT.mp4, OUT.gif, a folder for PNG frames, or with --node a .png sheet")
    parser.add_argument("--node", metavar="NAME", help="render a contact sheet of this motion's texton")
    options.add_forbid(parser)
    parser.add_argument("--loops", type=options.cycles, default=1, metavar="N",
                        help="cycles of the last key motion (default 1)")
    options.add_timing(parser)
    options.add_wander(parser)
    parser.add_argument("--size", type=options.size, default=None, metavar="WxH",
                        help="frame size (default 640x480); with --node the size of each tile "
                             "(default 160x120; 640x480 for a textured capture)")
    parser.add_argument("--camera", type=options.camera, metavar="AZ,EL,DIST",
                        help="camera azimuth, elevation (degrees) and distance (m; 0 = automatic)")
    parser.add_argument("--orbit", type=options.finite, default=0.0, metavar="DEG_PER_S",
                        help="turn the camera this many degrees per second (free viewpoint)")
    parser.add_argument("--fps", type=options.positive, default=None,
                        help="output frame rate (default: the library's); the edit's timing is kept")
    options.add_smooth(parser)
    parser.add_argument("--grid", action="store_true", help="draw a floor grid")
    options.add_shading(parser)
    parser.add_argument("--force", action="store_true",
                        help="replace OUT if it is a video, GIF, PNG or frame folder tvmedit could have written")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def camera_for(library, size, camera_arg, orbit=0.0, bounds=None):
    """The automatic framing, with --camera's angles and distance applied."""
    from tvmedit.player.camera import Camera

    azimuth, elevation, distance = camera_arg or (-90.0, 10.0, 0.0)
    camera = Camera.framing(bounds or library.bounds(), size[0] / size[1], azimuth=azimuth,
                            elevation=elevation, all_azimuths=bool(orbit))
    return dataclasses.replace(camera, distance=distance) if distance > 0 else camera


#: A contact sheet's most tiles, tiles a row and tile size: vertex-coloured, textured.
SHEET_PLAIN = (24, 8, (160, 120))
SHEET_TEXTURED = (12, 4, (640, 480))


def run(args):
    import numpy as np

    from tvmedit.engine.errors import TvmError
    from tvmedit.engine.store.library import Library
    from tvmedit import player
    from tvmedit.engine.inbetween.instants import instants

    options.check_wander(args)
    timing = options.check_timing(args) if args.node is None and len(args.keys) >= 2 and not args.wander else {}
    library = Library.open(args.library)
    try:
        if args.node is not None:
            if not args.out.lower().endswith(".png"):
                raise TvmError(f"a contact sheet is a PNG image: name it like sheet.png, not {args.out}.")
            node = library.node(args.node)
            most, columns, tile = SHEET_TEXTURED if library.textured else SHEET_PLAIN
            frames = player.spread_frames(node.start, node.end, most)
            keys = [(node.sequence, f) for f in frames]
            labels = [f"{node.name} {f}" for f in frames]
            tile = args.size or tile
            camera = None
            if args.camera:
                # Framed on this motion's frames, as the automatic camera of a sheet is.
                points = [library.frame_mesh(key)[0] for key in keys]
                bounds = (np.min([p.min(axis=0) for p in points], axis=0),
                          np.max([p.max(axis=0) for p in points], axis=0))
                camera = camera_for(library, tile, args.camera, bounds=bounds)
            player.contact_sheet(library, keys, args.out, columns=columns, tile=tile, labels=labels, camera=camera,
                                 grid=args.grid, shading=args.shading, force=args.force)
            shown = "" if len(frames) == node.n_frames else f", {len(frames)} of them shown"
            print(f"wrote the contact sheet of {node.name} ({node.n_frames} frames{shown}) to {args.out}")
            return 0
        if len(args.keys) < 2 and not args.wander:
            raise TvmError("give two or more key motions to render an edit, --wander SECONDS for a walk, "
                           "or --node NAME for a contact sheet.")
        edit = options.edit_of(library, args, timing)
        fps = args.fps or edit.fps
        size = args.size or (640, 480)
        camera = camera_for(library, size, args.camera, args.orbit) if args.camera else None
        out = player.render(edit, args.out, size=size, fps=fps, camera=camera,
                            orbit_deg_per_s=args.orbit, progress=not args.quiet, grid=args.grid,
                            shading=args.shading, smooth=args.smooth,
                            force=args.force)
    except (ValueError, FileExistsError) as error:
        raise TvmError(str(error).rstrip(".") + ".") from None
    frames = len(instants(len(edit.schedule), edit.fps or fps, fps))
    seconds = len(edit.schedule) / (edit.fps or fps)
    print(f"wrote {frames} frames ({seconds:.1f} s at {fps:g} fps) to {out}" + options.smooth_note(library, args, fps, edit.fps))
    return 0
