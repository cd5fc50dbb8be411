"""The inspector: a library's parse on a timeline, corrected by hand and rebuilt at once.

``InspectorApp`` holds everything a user can do, with no window or GL, so every action is
a Python call (scriptable, tested headless): move the playhead, add, delete or move the
cluster boundary or texton start nearest it, force the texton under it as its cluster's
representative, undo, rebuild the library from the corrections and read the new graph's
summary, save ``corrections.json``. After each edit the corrections are applied to the
automatic parse at once (:func:`tvmedit.engine.store.corrections.apply_structure`) and the timeline shows
the result; an edit the corrections refuse (a texton shorter than the atom window) is undone
and said. ``InspectorWindow`` is the glfw window around it: the source frame under the
playhead in 3D at the top, the timeline (:mod:`tvmedit.engine.parse.timeline`) below.

Keys: left/right one frame (held: repeat), up/down one second, home/end, page up/down
the next cluster; b add a boundary, t add a texton start, d or delete removes the marker
nearest the playhead, m moves it to the playhead, p forces the texton under the playhead as
representative, x drops the motion of the cluster under it, u undoes, tab the next
sequence, enter rebuilds, s saves, c screenshot, r resets the camera, q or escape quits.
Click or drag on the timeline to scrub, drag the view to orbit, scroll to zoom.
"""

import sys
import textwrap
from pathlib import Path

import networkx as nx

from ..engine.store.corrections import CorrectionError, Corrections, apply_database, apply_structure
from ..engine.graph.database import build_database
from ..engine.errors import TvmError
from ..engine.parse.timeline import timeline
from .camera import CameraControls
from .overlay import Label
from .window import Window

#: Share of the window's height the timeline takes, at the bottom.
TIMELINE_SHARE = 0.3

HELP_LINES = ["<- -> frame  up/dn 1 s  pgup/dn cluster", "b boundary  t texton  d delete  m move here",
              "p representative  x drop motion  u undo", "tab sequence  enter rebuild  s save",
              "c screenshot  q quit"]


def graph_summary(graph):
    """``{"motions", "transitions", "reachable"}``: nodes, edges, and ordered pairs (i, j),
    i != j, with a path from i to j.

    >>> g = nx.DiGraph([(0, 1), (1, 2)])
    >>> graph_summary(g)
    {'motions': 3, 'transitions': 2, 'reachable': 3}
    """
    reachable = sum(len(nx.descendants(graph, n)) for n in graph.nodes)
    return {"motions": graph.number_of_nodes(), "transitions": graph.number_of_edges(), "reachable": reachable}


