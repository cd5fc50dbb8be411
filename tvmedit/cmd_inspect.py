"""Inspect a library's parse on a timeline, correct it by hand and rebuild it at once.

The window shows the source frame under the playhead in 3D and, under it, the sequence's
timeline: the atom-distance curve d_A(t, t_first) of the paper's Figure 4, the motion
clusters as bands with each cluster's representative texton highlighted in yellow, texton
starts as ticks (as tall as the parser's confidence where it gives one), cluster boundaries
(orange where drawn by hand, red ghosts where removed by hand) and the playhead.

  left / right     one frame            up / down     one second
  home / end       first / last frame   pgup / pgdn   previous / next cluster
  click, drag      scrub the timeline   drag above    orbit     scroll   zoom
  B                add a cluster boundary at the playhead
  T                add a texton start at the playhead
  D, Delete        remove the boundary or texton start nearest the playhead
  M                move the boundary or texton start nearest the playhead onto it
  P                force the texton under the playhead as its cluster's representative
  X                drop the motion of the cluster under the playhead
  U                undo                 Tab           next sequence
  Enter            rebuild the library from the corrections (about a second) and show the
                   new graph: motions, transitions, pairs of motions with a path
  S                save the corrections (FILE, default corrections.json)
  C                screenshot (tvmedit-screenshot-<n>.png)     R  reset camera   Esc, Q  quit

Edits are applied to the timeline at once; one the corrections refuse (a texton shorter
than the atom window) is undone and said. Enter replaces LIB (or writes --out); the saved
file is what `tvmedit correct LIB FILE` or `tvmedit build --corrections FILE` applies.
Needs a display: set DISPLAY, or run under xvfb-run.
"""

import os

from tvmedit.engine.errors import TvmError

from . import options

HELP = "correct a library's parse by hand on a timeline and rebuild it live (window)"


def add_arguments(parser):
    parser.add_argument("library", metavar="LIB", help="library folder made by tvmedit build")
    parser.add_argument("--corrections", metavar="FILE", default="corrections.json",
                        help="corrections file to start from when it exists, and to save to "
                             "(default: corrections.json; otherwise the library's own corrections)")
    parser.add_argument("--out", metavar="OUT", default=None,
                        help="where Enter writes the rebuilt library (default: replace LIB)")
    parser.add_argument("--force", action="store_true",
                        help="let Enter replace an existing library at --out (as tvmedit correct --force)")
    parser.add_argument("--sequence", default=None, help="sequence to show first (default: the first)")
    parser.add_argument("--frame", type=int, default=0, help="frame to put the playhead on first")
    parser.add_argument("--size", metavar="WxH", default="1024x720", type=options.size,
                        help="window size (default 1024x720)")
    parser.add_argument("--seconds", type=options.positive, default=None,
                        help="quit by itself after this many seconds")


def _check_paths(args, library):
    """Refuse at the start what would fail only when the user saves or rebuilds: a corrections
    file that cannot be written, an --out that Enter would not be allowed to replace."""
    import tempfile
    from pathlib import Path

    from tvmedit.engine import safewrite

    path = Path(args.corrections)
    try:
        if path.exists() and not path.is_file():
            raise OSError(0, "it is not a file")
        with tempfile.NamedTemporaryFile(dir=path.parent if str(path.parent) else "."):
            pass
    except OSError as error:
        raise TvmError(f"cannot save corrections to {path} ({error.strerror or error}); give --corrections a "
                       "file in a folder you can write to.") from None
    if args.out is not None and Path(args.out).absolute() != Path(library.path).absolute():
        safewrite.check_target(args.out, "library", force=args.force)   # one sentence, as correct says it


def run(args):
    from tvmedit.engine.store.library import Library

    library = Library.open(args.library)
    _check_paths(args, library)
    shown = library.sequence(args.sequence) if args.sequence is not None else library.sequences[0]
    if not 0 <= args.frame < shown.frames:
        raise TvmError(f"--frame {args.frame} is outside sequence {shown.name}, whose frames are "
                       f"0-{shown.frames - 1}; give one of those.")
    from tvmedit.player.inspect import TIMELINE_SHARE, InspectorApp, InspectorWindow

    InspectorWindow.check_display()

    width, height = args.size
    app = InspectorApp(library, args.corrections, out=args.out, force=args.force or None,
                       aspect=width / (height * (1 - TIMELINE_SHARE)))
    if args.sequence is not None:
        while app.sequence != args.sequence:
            app.next_sequence()
    app.seek(args.frame)
    window = InspectorWindow(app, size=args.size, title=f"tvmedit inspect - {os.path.basename(os.path.normpath(args.library))}")
    window.run(args.seconds)
    return 0
