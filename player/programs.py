"""GLSL programs loaded by name from ``shaders/<name>.glsl``.

Each file holds every stage of one program, fenced by ``#if defined VERTEX_SHADER`` /
``#elif defined FRAGMENT_SHADER`` (the moderngl-window layout); variants are switched with
defines, e.g. ``load_program(ctx, "mesh", FACET_NORMALS=1)``.
"""

import functools
from importlib import resources


@functools.lru_cache(maxsize=None)
def shader_text(name):
    """The text of ``shaders/<name>.glsl`` (read once per process)."""
    return resources.files("tvmedit.shaders").joinpath(f"{name}.glsl").read_text(encoding="utf-8")


@functools.lru_cache(maxsize=None)
def stage_source(name, stage, defines=()):
    """One stage of a program: the file with ``stage`` and ``defines`` (pairs) defined after ``#version``."""
    version, _, body = shader_text(name).partition("\n")
    if not version.startswith("#version"):
        raise ValueError(f"shaders/{name}.glsl should start with a #version line")
    lines = [version, f"#define {stage}"] + [f"#define {key} {value}" for key, value in defines]
    return "\n".join(lines) + "\n#line 2\n" + body


def load_program(ctx, name, **defines):
    """Compile ``shaders/<name>.glsl`` into a moderngl program on ``ctx``, Ctrl-C and SIGTERM
    held back meanwhile (:func:`tvmedit.engine.parallel.signals_held`)."""
    from ..engine.parallel import signals_held

    defines = tuple(sorted(defines.items()))
    vertex, fragment = stage_source(name, "VERTEX_SHADER", defines), stage_source(name, "FRAGMENT_SHADER", defines)
    with signals_held():
        return ctx.program(vertex_shader=vertex, fragment_shader=fragment)
