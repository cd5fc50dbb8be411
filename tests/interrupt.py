"""Run ``tvmedit`` in a child process, as a user does (:func:`tvmedit`), or receiving a real
signal at a chosen point of its work (:func:`run_signalled`).

Sending a signal from the test when a file appears is a race: on a fast machine the command
can finish between the check and the signal. Here the child sends the signal to itself,
right after the N-th call of a named function returns, so the signal always lands mid-work
and the test states exactly where.
"""

import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

_CHILD = """
import functools, importlib, os, sys
module, attribute, after, signum = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
owner = importlib.import_module(module)
*path, name = attribute.split(".")
for part in path:
    owner = getattr(owner, part)
original = getattr(owner, name)
calls = 0

@functools.wraps(original)
def signalled(*args, **kwargs):
    global calls
    result = original(*args, **kwargs)
    calls += 1
    if calls == after:
        os.kill(os.getpid(), signum)
    return result

setattr(owner, name, signalled)
from tvmedit.cli import main
sys.exit(main(sys.argv[5:]))
"""


def default_sigint():
    """``preexec_fn`` for a child that must see Ctrl-C as a user's terminal gives it: a suite run
    as a background job (``make test &``) starts with SIGINT ignored, and a Python child that
    inherits that never raises KeyboardInterrupt."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)


def run_signalled(args, *, at, signum, after=1, env=None):
    """Run ``tvmedit ARGS``, sending ``signum`` to itself after ``after`` calls of ``at``.

    ``at`` is ``"module:attribute"``, e.g. ``"tvmedit.engine.graph.export:write_ply"`` or
    ``"tvmedit.engine.store.arrays:NpyStream.append"``. Returns the ``subprocess.CompletedProcess``.
    """
    module, attribute = at.split(":")
    command = [sys.executable, "-c", _CHILD, module, attribute, str(after), str(int(signum)),
               *map(str, args)]
    return subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, timeout=300,
                          preexec_fn=default_sigint)


def tvmedit(*args, **kwargs):
    """``tvmedit ARGS`` in a child process: the ``subprocess.CompletedProcess``, text captured."""
    return subprocess.run([sys.executable, "-m", "tvmedit", *map(str, args)], capture_output=True,
                          text=True, **kwargs)


def refused(library, a, b):
    """Whether ``library`` refuses an edit from motion ``a`` to motion ``b`` (no path)."""
    from tvmedit.engine.errors import NoPath

    try:
        library.edit([a, b])
    except NoPath:
        return True
    return False


def reachable_pair(library):
    """Two different motions of ``library`` with a path between them, and the edit through them."""
    from tvmedit.engine.errors import NoPath

    for a in library.nodes:
        for b in library.nodes:
            if a.id != b.id:
                try:
                    return a, b, library.edit([a.id, b.id])
                except NoPath:
                    pass
    raise AssertionError("the test library has no transition at all")


def run_interrupted(args, signum=None, after=None):
    """``tvmedit ARGS`` in a child process of its own process group, which gets ``signum`` after
    ``after`` seconds if still running (what a terminal's Ctrl-C does: the workers get it too).
    Returns the ``subprocess.CompletedProcess``; a child still running after two minutes is
    killed, and the test then fails on its output."""
    import signal

    child = subprocess.Popen([sys.executable, "-m", "tvmedit", *map(str, args)], cwd=ROOT, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, start_new_session=True, preexec_fn=default_sigint)
    try:
        if signum is not None:
            try:
                child.wait(timeout=after)
            except subprocess.TimeoutExpired:
                os.killpg(child.pid, signum)
        out, err = child.communicate(timeout=120)
    finally:
        if child.poll() is None:
            os.killpg(child.pid, signal.SIGKILL)
    return subprocess.CompletedProcess(args, child.returncode, out, err)
