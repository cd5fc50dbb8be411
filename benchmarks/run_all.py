"""Print every figure the README quotes, one benchmark after another: ``make bench``.

Each benchmark measures against a peer or a limit in the same run (ratios), so the figures
mean the same on a faster or slower machine. Run them on a quiet machine: on 2 cores any
other load shows up in wall-clock times.

    python benchmarks/run_all.py [NAME ...]     # default: all, in this order
"""

import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
BENCHMARKS = ["accuracy", "bin_sizes", "analysis_speed", "synth_speed", "build_speed", "search_speed",
              "connect_speed", "timing_speed", "correct_speed", "blend_quality",
              "display_rate", "render_speed", "player_pacing", "read_speed", "export_speed"]


def main(names):
    failed = []
    for name in names or BENCHMARKS:
        script = HERE / f"{name}.py"
        if not script.exists():
            print(f"== {name}: missing ({script.name})")
            failed.append(name)
            continue
        print(f"== {name}", flush=True)
        start = time.perf_counter()
        result = subprocess.run([sys.executable, str(script)])
        print(f"   ({time.perf_counter() - start:.0f} s)\n", flush=True)
        if result.returncode:
            failed.append(name)
    if failed:
        print("failed or missing:", ", ".join(failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
