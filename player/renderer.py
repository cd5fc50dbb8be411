"""Draws one frame of a time-varying mesh; shared by headless output and the realtime window.

Topology changes every frame, so the renderer keeps one set of GPU buffers sized for the largest
frame and overwrites the front of them each frame (``Buffer.write`` at offset 0), drawing only
the frame's own face count; they grow only when a larger frame appears. The context decides
where pixels go: headless rendering draws into the renderer's own framebuffer and reads it
back, the window passes ``ctx.screen``.

Anti-aliasing is either 4x multisampling (MSAA) or FXAA, one fullscreen pass that softens the
edges it finds in the finished image (``shaders/fxaa.glsl``). On a GPU multisampling is nearly
free and better; a software rasteriser shades every sample on the CPU, where 4x MSAA about
triples the frame time and FXAA adds about a third, so by default each gets its own. With FXAA
the scene (grid included) is drawn into a texture sized like the output, which the pass then
copies into the output, anti-aliased and the same way up. The scene's alpha marks the mesh, and
the pass changes only pixels next to it (the grid's lines are anti-aliased already), so for the
own framebuffer it covers just the mesh's box on screen and ``read`` takes the rest of the image
from the scene texture: the pass then costs what the person's pixels cost, not the image's.
"""

import moderngl
import numpy as np

from .programs import load_program

BACKGROUND = (0.12, 0.13, 0.15)
"""Default clear colour, sRGB in 0..1."""

ANTIALIAS = ("auto", "msaa", "fxaa", "none")
"""Anti-aliasing modes; "auto" is FXAA on a software rasteriser and MSAA otherwise."""

SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "swiftshader", "software rasterizer", "gdi generic")
"""Words in ``GL_RENDERER`` that mark a rasteriser running on the CPU (Mesa, Google, Windows)."""

_GROWTH = 1.25
"""Buffers grow by this factor beyond the frame that outgrew them, so slowly growing
sequences do not reallocate every frame."""


