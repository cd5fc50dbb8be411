"""The only place OpenGL contexts are created.

Everything else (renderer, headless output, tests, benchmarks) receives a moderngl context
from here, so the requirements (GL 3.3 core, EGL for headless) and the error a user sees when
they are not met live in one function each.
"""

import functools

import moderngl

from ..engine.errors import TvmError
from ..engine.parallel import signals_held

GL_VERSION = 330


class ContextError(TvmError):
    """No OpenGL context can be created (EGL or a window system is missing)."""


def headless_context():
    """A new standalone OpenGL context through EGL, for rendering without a display.

    Raises ``ContextError`` with one sentence naming what is missing when EGL cannot be used.

    >>> ctx = headless_context()    # doctest: +SKIP
    >>> ctx.version_code >= 330     # doctest: +SKIP
    True
    """
    try:
        with signals_held():
            return moderngl.create_context(standalone=True, backend="egl", require=GL_VERSION)
    except Exception as error:  # moderngl/glcontext raise plain Exception with the loader's words
        raise ContextError(
            f"cannot create a headless OpenGL {GL_VERSION // 100}.{GL_VERSION % 100 // 10} context "
            f"through EGL ({_first_line(error)}): libEGL.so.1 with an OpenGL driver is needed, "
            "which Mesa provides (Debian/Ubuntu: apt install libegl1 libegl-mesa0 libgl1-mesa-dri)"
        ) from error


@functools.lru_cache(maxsize=None)
def shared_headless_context():
    """One headless context per process, created on first use and kept.

    ``render_frame`` and friends draw many small jobs; creating an EGL context costs tens of
    milliseconds, so they share this one instead of paying it per call.
    """
    return headless_context()


def window_context():
    """The moderngl context of the current glfw window (the realtime player's hook).

    The window module creates the glfw window and makes its context current; this wraps it so
    the same ``Renderer`` draws into ``ctx.screen`` exactly as it draws headless.
    """
    try:
        return moderngl.create_context(require=GL_VERSION)
    except Exception as error:
        raise ContextError(
            f"cannot use the window's OpenGL context ({_first_line(error)}): "
            f"an OpenGL {GL_VERSION // 100}.{GL_VERSION % 100 // 10} core profile driver is needed"
        ) from error


def _first_line(error):
    text = str(error).strip() or type(error).__name__
    return text.splitlines()[0]
