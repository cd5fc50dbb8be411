"""Rendering without a display: single images, videos (MP4, GIF, PNG folders) and contact sheets.

Everything here draws through one ``Renderer`` on the process's shared EGL context and streams
frames to the output as they are drawn, so memory stays flat however long the schedule is
(except GIF, which Pillow writes in one go). Outputs are written under a temporary name next to
the target and renamed at the end, so a failure never leaves a half-written file.
"""

import contextlib
import math
from pathlib import Path

import imageio.v3 as iio
import imageio_ffmpeg
import numpy as np
from tqdm import tqdm

from ..engine import safewrite
from ..engine.errors import ParameterError
from ..engine.checks import MAX_FPS, number, whole
from .camera import Camera
from .context import shared_headless_context
from .font import draw_text
from .renderer import BACKGROUND, Renderer
from .source import check_shading, texture_of

FRAME_PATTERN = "frame_{:05d}.png"
#: Largest image side a GL context is sure to allocate (GL_MAX_TEXTURE_SIZE is 16384 or more).
MAX_SIZE = 8192
VIDEO_QUALITY = 7
"""imageio-ffmpeg's 1..10 scale; 7 is x264 CRF 15, visually clean for flat-shaded meshes."""


def render_frame(source, key, camera=None, size=(640, 480), grid=False, background=BACKGROUND, samples=4,
                 shading="auto"):
    """One frame of ``source`` as an (H, W, 3) uint8 sRGB image, first row at the top.

    Parameters
    ----------
    source : MeshSource (see ``tvmedit.player.source``)
    key : (sequence_name, frame_index)
    camera : ``Camera``; default frames ``source.bounds()`` from the front
    size : (width, height) in pixels
    shading : "auto" (the frame's texture where it has one), "texture" or "colour" (vertex
        colours); see ``tvmedit.player.source.SHADINGS``
    """
    size = _check_size(size)
    check_shading(source, shading)
    with _renderer(source, size, grid, background, samples) as renderer:
        renderer.draw(source.frame_mesh(key), _camera(camera, source.bounds(), size),
                      texture=texture_of(source, key, shading))
        return renderer.read()


def render_frames(source, keys, out, size=(640, 480), fps=10, camera=None, orbit_deg_per_s=0.0,
                  progress=True, grid=False, background=BACKGROUND, samples=4, force=False, shading="auto",
                  capture_fps=None, smooth=True):
    """Render ``keys`` in order into ``out`` and return its path.

    The kind of output follows ``out``'s suffix: ``.mp4`` (H.264, yuv420p; an odd width or
    height is rounded down to even, as yuv420p requires), ``.gif`` (looping), or no suffix for a
    folder of ``frame_00000.png``, ``frame_00001.png``, ... An existing output is replaced only
    with ``force``, and only a file of that kind or a folder of frames rendered before (see
    :func:`tvmedit.engine.safewrite.check_target`); nothing goes inside the source's own folders.

    Parameters
    ----------
    source : MeshSource
    keys : iterable of (sequence_name, frame_index), the frames shown one after another
    out : str or Path
    fps : frames per second of the output (and of the orbit)
    capture_fps : the rate ``keys`` are shown at; None: one output frame per key. Given, the
        output keeps their timing: ``len(keys) / capture_fps`` seconds at ``fps``, each output
        frame the surface at its instant (:func:`tvmedit.engine.inbetween.instants.instants`)
    smooth : draw the surface between two frames where the source holds the step's field
        (``instant_field``); False: each frame held until the next (the capture as it is)
    camera : ``Camera``; default frames ``source.bounds()`` so that no orbit angle cuts it
    orbit_deg_per_s : the camera turns this many degrees of azimuth per second of output
    progress : show a progress bar
    force : replace an existing output of the same kind
    shading : "auto", "texture" or "colour" (see :func:`render_frame`)
    """
    keys = list(keys)
    check_shading(source, shading)
    if not keys:
        raise ValueError("nothing to render: the list of frames is empty")
    fps = number("fps", fps, above=0, at_most=MAX_FPS)
    out = Path(out)
    kind = {".mp4": "mp4", ".gif": "gif", "": "folder"}.get(out.suffix.lower())
    if kind is None:
        raise ValueError(f"{out}: unknown output kind {out.suffix!r}; use .mp4, .gif, or no suffix for a folder of PNG frames")
    width, height = _check_size(size, smallest=2 if kind == "mp4" else 1)
    if kind == "mp4":
        width, height = width - width % 2, height - height % 2
    _check_output(out, kind, force, source)
    out.parent.mkdir(parents=True, exist_ok=True)
    # A library's frames hold the bytes written, or nothing is kept: the checksums name the
    # damaged files where a read fails here, then run beside the drawing.
    checked = (lambda beside: source.verifying(source.MESH_FILES, beside)) if hasattr(source, "verifying") \
        else (lambda beside: contextlib.nullcontext())
    with checked(False):
        base = _camera(camera, source.bounds(), (width, height), all_azimuths=bool(orbit_deg_per_s))
        shown = list(_shown(source, keys, capture_fps, fps, smooth))
    bar = tqdm(shown, desc=f"render {out.name}", unit="frame", disable=not progress)
    # A folder is swapped in whole; a file is written under a temporary name with its suffix.
    target = safewrite.replacing_folder(out, kind="frames") if kind == "folder" else safewrite.replacing_file(out)
    try:
        with target as temporary, checked(True), _renderer(source, (width, height), grid, background, samples) as renderer:
            frames = (_draw(renderer, source, key, base.orbit(orbit_deg_per_s * i / fps), shading, instant)
                      for i, (key, instant) in enumerate(bar))
            _WRITERS[kind](frames, temporary, (width, height), fps)
    finally:
        bar.close()
    return out


