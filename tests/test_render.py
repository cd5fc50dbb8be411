"""Renderer and headless output on an EGL context (skipped with the reason where EGL is missing).

Scenes are built from fixed numpy/trimesh primitives, never from generated data, so the
reference images in ``tests/reference`` change only when the renderer does
(``tests/regen_references.py`` rewrites them).
"""

import dataclasses
import os
from pathlib import Path
from types import SimpleNamespace

import imageio.v2 as iio2
import imageio.v3 as iio
import numpy as np
import pytest
import trimesh

from tvmedit import player
from tvmedit.engine.errors import InputError
from tvmedit.player.camera import Camera
from tvmedit.player.renderer import ANTIALIAS, BACKGROUND, Renderer, is_software

pytestmark = pytest.mark.gl

REFERENCE = Path(__file__).resolve().parent / "reference"
SIZE = (160, 120)
BACKGROUND_RGB = np.round(np.asarray(BACKGROUND) * 255).astype(np.uint8)
TOLERANCE = 3.0
"""Mean absolute error (0..255 levels, over the subject's pixels) allowed against a reference
image: drivers rasterise edges and round colours slightly differently; a wrong colour, light or
pose moves it far above this."""


def figure():
    """A red tower (0.4 x 0.3 x 1.6 m) with a blue arm sticking out to +X at shoulder height:
    asymmetric, so turning the camera changes its silhouette. 16 vertices, 24 faces."""
    tower = trimesh.creation.box((0.4, 0.3, 1.6))
    tower.apply_translation((0.0, 0.0, 0.8))
    arm = trimesh.creation.box((0.6, 0.15, 0.15))
    arm.apply_translation((0.5, 0.0, 1.3))
    positions = np.vstack([tower.vertices, arm.vertices])
    faces = np.vstack([tower.faces, arm.faces + len(tower.vertices)])
    colours = np.vstack([np.tile([200, 40, 30], (len(tower.vertices), 1)),
                         np.tile([40, 70, 210], (len(arm.vertices), 1))]).astype(np.uint8)
    return positions, colours, faces


def ball():
    """An icosphere of radius 0.5 m at z = 1 coloured by height, 642 vertices, 1280 faces."""
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    positions = sphere.vertices + (0.0, 0.0, 1.0)
    t = (positions[:, 2:3] - 0.5)
    colours = np.round(255 * np.hstack([t, 0.3 + 0.4 * t, 1 - t])).clip(0, 255).astype(np.uint8)
    return positions, colours, sphere.faces


def slab(colour):
    """A 1 x 1 m slab facing -Y (the default camera), 0.1 m thick, of one colour."""
    box = trimesh.creation.box((1.0, 0.1, 1.0))
    box.apply_translation((0.0, 0.0, 1.0))
    return box.vertices, np.tile(colour, (len(box.vertices), 1)).astype(np.uint8), box.faces


def scene_source():
    return player.ArraySource({("figure", 0): figure(), ("ball", 0): ball()})


def reference_scenes():
    """name -> function(ctx) returning the (120, 160, 3) image that ``tests/reference/<name>.png`` holds.

    They are drawn with FXAA, the default on the software GL the tests run on, named here so
    that a GPU (whose default is multisampling) draws the same images."""
    source = scene_source()
    aspect = SIZE[0] / SIZE[1]
    front = Camera.framing(source.bounds(), aspect, azimuth=-90, elevation=10)

    def figure_front(ctx):
        return _render(ctx, source.frame_mesh(("figure", 0)), front, antialias="fxaa")

    def figure_orbit_grid(ctx):
        return _render(ctx, source.frame_mesh(("figure", 0)), front.orbit(50), grid=True, antialias="fxaa")

    def ball_facets(ctx):
        positions, colours, faces, _ = source.frame_mesh(("ball", 0))
        return _render(ctx, (positions, colours, faces, None), front, antialias="fxaa")

    return {"figure_front": figure_front, "figure_orbit_grid": figure_orbit_grid, "ball_facets": ball_facets}


def _render(ctx, mesh, camera, size=SIZE, **options):
    renderer = Renderer(ctx, size, **options)
    try:
        renderer.draw(mesh, camera)
        return renderer.read()
    finally:
        renderer.release()


@pytest.fixture(autouse=True)
def no_gl_errors(ctx):
    assert ctx.error == "GL_NO_ERROR"
    yield
    assert ctx.error == "GL_NO_ERROR"