class Renderer:
    """Draw vertex-coloured or textured meshes with a camera into an RGB framebuffer.

    Parameters
    ----------
    ctx : moderngl.Context, from ``tvmedit.player.context``
    size : (width, height) of the own framebuffer, pixels
    samples : samples per pixel when multisampling, clamped to what the context allows; 0 (or 1)
        for no multisampling
    antialias : "auto" (FXAA on a software rasteriser, otherwise MSAA with ``samples``), "msaa"
        (none with ``samples`` 0, FXAA where the context cannot multisample), "fxaa" or "none";
        ``self.antialias`` and ``self.samples`` say what was chosen
    max_counts : (max_vertices, max_faces) to size buffers up front (``MeshSource.max_counts()``)
    background : sRGB (r, g, b) in 0..1
    grid : draw a floor grid at z = 0
    """

    def __init__(self, ctx, size=(640, 480), samples=4, max_counts=(0, 0), background=BACKGROUND,
                 grid=False, antialias="auto"):
        width, height = (int(v) for v in size)
        if width <= 0 or height <= 0:
            raise ValueError(f"size should be two positive pixel counts, got {size!r}")
        self.ctx = ctx
        self.size = (width, height)
        self.background = tuple(float(c) for c in background)
        self.grid = grid
        self._programs = {}
        self._vaos = {}
        self._vertex_capacity = self._face_capacity = 0
        self._buffers = None
        self._uploaded = None  # the mesh tuple now in the buffers
        self._texture = None  # the frame's texture image on the GPU, reused while its size holds
        self._uploaded_texture = None  # the (uv, image) tuple now in the uv buffer and texture
        self._uploaded_field = None  # the step's field now in the offset buffer
        if antialias not in ANTIALIAS:
            raise ValueError(f"antialias should be one of {', '.join(ANTIALIAS)}, got {antialias!r}")
        self._reserve(*max_counts)

        samples = int(samples or 0)
        if antialias == "auto":
            antialias = "fxaa" if is_software(ctx) else "msaa" if samples > 1 else "none"
        elif antialias == "msaa" and samples < 2:
            antialias = "none"
        self.framebuffer = ctx.simple_framebuffer(self.size, components=4)
        self._multisample = None
        if antialias == "msaa":
            samples = min(samples, ctx.max_samples)
            try:
                if samples > 1:
                    self._multisample = ctx.framebuffer(
                        ctx.renderbuffer(self.size, 4, samples=samples),
                        ctx.depth_renderbuffer(self.size, samples=samples))
            except moderngl.Error:
                pass
            if self._multisample is None:
                antialias = "fxaa"  # the context cannot multisample (this size)
        self.antialias = antialias
        self.samples = samples if antialias == "msaa" else 0
        self._scene = None  # FXAA's input: colour texture + depth, sized like the last target
        self._fxaa_box = None  # where the last FXAA pass wrote the own framebuffer, if it did
        if antialias == "fxaa":
            self._fxaa_program = load_program(ctx, "fxaa")
            self._fxaa_vao = ctx.vertex_array(self._fxaa_program, [])

        self._grid_program = load_program(ctx, "grid")
        corners = np.array([-1, -1, 1, -1, -1, 1, 1, 1], np.float32)
        self._grid_corners = ctx.buffer(corners)
        self._grid_vao = ctx.vertex_array(self._grid_program, [(self._grid_corners, "2f", "in_corner")])

    def draw(self, mesh, camera, framebuffer=None, texture=None, instant=None):
        """Draw one frame.

        Parameters
        ----------
        mesh : (positions (N, 3) float32, colours (N, 3) uint8, faces (M, 3) uint32,
                normals (N, 3) float32 or None), as ``MeshSource.frame_mesh`` returns
        camera : ``tvmedit.player.camera.Camera``; its aspect should match the target's
        framebuffer : draw there instead of the own framebuffer (e.g. ``ctx.screen``)
        texture : (uv (N, 2) float32, image (H, W, 3) uint8) to draw the frame's texture
            instead of its vertex colours, as ``MeshSource.frame_texture`` returns; None for
            vertex colours
        instant : (field (N, 3) float16, s) to draw the surface at fraction ``s`` of the step to
            the next frame shown, ``positions + s * field`` (the vertex shader adds it; the field
            is uploaded when a new one is passed, ``s`` is a uniform), as
            ``Library.instant_field`` gives the field; None for the frame as stored
        """
        positions, colours, faces, normals = mesh
        n_faces = len(faces)
        if mesh is not self._uploaded:
            # A window redraws the same sequence frame many times between frames (60 Hz
            # against 10 fps); it passes the same tuple, and only a new one is uploaded.
            self._upload_mesh(mesh)
        moving = instant is not None and instant[0] is not None
        if moving and instant[0] is not self._uploaded_field:
            self._upload_field(instant[0], len(positions))
        if texture is not None and texture is not self._uploaded_texture:
            self._upload_texture(*texture, len(positions))
            self._uploaded_texture = texture

        output = framebuffer or self.framebuffer
        if self.antialias == "fxaa":
            target = self._scene_target(output)
        elif framebuffer is None and self._multisample is not None:
            target = self._multisample
        else:
            target = output  # a given framebuffer multisamples by itself, or not at all
        target.use()
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.disable(moderngl.CULL_FACE)
        # FXAA's input keeps alpha 0 off the mesh: the pass leaves those pixels alone.
        target.clear(*self.background, 0.0 if target is self._scene else 1.0, depth=1.0)

        facets = normals is None
        textured = texture is not None
        program = self._program(facets, textured, moving)
        projection = camera.projection_matrix()
        if framebuffer is None:
            # Draw the own framebuffer upside down: GL reads rows bottom-up, so ``read`` then
            # returns top-down rows with no flipping copy. (Lighting is two-sided, so the
            # reversed winding changes nothing; FXAA copies without flipping.)
            projection = projection * np.array([1, -1, 1, 1], np.float32)
        view_projection = np.asarray(camera.view_matrix()) @ np.asarray(projection)
        view, projection = camera.view_matrix().tobytes(), projection.tobytes()
        program["view"].write(view)
        program["projection"].write(projection)
        if textured:
            self._texture.use(0)
            program["albedo_map"].value = 0
        if moving:
            program["instant"].value = float(instant[1])
        if n_faces:
            self._vao(facets, textured, moving).render(moderngl.TRIANGLES, vertices=3 * n_faces)
        if self.grid:
            self._draw_grid(target, camera, view, projection)

        self._fxaa_box = None
        if target is self._multisample:
            self.ctx.copy_framebuffer(self.framebuffer, self._multisample)
        elif target is not output and framebuffer is None:
            # Only pixels near the mesh can change, so the pass covers the mesh's box on screen;
            # ``read`` takes the rest of the image straight from the scene.
            shown = positions if not moving else (
                np.asarray(positions, np.float32) + np.float32(instant[1]) * np.asarray(instant[0], np.float32))
            self._fxaa_box = _screen_box(shown, view_projection, self.size)
            self._fxaa(output, self._fxaa_box)
        elif target is not output:
            self._fxaa(output, output.viewport)

    def read(self):
        """The own framebuffer's pixels, (H, W, 3) uint8, first row at the top of the image."""
        pixels = np.empty((self.size[1], self.size[0], 3), np.uint8)
        if self._fxaa_box is None:
            self.framebuffer.read_into(pixels, components=3, alignment=1)
            return pixels
        self._scene.read_into(pixels, components=3, alignment=1)
        x, y, w, h = self._fxaa_box
        if w and h:
            box = self.framebuffer.read(viewport=self._fxaa_box, components=3, alignment=1)
            pixels[y:y + h, x:x + w] = np.frombuffer(box, np.uint8).reshape(h, w, 3)
        return pixels

    def release(self):
        if self.ctx.fbo in (self.framebuffer, self._multisample, self._scene):
            # moderngl rebinds the current framebuffer when it creates the next one; a deleted
            # name there is GL_INVALID_OPERATION, so hand the context back its default one.
            self.ctx.detect_framebuffer(0).use()
        for vao in self._vaos.values():
            vao.release()
        for buffer in (self._buffers or {}).values():
            buffer.release()
        for program in self._programs.values():
            program.release()
        if self._texture is not None:
            self._texture.release()
        self._grid_vao.release()
        self._grid_corners.release()
        self._grid_program.release()
        _release_with_attachments(self._multisample)
        if self.antialias == "fxaa":
            self._fxaa_vao.release()
            self._fxaa_program.release()
        self._release_scene()
        # simple_framebuffer made a colour and a depth renderbuffer that releasing the
        # framebuffer alone would leave behind (a render per report thumbnail adds up).
        _release_with_attachments(self.framebuffer)

    def _reserve(self, n_vertices, n_faces):
        """Make the buffers hold at least this many vertices and faces, growing if needed."""
        if self._buffers is not None and n_vertices <= self._vertex_capacity and n_faces <= self._face_capacity:
            return
        vertices = max(self._vertex_capacity, int(n_vertices * _GROWTH) if self._buffers else n_vertices, 1)
        faces = max(self._face_capacity, int(n_faces * _GROWTH) if self._buffers else n_faces, 1)
        for vao in self._vaos.values():
            vao.release()
        self._vaos = {}
        self._uploaded_field = None  # a grown buffer starts empty
        old = self._buffers or {}
        self._buffers = {
            "in_position": self._grown(old.get("in_position"), vertices * 12),
            "in_colour": self._grown(old.get("in_colour"), vertices * 3),
            "in_normal": self._grown(old.get("in_normal"), vertices * 12),
            "in_uv": self._grown(old.get("in_uv"), vertices * 8),
            "in_offset": self._grown(old.get("in_offset"), vertices * 6),
            "index": self._grown(old.get("index"), faces * 12),
        }
        self._vertex_capacity, self._face_capacity = vertices, faces

    def _grown(self, buffer, nbytes):
        if buffer is not None and buffer.size >= nbytes:
            return buffer
        if buffer is not None:
            buffer.release()
        return self.ctx.buffer(reserve=nbytes, dynamic=True)

    def _program(self, facets, textured=False, moving=False):
        key = (facets, textured, moving)
        if key not in self._programs:
            defines = {**({"FACET_NORMALS": 1} if facets else {}), **({"TEXTURED": 1} if textured else {}),
                       **({"MOVING": 1} if moving else {})}
            self._programs[key] = load_program(self.ctx, "mesh", **defines)
        return self._programs[key]

    def _vao(self, facets, textured=False, moving=False):
        key = (facets, textured, moving)
        if key not in self._vaos:
            b, program = self._buffers, self._program(facets, textured, moving)
            formats = {"in_position": "3f", "in_colour": "3f1", "in_normal": "3f", "in_uv": "2f", "in_offset": "3f2"}
            # Only attributes the compiled program kept: drivers drop unused ones.
            content = [(b[name], fmt, name) for name, fmt in formats.items() if name in program]
            self._vaos[key] = self.ctx.vertex_array(program, content, b["index"], index_element_size=4)
        return self._vaos[key]

    def _upload_mesh(self, mesh):
        """Write a frame's positions, colours, normals and faces, growing the buffers if needed."""
        positions, colours, faces, normals = mesh
        _check(positions, colours, faces, normals)
        self._reserve(len(positions), len(faces))
        self._buffers["in_position"].write(_contiguous(positions, np.float32))
        self._buffers["in_colour"].write(_contiguous(colours, np.uint8))
        if normals is not None:
            self._buffers["in_normal"].write(_contiguous(normals, np.float32))
        self._buffers["index"].write(_contiguous(faces, np.uint32))
        self._uploaded = mesh

    def _upload_field(self, field, n_vertices):
        """Write a step's field (the display-rate in-between) into the offset buffer."""
        if np.shape(field) != (n_vertices, 3):
            raise ValueError(f"the step's field should be ({n_vertices}, 3) like the positions, "
                             f"got shape {np.shape(field)}")
        self._buffers["in_offset"].write(_contiguous(field, np.float16))
        self._uploaded_field = field

    def _upload_texture(self, uv, image, n_vertices):
        """Write a frame's texture coordinates and image; the GPU texture is remade only when
        the image's size changes, and its mipmaps keep the texture readable when it is small
        on screen (a contact sheet's tile)."""
        if np.shape(uv) != (n_vertices, 2) or np.ndim(image) != 3 or np.shape(image)[2] != 3:
            raise ValueError(f"texture should be uv ({n_vertices}, 2) and an (H, W, 3) image; got shapes "
                             f"{np.shape(uv)} and {np.shape(image)}")
        self._buffers["in_uv"].write(_contiguous(uv, np.float32))
        height, width = np.shape(image)[:2]
        if self._texture is None or self._texture.size != (width, height):
            if self._texture is not None:
                self._texture.release()
            self._texture = self.ctx.texture((width, height), 3, alignment=1)
            self._texture.filter = moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR
            self._texture.repeat_x = self._texture.repeat_y = True
        self._texture.write(_contiguous(image, np.uint8), alignment=1)
        self._texture.build_mipmaps()

    def _scene_target(self, output):
        """FXAA's input for ``output``: a framebuffer of a colour texture and a depth buffer sized
        like ``output``'s viewport (a window's ``ctx.screen`` keeps the size it was opened with,
        its viewport follows the window), made anew when that size changes."""
        size = tuple(output.viewport[2:])
        if self._scene is None or self._scene.size != size:
            self._release_scene()
            self._scene = self.ctx.framebuffer(self.ctx.texture(size, 4), self.ctx.depth_renderbuffer(size))
        return self._scene

    def _release_scene(self):
        _release_with_attachments(self._scene)
        self._scene = None

    def _fxaa(self, output, box):
        """Anti-alias the scene texture into the ``box`` (x, y, width, height) of ``output``,
        its viewport or a part of the own framebuffer (one triangle covering the box)."""
        if not (box[2] and box[3]):
            return
        viewport = output.viewport
        output.viewport = box
        output.use()
        self.ctx.disable(moderngl.DEPTH_TEST)
        self._scene.color_attachments[0].use(0)
        self._fxaa_program["origin"].value = tuple(viewport[:2])
        self._fxaa_vao.render(moderngl.TRIANGLES, vertices=3)
        output.viewport = viewport

    def _draw_grid(self, target, camera, view, projection):
        program = self._grid_program
        program["view"].write(view)
        program["projection"].write(projection)
        program["centre"].value = tuple(camera.target[:2])
        program["extent"].value = float(max(4.0 * camera.radius, 2.0))
        program["spacing"].value = 0.5
        program["line_colour"].value = tuple(min(c + 0.25, 1.0) for c in self.background)
        self.ctx.enable(moderngl.BLEND)
        # The target's alpha stays as it was: FXAA reads it as "mesh here" (the grid's lines
        # are anti-aliased already).
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE
        # The floor is see-through: it must not hide mesh parts below z = 0 drawn after it.
        target.depth_mask = False
        self._grid_vao.render(moderngl.TRIANGLE_STRIP)
        target.depth_mask = True
        self.ctx.disable(moderngl.BLEND)