def render(edit, out, size=(640, 480), **options):
    """Render an edit: ``render_frames(edit.library, edit.schedule keys, out, size, **options)``,
    at the edit's own timing (``capture_fps=edit.fps`` unless given).

    ``edit.library`` is a MeshSource; ``edit.schedule`` lists frames as ``(sequence, frame)``
    pairs or as schedule entries (their ``.key``, which names in-between frames too).
    """
    keys = [item.key if hasattr(item, "key") else (item.sequence, item.frame) if hasattr(item, "sequence")
            else tuple(item) for item in edit.schedule]
    options.setdefault("capture_fps", getattr(edit, "fps", None))
    options.setdefault("fps", options["capture_fps"] or 10)
    return render_frames(edit.library, keys, out, size=size, **options)


def spread_frames(start, end, count):
    """Up to ``count`` evenly spaced frames from ``start`` to ``end`` inclusive, no repeats: the
    frames a contact sheet of a long motion shows.

    >>> spread_frames(10, 24, 8)
    [10, 12, 14, 16, 18, 20, 22, 24]
    >>> spread_frames(3, 5, 8), spread_frames(0, 149, 4)
    ([3, 4, 5], [0, 50, 99, 149])
    """
    return sorted({int(round(v)) for v in np.linspace(start, end, min(count, end - start + 1))})


