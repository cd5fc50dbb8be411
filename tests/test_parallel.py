"""Where build tasks run (tvmedit.engine.parallel): in order, here or on workers."""

import sys

import pytest

from tvmedit.engine.errors import TvmError
from tvmedit.engine.parallel import Workers, default_workers


def test_dask_missing_is_one_sentence(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(TvmError, match=r"pip install 'tvmedit\[dask\]'"):
        with Workers(2, dask="local") as pool:
            list(pool.map(abs, [1]))


@pytest.mark.parametrize("address", ["nonsense", "tcp://host:port", "ftp://host:8786"])
def test_a_malformed_dask_address_is_one_sentence(address):
    pytest.importorskip("distributed")
    with pytest.raises(TvmError, match=f"dask={address} is not a scheduler address .*; give one "
                                       r"such as tcp://host:8786, or local to start one here\.$"):
        with Workers(2, dask=address) as pool:
            list(pool.map(abs, [1]))


def test_tasks_come_back_in_order_in_this_process_or_on_workers():
    for workers, threads, kind in ((1, False, "serial"), (2, False, "processes"), (2, True, "threads")):
        with Workers(workers, threads=threads) as pool:
            assert pool.kind == kind
            assert list(pool.map(abs, range(-20, 0), window=3)) == list(range(20, 0, -1))


def test_threads_run_draco_encodings_side_by_side_each_as_alone():
    """The scvv export encodes Draco on threads: two run at once, and each frame's bytes are
    those one encoding alone writes."""
    import threading
    import time

    DracoPy = pytest.importorskip("DracoPy")
    import numpy as np

    grid = np.stack(np.meshgrid(np.arange(120), np.arange(120)), -1).reshape(-1, 2)
    points = np.c_[grid, np.sin(grid[:, 0] * 0.1)].astype(np.float32)
    quads = (grid[:, 0] < 119) & (grid[:, 1] < 119)
    corner = np.flatnonzero(quads)
    faces = np.r_[np.c_[corner, corner + 1, corner + 120], np.c_[corner + 1, corner + 121, corner + 120]].astype(np.uint32)
    running, most = [0], [0]
    lock = threading.Lock()

    def encode(_):
        with lock:
            running[0] += 1
            most[0] = max(most[0], running[0])
        data = DracoPy.encode(points, faces=faces, quantization_bits=14, compression_level=3)
        time.sleep(0.01)
        with lock:
            running[0] -= 1
        return data

    alone = encode(0)
    with Workers(2, threads=True) as pool:
        assert list(pool.map(encode, range(8))) == [alone] * 8
    assert most[0] == 2


def test_an_error_in_a_task_reaches_the_caller_unchanged():
    with Workers(2) as pool, pytest.raises(TypeError, match="bad operand type for abs"):
        list(pool.map(abs, [1, "x", 3]))


def test_workers_default_to_every_core_this_process_may_use():
    assert Workers().workers == default_workers() >= 1
    assert Workers(dask="local").kind == "dask"


def test_a_worker_count_below_one_is_refused():
    with pytest.raises(TvmError, match="workers"):
        Workers(0)


# A child that is interrupted twice, as a user pressing Ctrl-C twice is: first a few frames in,
# then again as the parent starts waiting for its workers to finish their frames.
_TWICE = """
import os, signal, sys, threading
from concurrent.futures import process
from tvmedit.engine import parallel

shutdown, original_map = process.ProcessPoolExecutor.shutdown, parallel.Workers.map

def map_(self, fn, tasks, window=None):
    for k, result in enumerate(original_map(self, fn, tasks, window)):
        if k == 5:
            os.kill(os.getpid(), signal.SIGINT)
        yield result

def shutdown_(self, *args, **kwargs):
    threading.Timer(0.01, os.kill, (os.getpid(), signal.SIGINT)).start()
    return shutdown(self, *args, **kwargs)

parallel.Workers.map, process.ProcessPoolExecutor.shutdown = map_, shutdown_
from tvmedit.cli import entry
sys.argv = ["tvmedit", *sys.argv[1:]]
entry()
"""


def test_a_second_ctrl_c_ends_the_workers_and_leaves_nothing(tmp_path):
    import os
    import signal
    import subprocess
    import time

    from interrupt import ROOT, default_sigint

    out = tmp_path / "take"
    child = subprocess.Popen([sys.executable, "-c", _TWICE, "synth", "--out", str(out), "--workers", "2",
                              "--preset", "walk"], cwd=ROOT, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, start_new_session=True, preexec_fn=default_sigint)
    try:
        _, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            os.killpg(child.pid, 9)
    # 130: "interrupted"; -SIGINT: the second Ctrl-C came once the command was over and ended
    # the process as its default does.
    assert child.returncode in (130, -signal.SIGINT), err
    assert err.strip().splitlines()[-1] == "interrupted" and "Traceback" not in err and "Exception" not in err, err
    deadline = time.monotonic() + 5   # the workers went with it: its process group is empty
    while time.monotonic() < deadline:
        try:
            os.killpg(child.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        pytest.fail("worker processes outlived the command")
    assert sorted(p.name for p in tmp_path.iterdir()) == []


_WAITED = """
import multiprocessing, os, signal, sys, threading, time
from tvmedit.engine.parallel import Workers

def nap(seconds):
    time.sleep(seconds)
    return seconds

for at in (0.5, 1.5):   # Ctrl-C while a task runs, then while the pool is waited for
    threading.Timer(at, os.kill, (os.getpid(), signal.SIGINT)).start()
start = time.monotonic()
try:
    with Workers(2) as pool:
        list(pool.map(nap, [60, 60, 60]))
except KeyboardInterrupt:
    pass
print(len(multiprocessing.active_children()), round(time.monotonic() - start))
sys.stdout.flush()
os._exit(0)
"""


def test_a_ctrl_c_while_workers_are_waited_for_ends_them():
    import subprocess

    from interrupt import ROOT, default_sigint

    done = subprocess.run([sys.executable, "-c", _WAITED], cwd=ROOT, capture_output=True, text=True, timeout=120,
                          preexec_fn=default_sigint)
    alive, _ = map(int, done.stdout.split())
    assert alive == 0, done.stderr   # not left to nap their minute out



# A fresh interpreter: threads other tests leave running would take the signal themselves.
_HELD_WITH_HELPER = """
import os, signal, threading, time
from tvmedit.engine.parallel import helper_threads, signals_held

# Ctrl-C as a terminal gives it: a shell starts a background job (CI's, say) with it ignored.
signal.signal(signal.SIGINT, signal.default_int_handler)
started = threading.Event()
with helper_threads(1) as pool:
    mask = pool.submit(lambda: (started.set(), signal.pthread_sigmask(signal.SIG_BLOCK, []), time.sleep(0.5))[1])
    started.wait()
    inside = False
    try:
        with signals_held():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.2)
            inside = True
    except KeyboardInterrupt:
        print("held" if inside else "raised inside the block")
    print("masked" if {signal.SIGINT, signal.SIGTERM} <= set(mask.result()) else "not masked")
"""


def test_helper_threads_leave_ctrl_c_to_the_main_thread_where_it_can_be_held():
    # A Ctrl-C while a helper thread runs (an export's checksums, its copier) is held back by
    # signals_held, as with no thread running: none is raised inside the block.
    import signal
    import subprocess

    if not hasattr(signal, "pthread_sigmask"):
        pytest.skip("no signal masks on this platform")
    result = subprocess.run([sys.executable, "-c", _HELD_WITH_HELPER], capture_output=True, text=True, timeout=60)
    assert result.stdout.split() == ["held", "masked"], result.stdout + result.stderr
