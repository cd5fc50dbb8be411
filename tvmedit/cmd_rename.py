"""Give a motion of a library a readable name, used by edits and the player from then on.

NODE is the motion's id or current name (see ``tvmedit info LIB``). Names are unique, and
a name of digits alone is refused because digits are read as an id. The name is stored in
the library at once (``names.json``); the analysis is not touched.
"""

HELP = "give a motion of a library a readable name"


def add_arguments(parser):
    parser.add_argument("library", metavar="LIB", help="library directory")
    parser.add_argument("node", metavar="NODE", help="the motion's id or current name")
    parser.add_argument("name", metavar="NAME", help="its new name")


def run(args):
    from tvmedit.engine.store.library import Library

    library = Library.open(args.library)
    before = library.node(args.node)
    after = library.rename(before.id, args.name)
    print(f"motion {after.id} ({after.sequence} {after.start}-{after.end}) is now {after.name!r} "
          f"(was {before.name!r})")
    return 0
