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
  the CPU);
* motion at the display's rate: with the camera still, screenshots of the window (ffmpeg's
  X11 grab) at up to 100 a second for 1.5 s, and how many times a second the body changes between
  two of them, with the display-rate in-betweens (``--smooth``, target >= 50) and without
  (``--no-smooth``, the capture's 10).

Run it on a quiet machine: on 2 shared cores any other load shows up in all three.
"""

import argparse
import ctypes
import ctypes.util
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
    from tvmedit import Library

    if not (out / "manifest.json").exists() or not Library.open(out).smooth:
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


class _XImage(ctypes.Structure):
    _fields_ = [("width", ctypes.c_int), ("height", ctypes.c_int), ("xoffset", ctypes.c_int),
                ("format", ctypes.c_int), ("data", ctypes.POINTER(ctypes.c_uint8)), ("byte_order", ctypes.c_int),
                ("bitmap_unit", ctypes.c_int), ("bitmap_bit_order", ctypes.c_int), ("bitmap_pad", ctypes.c_int),
                ("depth", ctypes.c_int), ("bytes_per_line", ctypes.c_int), ("bits_per_pixel", ctypes.c_int)]


class Screen:
    """Screenshots of a box of an X display through Xlib's XGetImage (ctypes: no tool to spawn
    per shot, a millisecond or two each)."""

    def __init__(self, display):
        self.x11 = ctypes.cdll.LoadLibrary(ctypes.util.find_library("X11"))
        self.x11.XOpenDisplay.restype = ctypes.c_void_p
        self.x11.XDefaultRootWindow.argtypes = [ctypes.c_void_p]
        self.x11.XDefaultRootWindow.restype = ctypes.c_ulong
        self.x11.XGetImage.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_int, ctypes.c_uint,
                                       ctypes.c_uint, ctypes.c_ulong, ctypes.c_int]
        self.x11.XGetImage.restype = ctypes.POINTER(_XImage)
        self.x11.XFree.argtypes = [ctypes.c_void_p]
        self.display = self.x11.XOpenDisplay(display.encode())
        self.root = self.x11.XDefaultRootWindow(self.display)

    def grab(self, x, y, width, height):
        image = self.x11.XGetImage(self.display, self.root, x, y, width, height, 0xFFFFFFFF, 2)  # ZPixmap
        line = image.contents.bytes_per_line
        pixels = np.ctypeslib.as_array(image.contents.data, shape=(height * line,)).copy()
        self.x11.XFree(image.contents.data)
        self.x11.XFree(image)
        return pixels.reshape(height, line)[:, :width * 4].reshape(height, width, 4)[:, :, :3]


def body_changes(lib_path, start, env, size, smooth, seconds=1.5, rate=100.0):
    """Changes of the body a second between screenshots of a player left alone (camera still),
    and screenshots a second (up to ``rate``): the middle of the window, away from the text on
    screen."""
    player = subprocess.Popen([sys.executable, "-m", "tvmedit", "play", str(lib_path), str(start), "--seconds", "8",
                               "--size", size, "--smooth" if smooth else "--no-smooth"],
                              env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        window = subprocess.run(["xdotool", "search", "--sync", "--name", "tvmedit"], env=env, capture_output=True,
                                text=True, timeout=30).stdout.split()[0]
        geometry = subprocess.run(["xdotool", "getwindowgeometry", "--shell", window], env=env, capture_output=True,
                                  text=True, timeout=10).stdout
        where = dict(line.split("=") for line in geometry.split())
        x, y, width, height = (int(where[k]) for k in ("X", "Y", "WIDTH", "HEIGHT"))
        box = (x + width // 4, y + height // 5, width // 2, height - height // 5 - height // 8)
        screen = Screen(env["DISPLAY"])
        time.sleep(1.5)
        shots, changes, previous = 0, 0, None
        began = time.monotonic()
        while (now := time.monotonic()) - began < seconds:
            shot = screen.grab(*box).astype(np.int16)
            if previous is not None and np.abs(shot - previous).max() > 8:
                changes += 1
            previous, shots = shot, shots + 1
            time.sleep(max(0.0, began + shots / rate - time.monotonic()))
        elapsed = time.monotonic() - began
    finally:
        player.kill()
        player.wait()
    return changes / elapsed, shots / elapsed


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
    from tvmedit.player.app import motion_keys

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
            seen = {smooth: body_changes(lib_path, start, env, args.size, smooth)
                    for smooth in (True, False)}
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
    if True:
        (smooth_hz, smooth_shots), (plain_hz, plain_shots) = seen[True], seen[False]
        print(f"motion: the body changes {smooth_hz:.0f} times a second between screenshots with the display-rate "
              f"in-betweens ({smooth_shots:.0f} screenshots a second; target 50: "
              f"{'met' if smooth_hz >= 50 else 'NOT met'}), {plain_hz:.0f} without (--no-smooth, "
              f"{plain_shots:.0f} screenshots a second)")
    load = os.getloadavg()[0]
    if load > (os.cpu_count() or 1):
        print(f"note: load average {load:.1f} on {os.cpu_count()} cores during the run; figures are pessimistic")
    return 0


if __name__ == "__main__":
    sys.exit(main())
