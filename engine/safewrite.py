"""Writing output so that nothing is ever half-written or lost: one helper for every command.

Every file and folder tvmedit writes is first written under a temporary name in the same
folder (``.NAME.tmp-PID``; a file keeps its suffix, ``.STEM.tmp-PID.SUFFIX``, so writers that
choose a format by suffix still can) and then renamed over the target with ``os.replace``,
which is atomic within one file system. A folder being replaced is first moved aside
(``.NAME.old-PID``), so no moment leaves neither the old nor the new one; what a killed
process left behind is tidied by :func:`clean_stale` on the next write to the same target,
and an old folder caught between the two renames is put back.

Nothing of the user's is ever replaced (:func:`check_target`): every folder tvmedit writes
carries a marker, ``.tvmedit``, naming its kind and every file written into it. An existing
output is replaced only when asked (``force``), only when it is tvmedit's own of the same kind
and only when it holds nothing it did not write; a file is replaced only when its content is
of the kind its suffix says. No output goes inside another tvmedit output (a library, an
export, a report) or inside one of the inputs, nor replaces the current folder.

>>> import tempfile
>>> folder = Path(tempfile.mkdtemp())
>>> write_text(folder / "a.txt", "one")
>>> with replacing_folder(folder / "out") as tmp:
...     write_text(tmp / "b.txt", "two")
>>> sorted(p.name for p in folder.iterdir()), (folder / "out" / "b.txt").read_text()
(['a.txt', 'out'], 'two')
"""

import contextlib
import glob
import json
import os
import shutil
from pathlib import Path

from .errors import OutputError, summarise
from .checks import json_value

__all__ = ["MARKER", "temporary", "exclusive", "made_once", "replacing_file", "write_text", "write_bytes", "replacing_folder",
           "swap_in", "clean_stale", "holds_cwd", "owner", "check_target", "check_file_target",
           "refuse_inside", "mark", "marked_files", "note_written"]

#: The file in every folder tvmedit writes: ``{"kind": ..., "files": [...]}``.
MARKER = ".tvmedit"

#: The first bytes of each kind of file tvmedit writes, by suffix.
MAGIC = {".png": (b"\x89PNG",), ".gif": (b"GIF8",), ".mp4": (b"ftyp",), ".json": (b"{",)}


def temporary(path, tag="tmp", keep_suffix=None):
    """The temporary name beside ``path``: ``.NAME.TAG-PID`` (``.STEM.TAG-PID.SUFFIX`` for files).

    >>> temporary(Path("out/edit.mp4")).name == f".edit.tmp-{os.getpid()}.mp4"
    True
    """
    path = Path(path)
    keep = bool(path.suffix) if keep_suffix is None else keep_suffix
    if keep:
        return path.with_name(f".{path.stem}.{tag}-{os.getpid()}{path.suffix}")
    return path.with_name(f".{path.name}.{tag}-{os.getpid()}")


@contextlib.contextmanager
def exclusive(path):
    """Hold the lock of ``path`` for the block (a file ``.NAME.lock`` beside it, locked with
    ``flock``): another process asking for it waits until the block ends, so that processes
    that would make the same output, such as the test processes of ``make test``, make it once.
    The lock goes when the block ends or the process does, however it ends (and any child it
    forked meanwhile). Where there is no ``flock`` (Windows) the block runs unlocked.

    >>> import tempfile
    >>> out = Path(tempfile.mkdtemp()) / "out"
    >>> with exclusive(out):
    ...     write_text(out, "made once")
    >>> sorted(p.name for p in out.parent.iterdir())
    ['.out.lock', 'out']
    """
    try:
        import fcntl  # POSIX only
    except ImportError:
        yield
        return
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path.with_name(f".{path.name}.lock"), "a") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        yield


def made_once(out, done, make):
    """``out``, made by ``make()`` unless its file ``done`` (written last) exists; one process
    makes it while any other that needs it waits (:func:`exclusive`), then finds it made.

    >>> import tempfile
    >>> out, runs = Path(tempfile.mkdtemp()) / "take", []
    >>> make = lambda: (runs.append(1), out.mkdir(), write_text(out / "truth.json", "{}"))
    >>> made_once(out, "truth.json", make) == made_once(out, "truth.json", make) == out, len(runs)
    (True, 1)
    """
    out = Path(out)
    if not (out / done).exists():
        with exclusive(out):
            if not (out / done).exists():
                make()
    return out


def _remove(path):
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(OSError):
            path.unlink()


