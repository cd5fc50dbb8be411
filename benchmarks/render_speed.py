"""Rendering speed of streamed time-varying meshes, against a peer and against the practical limit.

    .venv/bin/python benchmarks/render_speed.py [--frames 60] [--antialias auto] [--samples 4]

Each displayed frame is a different mesh (like TVM: new vertex count and topology every frame):
~17,000 vertices and ~34,000 triangles from marching cubes of a moving body, cycled. A frame
costs upload + draw + read back of a 640x480 RGB image. Three loops over the same arrays:

* tvmedit   ``player.Renderer`` at its default anti-aliasing (4x MSAA on a GPU, FXAA on a
            software rasteriser; ``--antialias`` picks another): buffers sized once, overwritten
            per frame;
* bare      moderngl with no other work: the same uploads, one minimal shader, same framebuffer
            (the practical limit on this machine), with tvmedit's multisampling when tvmedit
            multisamples and none otherwise: no anti-aliasing pass at all when tvmedit runs FXAA,
            so the ratio charges tvmedit with its FXAA pass;
* bare + FXAA  (when tvmedit runs FXAA) the bare loop plus the project's FXAA pass over the whole
            image, for scale: tvmedit runs the pass over the mesh's box on screen only;
* pyrender  ``OffscreenRenderer`` with a new ``pyrender.Mesh`` per frame (the 'bench' extra; it
            is skipped, saying why, when it cannot be imported).

Prints frames per second and CPU time per frame, and the ratios (targets: tvmedit >= 3x
pyrender, >= 90% of the bare loop doing the same anti-aliasing: bare + FXAA where tvmedit runs
FXAA, bare otherwise). With software GL the CPU time is the steadier figure.
"""

import argparse
import os
import statistics
import sys
import time

os.environ.setdefault("PYOPENGL_PLATFORM", "egl")  # must precede any PyOpenGL import (pyrender)

import moderngl  # noqa: E402
import numpy as np  # noqa: E402
from skimage.measure import marching_cubes  # noqa: E402

from tvmedit.player.camera import Camera  # noqa: E402
from tvmedit.player.context import headless_context  # noqa: E402
from tvmedit.player.programs import load_program  # noqa: E402
from tvmedit.player.renderer import ANTIALIAS, Renderer  # noqa: E402
from tvmedit.player.source import ArraySource  # noqa: E402

SIZE = (640, 480)
VOXEL = 0.0107
"""Marching-cubes voxel (m) that gives ~17k vertices for the body below, as a 2 mm-scale capture
decimated for playback would."""


def body_mesh(phase):
    """A walking metaball figure 1.8 m tall at phase ``phase`` (radians): positions, colours, faces."""
    s = np.sin(phase)
    blobs = [((0, 0, 1.25), (0.17, 0.11, 0.28)), ((0, 0, 1.68), (0.1, 0.1, 0.12)), ((0, 0, 0.95), (0.16, 0.1, 0.12))]
    for side in (-1, 1):
        blobs += [((side * 0.1, 0.12 * s * side, 0.72), (0.07, 0.07, 0.22)),
                  ((side * 0.1, 0.22 * s * side, 0.28), (0.06, 0.06, 0.24)),
                  ((side * 0.26, -0.1 * s * side, 1.3), (0.05, 0.05, 0.16)),
                  ((side * 0.28, -0.15 * s * side, 0.98), (0.045, 0.045, 0.15))]
    low, high = np.array([-0.45, -0.4, -0.05]), np.array([0.45, 0.4, 1.9])
    grid = np.meshgrid(*[np.arange(low[i], high[i], VOXEL) for i in range(3)], indexing="ij", sparse=True)
    field = sum(np.exp(-sum(((g - c) / r) ** 2 for g, c, r in zip(grid, centre, radii)))
                for centre, radii in blobs)
    positions, faces, _, _ = marching_cubes(field, 0.5, spacing=(VOXEL,) * 3)
    positions = (positions + low).astype(np.float32)
    t = positions[:, 2:3] / 1.9
    colours = np.round(255 * np.hstack([0.85 - 0.5 * t, 0.6 - 0.2 * t, 0.45 + 0.3 * t])).clip(0, 255)
    return positions, colours.astype(np.uint8), faces


def time_loop(step, frames, warmup=2):
    """(frames per second of wall time, CPU milliseconds per frame of this process, GL threads included).

    The CPU figure is steadier than wall time when other work shares the machine, and with
    software GL (llvmpipe) it is what the frame costs."""
    for i in range(warmup):
        step(i)
    wall, cpu = time.perf_counter(), time.process_time()
    for i in range(frames):
        step(i)
    return frames / (time.perf_counter() - wall), 1000 * (time.process_time() - cpu) / frames


