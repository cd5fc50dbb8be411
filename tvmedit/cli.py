"""The ``tvmedit`` command: one subcommand per module ``tvmedit/cmd_<name>.py``.

Each command module defines ``HELP`` (one line), ``add_arguments(parser)`` and ``run(args)``.
Modules are imported only when listed here, and GL is imported only inside the commands
that draw, so ``tvmedit --help`` and the analysis commands start fast and run without GL.
"""

import argparse
import importlib
import re
import signal
import sys
import warnings

from engine.errors import TvmError, UnknownMotion

from . import __version__

# Order is the order ``tvmedit --help`` lists them: the pipeline from data to pictures.
COMMANDS = ["synth", "check", "build", "info", "rename", "path", "export", "render", "play", "report"]


def _parser(argv):
    parser = argparse.ArgumentParser(
        prog="tvmedit",
        description="Edit time-varying meshes: find cyclic motions, link them in a motion graph, "
        "and play or render new sequences through the motions you choose.",
    )
    parser.add_argument("--version", action="version", version=f"tvmedit {__version__}")
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


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    # SIGTERM unwinds like Ctrl-C, so every command removes its temporary files.
    signal.signal(signal.SIGTERM, _terminate)
    warnings.showwarning = _show_warning
    parser = args = None
    try:
        # Building the parser imports the command (and for some, numpy): Ctrl-C may come here.
        parser = _parser(argv)
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 0
        parser = args._parser
        return args._run(args) or 0
    except TvmError as error:
        message = as_flags(str(error), parser) if parser is not None else str(error)
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


#: Options of other commands that engine advice may name (``rebuild with mu=2``).
_OTHER = {"mu": "--mu", "skip_bad_frames": "--skip-bad-frames", "fps": "--fps", "force": "--force",
          "workers": "--workers", "dask": "--dask"}


def as_flags(message, parser):
    """An engine message with its Python advice (``force=True``, ``mu=2``) as this command's options.

    The engine names parameters as ``name=value``; where the command has an option of that
    name (``--force``, ``--mu``), the advice is given as the option.

    >>> p = argparse.ArgumentParser()
    >>> _ = p.add_argument("--force", action="store_true"); _ = p.add_argument("--mu", type=float)
    >>> as_flags("library x already exists; pass force=True to replace it, or mu=2.5.", p)
    'library x already exists; pass --force to replace it, or --mu 2.5.'
    >>> as_flags("x is damaged; rebuild it with build(inputs, 'x', force=True).", p)
    'x is damaged; rebuild it with `tvmedit build INPUT... -o x --force`.'
    """
    options = {name: (option, name in ("force", "skip_bad_frames")) for name, option in _OTHER.items()}
    for action in parser._actions:
        if action.option_strings:
            option = action.option_strings[-1]
            for name in (action.dest, option.lstrip("-").replace("-", "_")):
                options[name] = (option, action.nargs == 0)

    def flag(match):
        name, value = match.group(1), match.group(2)
        found = options.get(name)
        if found is None:
            return match.group(0)
        option, switch = found
        pair = re.fullmatch(r"\((\d+), (\d+)\)", value)
        if pair:  # size=(640, 480) is --size 640x480
            return f"{option} {pair.group(1)}x{pair.group(2)}"
        return option if switch and value == "True" else f"{option} {value}"

    message = re.sub(r"\bbuild\((inputs|\[.*?\]), '(.+?)'(, force=True)?\)", _build_command, message)
    return re.sub(r"\b([a-z][a-z_]*)=(\(\d+, \d+\)|\S+?)(?=[,;.:)]*(?:\s|$))", flag, message)


def _sentence(message):
    """One line that ends as a sentence does."""
    message = " ".join(message.split())
    return message if message.endswith((".", "!", "?")) else message + "."


def _build_command(match):
    """``build(['a'], 'lib', force=True)`` (see ``engine.libformat.build_call``) as a command."""
    sources = "INPUT..." if match.group(1) == "inputs" else " ".join(re.findall(r"'(.*?)'", match.group(1)))
    force = " --force" if match.group(3) else ""
    return f"`tvmedit build {sources} -o {match.group(2)}{force}`"


def _terminate(signum, frame):
    raise SystemExit(128 + signum)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    # What the engine warns about (skipped frames, files left out) is for the user: one line,
    # without Python's file and line.
    print(f"warning: {message}", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
