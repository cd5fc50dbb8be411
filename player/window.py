"""The realtime player: a window that plays a library and queues key motions from the keyboard.

Two clocks run side by side (the playback clock is not the render clock). The window redraws
at the display rate, so camera moves stay smooth, while the sequence advances at the
library's frame rate: a sequence frame is due every ``1 / fps`` seconds, and its mesh is
fetched from the library once, when it is first shown; redraws in between pass the same
arrays, which ``Renderer.draw`` recognises and does not upload again. Which
frame comes next is decided by ``tvmedit.engine.graph.compose.Playhead``, the loop-then-transition rule of
section 8: the current texton is shown to its end, then each transition of the best path is
taken as early as the rule allows.

``PlayerApp`` holds everything a user can do (keys -> queue, clock -> frame, camera, the text
on screen, the ``--log``) and runs without a window or GL, so it is tested with a fake clock;
``Window`` is the glfw plumbing around it and the only code here that touches glfw.
"""

import json
import math
import sys
import textwrap
import time
from pathlib import Path

import networkx as nx

from ..engine.playback import Playhead
from ..engine.errors import NoPath, TvmError
from .camera import CameraControls
from .overlay import Label
from .source import check_shading, texture_of

#: Letters that are commands, so they never queue a motion.
COMMAND_LETTERS = "qrs"

#: A stall longer than this (a window drag, a slow disk) restarts the playback clock instead of
#: rushing through the frames it missed.
MAX_LAG_S = 0.25

#: The loop never redraws faster than this when the driver does not wait for vsync (Xvfb,
#: llvmpipe), so the player leaves the CPU to others; a real display's vsync is lower.
MAX_REDRAW_HZ = 100.0

ORBIT_DEG_PER_S = 90.0
TAP_S = 0.1              # a key tapped briefly still turns the camera this long
DRAG_DEG_PER_PIXEL = 0.4
ZOOM_STEP = 1.12
MESSAGE_S = 5.0


def motion_keys(count):
    """Keys that queue the first ``count`` motions: 1-9, 0, then letters except the commands.

    >>> motion_keys(12)
    ['1', '2', '3', '4', '5', '6', '7', '8', '9', '0', 'a', 'b']
    >>> motion_keys(40)[-1], len(motion_keys(40))
    ('z', 33)
    """
    keys = [str(d) for d in range(1, 10)] + ["0"]
    keys += [c for c in "abcdefghijklmnopqrstuvwxyz" if c not in COMMAND_LETTERS]
    return keys[:count]