def tvmedit_loop(ctx, source, keys, camera, antialias, samples):
    renderer = Renderer(ctx, SIZE, samples=samples, max_counts=source.max_counts(), antialias=antialias)

    def step(i):
        renderer.draw(source.frame_mesh(keys[i % len(keys)]), camera)
        renderer.read()
    return renderer, step


BARE_VERTEX = """
#version 330 core
uniform mat4 mvp;
in vec3 in_position; in vec3 in_colour; in vec3 in_normal;
out vec3 v_colour;
void main() { v_colour = in_colour * abs(in_normal.z); gl_Position = mvp * vec4(in_position, 1.0); }
"""
BARE_FRAGMENT = """
#version 330 core
in vec3 v_colour; out vec4 colour;
void main() { colour = vec4(v_colour, 1.0); }
"""


def bare_loop(ctx, meshes, camera, samples, fxaa=False):
    """Upload the same four arrays into fixed buffers, draw, resolve, read: nothing else.

    With ``fxaa`` the scene goes to a texture and the project's FXAA pass writes the whole plain
    framebuffer: about tvmedit's anti-aliased image, from a pass over every pixel.
    """
    program = ctx.program(vertex_shader=BARE_VERTEX, fragment_shader=BARE_FRAGMENT)
    program["mvp"].write((camera.view_matrix() @ camera.projection_matrix()).astype(np.float32).tobytes())
    n = max(len(m[0]) for m in meshes)
    m = max(len(m[2]) for m in meshes)
    vbo_p, vbo_c, vbo_n, ibo = (ctx.buffer(reserve=k, dynamic=True) for k in (12 * n, 3 * n, 12 * n, 12 * m))
    vao = ctx.vertex_array(program, [(vbo_p, "3f", "in_position"), (vbo_c, "3f1", "in_colour"),
                                     (vbo_n, "3f", "in_normal")], ibo, index_element_size=4)
    plain = ctx.simple_framebuffer(SIZE)
    draw_to = ctx.framebuffer(ctx.renderbuffer(SIZE, 4, samples=samples),
                              ctx.depth_renderbuffer(SIZE, samples=samples)) if samples > 1 else plain
    if fxaa:
        scene = ctx.texture(SIZE, 4)
        draw_to = ctx.framebuffer(scene, ctx.depth_renderbuffer(SIZE))
        fxaa_program = load_program(ctx, "fxaa")
        fxaa_program["origin"].value = (0, 0)
        fxaa_pass = ctx.vertex_array(fxaa_program, [])
    pixels = np.empty((SIZE[1], SIZE[0], 3), np.uint8)
    ctx.enable(moderngl.DEPTH_TEST)

    def step(i):
        positions, colours, faces, normals = meshes[i % len(meshes)]
        vbo_p.write(positions)
        vbo_c.write(colours)
        vbo_n.write(normals)
        ibo.write(faces)
        draw_to.use()
        draw_to.clear(0.1, 0.1, 0.1, 1.0)
        vao.render(moderngl.TRIANGLES, vertices=3 * len(faces))
        if fxaa:
            plain.use()
            ctx.disable(moderngl.DEPTH_TEST)
            scene.use(0)
            fxaa_pass.render(moderngl.TRIANGLES, vertices=3)
            ctx.enable(moderngl.DEPTH_TEST)
        elif draw_to is not plain:
            ctx.copy_framebuffer(plain, draw_to)
        plain.read_into(pixels, components=3, alignment=1)
    return step


