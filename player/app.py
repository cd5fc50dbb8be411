"""What a user can do in the player, with no window: keys, the playback clock, the body's instant.

Two clocks run side by side (the playback clock is not the render clock). The window redraws
at the display rate, so camera moves stay smooth, while the sequence advances at the
library's frame rate: a sequence frame is due every ``1 / fps`` seconds, and its mesh is
fetched from the library once, when it is first shown; redraws in between pass the same
arrays, which ``Renderer.draw`` recognises and does not upload again, and place the body by
the redraw clock between that frame and the next (:meth:`PlayerApp.instant`, the display-rate
in-betweens of :mod:`tvmedit.engine.inbetween.instants`). Which frame comes next is decided by
:class:`tvmedit.engine.playback.Playhead`, the loop-then-transition rule of section 8: the
current texton is shown to its end, then each transition of the best path is taken as early
as the rule allows.

:class:`PlayerApp` holds everything a user can do (keys -> queue, clock -> frame, camera, the
text on screen, the ``--log``) and runs without a window or GL, so it is tested with a fake
clock; :class:`tvmedit.player.window.Window` is the glfw plumbing around it.
"""

import json
import math
import sys

import networkx as nx

from ..engine.playback import Playhead
from ..engine.errors import NoPath
from .camera import CameraControls
from .source import check_shading, texture_of

#: Letters that are commands, so they never queue a motion.
COMMAND_LETTERS = "qrs"

#: A stall longer than this (a window drag, a slow disk) restarts the playback clock instead of
#: rushing through the frames it missed.
MAX_LAG_S = 0.25

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
