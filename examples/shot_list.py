"""A shot list: three motions that begin at set times, the last held, exported to shot_list/.

    python examples/shot_list.py [LIB]

LIB defaults to the demo library (demo/gym.tvmlib), built from the synthetic actor the first
time. The first three motions begin at 0, 6 and 14 s and the third plays 3 s before its last
cycle; each leg is planned to last its time to within a frame (tvmedit.engine.graph.timing), or the nearest
time a schedule makes, with a warning.
"""

import sys
import warnings

from tvmedit import Library
from tvmedit.engine.graph.export import export_edit
from tvmedit.demo import demo_library

lib = Library.open(sys.argv[1] if len(sys.argv) > 1 else demo_library())
keys = [node.name for node in lib.nodes[:3]]

with warnings.catch_warnings(record=True) as missed:
    warnings.simplefilter("always")
    edit = lib.edit(keys, at=[0, 6, 14], holds={keys[2]: 3})

for leg, begins in zip(edit.legs, edit.starts):
    what = "hold" if leg.source == leg.target else "leg"
    route = " -> ".join(lib.graph.nodes[n]["name"] for n in leg.path)
    print(f"{begins / edit.fps:5.1f} s  {what:4} {route}: {leg.frames / edit.fps:g} s (asked {leg.asked:g} s)")
for warning in missed:
    print("note:", warning.message)
export_edit(edit, "shot_list", force=True)
print(f"key motions begin at frames {edit.starts}; exported {len(edit.schedule)} frames to shot_list/")