def pyrender_loop(meshes, camera):
    import pyrender

    renderer = pyrender.OffscreenRenderer(*SIZE)
    scene = pyrender.Scene(bg_color=[0.1, 0.1, 0.1, 1.0], ambient_light=[0.2, 0.2, 0.2])
    pose = np.linalg.inv(camera.view_matrix().T.astype(np.float64))  # camera -> world, column vectors
    scene.add(pyrender.PerspectiveCamera(yfov=np.radians(camera.fov), aspectRatio=camera.aspect), pose=pose)
    scene.add(pyrender.DirectionalLight(intensity=3.0), pose=pose)
    node = None

    def step(i):
        nonlocal node
        positions, colours, faces, normals = meshes[i % len(meshes)]
        if node is not None:
            scene.remove_node(node)
        mesh = pyrender.Mesh([pyrender.Primitive(positions=positions, normals=normals, color_0=colours,
                                                 indices=faces, mode=pyrender.constants.GLTF.TRIANGLES)])
        node = scene.add(mesh)
        renderer.render(scene)
    return renderer, step


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=60, help="timed frames per round (default 60)")
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds; the median is reported")
    parser.add_argument("--meshes", type=int, default=8, help="different meshes cycled (default 8)")
    parser.add_argument("--antialias", choices=ANTIALIAS, default="auto",
                        help="tvmedit's anti-aliasing (default auto: FXAA on software GL, MSAA otherwise)")
    parser.add_argument("--samples", type=int, default=4,
                        help="multisampling of tvmedit and bare when tvmedit multisamples (pyrender: 4)")
    args = parser.parse_args(argv)

    print(f"generating {args.meshes} meshes ...", file=sys.stderr)
    frames = {("bench", i): body_mesh(2 * np.pi * i / args.meshes) for i in range(args.meshes)}
    source = ArraySource(frames)
    keys = list(frames)
    meshes = [source.frame_mesh(key) for key in keys]
    camera = Camera.framing(source.bounds(), SIZE[0] / SIZE[1])
    ctx = headless_context()
    print(f"{args.meshes} meshes, {np.mean([len(m[0]) for m in meshes]):.0f} vertices and "
          f"{np.mean([len(m[2]) for m in meshes]):.0f} triangles on average; {SIZE[0]}x{SIZE[1]}, "
          f"upload + draw + read back; {ctx.info['GL_RENDERER']}, {os.cpu_count()} CPUs")

    renderer, ours = tvmedit_loop(ctx, source, keys, camera, args.antialias, args.samples)
    loops = {"tvmedit": ours, "bare": bare_loop(ctx, meshes, camera, renderer.samples)}
    if renderer.antialias == "fxaa":
        loops["bare + FXAA"] = bare_loop(ctx, meshes, camera, 0, fxaa=True)
    frames_per_round = {name: args.frames for name in loops}
    try:
        peer, loops["pyrender"] = pyrender_loop(meshes, camera)
        frames_per_round["pyrender"] = max(args.frames // 3, 10)
    except ImportError as error:
        print(f"pyrender: skipped ({error}; install the 'bench' extra: pip install -e '.[bench]')")

    # Rounds interleave the loops so that a change in the machine's load hits all of them alike.
    # pyrender makes its own context current when it renders; ``with ctx`` makes ours current again.
    timings = {name: [] for name in loops}
    for _ in range(args.rounds):
        for name, step in loops.items():
            if name == "pyrender":
                timings[name].append(time_loop(step, frames_per_round[name]))
            else:
                with ctx:
                    timings[name].append(time_loop(step, frames_per_round[name]))
    with ctx:
        assert ctx.error == "GL_NO_ERROR", ctx.error
        renderer.release()
    if "pyrender" in loops:
        peer.delete()
    fps = {name: statistics.median(t[0] for t in values) for name, values in timings.items()}
    cpu = {name: statistics.median(t[1] for t in values) for name, values in timings.items()}

    chosen = {"msaa": f"{renderer.samples}x MSAA", "fxaa": "FXAA", "none": "no anti-aliasing"}[renderer.antialias]
    bare = f"{renderer.samples}x MSAA" if renderer.samples > 1 else "no MSAA, no AA pass"
    notes = {"tvmedit": f"{chosen}, antialias={args.antialias!r}", "bare": f"{bare}, the practical limit",
             "bare + FXAA": "with an FXAA pass over the whole image",
             "pyrender": "4x MSAA, new pyrender.Mesh per frame"}
    print(f"{'':18} {'fps':>7} {'CPU ms/frame':>13}   (median of {args.rounds} interleaved rounds)")
    for name in loops:
        print(f"{name:18} {fps[name]:7.1f} {cpu[name]:13.1f}   ({notes[name]})")
    if "pyrender" in loops:
        print(f"tvmedit / pyrender {fps['tvmedit'] / fps['pyrender']:7.2f}x{cpu['pyrender'] / cpu['tvmedit']:12.2f}x"
              "   (target >= 3x)")
    # Like for like: the bare loop doing tvmedit's anti-aliasing (its MSAA, its FXAA pass, or
    # none when tvmedit draws none); the bare loop without the FXAA pass is printed for scale.
    like = "bare + FXAA" if "bare + FXAA" in loops else "bare"
    for bare_name in [name for name in loops if name.startswith("bare")]:
        what = "(target >= 90 %, like for like)" if bare_name == like else "(for scale: no anti-aliasing pass)"
        print(f"{'tvmedit / ' + bare_name:18} {100 * fps['tvmedit'] / fps[bare_name]:6.0f} %"
              f"{100 * cpu[bare_name] / cpu['tvmedit']:11.0f} %   {what}")


if __name__ == "__main__":
    main()
