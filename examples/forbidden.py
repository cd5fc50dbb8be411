"""Forbidden motions: find an edit whose best path passes through a third motion, forbid that
motion, and compare the detour (or the reason there is none).

    python examples/forbidden.py [LIB]
"""

import sys

from tvmedit import Library, NoPath
from tvmedit.demo import demo_library

lib = Library.open(sys.argv[1] if len(sys.argv) > 1 else demo_library())
name = lambda node: lib.graph.nodes[node]["name"]  # noqa: E731

for a in lib.nodes:
    for b in lib.nodes:
        try:
            edit = lib.edit([a.name, b.name])
        except NoPath:
            continue
        path = edit.legs[0].path
        if len(path) > 2:
            via = path[1]
            print(f"{a.name} -> {b.name}: {' -> '.join(map(name, path))} (cost {edit.legs[0].cost:.3f})")
            try:
                detour = lib.edit([a.name, b.name], forbid=[name(via)])
                print(f"forbidding {name(via)}: {' -> '.join(map(name, detour.legs[0].path))} "
                      f"(cost {detour.legs[0].cost:.3f})")
            except NoPath as error:
                print(f"forbidding {name(via)}: {error}")
            sys.exit(0)
print("every best path in this library is a single transition; nothing to forbid")
