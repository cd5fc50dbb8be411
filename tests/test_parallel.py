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
    for workers, kind in ((1, "serial"), (2, "processes")):
        with Workers(workers) as pool:
            assert pool.kind == kind
            assert list(pool.map(abs, range(-20, 0), window=3)) == list(range(20, 0, -1))


def test_an_error_in_a_task_reaches_the_caller_unchanged():
    with Workers(2) as pool, pytest.raises(TypeError, match="bad operand type for abs"):
        list(pool.map(abs, [1, "x", 3]))


def test_workers_default_to_every_core_this_process_may_use():
    assert Workers().workers == default_workers() >= 1
    assert Workers(dask="local").kind == "dask"


def test_a_worker_count_below_one_is_refused():
    with pytest.raises(TvmError, match="workers"):
        Workers(0)