class PlayerApp(CameraControls):
    """Player state and logic, with no window: what each key does and when frames change.

    Parameters
    ----------
    graph : networkx.DiGraph, the library's motion graph (nodes with ``name``)
    source : MeshSource, frames by ``(sequence, frame)``
    order : node ids in the order ``tvmedit info`` lists them; key ``1`` queues ``order[0]``
    start : node id of the first motion, looped until something is queued
    fps : playback rate, sequence frames per second
    forbidden : node ids no path may pass through (section 8)
    aspect : width / height of the view, for framing the camera
    log : open text file for ``--log`` (one JSON line per displayed frame), or None
    clock_zero : the time (same clock as ``now``) that log times count from
    hold_seconds : how long a motion queued with Shift+key keeps looping once it begins
    walker : a Walker of :mod:`tvmedit.engine.playback.wander`, or None: with nothing queued,
        walk on to motions it draws instead of looping the one playing
    smooth : place the body by the redraw clock, between the frame on screen and the next one
        (the source's ``instant_field``, :mod:`tvmedit.engine.inbetween.instants`); False, or a
        source without them: each frame held until the next, the capture as it is

    Times (``now``) are seconds on one monotonic clock, passed in by the caller.
    """

    def __init__(self, graph, source, order, start, fps=10.0, forbidden=(), aspect=4 / 3, log=None,
                 clock_zero=0.0, print_=None, shading="auto", hold_seconds=3.0, walker=None, smooth=True):
        check_shading(source, shading)
        self.graph = graph
        self.source = source
        self.shading = shading
        self.fps = float(fps)
        self.period = 1.0 / self.fps
        self.hold_seconds = float(hold_seconds)
        self.forbidden = tuple(forbidden)
        self.playhead = Playhead(graph, start, forbidden=self.forbidden, walker=walker)
        self.keys = dict(zip(motion_keys(len(order)), order))
        self.order = list(order)
        self.log = log
        self.clock_zero = clock_zero
        self.print = print_ or (lambda text: print(text, file=sys.stderr, flush=True))
        self.paused = False
        self.entry = None           # the ScheduleEntry on screen
        self.frames_shown = 0
        self.message = None         # (text, until)
        self._next_slot = None      # when the next sequence frame is due
        self.slot = None            # when the frame ``tick`` produced should appear
        self._restarted = False
        self._pause_left = 0.0
        self._reach = None          # (node, motions unreachable from it), see unreachable()
        self._mesh = None
        self._texture = None
        self._field = None          # (field, next entry) of the step from the frame on screen
        self.smooth = bool(smooth) and getattr(source, "smooth", False)
        self.shown_at = None        # when the frame on screen appeared (its slot)
        self._paused_at = None
        self._bounds = source.bounds()
        self.camera = self.home_camera(aspect)


    def next_frame_at(self):
        """When the next sequence frame is due (``inf`` while paused)."""
        if self.paused:
            return math.inf
        return -math.inf if self._next_slot is None else self._next_slot

    def tick(self, now, lead=0.0):
        """Advance the playback clock to ``now``; True when a new sequence frame is to be shown.

        A frame is due ``lead`` seconds before its slot, the time the window needs to draw it;
        ``slot`` then says when it should appear (None for the first frame and the first after
        a stall: as soon as possible). At most one frame per call, so every frame the schedule
        produces is drawn (section 8 shows every frame of a texton); after a stall longer
        than ``MAX_LAG_S`` the clock restarts rather than rushing. Call ``displayed`` once the
        frame is on screen.
        """
        if now + lead < self.next_frame_at():
            return False
        restart = self._next_slot is None or now - self._next_slot > MAX_LAG_S
        self.slot = None if restart else self._next_slot
        self._next_slot = (now if restart else self._next_slot) + self.period
        self._restarted = restart
        self.entry = self.playhead.advance()
        self._mesh = None
        self._texture = None
        self._field = None
        self.shown_at = self.slot
        self.frames_shown += 1
        return True

    def displayed(self, now):
        """Log the frame ``tick`` produced as shown at ``now``.

        The slots of the following frames count from when the first frame (or the first after
        a stall) actually appeared, which the window learns only after drawing it.
        """
        if self._restarted:
            self._next_slot = now + self.period
            self._restarted = False
        if self.shown_at is None:
            self.shown_at = now
        self._write({"t": round(now - self.clock_zero, 6), "node": _plain(self.entry.node),
                     "sequence": self.entry.sequence, "frame": int(self.entry.frame),
                     **({} if self.entry.blend is None else {"blend": self.entry.to_json()["blend"]}),
                     "queue": [_plain(n) for n in self.playhead.queue_list]})

    def mesh(self):
        """The mesh of the frame on screen, fetched once per sequence frame."""
        if self._mesh is None and self.entry is not None:
            key = self.entry.key
            self._mesh = self.source.frame_mesh(key)
            self._texture = texture_of(self.source, key, self.shading)
        return self._mesh

    def texture(self):
        """The texture of the frame on screen (``(uv, image)``), None to draw vertex colours."""
        return self._texture if self.mesh() is not None else None

    def instant(self, now):
        """``(field, s)``: how far the body on screen is on its way to the next frame at ``now``
        (``s`` the share of the frame's period gone by, below 1), for ``Renderer.draw``; None
        to draw the frame as stored (not smooth, paused, or no field for this step). The next
        frame is asked of the playhead once per frame (:meth:`Playhead.peek`)."""
        if not self.smooth or self.entry is None or self.shown_at is None:
            return None
        if self.paused:
            now = self._paused_at
        if self._field is None:
            upcoming = self.playhead.peek()
            self._field = (self.source.instant_field(self.entry.key, upcoming.key), upcoming)
        if self._field[0] is None:
            return None
        s = min(max((now - self.shown_at) / self.period, 0.0), 0.999)
        return self._field[0], s

    def seconds_to_next_key(self, now):
        """Seconds until the next queued motion begins, None when the queue is empty."""
        frames = self.playhead.frames_until_next_key()
        if frames is None:
            return None
        if self.paused:
            first = self._pause_left
        elif self._next_slot is None:
            first = 0.0
        else:
            first = max(self._next_slot - now, 0.0)
        return first + frames * self.period


    def press(self, key, now, shift=False):
        """Act on a key by name (``"1"``, ``"a"``, ``"backspace"``, ``"space"``, ``"left"``...).

        A motion key with ``shift`` queues the motion held for :attr:`hold_seconds`.
        Returns ``"quit"`` or ``"screenshot"`` for the window to carry out, else None.
        """
        if shift and key in self.keys:
            self.queue(self.keys[key], now, key, hold=self.hold_seconds)
            return None
        if key in ("escape", "q"):
            return "quit"
        if key == "s":
            return "screenshot"
        if key == "r":
            self.reset_camera()
        elif key == "space":
            self.toggle_pause(now)
        elif key == "backspace":
            node = self.playhead.unqueue_last()
            if node is not None:
                self.say(f"removed {self.label(node)} from the queue", now)
                self._event(now, "unqueued", node)
        elif key in ("+", "=", "kp_add"):
            self.zoom(1 / ZOOM_STEP)
        elif key in ("-", "kp_subtract"):
            self.zoom(ZOOM_STEP)
        elif key in self.keys:
            self.queue(self.keys[key], now, key)
        return None

    def queue(self, node, now, key=None, hold=0.0):
        """Queue ``node`` as the next key motion, looping ``hold`` seconds once it begins.

        The motion the queue already ends at (the one playing when nothing is queued) is
        ignored quietly, unless held: then it loops ``hold`` seconds more (from now, if it is
        playing). One that the forbidden motions cut off is refused with a message (a
        connected graph has no other).
        """
        frames = round(hold * self.fps)
        try:
            path = self.playhead.queue(node, hold=frames)
        except NoPath as error:
            self.say(f"refused {self.label(node)}: {error}", now, echo=True)
            self._event(now, "refused", node, key=key, message=str(error))
            return False
        if frames:
            self.say(f"{self.label(node)} held for {frames / self.fps:g} s", now)
        if len(path) > 1 or frames:
            self._event(now, "queued", node, key=key, **({"hold": frames / self.fps} if frames else {}))
        return True

    def unreachable(self):
        """Motions no key can queue now: the forbidden ones and those they cut off from where
        the queue ends (greyed out in the legend)."""
        last = self.playhead.queue_list[-1] if self.playhead.queue_list else self.playhead.current_node
        if self._reach is None or self._reach[0] != last:
            allowed = self.graph.subgraph(n for n in self.graph if n not in self.forbidden or n == last)
            self._reach = (last, set(self.graph) - nx.descendants(allowed, last) - {last})
        return self._reach[1]

    def toggle_pause(self, now):
        if self.paused:
            self.paused = False
            if self._next_slot is not None:
                self._next_slot = now + self._pause_left
                if self.shown_at is not None:   # the body goes on from where it stopped
                    self.shown_at = self._next_slot - self.period
        else:
            self._paused_at = now
            self.paused = True
            self._pause_left = max(self._next_slot - now, 0.0) if self._next_slot is not None else 0.0

    def say(self, text, now, echo=False):
        self.message = (text, now + MESSAGE_S)
        if echo:
            self.print(text)



    def label(self, node):
        name = self.graph.nodes[node].get("name")
        key = next((k for k, n in self.keys.items() if n == node), None)
        text = f"{node} {name}" if name is not None and str(name) != str(node) else str(node)
        return f"[{key}] {text}" if key else text

    def status_lines(self, now):
        """The lines at the top left: motion on screen, queue, time to the next key motion."""
        if self.entry is None:
            return ["starting"]
        head = self.playhead
        lines = [f"now: {self.label(self.entry.node)}  ({self.entry.sequence} frame {self.entry.frame})"
                 + ("  passing through" if head.passing_through else "") + ("  paused" if self.paused else "")]
        queue = [self.label(n) + (f" (held {hold * self.period:g} s)" if hold else "")
                 for n, hold in zip(head.queue_list, head.queue_holds)]
        idle = "empty (wandering)" if head.walker is not None else "empty (looping)"
        lines.append("queue: " + (", ".join(queue) if queue else idle))
        seconds = self.seconds_to_next_key(now)
        lines.append("next in " + ("-" if seconds is None else f"{seconds:.1f} s"))
        held = self.playhead.holding()
        if held:
            lines[-1] += f"  (held {held * self.period:.1f} s more)"
        return lines

    def message_text(self, now):
        """The last message (a refusal, a removal) while it is fresh, else None."""
        if self.message is not None and now < self.message[1]:
            return self.message[0]
        return None

    def legend_lines(self):
        """Every motion with its key (as far as keys go), then the command keys."""
        lines = [self.label(n) for n in self.keys.values()]
        hidden = len(self.order) - len(self.keys)
        if hidden > 0:
            lines.append(f"({hidden} more without a key)")
        return lines + ["", f"shift+key hold {self.hold_seconds:g} s", "bksp unqueue  space pause",
                        "arrows/drag orbit  +/- zoom",
                        "r reset  s screenshot  q quit"]

    def legend_dimmed(self):
        """Indices of the legend lines to grey out: motions :meth:`unreachable` names."""
        cut = self.unreachable()
        return {k for k, n in enumerate(self.keys.values()) if n in cut}


    def write_header(self, wall_zero, library=None):
        self._write({"event": "start", "wall": wall_zero, "fps": self.fps, "library": library,
                     "keys": {k: _plain(n) for k, n in self.keys.items()},
                     "forbidden": [_plain(n) for n in self.forbidden]})

    def write_footer(self, now, redraws, draw_seconds, cpu_seconds=None):
        """The last log line: how many frames and redraws, the redraw rate and the CPU time."""
        self._write({"event": "stop", "t": round(now - self.clock_zero, 6), "frames": self.frames_shown,
                     "redraws": redraws, "redraw_hz": round(redraws / draw_seconds, 2) if draw_seconds > 0 else None,
                     "cpu_s": None if cpu_seconds is None else round(cpu_seconds, 3)})

    def _event(self, now, event, node, **details):
        """A log line for a change the frames alone do not show (the queue after it included)."""
        self._write({"t": round(now - self.clock_zero, 6), "event": event, "node": _plain(node), **details,
                     "queue": [_plain(n) for n in self.playhead.queue_list]})

    def _write(self, record):
        if self.log is not None:
            self.log.write(json.dumps(record) + "\n")
            self.log.flush()


