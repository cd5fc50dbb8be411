"""Running independent tasks on local worker processes, threads or a dask.distributed cluster.

A library build reads and summarises thousands of frame files, each independently of the
others once a sequence's origin is known. :class:`Workers` spreads such tasks and hands the
results back *in submission order*, so a parallel build stacks exactly what a serial one
does and the two libraries are identical.

Only a bounded number of tasks is in flight at a time: results (a chunk of histograms, or
a chunk of meshes on their way to disk) are consumed in order as they arrive, so memory stays
flat however long the input.

Dask is optional and imported only when a build asks for it (``dask="tcp://host:8786"`` or
``dask="local"``). Workers of a remote cluster must see the frame files under the same paths
(a shared file system) and have tvmedit installed.
"""

import contextlib
import os
import signal
from collections import deque

from .errors import TvmError
from .checks import whole

#: Most local worker processes a pool may start.
MAX_WORKERS = 512

__all__ = ["Workers", "default_workers", "signals_held", "helper_threads"]

#: Signals held back while workers are forked or GL compiles (:func:`signals_held`).
_HELD = {signal.SIGINT, signal.SIGTERM}


@contextlib.contextmanager
def signals_held():
    """Hold Ctrl-C and SIGTERM back in this thread for the block, then deliver them (the main
    thread; elsewhere, and where the platform cannot, the block runs as it is).

    Threads and processes started in the block inherit the mask: forked workers never run
    this process's handlers (:meth:`Workers._start`), and Mesa's software rasteriser, which
    crashed (a segmentation fault, in about one render in fifty stopped by SIGTERM) when a
    signal came while it made a context or compiled a shader, never takes one
    (:mod:`tvmedit.player.context`). Python handles a held signal right after the block.
    """
    import threading

    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _hold_in_thread():
    """Thread initializer: this thread never takes Ctrl-C or SIGTERM, so the kernel delivers
    them to the main thread alone, where :func:`signals_held` can hold them back."""
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)


def helper_threads(count):
    """A ``ThreadPoolExecutor`` of ``count`` threads that never take Ctrl-C or SIGTERM (nor
    do the threads they start): with one such signal arriving in a helper, Python would raise
    it in the main thread even inside :func:`signals_held`, while workers are forked or GL
    compiles, or while a pool's writers are waited for before a folder is tidied."""
    from concurrent.futures import ThreadPoolExecutor

    return ThreadPoolExecutor(count, initializer=_hold_in_thread)


def _watch_parent(parent):
    """Worker initializer: exit when the build process is gone (killed, it cannot say so).

    Signals are the parent's business: a forked worker would otherwise inherit its SIGTERM
    handler and print a KeyboardInterrupt traceback of its own on Ctrl-C.
    """
    import threading
    import time

    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # Forked with Ctrl-C and SIGTERM held back (:meth:`Workers._start`): one sent meanwhile is
    # now dropped (Ctrl-C) or ends the worker (SIGTERM), never raised in the parent's handlers.
    if hasattr(signal, "pthread_sigmask"):     # POSIX
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _HELD)

    def watch():
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


