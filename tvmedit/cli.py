"""The ``tvmedit`` command: one subcommand per module ``tvmedit/cmd_<name>.py``.

Each command module defines ``HELP`` (one line), ``add_arguments(parser)`` and ``run(args)``.
Modules are imported only when listed here, and GL is imported only inside the commands
that draw, so ``tvmedit --help`` and the analysis commands start fast and run without GL.
"""

import argparse
import importlib
import os
import signal
import sys
import warnings

from tvmedit.engine.errors import TvmError, UnknownMotion

from . import options


# Order is the order ``tvmedit --help`` lists them: the pipeline from data to pictures.
COMMANDS = ["synth", "check", "build", "correct", "info", "rename", "path", "export", "render", "play", "inspect", "report"]


def _parser(argv):
    parser = argparse.ArgumentParser(
        prog="tvmedit",
        description="Edit time-varying meshes: find cyclic motions, link them in a motion graph, "
        "and play or render new sequences through the motions you choose.",
    )
    parser.add_argument("--version", action=_Version, help="show the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    # Only the invoked command's options are built: some read their defaults from engine
    # modules (networkx, scikit-image), which `tvmedit play` should not wait for.
    wanted = next((arg for arg in argv if arg in COMMANDS), None)
    for name in COMMANDS:
        module = importlib.import_module(f"tvmedit.cmd_{name}")
        p = sub.add_parser(name, help=module.HELP, description=module.__doc__,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        if name == wanted:
            module.add_arguments(p)
        p.set_defaults(_run=module.run, _parser=p)
    return parser


class _Version(argparse.Action):
    """--version, looked up only when asked for (importlib.metadata is slow to import)."""

    def __init__(self, option_strings, dest, help=None):
        super().__init__(option_strings, dest, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        import tvmedit

        parser.exit(message=f"tvmedit {tvmedit.__version__}\n")


def entry():
    """The ``tvmedit`` command (after :mod:`tvmedit.command`): :func:`main`, and the process's
    exit. Once the command is over, a signal ends the process at once, as its default does:
    Python's shutdown would print from exit handlers it lands in. After Ctrl-C or SIGTERM the
    process ends at once, every file already tidied: the interpreter would otherwise wait on
    the threads of a process pool whose workers a second Ctrl-C ended
    (:mod:`tvmedit.engine.parallel`)."""
    sys.unraisablehook = _unraisable
    try:
        status = main()
    except SystemExit as leaving:       # SIGTERM (_terminate), or argparse's own exit
        if not isinstance(leaving.code, int):
            raise
        status = leaving.code
    except KeyboardInterrupt:           # a Ctrl-C while main said why it stopped
        status = 130
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):   # the reader went away, or stderr was closed (141)
            pass
    if status in (130, 128 + signal.SIGTERM):
        if "multiprocessing" in sys.modules:  # workers still on a task end with the command
            for child in sys.modules["multiprocessing"].active_children():
                child.terminate()
        os._exit(status)
    sys.exit(status)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    # SIGTERM unwinds like Ctrl-C, so every command removes its temporary files; both are
    # noted as they come (_signalled).
    _signalled.clear()
    signal.signal(signal.SIGTERM, _terminate)
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:   # not where ignored
        signal.signal(signal.SIGINT, _interrupt)
    warnings.showwarning = _show_warning
    parser = args = None
    try:
        # Building the parser imports the command (and for some, numpy): Ctrl-C may come here.
        parser = _parser(argv)
        args = _parse(parser, argv)
        if args.command is None:
            parser.print_help()
            return 0
        parser = args._parser
        return args._run(args) or 0
    except TvmError as error:
        message = options.as_flags(str(error), parser)
        if isinstance(error, UnknownMotion) and getattr(args, "library", None):
            message = f"{message.rstrip('.')}; `tvmedit info {args.library}` lists them."
        print(f"error: {_sentence(message)}", file=sys.stderr)
        return error.exit_code
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader went away (`tvmedit path ... | head`): nothing more to say to it.
        sys.stderr.close()
        return 141
    except OSError as error:
        where = f" {error.filename}" if error.filename else ""
        print(f"error: cannot use{where} ({error.strerror or error}); check the path, its "
              "permissions and the free disk space.", file=sys.stderr)
        return 2
    except Exception:
        # A signal that a C extension's import turned into an error of its own (numpy's
        # "could not import module datetime"): the user pressed Ctrl-C, and reads that.
        if not _signalled:
            raise
        if _signalled[-1] == signal.SIGINT:
            print("interrupted", file=sys.stderr)
        return 128 + _signalled[-1]


#: Options whose value may be a negative axis (``--up -y``), which argparse takes for an option.
_AXIS_OPTIONS = ("--up", "--front")


def _axis_values(argv):
    """``--up -y`` as ``--up=-y``: argparse reads a value that starts with "-" as an option
    and says "expected one argument", where the user wrote what the help asks for.

    >>> _axis_values(["build", "in", "--front", "-z", "--up", "+y", "-q"])
    ['build', 'in', '--front=-z', '--up', '+y', '-q']
    """
    out, k = [], 0
    while k < len(argv):
        if argv[k] in _AXIS_OPTIONS and k + 1 < len(argv) and argv[k + 1].lower() in ("-x", "-y", "-z"):
            out.append(f"{argv[k]}={argv[k + 1]}")
            k += 2
            continue
        out.append(argv[k])
        k += 1
    return out


def _parse(parser, argv):
    """The arguments; KEYs written after options (``path LIB --wander 60 walk/01``) are KEYs
    too, which argparse alone leaves over once an optional positional has taken none."""
    argv = _axis_values(argv)
    args, extra = parser.parse_known_args(argv)
    if extra and isinstance(getattr(args, "keys", None), list) and not any(a.startswith("-") for a in extra):
        args.keys += extra
        return args
    return parser.parse_args(argv)


def _sentence(message):
    """One line that ends as a sentence does."""
    message = " ".join(message.split())
    return message if message.endswith((".", "!", "?")) else message + "."


def _unraisable(unraisable, default=sys.unraisablehook):
    """A Ctrl-C or SIGTERM that lands in a finaliser (a progress bar or a weak reference going
    away) is not raised there: Python prints "Exception ignored in ..." and goes on. It is
    raised again in the main thread, a moment later (raised at once, it would land in this
    hook), where the command ends as at any other. Once a signal has come, what finalisers of
    objects it left half-made raise is noise, and is not printed either."""
    import _thread
    import threading

    if issubclass(unraisable.exc_type, KeyboardInterrupt):
        threading.Timer(0.01, _thread.interrupt_main, (signal.SIGINT,)).start()
    elif issubclass(unraisable.exc_type, SystemExit) and unraisable.exc_value.code == 128 + signal.SIGTERM:
        threading.Timer(0.01, _thread.interrupt_main, (signal.SIGTERM,)).start()
    elif not _signalled:
        default(unraisable)


#: Signals received by this command (SIGINT, SIGTERM), in order.
_signalled = []


def _interrupt(signum, frame):
    _signalled.append(signum)
    raise KeyboardInterrupt


def _terminate(signum, frame):
    _signalled.append(signum)
    raise SystemExit(128 + signum)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    # What the engine warns about (skipped frames, files left out) is for the user: one line,
    # without Python's file and line.
    print(f"warning: {options.as_flags(str(message))}", file=sys.stderr)


if __name__ == "__main__":
    entry()
