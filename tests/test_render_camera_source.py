"""The player's parts that need no GL context: camera framing, mesh sources, normals, labels, shader text."""

import numpy as np
import pytest
import trimesh

from tvmedit.engine.errors import InputError
from tvmedit.player.camera import Camera
from tvmedit.player.font import draw_text, text_mask
from tvmedit.player.programs import stage_source
from tvmedit.player.source import ArraySource, vertex_normals

PERSON = ((-0.3, -0.15, 0.0), (0.3, 0.15, 1.8))


def _ndc(camera, points):
    """Normalised device coordinates (x, y) of world points, and their depth in front of the eye."""
    h = np.hstack([points, np.ones((len(points), 1))])
    # pyrr's matrices are laid out for row vectors: clip = p @ view @ projection.
    clip = h @ camera.view_matrix() @ camera.projection_matrix()
    return clip[:, :2] / clip[:, 3:], clip[:, 3]


def _corners(bounds):
    (x0, y0, z0), (x1, y1, z1) = bounds
    return np.array([[x, y, z] for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)], float)


@pytest.mark.parametrize("azimuth, elevation, aspect", [(-90, 10, 4 / 3), (-30, 25, 16 / 9), (0, 0, 0.75)])
def test_framing_keeps_every_corner_in_view_and_fills_it(azimuth, elevation, aspect):
    camera = Camera.framing(PERSON, aspect, azimuth=azimuth, elevation=elevation, margin=1.08)
    ndc, depth = _ndc(camera, _corners(PERSON))
    assert (depth > camera.near).all() and (depth < camera.far).all()
    assert np.abs(ndc).max() <= 1 / 1.08 + 1e-6
    assert np.abs(ndc).max() > 1 / 1.08 - 1e-3, "some corner should touch the margin: the subject fills the view"


def test_framing_for_an_orbit_keeps_the_subject_in_view_at_every_azimuth():
    wide = ((-2.0, -0.2, 0.0), (2.0, 0.2, 1.8))
    camera = Camera.framing(wide, 4 / 3, all_azimuths=True)
    for degrees in range(0, 360, 15):
        ndc, _ = _ndc(camera.orbit(degrees), _corners(wide))
        assert np.abs(ndc).max() <= 1.0
    assert camera.distance > Camera.framing(wide, 4 / 3).distance


def test_orbit_turns_the_eye_around_the_target_at_the_same_distance():
    camera = Camera(target=(1.0, 2.0, 1.0), azimuth=-90, elevation=0, distance=3.0)
    turned = camera.orbit(90)
    assert np.allclose(camera.eye, (1.0, -1.0, 1.0)) and np.allclose(turned.eye, (4.0, 2.0, 1.0))
    assert np.allclose(camera.orbit(360).eye, camera.eye)


def test_the_image_has_z_up_and_x_to_the_right_from_the_default_camera():
    camera = Camera.framing(PERSON, 4 / 3)
    ndc, _ = _ndc(camera, np.array([[0.0, 0.0, 1.8], [0.0, 0.0, 0.0], [0.3, 0.0, 0.9], [-0.3, 0.0, 0.9]]))
    assert ndc[0, 1] > ndc[1, 1] and ndc[2, 0] > ndc[3, 0]


def test_bad_bounds_are_refused_in_words():
    with pytest.raises(ValueError, match="bounds"):
        Camera.framing(((0, 0, 0), (np.nan, 1, 1)), 1.0)


def test_vertex_normals_of_a_sphere_point_outwards_and_weigh_faces_by_area():
    sphere = trimesh.creation.icosphere(subdivisions=2)
    normals = vertex_normals(sphere.vertices, sphere.faces)
    unit = sphere.vertices / np.linalg.norm(sphere.vertices, axis=1, keepdims=True)
    assert normals.dtype == np.float32 and (np.sum(normals * unit, axis=1) > 0.99).all()
    # A big and a tiny triangle sharing vertex 0: the big one dominates that vertex's normal.
    p = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [0, 0.1, 0], [0, 0, 0.1]], float)
    n = vertex_normals(p, np.array([[0, 1, 2], [0, 3, 4]]))
    assert n[0, 2] > 0.99 and np.allclose(n[3], (1, 0, 0))


def test_array_source_answers_the_protocol():
    sphere = trimesh.creation.icosphere(subdivisions=1)
    box = trimesh.creation.box((2, 2, 2))
    source = ArraySource({
        ("a", 0): (sphere.vertices, np.zeros((len(sphere.vertices), 3), np.uint8), sphere.faces),
        ("b", 7): (box.vertices + 5, np.full((8, 3), 255), box.faces),
    })
    positions, colours, faces, normals = source.frame_mesh(("b", 7))
    assert (positions.dtype, colours.dtype, faces.dtype, normals.dtype) == (np.float32, np.uint8, np.uint32, np.float32)
    assert normals.shape == (8, 3)
    assert source.max_counts() == (len(sphere.vertices), len(sphere.faces))
    assert np.allclose(source.bounds(), ((-1, -1, -1), (6, 6, 6)))
    with pytest.raises(InputError, match="not in this source"):
        source.frame_mesh(("a", 1))


@pytest.mark.parametrize("positions, colours, faces, words", [
    (np.zeros((3, 2)), np.zeros((3, 3)), [[0, 1, 2]], "positions"),
    (np.zeros((3, 3)), np.zeros((4, 3)), [[0, 1, 2]], "colours"),
    (np.zeros((3, 3)), np.full((3, 3), 300), [[0, 1, 2]], "0..255"),
    (np.zeros((3, 3)), np.zeros((3, 3)), [[0, 1, 3]], "outside 0..2"),
    (np.full((3, 3), np.nan), np.zeros((3, 3)), [[0, 1, 2]], "NaN"),
])
def test_array_source_names_the_frame_and_the_problem(positions, colours, faces, words):
    with pytest.raises(InputError, match=words) as error:
        ArraySource({("walk", 4): (positions, colours, faces)})
    assert "('walk', 4)" in str(error.value)


def test_labels_are_drawn_in_the_corner_and_clipped_at_the_edge():
    image = np.zeros((20, 30, 3), np.uint8)
    draw_text(image, "A1", (2, 2))
    assert text_mask("A1").shape == (5, 7)
    assert image[2:7, 2:9].any() and not image[9:].any() and not image[:, 10:].any()
    draw_text(image, "WIDE LABEL TEXT", (25, 17), scale=2)  # must not raise
    assert image[18:, 25:].any()


def test_shader_stages_define_their_stage_and_variant_right_after_version():
    text = stage_source("mesh", "FRAGMENT_SHADER", (("FACET_NORMALS", 1),))
    lines = text.splitlines()
    assert lines[0].startswith("#version") and lines[1:3] == ["#define FRAGMENT_SHADER", "#define FACET_NORMALS 1"]


def test_a_missing_egl_is_reported_in_one_sentence_naming_the_packages(monkeypatch):
    import moderngl

    from tvmedit.player.context import ContextError, headless_context

    def no_egl(**options):
        raise Exception("libEGL.so.1: cannot open shared object file: No such file or directory")

    monkeypatch.setattr(moderngl, "create_context", no_egl)
    with pytest.raises(ContextError) as error:
        headless_context()
    message = str(error.value)
    assert "libEGL.so.1" in message and "libegl1 libegl-mesa0 libgl1-mesa-dri" in message
    assert "\n" not in message
