"""Write an HTML report of a built library: what the analysis found, figure by figure.

DIR gets index.html and its PNG figures (open the page in any browser; it needs no server
and no network):

  motion structure   per sequence, the atom distance d_A(t, t_first) with texton starts
                     and cluster bands (the paper's Figure 4); with a truth.json beside the
                     sequence's frames, its segments and the clusters' boundary precision
                     and recall (Figure 5); where the parse was corrected by hand, the
                     automatic clusters above the corrected ones, boundaries drawn by hand
                     in orange and removed ones dotted red; each boundary's confidence
                     (0-1) above it, the least sure (under 0.1) dashed bright red: look
                     there first
  motion database    a contact sheet of every motion (Figure 6) with its length, texton
                     distance and motion intensity
  motion graph       motions with a rendered frame each, transitions labelled with their
                     weights (Figure 7); also graph.png
  transitions        every kept transition by weight, with exit and entry frames side by
                     side for the cheapest and the costliest

An existing report in DIR is replaced only with --force, and only if DIR holds nothing
but what tvmedit wrote there; the new one appears only once it is complete.
Rendering needs EGL; plotting needs matplotlib (pip install 'tvmedit[report]').

example:
  tvmedit report lib -o lib-report
"""

HELP = "write an HTML report of a library: structure, database, graph and transitions"


def add_arguments(parser):
    parser.add_argument("library", metavar="LIB", help="library directory made by tvmedit build")
    parser.add_argument("-o", "--out", metavar="DIR", required=True, help="folder to write the report into")
    parser.add_argument("--force", action="store_true", help="replace a previous report in DIR")
    parser.add_argument("--show-pruned", action="store_true",
                        help="draw the edges pruned by eq. (14) faintly in the motion graph")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress output")


def run(args):
    from tvmedit.engine.store.library import Library
    from tvmedit.player.figures import require_matplotlib
    from tvmedit.player.report import write_report

    require_matplotlib()  # says how to install matplotlib before any work is done
    library = Library.open(args.library)
    index = write_report(library, args.out, show_pruned=args.show_pruned, progress=not args.quiet,
                         force=args.force)
    print(index)
    return 0