class InspectorApp(CameraControls):
    """Inspector state and actions, with no window.

    Parameters
    ----------
    library : tvmedit.engine.store.library.Library
    corrections_path : str or Path
        Where :meth:`save` writes; read at start when it exists (else the library's own).
    out : str or Path, optional
        Where :meth:`rebuild` writes; default: the library itself.
    aspect : float
        Width / height of the 3D view.
    """

    def __init__(self, library, corrections_path="corrections.json", out=None, aspect=16 / 7, print_=None,
                 force=None):
        self.library = library
        self.path = Path(corrections_path)
        self.out = out
        self.force = force          # replace an existing --out (None: only LIB itself)
        self.print = print_ or (lambda text: print(text, file=sys.stderr, flush=True))
        self.corrections = (Corrections.load(self.path) if self.path.exists() else library.corrections().copy())
        self.history = []
        self.sequence = library.sequences[0].name
        self.frame = 0
        self.message = None
        self.summary = graph_summary(library.graph)
        self._meshes = {}
        self._bounds = library.bounds()
        self.camera = self.home_camera(aspect)
        self._preview()

    @property
    def source(self):
        """What the window's renderer is sized for (the library's stored frames)."""
        return self.library

    # --- the playhead --------------------------------------------------------------------

    @property
    def frames(self):
        return len(self.library.sequence(self.sequence))

    def seek(self, frame):
        """Put the playhead on ``frame`` (clamped to the sequence)."""
        self.frame = int(min(max(int(frame), 0), self.frames - 1))

    def step(self, frames):
        self.seek(self.frame + frames)

    def next_cluster(self, direction=1):
        """Jump to the start of the next (or, with -1, the previous) cluster."""
        starts = [s for s, _ in self.timeline.clusters]
        ahead = [s for s in starts if (s - self.frame) * direction > 0]
        if ahead:
            self.seek(min(ahead) if direction > 0 else max(ahead))

    def next_sequence(self):
        names = [s.name for s in self.library.sequences]
        self.sequence = names[(names.index(self.sequence) + 1) % len(names)]
        self.seek(self.frame)
        self._preview()

    # --- edits -----------------------------------------------------------------------------

    def add_boundary(self):
        """Begin a cluster at the playhead."""
        return self._edit(f"boundary added at {self.frame}", lambda c: c.add_boundary(self.sequence, self.frame))

    def add_texton(self):
        """Begin a texton at the playhead."""
        return self._edit(f"texton start added at {self.frame}", lambda c: c.add_texton(self.sequence, self.frame))

    def delete_nearest(self):
        """Remove the boundary or texton start nearest the playhead."""
        near = self.timeline.nearest_marker(self.frame)
        if near is None:
            return self._say("nothing to delete: no boundary or texton start")
        kind, frame = near
        remove = (Corrections.remove_boundary if kind == "boundary" else Corrections.remove_texton)
        return self._edit(f"{kind} at {frame} removed", lambda c: remove(c, self.sequence, frame))

    def move_nearest(self):
        """Move the boundary or texton start nearest the playhead onto it."""
        near = self.timeline.nearest_marker(self.frame)
        if near is None or near[1] == self.frame:
            return self._say("nothing to move: put the playhead where the nearest marker should go")
        kind, frame = near
        move = (Corrections.move_boundary if kind == "boundary" else Corrections.move_texton)
        return self._edit(f"{kind} moved from {frame} to {self.frame}", lambda c: move(c, self.sequence, frame, self.frame))

    def represent(self):
        """Force the texton under the playhead as its cluster's representative."""
        if self.timeline.texton_at(self.frame) is None:
            return self._say(f"frame {self.frame} lies in no texton; add a texton start first")
        return self._edit(f"texton at {self.frame} is now its cluster's representative",
                          lambda c: c.represent(self.sequence, self.frame))

    def drop(self):
        """Leave the motion of the cluster under the playhead out of the database."""
        cluster = self.timeline.cluster_at(self.frame)
        node = next((n for n in self.nodes if n.cluster == cluster), None)
        if node is None:
            return self._say("no motion to drop here")
        return self._edit(f"motion {node.name} dropped", lambda c: c.drop(self.sequence, node.name))

    def undo(self):
        """Take back the last edit."""
        if not self.history:
            return self._say("nothing to undo")
        self.corrections = self.history.pop()
        self._preview()
        return self._say("undone")

    def _edit(self, what, change):
        before = self.corrections.copy()
        change(self.corrections)
        try:
            self._preview()
        except CorrectionError as error:
            self.corrections = before
            self._preview()
            return self._say(f"refused: {error}")
        self.history.append(before)
        return self._say(what)

    def _preview(self):
        """The corrected structure of the sequence shown, and its representatives, at once."""
        name = self.sequence
        parse = self.library.parse(name)
        entry = self.corrections.sequences.get(name)
        mine = Corrections({name: entry} if entry else {}, self.corrections.source)
        mine.check_sequences({s.name: len(s) for s in self.library.sequences})
        features = self.library.features(name)
        structure = (apply_structure(parse, features.vectors, entry, name=name, theta=features.theta_columns,
                                     centred=features.centred, source="corrections")
                     if entry else parse)
        nodes = apply_database(build_database({name: structure}), {name: structure}, mine,
                               whole=len(self.library.sequences) == 1)
        self.structure, self.nodes = structure, nodes
        self.timeline = timeline(name, structure, parse, nodes)

    # --- rebuild and save ------------------------------------------------------------------

    def rebuild(self):
        """Write the library again with the corrections (in about a second) and show the new
        graph's summary; returns it (:func:`graph_summary`)."""
        try:
            self.library = self.library.correct(self.corrections, self.out, force=self.force)
        except TvmError as error:
            self._say(f"rebuild refused: {error}")
            return None
        self.summary = graph_summary(self.library.graph)
        self._meshes.clear()
        self._preview()
        s = self.summary
        self._say(f"rebuilt {self.library.path.name} in {self.library.report['seconds']:.2f} s: "
                  f"{s['motions']} motions, {s['transitions']} transitions, {s['reachable']} reachable pairs")
        return self.summary

    def save(self, path=None):
        """Write the corrections to ``path`` (default: the path given at start). A save that
        fails says why on screen and keeps the corrections and the window: nothing is lost."""
        path = Path(path or self.path)
        try:
            self.corrections.save(path)
        except (TvmError, OSError) as error:
            detail = error.strerror if isinstance(error, OSError) and error.strerror else str(error)
            return self._say(f"not saved: {detail}; the corrections are kept, fix the path and press S again")
        return self._say(f"saved {path}")

    # --- what the window shows -------------------------------------------------------------

    def mesh(self):
        """The source frame under the playhead (stored in the library, else read from its file),
        or None when it cannot be read."""
        key = (self.sequence, self.frame)
        if key not in self._meshes:
            try:
                self._meshes = {key: self.library.source_mesh(key)}
            except TvmError as error:
                self._meshes = {key: None}
                self._say(f"frame {self.frame} cannot be shown: {error}")
        return self._meshes[key]

    def status_lines(self):
        t = self.timeline
        cluster = t.cluster_at(self.frame)
        texton = t.texton_at(self.frame)
        s = self.summary
        return [f"{self.sequence} frame {self.frame}/{self.frames - 1} ({self.frame / t.fps:.1f} s)",
                f"cluster {cluster + 1}/{len(t.clusters)} {t.clusters[cluster][0]}-{t.clusters[cluster][1]}"
                + (f"  texton {texton[0]}-{texton[1]}" if texton else "  no texton"),
                f"graph: {s['motions']} motions, {s['transitions']} transitions, {s['reachable']} reachable pairs"]

    def press(self, key):
        """Act on a key by name; returns ``"quit"`` or ``"screenshot"`` for the window, else None."""
        moves = {"left": -1, "right": 1, "up": round(self.timeline.fps), "down": -round(self.timeline.fps)}
        actions = {"b": self.add_boundary, "t": self.add_texton, "d": self.delete_nearest,
                   "delete": self.delete_nearest, "m": self.move_nearest, "p": self.represent, "x": self.drop,
                   "u": self.undo, "tab": self.next_sequence, "enter": self.rebuild, "s": self.save,
                   "r": self.reset_camera, "home": lambda: self.seek(0), "end": lambda: self.seek(self.frames - 1),
                   "page_up": lambda: self.next_cluster(-1), "page_down": self.next_cluster}
        if key in ("escape", "q"):
            return "quit"
        if key == "c":
            return "screenshot"
        if key in moves:
            self.step(moves[key])
        elif key in actions:
            actions[key]()
        return None

    def _say(self, text):
        self.message = text
        self.print(text)
        return text