def _plain(value):
    """Node ids as JSON numbers where they are integers (numpy ints included)."""
    try:
        return int(value) if int(value) == value else value
    except (TypeError, ValueError):
        return value


def screenshot_path(directory="."):
    """The first unused ``tvmedit-screenshot-<n>.png`` in ``directory``."""
    n = 1
    while (path := Path(directory) / f"tvmedit-screenshot-{n}.png").exists():
        n += 1
    return path


class Window:
    """A glfw window that draws a ``PlayerApp`` with the shared ``Renderer``.

    Parameters
    ----------
    app : PlayerApp
    size : (width, height) of the window, screen coordinates
    title : window title (the tests find the window by it)
    clock : the monotonic clock the app's times come from
    """

    def __init__(self, app, size=(960, 720), title="tvmedit", clock=time.perf_counter, vsync=True):
        import glfw

        from .overlay import TextOverlay
        from .renderer import Renderer, is_software

        self.glfw = glfw
        self.app = app
        self.clock = clock
        # glfw's own reports become exceptions here, so a user reads one sentence, not a warning.
        glfw.ERROR_REPORTING = "raise"
        try:
            initialised = glfw.init()
        except glfw.GLFWError:
            initialised = False
        if not initialised:
            raise TvmError("no display: set DISPLAY or run under xvfb-run; for files use tvmedit render")
        # Opened hidden and untitled, so nothing finds a window that is about to be replaced.
        self.window, self.ctx = self._open(size, samples=4, vsync=vsync)
        if is_software(self.ctx):
            # Multisampling quadruples the fragment work, which a software rasteriser cannot
            # afford at 60 Hz: reopen without it.
            glfw.destroy_window(self.window)
            self.window, self.ctx = self._open(size, samples=0, vsync=vsync)
        glfw.set_window_title(self.window, title)
        glfw.show_window(self.window)
        glfw.ERROR_REPORTING = "warn"
        # The window is multisampled itself on a GPU and the renderer draws straight into it.
        # On a software rasteriser even an FXAA pass costs a third of the redraw rate
        # (measured: 49 Hz with it, 73 Hz without), and a window must stay smooth: no pass.
        self.renderer = Renderer(self.ctx, size=glfw.get_framebuffer_size(self.window), samples=0,
                                 antialias="none", max_counts=app.source.max_counts(), grid=True)
        self.overlay = TextOverlay(self.ctx, scale=2)
        self._key_names = {
            glfw.KEY_ESCAPE: "escape", glfw.KEY_BACKSPACE: "backspace", glfw.KEY_SPACE: "space",
            glfw.KEY_LEFT: "left", glfw.KEY_RIGHT: "right", glfw.KEY_UP: "up", glfw.KEY_DOWN: "down",
            glfw.KEY_KP_ADD: "kp_add", glfw.KEY_KP_SUBTRACT: "kp_subtract"}
        self.redraws = 0
        self.elapsed = None       # seconds played, once run() ends
        self._redraw_s = 0.0        # how long a camera redraw takes (80th percentile of recent ones)
        self._redraw_times = []     # recent camera redraws, seconds
        self._swap_s = 0.0          # how long a swap takes (moving average)
        self._prepare_s = 0.0       # how long before its slot a sequence frame is started
        self._prepares = []         # recent times to fetch, upload and draw a sequence frame
        self._held = {}            # arrow key -> (pressed at, seconds already applied)
        self._drag = None          # last cursor position while the left button is down
        self._screenshot = False
        self._resize(*glfw.get_framebuffer_size(self.window))
        glfw.set_key_callback(self.window, self._on_key)
        glfw.set_mouse_button_callback(self.window, self._on_mouse_button)
        glfw.set_cursor_pos_callback(self.window, self._on_cursor)
        glfw.set_scroll_callback(self.window, self._on_scroll)
        glfw.set_framebuffer_size_callback(self.window, lambda _w, width, height: self._resize(width, height))

    def _open(self, size, samples, vsync):
        from .context import window_context

        glfw = self.glfw
        glfw.default_window_hints()
        glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, 3)
        glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, 3)
        glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
        glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
        glfw.window_hint(glfw.SAMPLES, samples)
        glfw.window_hint(glfw.VISIBLE, False)
        try:
            window = glfw.create_window(int(size[0]), int(size[1]), "", None, None)
        except glfw.GLFWError as error:
            glfw.terminate()
            reason = error.args[0] if error.args else error
            raise TvmError(f"cannot open a window with an OpenGL 3.3 core profile context on this display "
                           f"({reason})") from None
        glfw.make_context_current(window)
        glfw.swap_interval(1 if vsync else 0)
        return window, window_context()

    def run(self, seconds=None):
        """Play until the window closes, Esc or Q, or ``seconds`` after the app's clock zero.

        A new sequence frame is drawn and finished ahead of its slot and swapped onto the
        screen on the slot, so it appears on time however long drawing takes; camera redraws
        fill the time between, unless one would delay the next sequence frame.
        """
        glfw, app = self.glfw, self.app
        start, cpu = self.clock(), time.process_time()
        next_redraw = start
        end = math.inf if seconds is None else app.clock_zero + seconds
        try:
            while not glfw.window_should_close(self.window):
                now = self.clock()
                if now >= end:
                    break
                prepare_at = app.next_frame_at() - self._prepare_s
                deadline = min(next_redraw, prepare_at, end)
                if next_redraw < prepare_at < max(now, next_redraw) + self._redraw_s:
                    deadline = prepare_at
                if now < deadline:
                    glfw.wait_events_timeout(deadline - now)   # wakes early for input
                    continue
                glfw.poll_events()
                began = self.clock()
                self._turn(began)
                new_frame = app.tick(began, lead=self._prepare_s)
                self._draw(began)
                if new_frame:
                    self.ctx.finish()       # software GL rasterises here, not in the swap
                ready = self.clock()
                if new_frame and app.slot is not None:
                    self._wait_until(app.slot - self._swap_s)
                swapping = self.clock()
                glfw.swap_buffers(self.window)
                shown = self.clock()
                self.redraws += 1
                self._learn(began, ready, swapping, shown, new_frame)
                if new_frame:
                    app.displayed(shown)
                next_redraw = max(began + 1 / MAX_REDRAW_HZ, shown)
        finally:
            now = self.clock()
            self.elapsed = now - start
            app.write_footer(now, self.redraws, self.elapsed, time.process_time() - cpu)
            self.close()
        return self.redraws, self.elapsed

    def _wait_until(self, moment):
        while (left := moment - self.clock()) > 0:
            time.sleep(left)

    def _learn(self, began, ready, swapping, shown, new_frame):
        """Track how long drawing and swapping take, to start each sequence frame in time."""
        if not new_frame:
            # A redraw that does not fit before the next sequence frame's start is put off;
            # one that overruns a little is absorbed by the start's own margin.
            self._redraw_times = (self._redraw_times + [shown - began])[-30:]
            self._redraw_s = sorted(self._redraw_times)[int(0.8 * (len(self._redraw_times) - 1))]
            return
        # Only sequence frames are finished before their swap, so only their swaps tell how
        # long presenting a finished frame takes.
        swap = shown - swapping
        self._swap_s = swap if self.app.frames_shown == 1 else 0.8 * self._swap_s + 0.2 * swap
        work = ready - began
        if self.app.frames_shown == 1:
            work = min(work, 0.25 * self.app.period)   # the first frame also compiled shaders
        self._prepares = (self._prepares + [work])[-20:]
        # Start early enough for the slowest recent frame, and a little more: starting early
        # costs only a wait, starting late makes the frame late.
        prepare = max(self._prepares) + self._swap_s + 0.004
        self._prepare_s = min(prepare, 0.5 * self.app.period)

    def close(self):
        if self.window is not None:
            self.overlay.release()
            self.renderer.release()
            self.glfw.destroy_window(self.window)
            self.glfw.terminate()
            self.window = None

    def _draw(self, now):
        mesh = self.app.mesh()
        if mesh is None:
            self.ctx.screen.use()
            self.ctx.screen.clear(*self.renderer.background)
        else:
            self.renderer.draw(mesh, self.app.camera, framebuffer=self.ctx.screen, texture=self.app.texture(),
                               instant=self.app.instant(now))
        if self._screenshot:
            self._screenshot = False
            self._save_screenshot()
        labels = [Label(self.app.status_lines(now), "top-left"),
                  Label(self.app.legend_lines(), "top-right", colour=(0.85, 0.9, 1.0),
                        dimmed=self.app.legend_dimmed())]
        message = self.app.message_text(now)
        if message:
            width = self.ctx.screen.viewport[2]
            lines = textwrap.wrap(message, max(self.overlay.columns(width - 40), 20))
            labels.append(Label(lines, "bottom-left", colour=(1.0, 0.8, 0.4)))
        self.overlay.draw(labels, self.ctx.screen)

    def _save_screenshot(self):
        import imageio.v3 as iio
        import numpy as np

        width, height = self.glfw.get_framebuffer_size(self.window)
        data = self.ctx.screen.read(viewport=(0, 0, width, height), components=3, alignment=1)
        image = np.frombuffer(data, np.uint8).reshape(height, width, 3)[::-1]
        path = screenshot_path()
        iio.imwrite(path, image)
        print(f"screenshot saved to {path}", flush=True)

    def _resize(self, width, height):
        if width > 0 and height > 0:
            self.ctx.screen.viewport = (0, 0, width, height)
            self.app.set_aspect(width / height)

    def _turn(self, now):
        """Turn the camera for arrow keys held down (smoothly, per redraw, not per key repeat)."""
        for key, (since, applied) in list(self._held.items()):
            self._apply_turn(key, now - since - applied)
            self._held[key] = (since, now - since)

    def _apply_turn(self, key, seconds):
        degrees = ORBIT_DEG_PER_S * seconds
        turns = {"left": (degrees, 0.0), "right": (-degrees, 0.0), "up": (0.0, degrees), "down": (0.0, -degrees)}
        self.app.orbit(*turns[key])

    def _on_key(self, _window, key, scancode, action, mods):
        glfw = self.glfw
        name = self._key_names.get(key) or glfw.get_key_name(key, scancode)
        if name is None:
            return
        name = name.lower()
        if mods & glfw.MOD_SHIFT and name == "=":
            name = "+"
        now = self.clock()
        if name in ("left", "right", "up", "down"):
            if action == glfw.PRESS:
                self._held[name] = (now, 0.0)
            elif action == glfw.RELEASE and name in self._held:
                since, applied = self._held.pop(name)
                self._apply_turn(name, max(now - since, TAP_S) - applied)
            return
        if action == glfw.RELEASE or (action == glfw.REPEAT and name not in ("+", "=", "-", "kp_add", "kp_subtract")):
            return
        command = self.app.press(name, now, shift=bool(mods & glfw.MOD_SHIFT))
        if command == "quit":
            glfw.set_window_should_close(self.window, True)
        elif command == "screenshot":
            self._screenshot = True

    def _on_mouse_button(self, window, button, action, _mods):
        if button == self.glfw.MOUSE_BUTTON_LEFT:
            self._drag = self.glfw.get_cursor_pos(window) if action == self.glfw.PRESS else None

    def _on_cursor(self, _window, x, y):
        if self._drag is not None:
            dx, dy = x - self._drag[0], y - self._drag[1]
            self._drag = (x, y)
            self.app.orbit(-dx * DRAG_DEG_PER_PIXEL, dy * DRAG_DEG_PER_PIXEL)

    def _on_scroll(self, _window, _dx, dy):
        self.app.zoom(ZOOM_STEP ** -dy)