def fitted_label(text, width, scale):
    """``(text, position, scale)`` of a tile's label that fits ``width`` pixels: the scale made
    smaller first, then the start of the text left out ("..") so that its end (the frame
    number) stays readable.

    >>> fitted_label("geometry_draco/01 27", 160, 2)
    ('geometry_draco/01 27', (2, 2), 1)
    >>> fitted_label("gym/01 71", 160, 2)
    ('gym/01 71', (2, 2), 2)
    >>> fitted_label("a_capture_with_a_very_long_name/01 27", 100, 1)
    ('.._very_long_name/01 27', (2, 2), 1)
    """
    room = width - 4                                     # 2 px each side, the backing's margin
    for size in range(scale, 0, -1):
        if (4 * len(text) - 1) * size + 2 * size <= room:
            return text, (2, 2), size
    keep = max(1, (room - 1) // 4 - 2)                   # characters at scale 1 beside ".."
    return ".." + text[len(text) - keep:], (2, 2), 1


def contact_sheet(source, keys, out_png, columns=8, tile=(160, 120), labels=True, camera=None,
                  grid=False, background=BACKGROUND, samples=4, force=False, shading="auto"):
    """Render ``keys`` as tiles of one PNG grid, row by row, and return the image (H, W, 3) uint8.

    All tiles share one camera, framed on the union of these frames only (not the whole source),
    so a cycle of frames appears large and its motion comparable from tile to tile.

    Parameters
    ----------
    columns : tiles per row (fewer if there are fewer frames)
    tile : (width, height) of each tile in pixels
    labels : True to label each tile "sequence frame", a list of strings (one per key), or
        False for none
    force : replace an existing PNG at ``out_png``
    shading : "auto", "texture" or "colour" (see :func:`render_frame`)
    """
    keys = list(keys)
    check_shading(source, shading)
    _check_output(Path(out_png), "png", force, source)
    if not keys:
        raise ValueError("nothing to render: the list of frames is empty")
    if labels is True:
        labels = [f"{key[0]} {key[1]}" for key in keys]
    elif labels and len(labels) != len(keys):
        raise ValueError(f"labels should give one string per frame: {len(labels)} labels for {len(keys)} frames")
    columns = max(1, min(int(columns), len(keys)))
    rows = math.ceil(len(keys) / columns)
    tw, th = _check_size(tile)
    meshes = [source.frame_mesh(key) for key in keys]
    low = np.min([m[0].min(axis=0) for m in meshes], axis=0)
    high = np.max([m[0].max(axis=0) for m in meshes], axis=0)
    sheet = np.empty((rows * th, columns * tw, 3), np.uint8)
    sheet[:] = np.round(np.asarray(background) * 255).astype(np.uint8)
    with _renderer(source, (tw, th), grid, background, samples) as renderer:
        cam = _camera(camera, (low, high), (tw, th))
        for i, (key, mesh) in enumerate(zip(keys, meshes)):
            renderer.draw(mesh, cam, texture=texture_of(source, key, shading))
            image = renderer.read()
            if labels:
                draw_text(image, *fitted_label(str(labels[i]), tw, 1 if th < 100 else 2))
            r, c = divmod(i, columns)
            sheet[r * th:(r + 1) * th, c * tw:(c + 1) * tw] = image
    out_png = Path(out_png)
    out_png.parent.mkdir(parents=True, exist_ok=True)
    with safewrite.replacing_file(out_png) as temporary:
        iio.imwrite(temporary, sheet, extension=".png")
    return sheet


@contextlib.contextmanager
def _renderer(source, size, grid, background, samples):
    renderer = Renderer(shared_headless_context(), size, samples=samples, max_counts=source.max_counts(),
                        background=background, grid=grid)
    try:
        yield renderer
    finally:
        renderer.release()


def _draw(renderer, source, key, camera, shading="auto", instant=None):
    renderer.draw(source.frame_mesh(key), camera, texture=texture_of(source, key, shading), instant=instant)
    return renderer.read()


def _shown(source, keys, capture_fps, fps, smooth):
    """``(key, instant)`` of each output frame: the frame, and ``(field, s)`` of the step to
    the next one or None (the frame as stored); see :func:`tvmedit.engine.inbetween.instants.shown`.
    A step's field is the same object for the frames inside it, so the renderer uploads it once."""
    from ..engine.inbetween.instants import shown

    if capture_fps is None:
        yield from ((key, None) for key in keys)
        return
    fields = getattr(source, "instant_field", None) if smooth else None
    field_of = (lambda i: fields(keys[i], keys[i + 1])) if fields is not None else (lambda i: None)
    for index, s, field in shown(len(keys), capture_fps, fps, field_of):
        yield keys[index], None if field is None else (field, s)


def _camera(camera, bounds, size, all_azimuths=False):
    aspect = size[0] / size[1]
    if camera is None:
        return Camera.framing(bounds, aspect, all_azimuths=all_azimuths)
    return camera.with_aspect(aspect)


def _check_size(size, smallest=1):
    """``(width, height)`` as whole pixel counts from ``smallest`` to :data:`MAX_SIZE`."""
    try:
        width, height = size
    except (TypeError, ValueError):
        raise ParameterError(f"size={size!r} must be a (width, height) pair of pixel counts.") from None
    why = " (an MP4 is encoded in 2x2 blocks)" if smallest > 1 else ""
    try:
        return tuple(whole("size", v, at_least=smallest, at_most=MAX_SIZE) for v in (width, height))
    except ParameterError:
        raise ParameterError(f"size=({width}, {height}) is out of range: width and height must be "
                             f"whole pixel counts from {smallest} to {MAX_SIZE}{why}.") from None


def _legacy_frames(path):
    """A folder of frames rendered before the ownership marker: frame_*.png and nothing else."""
    names = [p.name for p in path.iterdir()]
    if not any(n.startswith("frame_") and n.endswith(".png") for n in names):
        return None
    return [n for n in names if not (n.startswith("frame_") and n.endswith(".png"))]


def _check_output(out, kind, force, source):
    inputs = source.sources() if hasattr(source, "sources") else ()
    if kind == "folder":
        safewrite.check_target(out, "frames", force, inputs=inputs, legacy=_legacy_frames)
    else:
        safewrite.check_file_target(out, force, inputs=inputs)


def _write_mp4(frames, path, size, fps):
    writer = imageio_ffmpeg.write_frames(str(path), size, fps=fps, codec="libx264", pix_fmt_out="yuv420p",
                                         quality=VIDEO_QUALITY, macro_block_size=2, ffmpeg_log_level="error")
    writer.send(None)
    try:
        for image in frames:
            writer.send(image)
    finally:
        writer.close()


def _write_gif(frames, path, size, fps):
    # Pillow merges consecutive identical frames into one longer frame; playback is the same.
    iio.imwrite(path, np.stack(list(frames)), extension=".gif", plugin="pillow",
                duration=1000.0 / fps, loop=0)


def _write_folder(frames, path, size, fps):
    for i, image in enumerate(frames):
        iio.imwrite(path / FRAME_PATTERN.format(i), image)


_WRITERS = {"mp4": _write_mp4, "gif": _write_gif, "folder": _write_folder}