class TimelineView:
    """Draws :class:`tvmedit.engine.parse.timeline.Shapes` (rectangles and the curve) with ``shaders/flat.glsl``."""

    def __init__(self, ctx):
        import numpy as np

        from .programs import load_program

        self.ctx = ctx
        self.program = load_program(ctx, "flat")
        self._vertex = np.dtype([("pixel", np.float32, 2), ("colour", np.float32, 4)])
        self._buffer = ctx.buffer(reserve=1 << 16, dynamic=True)
        self._vao = self._array()

    def _array(self):
        return self.ctx.vertex_array(self.program, [(self._buffer, "2f 4f", "in_pixel", "in_colour")])

    def draw(self, shapes, framebuffer):
        """Draw ``shapes`` over ``framebuffer`` (its pixels, y down)."""
        import moderngl
        import numpy as np

        x, y, w, h = shapes.rects.T
        corners = np.stack([np.stack(c, axis=1) for c in
                            ((x, y), (x + w, y), (x, y + h), (x + w, y), (x + w, y + h), (x, y + h))], axis=1)
        triangles = np.zeros(corners.shape[:2], self._vertex)
        triangles["pixel"] = corners
        triangles["colour"] = shapes.colours[:, None, :]
        curve = np.zeros(len(shapes.curve), self._vertex)
        curve["pixel"], curve["colour"] = shapes.curve, shapes.curve_colour
        data = np.concatenate([triangles.reshape(-1), curve]).view(np.uint8)
        if data.nbytes > self._buffer.size:
            self._vao.release()
            self._buffer.release()
            self._buffer = self.ctx.buffer(reserve=int(data.nbytes * 1.5), dynamic=True)
            self._vao = self._array()
        self._buffer.write(data)
        framebuffer.use()
        self.ctx.disable(moderngl.DEPTH_TEST)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.program["screen"].value = tuple(float(v) for v in framebuffer.viewport[2:])
        n = triangles.size
        self._vao.render(moderngl.TRIANGLES, vertices=n)
        if len(curve) > 1:
            self._vao.render(moderngl.LINE_STRIP, vertices=len(curve), first=n)
        self.ctx.disable(moderngl.BLEND)

    def release(self):
        self._vao.release()
        self._buffer.release()
        self.program.release()