@contextlib.contextmanager
def replacing_file(path, keep_suffix=None):
    """Yield a temporary path to write; when the block ends without error it becomes ``path``.

    The temporary file exists (empty) when the block starts. On an error (or Ctrl-C) it is
    removed and ``path`` is left as it was.
    """
    path = Path(path)
    tmp = temporary(path, keep_suffix=keep_suffix)
    _remove(tmp)
    # Created at once, so that a folder that cannot be written to is found before any work
    # (an OSError naming the file), not by a writer deep in a library.
    try:
        tmp.touch()
    except OSError as error:
        raise OSError(error.errno, error.strerror, str(path)) from None
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        if tmp.exists() or tmp.is_symlink():
            _remove(tmp)


def write_text(path, text, encoding="utf-8"):
    """Write ``text`` to ``path`` atomically."""
    with replacing_file(path, keep_suffix=False) as tmp:
        tmp.write_text(text, encoding=encoding)


def write_bytes(path, data):
    """Write ``data`` to ``path`` atomically."""
    with replacing_file(path, keep_suffix=False) as tmp:
        tmp.write_bytes(data)


@contextlib.contextmanager
def replacing_folder(out, recheck=None, kind=None):
    """Yield a fresh temporary folder beside ``out``; when the block ends it becomes ``out``.

    With ``kind``, the folder gets its :data:`MARKER` listing what was written into it.
    ``recheck(out)``, if given, runs just before the swap (the target may have changed while
    the folder was being written) and may raise to refuse it. On any error the temporary
    folder is removed and ``out`` is left as it was.
    """
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    clean_stale(out)
    tmp = temporary(out, keep_suffix=False)
    tmp.mkdir()
    try:
        yield tmp
        if kind is not None:
            mark(tmp, kind)
        if recheck is not None:
            recheck(out)
        swap_in(tmp, out)
    except BaseException:
        with _uninterrupted():
            shutil.rmtree(tmp, ignore_errors=True)
        raise