def is_software(ctx):
    """Whether ``ctx`` rasterises on the CPU (``GL_RENDERER`` names one of ``SOFTWARE_RENDERERS``)."""
    renderer = ctx.info.get("GL_RENDERER", "").lower()
    return any(name in renderer for name in SOFTWARE_RENDERERS)


def _screen_box(positions, view_projection, size, margin=2):
    """The pixels (x, y, width, height) that the mesh's bounding box covers, ``margin`` pixels
    wider on each side and clipped to the image; the whole image when part of the box is behind
    the camera. ``view_projection`` is row-vector (pyrr) like the camera's matrices."""
    width, height = size
    if not len(positions):
        return (0, 0, 0, 0)
    # Column by column: numpy reduces an (N, 3) array over axis 0 about ten times slower.
    low = [positions[:, k].min() for k in range(3)]
    high = [positions[:, k].max() for k in range(3)]
    corners = np.array([[x, y, z, 1.0] for x in (low[0], high[0]) for y in (low[1], high[1])
                        for z in (low[2], high[2])])
    clip = corners @ np.asarray(view_projection, np.float64)
    if (clip[:, 3] <= 1e-6).any():
        return (0, 0, width, height)
    ndc = clip[:, :2] / clip[:, 3:]
    x0, y0 = np.floor((ndc.min(axis=0) + 1) / 2 * size).astype(int) - margin
    x1, y1 = np.ceil((ndc.max(axis=0) + 1) / 2 * size).astype(int) + margin
    x0, x1 = min(max(x0, 0), width), min(max(x1, 0), width)
    y0, y1 = min(max(y0, 0), height), min(max(y1, 0), height)
    return (int(x0), int(y0), int(x1 - x0), int(y1 - y0))


def _release_with_attachments(framebuffer):
    """Release a framebuffer made here and its attachments (moderngl keeps them otherwise)."""
    if framebuffer is not None:
        attachments = (*framebuffer.color_attachments, framebuffer.depth_attachment)
        framebuffer.release()
        for attachment in attachments:
            attachment.release()


def _contiguous(array, dtype):
    """The array as C-contiguous ``dtype`` without copying when it already is (memory maps are)."""
    return np.ascontiguousarray(array, dtype=dtype)


def _check(positions, colours, faces, normals):
    n = len(positions)
    if np.shape(positions) != (n, 3) or np.shape(colours) != (n, 3) or np.ndim(faces) != 2 or np.shape(faces)[1] != 3:
        raise ValueError("mesh should be positions (N, 3), colours (N, 3), faces (M, 3), normals (N, 3) or None; "
                         f"got shapes {np.shape(positions)}, {np.shape(colours)}, {np.shape(faces)}, "
                         f"{None if normals is None else np.shape(normals)}")
    if normals is not None and np.shape(normals) != (n, 3):
        raise ValueError(f"normals should be ({n}, 3) like the positions, got shape {np.shape(normals)}")
