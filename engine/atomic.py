"""Writing output so that a crash never leaves half of it: one helper for every command.

Every file and folder tvmedit writes is first written under a temporary name in the same
folder (``.NAME.tmp-PID``; a file keeps its suffix, ``.STEM.tmp-PID.SUFFIX``, so writers that
choose a format by suffix still can) and then renamed over the target with ``os.replace``,
which is atomic within one file system. A folder being replaced is first moved aside
(``.NAME.old-PID``), so no moment leaves neither the old nor the new one; what a killed
process left behind is tidied by :func:`clean_stale` on the next write to the same target,
and an old folder caught between the two renames is put back.

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
import os
import shutil
from pathlib import Path

__all__ = ["temporary", "replacing_file", "write_text", "write_bytes", "replacing_folder",
           "swap_in", "clean_stale", "holds_cwd"]


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


def _remove(path):
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(OSError):
            path.unlink()


@contextlib.contextmanager
def replacing_file(path, keep_suffix=None):
    """Yield a temporary path to write; when the block ends without error it becomes ``path``.

    On an error (or Ctrl-C) the temporary file is removed and ``path`` is left as it was.
    """
    path = Path(path)
    tmp = temporary(path, keep_suffix=keep_suffix)
    _remove(tmp)
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
def replacing_folder(out, recheck=None):
    """Yield a fresh temporary folder beside ``out``; when the block ends it becomes ``out``.

    ``recheck(out)``, if given, runs just before the swap (the target may have changed while
    the folder was being written) and may raise to refuse it. On any error the temporary
    folder is removed and ``out`` is left as it was.
    """
    out = Path(out)
    clean_stale(out)
    tmp = temporary(out, keep_suffix=False)
    tmp.mkdir()
    try:
        yield tmp
        if recheck is not None:
            recheck(out)
        swap_in(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def swap_in(tmp, out):
    """Rename folder ``tmp`` to ``out``, moving an existing ``out`` aside first, then deleting it."""
    out = Path(out)
    if out.exists():
        old = temporary(out, "old", keep_suffix=False)
        os.replace(out, old)
        os.replace(tmp, out)
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
