"""Two motions and back: A, then B, then A again, rendered to there_and_back.mp4.

    python examples/there_and_back.py [LIB]

LIB defaults to the demo library (demo/gym.tvmlib), built from the synthetic actor the first
time. The two motions are the cheapest round trip the motion graph allows.
"""

import sys

from tvmedit import player
from tvmedit import Library, NoPath
from tvmedit.demo import demo_library

lib = Library.open(sys.argv[1] if len(sys.argv) > 1 else demo_library())

trips = []
for a in lib.nodes:
    for b in lib.nodes:
        if a.id != b.id:
            try:
                edit = lib.edit([a.name, b.name, a.name])
            except NoPath:
                continue
            trips.append((max(leg.cost for leg in edit.legs), edit))
cost, edit = min(trips, key=lambda trip: trip[0])

for leg in edit.legs:
    print(" -> ".join(lib.graph.nodes[n]["name"] for n in leg.path), f"cost {leg.cost:.3f}")
print(f"{len(edit.schedule)} frames; worst transition cost {cost:.3f}")
player.render(edit, "there_and_back.mp4", size=(320, 240), progress=False)
print("wrote there_and_back.mp4")