def foreground(image):
    return np.any(image != BACKGROUND_RGB, axis=2)


def neighbourhood(mask):
    """``mask`` grown by one pixel in the four directions."""
    grown = mask.copy()
    grown[1:] |= mask[:-1]
    grown[:-1] |= mask[1:]
    grown[:, 1:] |= mask[:, :-1]
    grown[:, :-1] |= mask[:, 1:]
    return grown


def not_flat(image):
    """Pixels that differ from one of their four neighbours (the edges FXAA may touch)."""
    pixels = image.astype(np.int16)
    edge = np.zeros(image.shape[:2], bool)
    for axis in (0, 1):
        step = np.any(np.diff(pixels, axis=axis) != 0, axis=2)
        if axis == 0:
            edge[1:] |= step
            edge[:-1] |= step
        else:
            edge[:, 1:] |= step
            edge[:, :-1] |= step
    return edge


@pytest.mark.parametrize("name", sorted(reference_scenes()))
def test_matches_reference_image(ctx, name):
    image = reference_scenes()[name](ctx)
    path = REFERENCE / f"{name}.png"
    assert path.exists(), f"{path} is missing: run .venv/bin/python tests/regen_references.py"
    expected = iio.imread(path)[..., :3]
    error = np.abs(image.astype(np.int16) - expected.astype(np.int16))
    # Averaged over the subject (where either image is not background), so that a subject
    # covering a tenth of the image cannot hide a change behind the untouched background.
    subject = foreground(image) | foreground(expected)
    mean_error = error[subject].mean() if subject.any() else 0.0
    if mean_error > TOLERANCE:
        iio.imwrite(path.with_suffix(".actual.png"), image)
        iio.imwrite(path.with_suffix(".diff.png"), np.clip(error * 4, 0, 255).astype(np.uint8))
        pytest.fail(f"{name}: mean abs error {mean_error:.2f} over the subject > {TOLERANCE}; "
                    f"see {path.with_suffix('.actual.png').name} and {path.with_suffix('.diff.png').name}")


def test_colour_of_a_front_facing_surface_survives_and_background_stays(ctx):
    colour = np.array([200, 120, 40])
    source = player.ArraySource({("slab", 0): slab(colour)})
    image = _render(ctx, source.frame_mesh(("slab", 0)), Camera.framing(source.bounds(), 4 / 3, elevation=0))
    centre = image[50:70, 70:90].reshape(-1, 3).astype(int)
    assert np.abs(centre - colour).max() <= 20, centre.mean(axis=0)
    assert (image[:3, :3] == BACKGROUND_RGB).all() and (image[-3:, -3:] == BACKGROUND_RGB).all()
    assert foreground(image).mean() > 0.4, "the framed slab should fill a large part of the view"


def test_orbit_moves_the_silhouette_and_a_full_turn_restores_it(ctx):
    positions, colours, faces = figure()
    source = player.ArraySource({("figure", 0): (positions, colours, faces)})
    mesh = source.frame_mesh(("figure", 0))
    camera = Camera.framing(source.bounds(), 4 / 3, all_azimuths=True)
    masks = [foreground(_render(ctx, mesh, camera.orbit(deg))) for deg in (0, 90, 360)]
    assert (masks[0] != masks[1]).mean() > 0.02
    assert (masks[0] != masks[2]).mean() < 0.001


def test_frames_of_different_sizes_leave_no_stale_triangles(ctx):
    source = scene_source()
    small, large = source.frame_mesh(("figure", 0)), source.frame_mesh(("ball", 0))
    camera = Camera.framing(source.bounds(), 4 / 3)
    renderer = Renderer(ctx, SIZE, max_counts=(len(small[0]), len(small[2])))
    try:
        images = []
        for mesh in (small, large, small):
            renderer.draw(mesh, camera)
            images.append(renderer.read())
    finally:
        renderer.release()
    assert np.array_equal(images[0], images[2])
    assert np.array_equal(images[1], _render(ctx, large, camera))
    assert not np.array_equal(images[0], images[1])


def test_draws_only_the_frames_own_faces(ctx):
    positions, colours, faces, normals = scene_source().frame_mesh(("figure", 0))
    camera = Camera.framing(scene_source().bounds(), 4 / 3)
    tower_only = faces[:12]
    renderer = Renderer(ctx, SIZE)
    try:
        renderer.draw((positions, colours, faces, normals), camera)
        renderer.draw((positions, colours, tower_only, normals), camera)
        image = renderer.read()
    finally:
        renderer.release()
    blue = (image[..., 2] > 120) & (image[..., 0] < 100)
    assert not blue.any(), "the arm's faces of the previous frame are still drawn"
    assert foreground(image).any()


