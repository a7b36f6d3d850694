"""Executors of the batch studies: local workers capped at the cores, started immune to
Ctrl-C, and ended at once when the study is left by an exception."""

from __future__ import annotations

import os
import signal
import warnings

import numpy as np
import pytest

from rotorcontact.errors import ParameterError
from rotorcontact.studies.execution import JoblibExecutor, available_cores, local_workers, make_executor

psutil = pytest.importorskip("psutil")


def _sigint_blocked() -> bool:
    return signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, [])


def test_local_workers_are_capped_at_the_cores():
    cores = available_cores()
    assert 1 <= cores <= (os.cpu_count() or cores)
    assert local_workers(-1) == (cores, False)
    assert local_workers(1) == (1, False)
    assert local_workers(cores) == (cores, False)
    assert local_workers(cores + 1) == (cores, True)
    assert local_workers(10**6) == (cores, True)


@pytest.mark.parametrize("bad", [0, -2, 1.5, True, "2"])
def test_make_executor_refuses_bad_worker_counts(bad):
    with pytest.raises(ParameterError, match="n_jobs"):
        make_executor(n_jobs=bad)


def test_too_many_joblib_workers_are_capped_with_a_warning():
    with pytest.warns(RuntimeWarning, match="more than the .* cores"):
        executor = make_executor(n_jobs=10**6)
    with executor:
        assert isinstance(executor, JoblibExecutor)
        assert executor.n_jobs == available_cores()


def _loky_workers() -> list:
    out = []
    for p in psutil.Process().children(recursive=True):
        try:
            if any("popen_loky" in part for part in p.cmdline()):
                out.append(p)
        except psutil.Error:
            pass
    return out


@pytest.mark.skipif(not hasattr(signal, "pthread_sigmask"), reason="POSIX signal masks")
def test_joblib_workers_ignore_ctrl_c_and_end_when_the_study_is_left_by_an_exception():
    from joblib import delayed

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        executor = JoblibExecutor(2)
    assert not _sigint_blocked()  # the block is lifted in this process
    masks = set(executor._parallel(delayed(_sigint_blocked)() for _ in range(8)))
    assert masks == {True}  # a Ctrl-C in a terminal reaches the parent alone
    workers = _loky_workers()
    assert len(workers) >= 2
    with pytest.raises(KeyboardInterrupt):
        with executor:
            raise KeyboardInterrupt
    gone, alive = psutil.wait_procs(workers, timeout=30)
    assert not [p for p in alive if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]


def test_with_a_store_waves_read_earlier_chunks_from_it_and_memory_keeps_none(tmp_path):
    """A study with a chunk store holds no results in memory: the sink is a view of the store, from which
    a later wave reads the chunks of the earlier ones (as a carried sweep does)."""
    from rotorcontact.studies.execution import ChunkStore, StoredChunks, run_waves

    class Echo:
        def run(self, tasks):
            for i, task in enumerate(tasks):
                yield i, {"value": np.full(2, task.n_items, dtype=float)}

    class Task:
        def __init__(self, key, n):
            self.key, self.n_items = key, n

    class Bar:
        def update(self, _n):
            pass

    store = ChunkStore(tmp_path / "chunks", {"study": "echo"})
    sink = StoredChunks(store, ["a", "b"])
    seen = []

    def waves(sink):
        yield [Task("a", 3)]
        seen.append(sink["a"]["value"].tolist())  # the first wave's chunk, read from its file
        yield [Task("b", 5)]

    assert run_waves(Echo(), waves(sink), store, Bar(), sink) == 2
    assert seen == [[3.0, 3.0]] and sorted(sink) == ["a", "b"] and len(sink) == 2
    assert store.load("b")["value"].tolist() == [5.0, 5.0]
    with pytest.raises(KeyError):
        sink["c"]
    # without a store the results stay in the dict
    plain = {}
    assert run_waves(Echo(), iter([[Task("c", 1)]]), None, Bar(), plain) == 1
    assert plain["c"]["value"].tolist() == [1.0, 1.0]
