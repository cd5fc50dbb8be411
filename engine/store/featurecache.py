"""The feature cache: a sequence's histograms (section 3) kept between builds and evaluations.

Reading the frames is what a build costs, so the features of every sequence are kept in
``$XDG_CACHE_HOME/tvmedit/features/KEY.npz`` (``~/.cache/tvmedit``). The key is a hash of
what they depend on and nothing else: every frame file's resolved path, size and mtime, the
bin sizes, whether bad frames were skipped, and the code that reads frames and computes
histograms (so a change there recomputes, with nothing to bump). The builder
(:mod:`tvmedit.engine.store.builder`) and the scorer (:mod:`tvmedit.engine.lab.evaluate`) share it.

An entry holds the arrays of :class:`tvmedit.engine.features.Features` and ``meta``: the frame
files kept (resolved) and the ones skipped with their reasons.
"""

import hashlib
import json
import os
from pathlib import Path

import numpy as np

from .. import safewrite
from ..errors import InputError
from ..checks import json_value

__all__ = ["cache_dir", "code_version", "stat_list", "key", "read", "write"]


def cache_dir():
    """Where features are cached between builds: ``$XDG_CACHE_HOME/tvmedit`` (``~/.cache/tvmedit``)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "tvmedit"


def code_version():
    """A hash of the modules that read frames and compute histograms."""
    digest = hashlib.sha1()
    engine = Path(__file__).resolve().parents[1]
    for module in ("capture/load.py", "capture/plyfast.py", "capture/readers.py", "capture/orientation.py",
                   "features/histograms.py", "features/vectors.py"):
        digest.update((engine / module).read_bytes())
    return digest.hexdigest()[:12]


def stat_list(paths):
    """``[resolved path, size, mtime_ns]`` of every frame file, as the key and the manifest hold them."""
    from ..capture.load import resolved

    rows = []
    for path, real in zip(paths, resolved(paths)):
        try:
            stat = os.stat(path)
        except OSError as error:
            raise InputError(f"frame {path} cannot be read ({error.strerror}); check the input.") from None
        rows.append([real, stat.st_size, stat.st_mtime_ns])
    return rows


def key(stats, bins, skip_bad_frames=False, orientation=None, meshes=None):
    """The cache key of features computed from files ``stats`` (:func:`stat_list`) with ``bins``,
    the frames mapped by ``orientation`` (an :class:`tvmedit.engine.capture.orientation.Orientation`, None for as
    they are) and stored as ``meshes`` maps them (the sequence's own orientation).

    A library reuses what another holds under the same key: features, and the meshes, runs and
    display fields made from the same frames. Features in the body's own frame do not change
    when the take is turned about up (``--front``), but its meshes do, so both maps count."""
    frame = [] if orientation is None or orientation.is_identity else [orientation.matrix, orientation.scale]
    if meshes is not None and not meshes.is_identity:
        frame.append(["meshes", meshes.matrix, meshes.scale])
    blob = json.dumps([stats, bins.to_json(), code_version(), bool(skip_bad_frames)] + frame)
    return hashlib.sha1(blob.encode()).hexdigest()[:20]


def _file(entry_key, folder):
    return (Path(folder) if folder is not None else cache_dir() / "features") / f"{entry_key}.npz"


def read(entry_key, bins, folder=None):
    """``(Features, meta)`` cached under ``entry_key``, or None when absent or unreadable."""
    from ..features import Features

    try:
        with np.load(_file(entry_key, folder), allow_pickle=False) as data:
            meta = json_value(str(data["meta"]))
            centred = (Features(data["centred_r"], data["centred_theta"], data["centred_phi"], data["origin"], bins)
                       if "centred_r" in data else None)
            features = Features(data["r"], data["theta"], data["phi"], data["origin"], bins, centred)
    except (OSError, ValueError, KeyError, EOFError):
        return None
    return features, meta


def write(entry_key, features, meta, folder=None):
    """Store ``features`` and ``meta`` (JSON-ready) under ``entry_key``; a failure only costs time."""
    path = _file(entry_key, folder)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with safewrite.replacing_file(path) as tmp, open(tmp, "wb") as handle:
            f, c = features, features.centred
            centred = {} if c is None else {"centred_r": c.r, "centred_theta": c.theta, "centred_phi": c.phi}
            np.savez(handle, r=f.r, theta=f.theta, phi=f.phi, origin=f.origin, meta=np.array(json.dumps(meta)),
                     **centred)
    except OSError:
        pass  # a cache that cannot be written only costs time on the next build