def test_auto_antialiasing_is_fxaa_on_software_gl_and_msaa_on_a_gpu(ctx):
    renderer = Renderer(ctx, SIZE)
    try:
        if is_software(ctx):
            assert (renderer.antialias, renderer.samples) == ("fxaa", 0)
        else:
            assert renderer.antialias == "msaa" and renderer.samples > 1
    finally:
        renderer.release()
    explicit = Renderer(ctx, SIZE, antialias="msaa", samples=0)
    try:
        assert (explicit.antialias, explicit.samples) == ("none", 0), "samples=0 asks for no multisampling"
    finally:
        explicit.release()
    with pytest.raises(ValueError, match="antialias"):
        Renderer(ctx, SIZE, antialias="ssaa")


@pytest.mark.parametrize("antialias", ["msaa", "fxaa"])
def test_antialiasing_draws_the_same_silhouette_as_none(ctx, antialias):
    source = scene_source()
    mesh, camera = source.frame_mesh(("figure", 0)), Camera.framing(source.bounds(), 4 / 3).orbit(20)
    hard = foreground(_render(ctx, mesh, camera, antialias="none"))
    smooth = foreground(_render(ctx, mesh, camera, antialias=antialias))
    band = neighbourhood(hard) & neighbourhood(~hard)  # one pixel either side of the outline
    assert (smooth != hard).any(), "anti-aliasing should change the outline's pixels"
    assert not ((smooth != hard) & ~band).any(), "anti-aliasing moved the silhouette"


def test_fxaa_softens_edges_and_leaves_flat_areas_alone(ctx):
    positions, colours, faces, _ = scene_source().frame_mesh(("ball", 0))
    mesh = (positions, colours, faces, None)  # flat facets: edges inside the silhouette too
    camera = Camera.framing(scene_source().bounds(), 4 / 3, azimuth=-70, elevation=20)
    hard = _render(ctx, mesh, camera, antialias="none")
    soft = _render(ctx, mesh, camera, antialias="fxaa")
    changed = np.any(soft != hard, axis=2)
    assert not (changed & ~not_flat(hard)).any(), "FXAA touched a pixel whose neighbours all match it"
    # On the outline, FXAA mixes the ball's colours with the background's: the aliased image has
    # only ball or background colours there, the smoothed one many in-between.
    outline = neighbourhood(foreground(hard)) & neighbourhood(~foreground(hard))
    assert changed[outline].mean() > 0.5
    colours_on_outline = [len(np.unique(image[outline], axis=0)) for image in (hard, soft)]
    assert colours_on_outline[1] > 1.3 * colours_on_outline[0], colours_on_outline
    assert np.abs(soft.astype(int) - hard.astype(int)).mean() < 0.5


@pytest.mark.parametrize("antialias", ANTIALIAS)
def test_a_given_framebuffer_gets_the_same_picture_upright_at_its_own_size(ctx, antialias):
    # The window passes ctx.screen, whose size follows the window: the renderer draws at the
    # framebuffer's size, not its own, and (unlike its own framebuffer) right side up.
    source = scene_source()
    mesh, camera = source.frame_mesh(("figure", 0)), Camera.framing(source.bounds(), 4 / 3).orbit(20)
    renderer = Renderer(ctx, SIZE, antialias=antialias)
    targets = [ctx.simple_framebuffer(size, components=4) for size in ((96, 72), SIZE)]
    try:
        images = []
        for target in targets:
            renderer.draw(mesh, camera, framebuffer=target)
            pixels = np.frombuffer(target.read(components=3, alignment=1), np.uint8)
            images.append(pixels.reshape(target.height, target.width, 3)[::-1])
        # A given framebuffer multisamples by itself (a window asks for it); these do not.
        drawn = "none" if renderer.antialias == "msaa" else renderer.antialias
        expected = [_render(ctx, mesh, camera, size=target.size, antialias=drawn) for target in targets]
    finally:
        renderer.framebuffer.use()
        for target in targets:
            target.release()
        renderer.release()
    for image, reference in zip(images, expected):
        assert image.shape == reference.shape
        # Upright and at the target's size: the same picture as the renderer's own output
        # (a flipped image differs by several levels on average).
        assert np.abs(image.astype(float) - reference).mean() < 0.5


