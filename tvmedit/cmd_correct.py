"""Apply corrections by hand to a library's parse and derive its database and graph again.

FILE is a corrections.json (see ``tvmedit.engine.store.corrections``; ``tvmedit inspect`` writes one): per
sequence, cluster boundaries and texton starts to add, remove or move, textons forced as
their cluster's representative, and motions to drop. It replaces the corrections the
library holds. Nothing is recomputed from the frames: features and the automatic parse are
the library's own, and only the frames of a motion the library never stored are read (none
from a library built with --keep-frames all); transitions the correction leaves as they
were keep their in-between frames. The library is replaced atomically (or written to -o
OUT). For example:

  {"sequences": {
    "gym": {"boundaries": {"add": [412], "remove": [118], "move": [[240, 236]]},
            "textons": {"add": [300], "remove": [310], "move": [[150, 152]]},
            "representatives": [305], "drop": ["gym/06"]}
  }}

Frames are 0-based; remove and move act on the boundary or texton start nearest the frame
given (within 0.5 s). An entry that cannot be applied is named in one sentence (exit 2).
"""

import sys

from . import options

HELP = "apply corrections by hand (corrections.json) to a library's parse, recomputing no feature"


def add_arguments(parser):
    parser.add_argument("library", metavar="LIB", help="library directory")
    parser.add_argument("corrections", metavar="FILE", help="corrections.json to apply (replaces the stored ones)")
    parser.add_argument("-o", "--out", metavar="OUT", default=None,
                        help="write the corrected library here instead of replacing LIB")
    parser.add_argument("--force", action="store_true", help="replace OUT if it exists")


def run(args):
    from tvmedit.engine.store.library import Library

    library = Library.open(args.library)
    corrected = library.correct(args.corrections, args.out, force=args.force or None,
                                log=lambda m: print(options.as_flags(m, args._parser), file=sys.stderr))
    report = corrected.report
    print(f"corrected {corrected.path}: {report['clusters']} clusters, {report['nodes']} motions, "
          f"{report['edges']} graph edges; {report['read_frames']} frame file(s) read, "
          f"in {report['seconds']:.2f} s")
    return 0