class InspectorWindow(Window):
    """The player's glfw window, showing an :class:`InspectorApp`: the source frame under
    the playhead at the top, the timeline below, redrawn when something changed."""

    WITHOUT_DISPLAY = "`tvmedit correct` applies a corrections file without one"

    def __init__(self, app, size=(1024, 720), title="tvmedit inspect"):
        self.timeline_view = None
        super().__init__(app, size=size, title=title)
        glfw = self.glfw
        self._key_names.update({glfw.KEY_ENTER: "enter", glfw.KEY_KP_ENTER: "enter", glfw.KEY_TAB: "tab",
                                glfw.KEY_DELETE: "delete", glfw.KEY_HOME: "home", glfw.KEY_END: "end",
                                glfw.KEY_PAGE_UP: "page_up", glfw.KEY_PAGE_DOWN: "page_down"})
        self.timeline_view = TimelineView(self.ctx)
        self._scrub = False
        self._shown = None

    def run(self, seconds=None):
        glfw = self.glfw
        end = None if seconds is None else self.clock() + seconds
        try:
            while not glfw.window_should_close(self.window) and (end is None or self.clock() < end):
                glfw.wait_events_timeout(0.05)
                state = self._state()
                if state != self._shown or self._screenshot:
                    self._draw(self.clock())
                    glfw.swap_buffers(self.window)
                    self._shown = state
                    self.redraws += 1
        finally:
            self.close()
        return self.redraws

    def _state(self):
        app = self.app
        return (app.sequence, app.frame, repr(app.corrections), app.camera, app.message,
                tuple(self.ctx.screen.viewport), id(app.library))

    def _boxes(self):
        width, height = self.glfw.get_framebuffer_size(self.window)
        top = int(round(height * (1 - TIMELINE_SHARE)))
        return (width, height, top), (0, top, width, height - top)

    def _draw(self, now):
        app, screen = self.app, self.ctx.screen
        (width, height, top), box = self._boxes()
        mesh = app.mesh()
        screen.viewport = (0, height - top, width, top)
        if mesh is None:
            screen.use()
            screen.clear(*self.renderer.background)
        else:
            self.renderer.draw(mesh, app.camera, framebuffer=screen)
        screen.viewport = (0, 0, width, height)
        self.timeline_view.draw(app.timeline.shapes(box, app.frame), screen)
        columns = max(self.overlay.columns(width // 2), 20)
        lines = app.status_lines() + (textwrap.wrap(app.message, columns) if app.message else [])
        self.overlay.draw([Label(lines, "top-left"), Label(HELP_LINES, "top-right", colour=(0.85, 0.9, 1.0))],
                          screen)
        if self._screenshot:
            self._screenshot = False
            self._save_screenshot()

    def close(self):
        if self.window is not None and self.timeline_view is not None:
            self.timeline_view.release()
        super().close()

    def _resize(self, width, height):
        if width > 0 and height > 0:
            self.ctx.screen.viewport = (0, 0, width, height)
            self.app.set_aspect(width / max(1.0, height * (1 - TIMELINE_SHARE)))

    def _on_key(self, _window, key, scancode, action, mods):
        glfw = self.glfw
        if action == glfw.RELEASE:
            return
        name = self._key_names.get(key) or glfw.get_key_name(key, scancode)
        if name is None or (action == glfw.REPEAT and name not in ("left", "right", "up", "down")):
            return
        command = self.app.press(name.lower())
        if command == "quit":
            glfw.set_window_should_close(self.window, True)
        elif command == "screenshot":
            self._screenshot = True

    def _pixel(self, x, y):
        """Cursor position in framebuffer pixels."""
        (fb_w, fb_h, _), _ = self._boxes()
        w, h = self.glfw.get_window_size(self.window)
        return x * fb_w / max(w, 1), y * fb_h / max(h, 1)

    def _on_mouse_button(self, window, button, action, _mods):
        if button != self.glfw.MOUSE_BUTTON_LEFT:
            return
        x, y = self._pixel(*self.glfw.get_cursor_pos(window))
        (_, _, top), box = self._boxes()
        self._scrub = action == self.glfw.PRESS and y >= top
        if self._scrub:
            self.app.seek(self.app.timeline.frame_at(x, box))
        super()._on_mouse_button(window, button, action if not self._scrub else self.glfw.RELEASE, _mods)

    def _on_cursor(self, window, x, y):
        if self._scrub:
            px, _ = self._pixel(x, y)
            self.app.seek(self.app.timeline.frame_at(px, self._boxes()[1]))
        else:
            super()._on_cursor(window, x, y)
