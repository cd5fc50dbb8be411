"""The realtime player's window: glfw plumbing around :class:`tvmedit.player.app.PlayerApp`.

The window draws what the app says (the frame on screen, moved to its instant, the text on
screen), passes keys and the mouse to it, and paces the redraws: a new sequence frame is drawn
and finished ahead of its slot and swapped on it; redraws fill the time between. It is the only
code that touches glfw.
"""

import math
import os
import textwrap
import time
from pathlib import Path

from ..engine.errors import TvmError
from .app import ZOOM_STEP
from .overlay import Label

#: The loop never redraws faster than this when the driver does not wait for vsync (Xvfb,
#: llvmpipe), so the player leaves the CPU to others; a real display's vsync is lower.
MAX_REDRAW_HZ = 100.0

ORBIT_DEG_PER_S = 90.0
TAP_S = 0.1              # a key tapped briefly still turns the camera this long
DRAG_DEG_PER_PIXEL = 0.4


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

    #: What a user can do without a display, said where the window cannot open.
    WITHOUT_DISPLAY = "for files use tvmedit render"

    @classmethod
    def check_display(cls):
        """Raise the one-sentence :class:`TvmError` where no display is set (``DISPLAY`` or
        ``WAYLAND_DISPLAY``), before a command loads what its window needs."""
        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            raise TvmError(f"no display: set DISPLAY or run under xvfb-run; {cls.WITHOUT_DISPLAY}")

    def __init__(self, app, size=(960, 720), title="tvmedit", clock=time.perf_counter, vsync=True):
        import glfw

        from .overlay import TextOverlay
        from .renderer import Renderer, is_software

        self.glfw = glfw
        self.app = app
        self.clock = clock
        # Only a failed init stops the player, with glfw's own words in the sentence: a report
        # that init survives (an input method, a monitor) is no reason to refuse a display.
        initialised, reports = self._init_glfw(glfw)
        if not initialised:
            reason = "; ".join(reports) or "glfw could not start"
            wayland = reason.startswith("Wayland") or not os.environ.get("DISPLAY")
            display = os.environ.get("WAYLAND_DISPLAY" if wayland else "DISPLAY") or "(none)"
            raise TvmError(f"cannot open the display {display} ({reason}): set DISPLAY to a running X server "
                           f"or run under xvfb-run; {self.WITHOUT_DISPLAY}")
        # glfw's own reports become exceptions from here, so a user reads one sentence, not a warning.
        glfw.ERROR_REPORTING = "raise"
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

    #: Tries to open an X display that refuses the connection, a quarter of a second apart.
    DISPLAY_TRIES = 5
    #: What glfw says of a display that refused it: an X11 build's words, and those of a build
    #: for X11 and Wayland, which tries both and finds neither.
    REFUSED = ("Failed to open display", "Failed to detect any supported platform")

    @classmethod
    def _init_glfw(cls, glfw):
        """``(glfw.init() succeeded, glfw's reports of the last try)``.

        An X server resets when its last client leaves and refuses connections meanwhile: on
        an Xvfb, two clients started together over and over were refused 3 times in 1,800
        here (the player tests' rare "Failed to open display" on a running server). A refused
        display is tried again for a second before the player gives up; one that no server
        answers costs that second before its sentence."""
        for attempt in range(cls.DISPLAY_TRIES):
            reports = []
            glfw.set_error_callback(lambda code, text: reports.append(text.decode(errors="replace")))
            try:
                if glfw.init():
                    return True, reports
            finally:
                glfw.set_error_callback(None)
            refused = any(text in report for report in reports for text in cls.REFUSED)
            if not refused or attempt == cls.DISPLAY_TRIES - 1:
                break
            time.sleep(0.25)
        return False, reports

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

