"""Executors of the batch studies: local workers capped at the cores, started immune to
Ctrl-C, and ended at once when the study is left by an exception."""

from __future__ import annotations

import os
import signal
import warnings

import numpy as np
import pytest

from rotorcontact.errors import ParameterError
from rotorcontact.studies.execution import (CHUNKS_PER_WORKER, MIN_FITTED_CHUNK, JoblibExecutor, available_cores,
                                            fitted_chunk_size, local_workers, make_executor)

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


def test_fitted_chunk_size_gives_each_worker_its_share_of_chunks():
    # in this process (None) or on one worker, the default stands
    assert fitted_chunk_size(4000, 64, None) == 64 and fitted_chunk_size(4000, 64, 1) == 64
    for n_items, workers in [(4000, 16), (4001, 16), (160_000, 16), (100, 16), (7, 3), (10**6, 2), (5, 2)]:
        for default in (64, 3):
            size = fitted_chunk_size(n_items, default, workers)
            assert min(default, MIN_FITTED_CHUNK) <= size <= default
            chunks = -(-n_items // size)
            target = CHUNKS_PER_WORKER * workers
            # at least as many chunks per worker as asked for, unless the default or the smallest chunk
            # allows fewer
            assert chunks >= target or size in (default, MIN_FITTED_CHUNK)
            # and chunks no smaller than needed: fewer than twice as many
            assert chunks < 2 * target or size in (default, MIN_FITTED_CHUNK)


def test_worker_processes_take_smaller_chunks_of_a_default_study(tmp_path):
    from rotorcontact.studies.sweep import sweep, sweep_values

    from reference_parameters import REF

    values = sweep_values(0.08, 0.2, 200)
    kw = dict(mode="independent", n_transient=40, n_record=10, progress=False)
    here = sweep(REF, "gamma", values, **kw)
    there = sweep(REF, "gamma", values, n_jobs=2, **kw)
    workers = min(2, available_cores())
    size = fitted_chunk_size(200, 64, workers)
    assert here.dataset.attrs["chunk_size"] == 64
    assert there.dataset.attrs["chunk_size"] == size and there.chunks_computed == -(-200 // size)
    assert workers == 1 or size < 64
    for name in here.dataset.data_vars:
        assert here.dataset[name].values.tobytes() == there.dataset[name].values.tobytes(), name
    # a chunk size given is kept
    assert sweep(REF, "gamma", values, n_jobs=2, chunk_size=64, **kw).chunks_computed == 4


def test_executors_count_the_workers_that_take_chunks():
    assert make_executor().workers is None
    workers = min(2, available_cores())
    with make_executor(n_jobs=2, scheduler="local", processes=False) as dask:
        assert dask.workers == workers
    with make_executor(n_jobs=2) as joblib:
        assert joblib.workers == workers


class _Ones:
    """A task of another kind (`run_task`): a block of ones, under its own key."""

    def __init__(self, key: str) -> None:
        self.key, self.n_items = key, 1

    def compute(self, parallel: bool) -> dict[str, np.ndarray]:
        return {"summary": np.ones((64, 64))}


def test_dask_lets_go_of_each_chunk_once_it_is_handed_over():
    """The cluster keeps a chunk's result only until the study has it: after all but one chunk are handed
    over, at most that one is held in the workers' memory."""
    import time

    n = 12
    with make_executor(n_jobs=1, scheduler="local", processes=False) as dask:
        chunks = dask.run([_Ones(f"c{i}") for i in range(n)])
        for _ in range(n - 1):
            assert next(chunks)[1]["summary"].sum() == 64 * 64
        deadline = time.monotonic() + 20.0
        while (held := len(dask.client.who_has())) > 1 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert held <= 1
        assert len(list(chunks)) == 1


def test_a_local_cluster_leaves_port_8787_alone():
    """Another cluster's dashboard on 8787 neither warns nor is taken: the local cluster has no dashboard."""
    import socket
    import warnings

    held = socket.socket()
    try:
        held.bind(("127.0.0.1", 8787))
        held.listen()
    except OSError:  # already held by something else: as good for the test
        pass
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with make_executor(n_jobs=1, scheduler="local", processes=False) as dask:
                port = dask._cluster.scheduler.http_server.port
        assert port != 8787
        assert not [w for w in caught if "already in use" in str(w.message)], [str(w.message) for w in caught]
    finally:
        held.close()


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


# ---------------------------------------------------------------------------
# Dask clusters that cannot be used: refused in bounded time, with the cause named
# ---------------------------------------------------------------------------


def _raised_within(seconds, fn):
    """The exception ``fn()`` raises, asserting it came within ``seconds`` (a hang fails, it does not block)."""
    import threading

    outcome = []

    def target():
        try:
            fn()
        except BaseException as exc:  # handed to the test
            outcome.append(exc)
        else:
            outcome.append(None)

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(seconds)
    assert outcome, f"still waiting after {seconds} s"
    return outcome[0]


def _server(reply):
    """A TCP server on a free local port that answers every connection with ``reply`` (None: never answers)."""
    import socket
    import threading
    import time

    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen()
    held = []

    def serve():
        while True:
            try:
                conn, _ = srv.accept()
            except OSError:  # the server is closed
                for conn in held:
                    conn.close()
                return
            held.append(conn)
            if reply is not None:
                conn.sendall(reply)
                time.sleep(0.2)
                conn.close()

    threading.Thread(target=serve, daemon=True).start()
    return srv, f"tcp://127.0.0.1:{srv.getsockname()[1]}"


@pytest.mark.parametrize("address, why", [
    ("http://127.0.0.1:8786", "unknown address scheme"),
    ("tcp://127.0.0.1", "missing port"),
    ("tcp://127.0.0.1:port", ""),
])
def test_a_malformed_scheduler_address_is_refused_before_connecting(address, why):
    with pytest.raises(ParameterError) as info:
        make_executor(scheduler=address)
    assert str(info.value).startswith(f"scheduler = '{address}' is not a valid address ({why}")


@pytest.mark.parametrize("reply, why", [
    (None, "accepts connections but does not answer as a Dask scheduler"),
    (b"HTTP/1.0 400 Bad Request\r\n\r\n", "is not a Dask scheduler"),
    (b"\xff" * 64, "is not a Dask scheduler"),
])
def test_a_service_that_is_not_a_dask_scheduler_is_refused_in_bounded_time(monkeypatch, reply, why):
    """distributed's own handshake waits for ever on a port that accepts and never answers (a dashboard's)."""
    from rotorcontact.studies import execution

    monkeypatch.setattr(execution, "CONNECT_TIMEOUT_S", 1.0)
    srv, address = _server(reply)
    try:
        exc = _raised_within(60, lambda: make_executor(scheduler=address))
    finally:
        srv.close()
    assert isinstance(exc, ParameterError) and why in str(exc) and repr(address) in str(exc)


@pytest.fixture
def tcp_cluster():
    """An in-process LocalCluster on TCP, with one worker, and a factory of more such clusters."""
    from rotorcontact.studies.execution import local_cluster

    clusters = []

    def make(n_workers):
        cluster = local_cluster(n_workers, processes=False, protocol="tcp")
        clusters.append(cluster)
        return cluster

    yield make
    for cluster in clusters:
        cluster.close()


def test_a_workers_address_and_a_cluster_without_workers_are_refused(monkeypatch, tcp_cluster):
    from rotorcontact.studies import execution

    monkeypatch.setattr(execution, "CONNECT_TIMEOUT_S", 1.0)
    worker = next(iter(tcp_cluster(1).workers.values())).address
    with pytest.raises(ParameterError) as info:
        make_executor(scheduler=worker)
    assert str(info.value).startswith(f"scheduler = '{worker}' is a Dask worker, not a Dask scheduler")
    empty = tcp_cluster(0).scheduler_address
    exc = _raised_within(60, lambda: make_executor(scheduler=empty))
    assert isinstance(exc, ParameterError) and "has no workers (none joined within 1 s)" in str(exc)


def test_workers_must_run_this_version_of_rotorcontact(monkeypatch, tcp_cluster):
    from distributed import Client

    from rotorcontact import __version__
    from rotorcontact.studies import execution

    address = tcp_cluster(1).scheduler_address
    executor = make_executor(scheduler=address)  # the same package in the workers: accepted
    executor.close()
    monkeypatch.setattr(execution, "_worker_version", lambda: "0.0.0")
    with pytest.raises(ParameterError, match=f"must run rotorcontact {__version__}, .*has 0.0.0"):
        make_executor(scheduler=address)

    def missing():
        raise ModuleNotFoundError("No module named 'rotorcontact'")

    monkeypatch.setattr(execution, "_worker_version", missing)
    with Client(address) as client:  # a client of the user's is checked too, and left open
        with pytest.raises(ParameterError, match="workers cannot run rotorcontact .*No module named"):
            make_executor(scheduler=client)
        assert client.status == "running"


def test_a_study_stops_when_its_cluster_has_no_workers_left(monkeypatch, tcp_cluster, tmp_path):
    """A cluster whose workers have left keeps the chunks waiting for ever: the study stops instead."""
    from distributed import Client

    from rotorcontact.model.params import Parameters
    from rotorcontact.studies import execution
    from rotorcontact.studies.sweep import sweep

    monkeypatch.setattr(execution, "NO_WORKERS_TIMEOUT_S", 0.5)
    monkeypatch.setattr(execution, "_WORKER_POLL_S", 0.2)
    with Client(tcp_cluster(0).scheduler_address) as client:
        exc = _raised_within(60, lambda: sweep(Parameters.reference(), "gamma", [0.1, 0.11], scheduler=client,
                                                n_transient=1, n_record=1, progress=False))
    assert isinstance(exc, RuntimeError) and "has had no workers for 0.5 s" in str(exc)


def test_a_cluster_that_cannot_be_used_leaves_no_chunk_folder(tmp_path):
    from rotorcontact.model.params import Parameters
    from rotorcontact.studies.sweep import sweep

    with pytest.raises(ParameterError, match="not a valid address"):
        sweep(Parameters.reference(), "gamma", [0.1, 0.11], scheduler="tcp://127.0.0.1", n_transient=1,
              n_record=1, progress=False, out=tmp_path / "s.nc")
    assert list(tmp_path.iterdir()) == []


def test_chunks_cancelled_on_the_cluster_stop_the_study_with_an_error(monkeypatch, tcp_cluster):
    """Chunks cancelled on the cluster (as when the client loses its scheduler) end the study with a RuntimeError."""
    import threading
    import time

    from distributed import Client

    from rotorcontact.model.params import Parameters
    from rotorcontact.studies import execution
    from rotorcontact.studies.sweep import sweep

    made = []

    class Recorded(execution.DaskExecutor):
        """The study's executor, recorded so that its tasks can be cancelled from outside."""

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            made.append(self)

    monkeypatch.setattr(execution, "DaskExecutor", Recorded)
    with Client(tcp_cluster(0).scheduler_address) as client:  # no workers: the chunks wait until cancelled

        def cancel_once_sent():
            for _ in range(600):
                if made and made[0]._futures:
                    client.cancel(made[0]._futures)
                    return
                time.sleep(0.05)

        threading.Thread(target=cancel_once_sent, daemon=True).start()
        exc = _raised_within(60, lambda: sweep(Parameters.reference(), "gamma", [0.1, 0.11], scheduler=client,
                                                n_transient=1, n_record=1, progress=False))
    assert isinstance(exc, RuntimeError) and "cancelled the study's chunks" in str(exc)



def test_a_worker_loads_only_what_a_chunk_needs():
    """A joblib or Dask worker imports the chunk runner and its kernel's module. numba brings scipy's base
    package (and scipy.linalg when it loads a kernel); the interpolation, optimisation and data libraries,
    half a second or more of every worker's start, wait until something uses them."""
    import subprocess
    import sys

    code = "import sys, rotorcontact.studies.execution\nprint(' '.join(sys.modules))"
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert "rotorcontact.studies.batch" in loaded and "numba" in loaded
    heavy = {"xarray", "matplotlib", "dask", "distributed", "pandas", "pint", "scipy.interpolate", "scipy.optimize",
             "scipy.special", "scipy.integrate"}
    assert sorted(m for m in loaded if m in heavy or m.split(".")[0] in heavy) == []


@pytest.mark.parametrize("bad", [0, 2**31, 10**12, 2.5, True, "8"])
def test_a_chunk_size_beyond_what_the_chunk_files_store_is_refused(bad):
    from rotorcontact.studies.execution import MAX_CHUNK_SIZE, check_chunk_size
    from rotorcontact.studies.sweep import sweep
    from reference_parameters import REF

    assert check_chunk_size(MAX_CHUNK_SIZE) == 2**31 - 1
    with pytest.raises(ParameterError, match=r"^chunk_size = .* is invalid; allowed: an integer from 1 to 2147483647$"):
        check_chunk_size(bad)
    with pytest.raises(ParameterError, match=r"^chunk_size = "):
        sweep(REF, "gamma", [0.1, 0.2], chunk_size=bad, progress=False)


@pytest.mark.parametrize("flag", ["resume", "keep_chunks", "progress"])
def test_the_yes_no_flags_of_a_study_are_bools(flag, tmp_path):
    from rotorcontact.studies.sweep import sweep
    from reference_parameters import REF

    with pytest.raises(ParameterError, match=rf"^{flag} = 'no' is invalid; allowed: True or False$"):
        sweep(REF, "gamma", [0.1, 0.2], out=tmp_path / "s.nc", **{flag: "no"})
    assert not any(tmp_path.iterdir())


def test_a_store_never_deletes_or_writes_into_a_folder_of_other_files(tmp_path):
    from rotorcontact.studies.execution import ChunkStore

    folder = tmp_path / "results"
    folder.mkdir()
    (folder / "thesis.tex").write_text("precious")
    (folder / "data.npz").write_bytes(b"not a chunk")
    for resume in (False, True):
        with pytest.raises(ParameterError, match=r"^folder = .* holds files that are not chunks of a study "
                                                 r"\(thesis\.tex\); allowed: a chunk folder"):
            ChunkStore(folder, {"study": "a"}, resume=resume)
    (folder / "thesis.tex").unlink()
    # .npz files without a store's manifest are not chunks either
    with pytest.raises(ParameterError, match=r"^folder = .* \(no manifest\.json\)"):
        ChunkStore(folder, {"study": "a"}, resume=False)
    assert (folder / "data.npz").read_bytes() == b"not a chunk" and not (folder / "manifest.json").exists()
    file = tmp_path / "file"
    file.write_text("x")
    with pytest.raises(ParameterError, match=r"^folder = .* is a file, not a folder of chunks"):
        ChunkStore(file, {"study": "a"})
    for bad in ("", None):
        with pytest.raises(ParameterError, match=r"^folder = "):
            ChunkStore(bad, {"study": "a"})


def test_a_store_starting_afresh_or_removed_deletes_only_its_own_files(tmp_path):
    from rotorcontact.studies.execution import ChunkStore

    folder = tmp_path / "s.nc.chunks"
    store = ChunkStore(folder, {"study": "a"})
    store.save("c0", {"x": np.arange(3.0)})
    again = ChunkStore(folder, {"study": "a"}, resume=False)
    assert again.count() == 0 and (folder / "manifest.json").exists()
    again.save("c1", {"x": np.arange(2.0)})
    again.remove()
    assert not folder.exists()


def test_worker_counts_and_chunk_keys_are_checked(tmp_path):
    from rotorcontact.studies.execution import ChunkStore, fitted_chunk_size, local_workers, make_executor

    for bad in (0, -2, 1.5, True, "2", None):
        with pytest.raises(ParameterError, match=r"^n_jobs = .* is invalid; allowed: an integer >= 1, or -1"):
            local_workers(bad)
    assert local_workers(np.int64(1)) == (1, False)
    with pytest.raises(ParameterError, match=r"^processes = 'x' is invalid; allowed: True or False$"):
        make_executor(None, processes="x")
    with pytest.raises(ParameterError, match=r"^workers = 0 is invalid"):
        fitted_chunk_size(10, 4, 0)
    with pytest.raises(ParameterError, match=r"^default = 0 is invalid"):
        fitted_chunk_size(10, 0, 2)
    store = ChunkStore(tmp_path / "s.chunks", {"study": "k"})
    for key in ("../x", "/abs", "a/b", ".hidden", "", None, 5):
        with pytest.raises(ParameterError, match=r"^key = .* is invalid; allowed: a chunk name"):
            store.save(key, {"x": np.zeros(1)})
    store.remove()


def test_a_task_is_a_chunk_task_or_computes_itself():
    from rotorcontact.studies.execution import run_task

    for bad in (None, "x", {"compute": 1}):
        with pytest.raises(ParameterError, match=r"^task = .* is invalid; allowed: a ChunkTask, or a task with a"):
            run_task(bad)
    with pytest.raises(ParameterError, match=r"^parallel = 'x' is invalid"):
        run_task(None, parallel="x")


def test_study_digest_is_exact_in_every_float_and_refuses_objects_it_cannot_write():
    """Two settings that differ in the last bit of a float have different digests; an object whose str()
    could hold an address, or leave out what tells two studies apart, is refused by type."""
    from rotorcontact import ParameterError
    from rotorcontact.studies.execution import study_digest

    base = {"values": np.array([0.1, 0.2]), "grid": (1, 2.5, 1j), "flag": True, "name": None}
    bumped = dict(base, values=np.array([0.1, np.nextafter(0.2, 1.0)]))
    assert study_digest(base) == study_digest(dict(base))
    assert study_digest(base) != study_digest(bumped)

    class Opaque:
        pass

    with pytest.raises(ParameterError, match="type Opaque"):
        study_digest({"settings": [Opaque()]})


def _chunk_tasks(lanes: list[int], steps: int = 2) -> list:
    """Chunk tasks of the given lane counts, over a spread of gammas and starts."""
    from rotorcontact.studies.batch import BatchSettings, parameter_array
    from rotorcontact.studies.execution import ChunkTask
    from reference_parameters import REF

    st = BatchSettings(n_transient=80, n_record=20)
    tasks = []
    for k, n in enumerate(lanes):
        gammas = np.linspace(0.07, 0.19, n * steps) + 0.001 * k
        rows = parameter_array([REF.replace(gamma=g) for g in gammas]).reshape(n, steps, -1)
        u0 = np.linspace(-0.4, 0.4, n * steps).reshape(n, steps) * (1 - 0.3j)
        tasks.append(ChunkTask(key=f"c{k}", params=rows, u0=u0, du0=np.zeros_like(u0), carry=k % 2 == 1,
                               settings=st))
    return tasks


def _lane_threads() -> list:
    import threading

    return [t for t in threading.enumerate() if t.name.startswith("rotorcontact-lanes-")]


@pytest.mark.parametrize("threads", [1, 2, 5])
def test_threads_in_process_give_every_chunk_the_bits_of_one_core(threads):
    from rotorcontact.studies.execution import InProcessExecutor, run_task

    tasks = _chunk_tasks([9, 1, 4, 13])
    tasks.insert(2, _Ones("other"))
    executor = InProcessExecutor()
    executor.threads = threads  # Python threads: as many as asked, whatever numba's count
    got = dict(executor.run(tasks))
    assert sorted(got) == list(range(len(tasks)))
    for i, task in enumerate(tasks):
        want = run_task(task, parallel=False)
        assert sorted(got[i]) == sorted(want)
        for name in want:
            assert got[i][name].tobytes() == want[name].tobytes(), (i, name)
    assert not _lane_threads()


def test_an_error_in_a_thread_is_raised_by_the_study_and_the_threads_end(monkeypatch):
    import itertools

    from rotorcontact.studies import execution

    real, blocks = execution.run_lane_block, itertools.count()

    def failing(args, first, end):
        if next(blocks) == 2:  # the third block claimed, whichever thread runs it
            raise FloatingPointError("block three")
        real(args, first, end)

    monkeypatch.setattr(execution, "run_lane_block", failing)
    executor = execution.InProcessExecutor()
    executor.threads = 3
    with pytest.raises(FloatingPointError, match="block three"):
        list(executor.run(_chunk_tasks([6, 6, 6])))
    assert not _lane_threads()


def test_a_wave_left_early_ends_its_threads():
    from rotorcontact.studies.execution import InProcessExecutor

    executor = InProcessExecutor()
    executor.threads = 2
    wave = executor.run(_chunk_tasks([1] + [8] * 12, steps=1))
    next(wave)
    wave.close()
    assert not _lane_threads()


def test_a_study_left_by_an_exception_between_two_chunks_ends_its_threads():
    # the wave's generator is left suspended (and kept alive by the test's own reference, as a traceback
    # would): leaving the executor stops its threads instead of letting them run the wave out
    from rotorcontact.studies.execution import InProcessExecutor

    with pytest.raises(ValueError, match="the caller failed"):
        with InProcessExecutor() as executor:
            executor.threads = 2
            wave = executor.run(_chunk_tasks([1] + [8] * 12, steps=1))
            next(wave)
            raise ValueError("the caller failed")
    assert not _lane_threads()
    del wave