@pytest.mark.parametrize("view", ["framed", "close", "inside"])
def test_fxaa_on_the_meshs_box_equals_a_pass_over_the_whole_image(ctx, view):
    # The own framebuffer gets FXAA only on the mesh's box on screen, a window's the whole
    # pass: both must give the same picture, grid included, also when the mesh leaves the frame
    # or the eye is inside the mesh's bounding box.
    source = scene_source()
    mesh = source.frame_mesh(("figure", 0))
    camera = Camera.framing(source.bounds(), 4 / 3).orbit(20)
    camera = {"framed": camera, "close": dataclasses.replace(camera, distance=0.45 * camera.distance),
              "inside": dataclasses.replace(camera, distance=0.3)}[view]
    renderer = Renderer(ctx, SIZE, antialias="fxaa", grid=True)
    target = ctx.simple_framebuffer(SIZE, components=4)
    try:
        renderer.draw(mesh, camera)
        own = renderer.read()
        renderer.draw(mesh, camera, framebuffer=target)
        whole = np.frombuffer(target.read(components=3, alignment=1), np.uint8).reshape(own.shape)[::-1]
    finally:
        renderer.framebuffer.use()
        target.release()
        renderer.release()
    assert foreground(own).any()
    difference = np.abs(own.astype(int) - whole).max(axis=2)
    # Drawn upside down, the grid's blending may round a few pixels the other way.
    assert difference.max() <= 2 and (difference > 0).mean() < 0.001, (difference > 0).sum()


def test_the_fxaa_box_holds_the_mesh_or_the_whole_image_behind_the_eye():
    from tvmedit.player.renderer import _screen_box

    camera = Camera(target=(0, 0, 1), azimuth=-90, elevation=0, distance=3, aspect=4 / 3)
    matrix = np.asarray(camera.view_matrix()) @ np.asarray(camera.projection_matrix())
    points = np.random.default_rng(0).uniform((-0.4, -0.3, 0.0), (0.4, 0.3, 1.8), (500, 3))
    x, y, w, h = _screen_box(points, matrix, SIZE)
    clip = np.c_[points, np.ones(len(points))] @ matrix
    pixel = np.clip((clip[:, :2] / clip[:, 3:] + 1) / 2 * SIZE, 0, SIZE)  # the box ends at the image's
    assert 0 < w < SIZE[0] and 0 < h < SIZE[1]
    assert (pixel >= (x, y)).all() and (pixel <= (x + w, y + h)).all()
    # The eye at (0, -3, 1): a mesh stretching from in front of it to behind it.
    assert np.allclose(camera.eye, (0, -3, 1))
    around_the_eye = np.array([[0.0, -2.0, 1.0], [0.1, -3.5, 1.1]])
    assert _screen_box(around_the_eye, matrix, SIZE) == (0, 0, *SIZE)
    assert _screen_box(np.zeros((0, 3)), matrix, SIZE)[2:] == (0, 0)


def test_render_frame_fits_the_subject_in_view(ctx):
    image = player.render_frame(scene_source(), ("figure", 0), size=SIZE)
    assert image.shape == (120, 160, 3) and image.dtype == np.uint8
    rows = np.flatnonzero(foreground(image).any(axis=1))
    assert rows[0] > 0 and rows[-1] < 119, "the subject touches the image edge"
    assert rows[-1] - rows[0] > 0.7 * 120, "the subject should fill most of the image height"


@pytest.mark.parametrize("name", ["out.mp4", "out.gif", "frames"])
def test_video_has_one_frame_per_scheduled_key(ctx, tmp_path, name):
    source = scene_source()
    keys = [("figure", 0), ("ball", 0), ("figure", 0), ("ball", 0), ("figure", 0)]
    out = player.render_frames(source, keys, tmp_path / name, size=(96, 72), fps=10, orbit_deg_per_s=90,
                               progress=False)
    assert sorted(os.listdir(tmp_path)) == [name], "a temporary file was left behind"
    if name == "frames":
        files = sorted(name for name in os.listdir(out) if name != ".tvmedit")
        assert files == [f"frame_{i:05d}.png" for i in range(len(keys))]
        assert iio.imread(out / files[0]).shape == (72, 96, 3)
    elif name.endswith(".mp4"):
        reader = iio2.get_reader(out)
        assert reader.count_frames() == len(keys)
        assert reader.get_data(0).shape == (72, 96, 3)
    else:
        assert len(iio2.mimread(out)) == len(keys)


