"""Frame pacing of the realtime player under Xvfb, against its 100 ms slots and a 60 Hz redraw.

    .venv/bin/python benchmarks/player_pacing.py [--seconds 30] [--size 960x720]

Plays a library of the synthetic actor (the gym preset at three cycles a motion and about
17,000 vertices a frame, generated and built once into ``.cache/testdata``) with
``tvmedit play --log --stats`` on an Xvfb display started here, queueing motions and orbiting
the camera with xdotool while it plays, and reads the log back:

* pacing: how far each displayed sequence frame lands from its slot, ``t0 + k / fps``
  (median, p95 and max of |deviation|; target within +/-5 ms);
* start-up: from spawning the process to the first frame on screen (target < 1 s);
* redraw rate: window redraws per second over the run (target >= 60 Hz), and the player's
  CPU milliseconds per redraw, the steadier figure on a shared machine (llvmpipe draws on
  the CPU).

Run it on a quiet machine: on 2 shared cores any other load shows up in all three.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from conftest import CACHE, synth_take  # noqa: E402  (the tests' generator and cache)

SLOT_TOLERANCE_S = 0.005
START_LIMIT_S = 1.0
REDRAW_TARGET_HZ = 60.0


def library():
    """The benchmark library: built once, keyed by its take (rebuild by deleting the folder)."""
    from tvmedit import engine

    take = synth_take("gym", cycles=3, vertices=17000)
    out = CACHE / f"library-{take.name}"
    if not (out / "manifest.json").exists():
        print(f"building {out.name} ...", flush=True)
        engine.build([str(take)], out, workers=2, cache=False, force=True)
    return out


def start_xvfb():
    for n in range(90, 140):
        if Path(f"/tmp/.X{n}-lock").exists() or Path(f"/tmp/.X11-unix/X{n}").exists():
            continue
        server = subprocess.Popen(["Xvfb", f":{n}", "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(200):
            if server.poll() is not None or Path(f"/tmp/.X11-unix/X{n}").exists():
                break
            time.sleep(0.05)
        if server.poll() is None:
            return server, f":{n}"
    raise SystemExit("no free X display number between :90 and :139")


def tour(graph):
    """A start motion and the motions reachable from it, to queue in turn while playing."""
    import networkx as nx

    start = max(graph, key=lambda node: (len(nx.descendants(graph, node)), -node))
    return start, sorted(nx.descendants(graph, start) | {start})


def drive(env, keys, seconds):
    """Queue motions in turn and orbit the camera (arrow key held) while the player runs."""
    window = subprocess.run(["xdotool", "search", "--sync", "--name", "tvmedit"], env=env,
                            capture_output=True, text=True, timeout=30).stdout.split()[0]
    subprocess.run(["xdotool", "windowfocus", "--sync", window], env=env, timeout=10)
    started = time.monotonic()
    step = 0
    while time.monotonic() - started < seconds - 4:
        xdotool = ["xdotool", "key", "--window", window, keys[(step + 1) % len(keys)]]
        subprocess.run(xdotool, env=env, capture_output=True, timeout=10)
        subprocess.run(["xdotool", "keydown", "--window", window, "Left"], env=env, capture_output=True, timeout=10)
        time.sleep(2.0)
        subprocess.run(["xdotool", "keyup", "--window", window, "Left"], env=env, capture_output=True, timeout=10)
        time.sleep(2.0)
        step += 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--size", default="960x720")
    parser.add_argument("--keep-log", metavar="FILE", help="copy the player's --log here")
    args = parser.parse_args()
    missing = [tool for tool in ("Xvfb", "xdotool") if shutil.which(tool) is None]
    if missing:
        print(f"skipped: {' and '.join(missing)} not installed (apt-get install xvfb xdotool)")
        return 0

    from tvmedit.engine.store.library import Library
    from tvmedit.player.window import motion_keys

    lib_path = library()
    lib = Library.open(lib_path)
    vertices, faces = lib.max_counts()
    server, display = start_xvfb()
    env = {**os.environ, "DISPLAY": display, "PYTHONPATH": str(ROOT)}
    with tempfile.TemporaryDirectory() as tmp:
        log_path = Path(tmp) / "play.jsonl"
        spawned = time.time()
        start, reachable = tour(lib.graph)
        order = [node.id for node in lib.nodes]
        keys = [motion_keys(len(order))[order.index(node)] for node in reachable]
        player = subprocess.Popen([sys.executable, "-m", "tvmedit", "play", str(lib_path), str(start),
                                   "--log", str(log_path),
                                   "--seconds", str(args.seconds + 2), "--size", args.size, "--stats"],
                                  env=env, cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            drive(env, keys, args.seconds)
            out, err = player.communicate(timeout=args.seconds + 60)
        finally:
            if player.poll() is None:
                player.kill()
            server.terminate()
            server.wait()
        rows = [json.loads(line) for line in log_path.read_text().splitlines()]
        if args.keep_log:
            shutil.copy(log_path, args.keep_log)
    if player.returncode:
        print(err)
        return 1

    header, footer = rows[0], rows[-1]
    frames = [row for row in rows if "event" not in row]
    t = np.array([row["t"] for row in frames])
    first = t[0]
    t = t[(t >= first) & (t < first + args.seconds)]
    fps = header["fps"]
    deviation = np.abs(t - (t[0] + np.arange(len(t)) / fps))
    startup = header["wall"] + first - spawned
    redraw_hz = footer["redraw_hz"]
    cpu_ms = 1000 * footer["cpu_s"] / footer["redraws"]
    transitions = sum(1 for a, b in zip(frames, frames[1:]) if a["node"] != b["node"])
    refused = sum(1 for row in rows if row.get("event") == "refused")

    print(f"library: {lib_path.name}, {len(lib.nodes)} motions, up to {vertices} vertices and {faces} "
          f"triangles a frame; window {args.size}; {len(t)} sequence frames at {fps:g} fps, "
          f"{transitions} transitions, {refused} keys refused")
    print(f"pacing: |deviation from the {1000 / fps:.0f} ms slots| median {1000 * np.median(deviation):.1f} ms, "
          f"p95 {1000 * np.percentile(deviation, 95):.1f} ms, max {1000 * deviation.max():.1f} ms; "
          f"{np.sum(deviation <= SLOT_TOLERANCE_S)} of {len(deviation)} frames within "
          f"+/-{1000 * SLOT_TOLERANCE_S:.0f} ms ({'met' if deviation.max() <= SLOT_TOLERANCE_S else 'NOT met'} "
          f"for every frame)")
    print(f"start-up: first frame {startup:.2f} s after spawning the process, {first:.2f} s after the command "
          f"began (limit {START_LIMIT_S:.0f} s: {'met' if startup < START_LIMIT_S else 'NOT met'})")
    print(f"redraws: {redraw_hz:.1f} Hz over the run (target {REDRAW_TARGET_HZ:.0f} Hz: "
          f"{'met' if redraw_hz >= REDRAW_TARGET_HZ else 'NOT met'}); {cpu_ms:.1f} ms of player CPU per redraw, "
          f"{1000 / cpu_ms:.0f} Hz if one core were its own")
    load = os.getloadavg()[0]
    if load > (os.cpu_count() or 1):
        print(f"note: load average {load:.1f} on {os.cpu_count()} cores during the run; figures are pessimistic")
    return 0


if __name__ == "__main__":
    sys.exit(main())
