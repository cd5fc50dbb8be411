"""``make demo``: the main job end to end on the built-in synthetic data set.

Generates the ``gym`` preset of the synthetic capture actor into ``demo/gym`` (once; a
complete folder is reused) and prints what it made.
"""

import json
import sys
import time
from pathlib import Path

DEMO = Path("demo")


def main():
    from engine.synth import generate

    start = time.perf_counter()
    data = DEMO / "gym"
    if (data / "truth.json").exists():
        truth = json.loads((data / "truth.json").read_text())
        print(f"using the gym data set already in {data}/")
    else:
        print(f"generating the built-in gym data set into {data}/ ...")
        truth = generate(data, preset="gym", overwrite=True)
    counts = truth.get("vertex_counts") or []
    print(f"  {truth['frames']} frames at {truth['fps']:g} fps, "
          + (f"{min(counts)}..{max(counts)} vertices per frame, " if counts else "")
          + f"{len(truth['segments'])} segments:")
    for segment in truth["segments"]:
        print(f"    {segment['start']:4d}-{segment['end']:4d}  {segment['label']}")
    print(f"done in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
