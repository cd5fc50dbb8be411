"""``make demo``: the main job end to end on the built-in synthetic data set.

1. generate the ``gym`` preset of the synthetic capture actor into ``demo/gym`` (reused
   when complete),
2. build it into the library ``demo/gym.tvmlib`` (reused when up to date),
3. compose an edit through three key motions,
4. render ``demo/out.mp4`` and a contact sheet of the first key motion,
5. write the report of the library to ``demo/report/index.html``,

printing what it did, where the files are, and how long it took.
"""

import itertools
import json
import sys
import time
from pathlib import Path

DEMO = Path("demo")


def demo_data(root=DEMO, progress=True):
    """The gym data set of the synthetic actor in ``root/gym``, generated the first time."""
    from tvmedit.engine.lab.synth import generate

    data = Path(root) / "gym"
    if not (data / "truth.json").exists():
        generate(data, preset="gym", overwrite=True, progress=progress)
    return data


def demo_library(root=DEMO, progress=True):
    """Path of the demo library ``root/gym.tvmlib``, generating and building it if needed.

    Example scripts call this so that they run on a fresh checkout.
    """
    from tvmedit import engine

    data = demo_data(root, progress)
    out = Path(root) / "gym.tvmlib"
    # Rebuild when the data or the analysis code is newer than the library; features come
    # from the cache, so a rebuild after a code change takes seconds.
    newest = max(p.stat().st_mtime for p in [data / "truth.json", *Path(engine.__file__).parent.rglob("*.py")])
    try:
        engine.Library.open(out)
        if (out / "manifest.json").stat().st_mtime > newest:
            return out
    except engine.TvmError:
        pass
    engine.build([("gym", data)], out, force=True, progress=progress)
    return out


def three_keys(library):
    """Three distinct key motions with a path between each neighbouring pair, cheapest first."""
    from tvmedit.engine.errors import NoPath

    best = None
    for keys in itertools.permutations([n.id for n in library.nodes], 3):
        try:
            edit = library.edit(list(keys))
        except NoPath:
            continue
        cost = max(leg.cost for leg in edit.legs)
        if best is None or cost < best[0]:
            best = (cost, list(keys))
    if best is None:
        raise SystemExit("the demo library has no three mutually reachable motions; "
                         "rebuild it with a larger --mu")
    return best[1]


def main():
    from tvmedit import engine
    from tvmedit import player
    from tvmedit.player.report import write_report

    start = time.perf_counter()
    print("1. data: the synthetic actor's gym take (six exercises)")
    data = demo_data()
    truth = json.loads((data / "truth.json").read_text())
    counts = truth["vertex_counts"]
    print(f"   {data}/: {truth['frames']} frames at {truth['fps']:g} fps, "
          f"{min(counts)}..{max(counts)} vertices per frame; true segments: "
          + ", ".join(f"{s['label']} {s['start']}-{s['end']}" for s in truth["segments"]))

    print("2. library: features, motion structure, database, motion graph")
    library = engine.Library.open(demo_library())
    info = library.info()
    seq = info["sequences"][0]
    ranges = ", ".join(f"{c['start']}-{c['end']}" for c in seq["clusters"])
    print(f"   {library.path}/: {len(seq['clusters'])} clusters ({ranges}), "
          f"{len(seq['textons'])} textons, {len(info['nodes'])} database motions, "
          f"{len(info['edges'])} transitions")

    print("3. edit through three key motions")
    keys = three_keys(library)
    edit = library.edit(keys)
    name = lambda node: library.graph.nodes[node]["name"]  # noqa: E731
    for leg in edit.legs:
        print(f"   {' -> '.join(name(n) for n in leg.path)}: cost {leg.cost:.3f}, "
              f"{leg.edges} transition(s), {leg.frames} frames")
    print(f"   {len(edit.schedule)} frames = {len(edit.schedule) / library.sequences[0].fps:.1f} s")

    print("4. render (headless EGL)")
    # The demo's own outputs: a second run replaces them (as its build does).
    video = player.render(edit, DEMO / "out.mp4", size=(640, 480), fps=library.sequences[0].fps,
                          orbit_deg_per_s=10, force=True)
    first = library.node(keys[0])
    sheet = DEMO / f"sheet-{first.name.replace('/', '-')}.png"
    frames = range(first.start, first.end + 1)
    player.contact_sheet(library, [(first.sequence, f) for f in frames], sheet,
                         labels=[f"{first.name} {f}" for f in frames], force=True)
    print(f"   {video}  (the edit)\n   {sheet}  (contact sheet of {first.name})")

    print("5. report")
    index = write_report(library, DEMO / "report", progress=False, force=True)
    print(f"   {index}")
    print(f"done in {time.perf_counter() - start:.1f} s. Next, with a display: "
          f".venv/bin/tvmedit play {library.path}  (or `source .venv/bin/activate` first, "
          "then plain `tvmedit ...`)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