@contextlib.contextmanager
def _uninterrupted():
    """Hold Ctrl-C and SIGTERM back while a failed write tidies up (milliseconds), then deliver
    them: a second one right after the first must not leave a temporary folder behind."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = []
    held = (signal.SIGINT, signal.SIGTERM)
    previous = {signum: signal.signal(signum, lambda signum, _: caught.append(signum)) for signum in held}
    try:
        yield
    finally:
        for signum in held:
            signal.signal(signum, previous[signum])
        for signum in dict.fromkeys(caught):
            signal.raise_signal(signum)


def swap_in(tmp, out):
    """Rename folder ``tmp`` to ``out``, moving an existing ``out`` aside first, then deleting it."""
    out = Path(out)
    if out.exists():
        old = temporary(out, "old", keep_suffix=False)
        os.replace(out, old)
        os.replace(tmp, out)
        with _uninterrupted():
            shutil.rmtree(old, ignore_errors=True)
    else:
        os.replace(tmp, out)


def clean_stale(out):
    """Remove what killed writers left beside ``out``; put back a folder caught mid-swap."""
    out = Path(out)
    for path in out.parent.glob(f".{glob.escape(out.name)}.*-*"):
        tag, _, pid = path.name.rpartition("-")
        if not pid.isdigit() or not tag.endswith((".tmp", ".old")) or _alive(int(pid)):
            continue
        if tag.endswith(".old") and not out.exists():
            os.replace(path, out)  # killed between the two renames: the old folder is whole
        else:
            _remove(path)


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def holds_cwd(path):
    """Whether ``path`` is the current folder or one of its parents (never to be replaced)."""
    here = Path.cwd().resolve()
    target = Path(path).resolve()
    return target == here or target in here.parents


# --- what is ours -------------------------------------------------------------------------

def _files(folder):
    return sorted(str(p.relative_to(folder)) for p in Path(folder).rglob("*")
                  if not p.is_dir() or p.is_symlink())


def mark(folder, kind, files=None):
    """Write the :data:`MARKER` of ``folder``: its kind and the files tvmedit wrote (default: all)."""
    files = sorted(files) if files is not None else [name for name in _files(folder) if name != MARKER]
    write_text(Path(folder) / MARKER, json.dumps({"kind": kind, "files": files}))


def marked_files(folder):
    """The files the marker of ``folder`` says tvmedit wrote (none without a marker)."""
    marker = _marker(folder)
    return list(marker["files"]) if marker is not None else []


def note_written(folder, *names):
    """Add ``names`` to the marker of ``folder`` (a file tvmedit wrote there later)."""
    marker = _marker(folder)
    if marker is not None:
        marker["files"] = sorted(set(marker["files"]) | set(names))
        write_text(Path(folder) / MARKER, json.dumps(marker))


def _marker(folder):
    try:
        data = json_value((Path(folder) / MARKER).read_text())
    except (OSError, ValueError):
        return None
    ok = isinstance(data, dict) and isinstance(data.get("kind"), str) and isinstance(data.get("files"), list)
    return data if ok else None


def _legacy_library(folder):
    # Libraries built before the marker existed are known by their manifest.
    try:
        data = json_value((Path(folder) / "manifest.json").read_text())
    except (OSError, ValueError):
        return False
    return isinstance(data, dict) and "format" in data and "tvmedit" in data


def owner(folder):
    """The kind of tvmedit output ``folder`` is (``"library"``, ``"export"``...), or None."""
    marker = _marker(folder)
    if marker is not None:
        return marker["kind"]
    return "library" if _legacy_library(folder) else None


def _foreign(folder):
    """Files in ``folder`` that its marker does not list (all of them without a marker), and
    folders that hold none of the files it lists (a user's empty folder is the user's too)."""
    marker = _marker(folder)
    written = set(marker["files"]) if marker is not None else set()
    files = [name for name in _files(folder) if name != MARKER and name not in written]
    holders = {str(parent) for name in written for parent in Path(name).parents}
    folders = [str(p.relative_to(folder)) + "/" for p in sorted(Path(folder).rglob("*"))
               if p.is_dir() and not p.is_symlink() and str(p.relative_to(folder)) not in holders
               and not any(p.iterdir())]
    return files + folders


def refuse_inside(out, inputs=()):
    """Refuse an output inside another tvmedit output, inside one of ``inputs``, or below a
    file (``notes.txt/out.mp4``)."""
    resolved = Path(os.path.abspath(out))
    for parent in resolved.parents:
        if parent.exists() and not parent.is_dir():
            raise OutputError(f"{out} cannot be written: {parent} is a file, not a folder; choose another output.")
    holders = [source for source in map(Path, map(os.path.abspath, inputs))
               if resolved == source or source in resolved.parents]
    inside_input = lambda source: OutputError(  # noqa: E731
        f"{out} is inside the input {source}; choose an output outside it.")
    # An input the user named is said as such (a synthetic take is one, though tvmedit wrote
    # it), except a library, whose rebuild is what would lose the output.
    plain = [source for source in holders if owner(source) != "library"]
    if plain:
        raise inside_input(plain[0])
    for parent in resolved.parents:
        kind = owner(parent)
        if kind is not None:
            raise OutputError(f"{out} is inside the tvmedit {kind} {parent}, which would lose it "
                              "when replaced; choose an output outside it.")
    if holders:
        raise inside_input(holders[0])


def check_target(out, kind, force=False, inputs=(), legacy=None):
    """Refuse folder ``out`` unless writing a ``kind`` there loses nothing of the user's.

    Parameters
    ----------
    out : path of the folder to write
    kind : str
        What is written (``"library"``, ``"export"``, ``"report"``, ``"frames"``, ``"take"``).
    force : bool
        Replace an existing output of the same kind (else any existing, non-empty folder is refused).
    inputs : paths the output must not be inside of (sequence folders, the library read).
    legacy : callable or None
        For outputs written before the marker existed: ``legacy(folder)`` is None when an
        unmarked folder is not such an output, else the files in it tvmedit did not write.

    Raises
    ------
    OutputError
        One sentence naming the folder and what is in the way.
    """
    out = Path(out)
    refuse_inside(out, inputs)
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise OutputError(f"{out} exists and is not a folder; choose another output for the {kind}.")
    if not out.exists() or not any(out.iterdir()):
        return
    foreign = legacy(out) if legacy is not None and _marker(out) is None else None
    found = kind if foreign is not None else owner(out)
    if found != kind:
        what = f"a tvmedit {found}, not a {kind}" if found else f"not a tvmedit {kind}"
        raise OutputError(f"{out} exists and is {what}, so it is not replaced; choose another "
                          "output or remove it yourself.")
    if not force:
        raise OutputError(f"{kind} {out} already exists; pass force=True to replace it.")
    if holds_cwd(out):
        raise OutputError(f"{out} is the current folder or holds it, so it is not replaced; "
                          "work from outside it.")
    foreign = _foreign(out) if foreign is None else foreign
    if foreign:
        raise OutputError(f"{out} holds {summarise(foreign)}, which tvmedit did not write, so it is "
                          "not replaced; move them out first or choose another output.")


def check_file_target(out, force=False, inputs=()):
    """Refuse file ``out`` unless it is new, or ``force`` and its content is of its suffix's kind."""
    out = Path(out)
    refuse_inside(out, inputs)
    if not out.exists() and not out.is_symlink():
        return
    if out.is_symlink() or not out.is_file():
        raise OutputError(f"{out} exists and is not a file; choose another output.")
    if not force:
        raise OutputError(f"{out} already exists; pass force=True to replace it.")
    try:
        with open(out, "rb") as handle:
            head = handle.read(12)
    except OSError:
        head = b""
    magic = MAGIC.get(out.suffix.lower(), ())
    if not any(head.startswith(m) or head[4:8] == m for m in magic):
        raise OutputError(f"{out} exists and is not a {out.suffix.lstrip('.').upper()} file, so it is "
                          "not replaced; choose another output or remove it yourself.")