def test_mp4_sizes_are_made_even(ctx, tmp_path):
    out = player.render_frames(scene_source(), [("ball", 0)], tmp_path / "odd.mp4", size=(97, 73), progress=False)
    assert iio2.get_reader(out).get_data(0).shape == (72, 96, 3)


def test_a_failed_render_leaves_nothing_behind(ctx, tmp_path):
    with pytest.raises(InputError, match="missing"):
        player.render_frames(scene_source(), [("figure", 0), ("missing", 3)], tmp_path / "out.mp4",
                             size=(96, 72), progress=False)
    assert os.listdir(tmp_path) == []


def test_render_takes_an_edits_library_and_schedule(ctx, tmp_path):
    schedule = [SimpleNamespace(sequence="figure", frame=0), ("ball", 0), SimpleNamespace(sequence="ball", frame=0)]
    edit = SimpleNamespace(library=scene_source(), schedule=schedule)
    out = player.render(edit, tmp_path / "edit", size=(64, 48), progress=False)
    assert len(list(out.glob("frame_*.png"))) == 3


def test_contact_sheet_tiles_frames_row_by_row(ctx, tmp_path):
    source = scene_source()
    keys = [("figure", 0), ("ball", 0), ("figure", 0)]
    sheet = player.contact_sheet(source, keys, tmp_path / "sheet.png", columns=2, tile=(80, 60), labels=False)
    assert sheet.shape == (120, 160, 3)
    assert np.array_equal(iio.imread(tmp_path / "sheet.png")[..., :3], sheet)
    tiles = [sheet[:60, :80], sheet[:60, 80:], sheet[60:, :80], sheet[60:, 80:]]
    assert np.array_equal(tiles[0], tiles[2])
    assert foreground(tiles[1]).any() and not np.array_equal(tiles[0], tiles[1])
    assert not foreground(tiles[3]).any(), "the empty slot should be background"
    labelled = player.contact_sheet(source, keys, tmp_path / "labelled.png", columns=2, tile=(80, 60))
    changed = np.any(labelled != sheet, axis=2)
    assert changed[:12, :60].any() and changed[60:72, :60].any(), "each tile should carry its label"
    assert not changed[12:60].any() and not changed[72:].any(), "labels belong in each tile's top-left corner"


def test_rendering_many_frames_does_not_grow_memory(ctx, tmp_path):
    # Each render_frame makes and releases a renderer; a framebuffer released without its
    # attachments left ~5 MB of 1024x768 renderbuffers behind per call.
    script = tmp_path / "many.py"
    script.write_text(
        "import resource, sys\n"
        "sys.path.insert(0, %r)\n"
        "from tvmedit import player\n"
        "from test_render import scene_source\n"
        "source = scene_source()\n"
        "player.render_frame(source, ('figure', 0), size=(1024, 768))\n"
        "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
        "for _ in range(60):\n"
        "    player.render_frame(source, ('figure', 0), size=(1024, 768))\n"
        "print((resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) // 1024)\n"
        % str(Path(__file__).parent))
    import subprocess
    import sys
    result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert int(result.stdout.strip()) < 100  # MB over 60 renders; the leak made about 280


def test_a_long_label_fits_its_tile_and_keeps_the_frame_number(ctx, tmp_path):
    from tvmedit.player.font import text_mask
    from tvmedit.player.headless import fitted_label

    source = scene_source()
    keys = [("figure", 0), ("ball", 0)]
    label = "geometry_draco/01 27"
    plain = player.contact_sheet(source, keys, tmp_path / "a.png", columns=2, tile=(160, 120), labels=False)
    sheet = player.contact_sheet(source, keys, tmp_path / "b.png", columns=2, tile=(160, 120), labels=[label] * 2)
    changed = np.any(sheet != plain, axis=2)
    columns = np.flatnonzero(changed[:20, :160].any(axis=0))
    assert columns.max() < 158, "the label must end inside its own tile"
    text, _, scale = fitted_label(label, 160, 2)
    assert text.endswith("01 27") and text_mask(text, scale).shape[1] + 2 * scale <= 156
    assert fitted_label("a_capture_with_a_very_long_name/01 27", 100, 1)[0].endswith("/01 27")