def default_workers():
    """All the cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


class Workers:
    """Where tasks run: in this process, on local processes, or on a dask cluster.

    Parameters
    ----------
    workers : int or None
        Local worker processes; ``None`` means all cores and ``1`` runs every task in this
        process (no pool at all). With ``dask="local"`` it is the LocalCluster's size.
    dask : str or None
        Address of a running dask.distributed scheduler, or ``"local"`` to start a
        ``LocalCluster`` for the duration of the build.
    threads : bool
        Run the tasks on threads of this process instead: for work that lets go of the GIL
        most of its time (Draco's encoder, writing a file), which then needs no fork and no
        pickling.

    Use as a context manager; :meth:`map` yields results in the order of the tasks.

    >>> with Workers(1) as pool:
    ...     list(pool.map(abs, [-1, 2, -3]))
    [1, 2, 3]
    """

    def __init__(self, workers=None, dask=None, threads=False):
        if workers is not None:
            workers = whole("workers", workers, at_least=1, at_most=MAX_WORKERS,
                            hint=" worker processes")
        self.workers = default_workers() if workers is None else workers
        self.dask = dask
        self.threads = bool(threads) and not dask
        self._executor = None
        self._client = None
        self._cluster = None

    @property
    def kind(self):
        """``"serial"``, ``"threads"``, ``"processes"`` or ``"dask"``: what :meth:`map` will use."""
        if self.dask:
            return "dask"
        if self.workers == 1:
            return "serial"
        return "threads" if self.threads else "processes"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _start(self):
        if self.dask and self._client is None:
            try:
                from distributed import Client, LocalCluster
            except ImportError:
                raise TvmError(f"dask={self.dask} needs dask.distributed, which is not installed; "
                               "install it with: pip install 'tvmedit[dask]'") from None
            try:
                if self.dask == "local":
                    self._cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1,
                                                 processes=True, dashboard_address=None)
                    self._client = Client(self._cluster)
                else:
                    _check_address(self.dask)
                    self._client = Client(self.dask, timeout=10)
            except ValueError as error:
                # "missing port number", "unknown address scheme", a port that is not a number.
                raise TvmError(f"dask={self.dask} is not a scheduler address ({error}); give one "
                               "such as tcp://host:8786, or local to start one here.") from None
            except (OSError, TimeoutError) as error:
                raise TvmError(f"cannot reach the dask scheduler at {self.dask} ({error}); "
                               "start one with `dask scheduler` or use dask=local.") from None
        elif self.kind == "threads" and self._executor is None:
            self._executor = helper_threads(self.workers)
        elif self.kind == "processes" and self._executor is None:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            # fork starts workers in milliseconds with numpy already imported; elsewhere the
            # platform's default start method is used.
            methods = multiprocessing.get_all_start_methods()
            context = multiprocessing.get_context("fork" if "fork" in methods else None)
            self._executor = ProcessPoolExecutor(self.workers, mp_context=context,
                                                 initializer=_watch_parent, initargs=(os.getpid(),))
            # The workers start at the first task. Forked while Ctrl-C and SIGTERM are held
            # back, none runs this process's handlers for them before it has its own (a worker
            # dying of them half-started would print from its fork); one sent meanwhile is
            # delivered to this process right after.
            with signals_held():
                _result(self._executor.submit(int))

    def start(self):
        """Start the local worker processes now rather than at the first task: before threads
        of the caller's start, so that none is running when they are forked."""
        if self.kind == "processes":
            self._start()

    def map(self, fn, tasks, window=None):
        """Yield ``fn(task)`` for every task, in order, running up to ``window`` at a time.

        For worker processes and dask ``fn`` must be a module-level function (it is pickled to
        the workers); threads take any callable. Exceptions raised by ``fn`` propagate to the
        caller unchanged.
        """
        tasks = iter(tasks)
        if self.kind == "serial":
            for task in tasks:
                yield fn(task)
            return
        self._start()
        window = window or 4 * self.workers
        submit = (self._client.submit if self._client is not None else self._executor.submit)
        pending = deque()
        # A local pool forks a worker inside a submit where none is idle (Python 3.9 and
        # later start them as tasks come): a Ctrl-C that lands between the fork and the pool
        # noting the worker would leave it unknown to close(), napping out its task. Submits
        # run with Ctrl-C and SIGTERM held back, delivered right after (microseconds).
        hold = signals_held if self.kind == "processes" else contextlib.nullcontext
        try:
            for task in tasks:
                with hold():
                    pending.append(submit(fn, task, pure=False) if self._client is not None
                                   else submit(fn, task))
                if len(pending) >= window:
                    yield _result(pending.popleft())
            while pending:
                yield _result(pending.popleft())
        finally:
            # A local pool's pending tasks are cancelled by close(), in the pool's own thread:
            # cancelled here, Python 3.11's pool trips over them when a worker is killed.
            if self._client is not None:
                for future in pending:
                    future.cancel()

    def close(self):
        """Stop the pool or disconnect from the cluster (a LocalCluster is shut down).

        Local workers finish the task they run (a second or less) and take no other. A Ctrl-C
        or SIGTERM while worker processes are waited for (a second one, after the one that
        ended the run) ends them at once: no worker outlives the command. Threads cannot be
        ended: they are waited for with Ctrl-C and SIGTERM held back, which take effect once
        the task they run (a frame written) is done.
        """
        if self._executor is not None and self.kind == "threads":
            executor, self._executor = self._executor, None
            # A thread cannot be ended: the task it runs (a frame, milliseconds) is waited for,
            # a Ctrl-C meanwhile delivered after, so none writes into a folder being tidied.
            with signals_held():
                executor.shutdown(wait=True, cancel_futures=True)
        if self._executor is not None:
            executor, self._executor = self._executor, None
            # Taken before shutdown, which lets go of them. Python 3.9 and later.
            thread = getattr(executor, "_executor_manager_thread", None)
            processes = list((getattr(executor, "_processes", None) or {}).values())
            try:
                executor.shutdown(wait=False, cancel_futures=True)
                _wait_for(thread, processes)
            except BaseException:       # Ctrl-C or SIGTERM while waiting: they end now
                _end(executor, processes)
                raise
        if self._client is not None:
            self._client.close()
            self._client = None
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None


def _result(future):
    """The result of ``future``; a worker that died under it is one sentence, not a traceback."""
    from concurrent.futures.process import BrokenProcessPool

    try:
        return future.result()
    except BrokenProcessPool:
        raise TvmError("a worker process ended abruptly (killed from outside, or out of memory); "
                       "run the command again, with fewer workers where it takes --workers.") from None


def _wait_for(thread, processes):
    """Wait until a shut-down pool's ``processes`` are gone and its ``thread`` has ended.
    Workers killed from outside (SIGTERM to the process group) may die writing an answer, and
    the pool's thread then waits for ever on the rest of it: once every worker is gone, it
    gets a second."""
    while thread is not None and thread.is_alive():
        thread.join(0.1)
        if processes and not any(process.is_alive() for process in processes):
            thread.join(1.0)
            return


def _end(executor, processes):
    """Terminate a process pool's worker ``processes`` now. They take SIGTERM's default, dying
    at once (:func:`_watch_parent`). The pool's own thread may then wait for ever on an answer
    a worker died writing: the command line exits without waiting for it
    (:func:`tvmedit.cli.entry`)."""
    # concurrent.futures has no public way to end its workers (``processes`` is its private
    # ``_processes``). Before Python 3.12 the pool's own thread, finding its workers gone, sets
    # an error on every pending future and stops with a traceback at one already cancelled
    # (by Ctrl-C or shutdown): those are taken out of ``_pending_work_items`` first.
    pending = getattr(executor, "_pending_work_items", None) or {}
    for work_id, item in list(pending.items()):
        if item.future.cancelled():
            pending.pop(work_id, None)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:   # gone before the caller tidies the folder they wrote into
        process.join(timeout=5)


def _check_address(address):
    """Raise ValueError for a scheduler address that cannot be one, before any connection.

    A ``Client`` finds out only once its event loop runs, which takes a second and has been
    seen to hang; distributed's own parsers answer at once, with its own messages.
    """
    from distributed.comm.addressing import parse_address, parse_host_port
    from distributed.comm.registry import get_backend

    scheme, location = parse_address(address)
    get_backend(scheme)
    if scheme in ("tcp", "tls"):
        parse_host_port(location)
