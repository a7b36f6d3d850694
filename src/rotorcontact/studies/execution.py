"""Running batches in chunks: in this process, through joblib, or on a Dask cluster.

A large study (a brute-force diagram, a basin of attraction) is cut into
*chunks*, each a `ChunkTask`: a small block of lanes and steps for the batch
kernel (`rotorcontact.studies.batch`). The cut is fixed by the study and its
``chunk_size`` alone, and every chunk is computed by the same compiled code
from the same inputs, so the results are identical bit for bit whichever
CPU executor runs them:

* ``n_jobs=None`` and no scheduler: in this process, on as many threads as numba's thread count
  (`InProcessExecutor`, all cores by default);
* ``n_jobs=N``: N joblib worker processes, one core each;
* ``scheduler="local"`` (a `distributed.LocalCluster` started and stopped here)
  or ``scheduler="tcp://host:port"`` (an existing Dask cluster, whose workers
  must have the same version of rotorcontact installed: `check_workers`);
* ``backend="cuda"``: in this process, the lanes on its GPU (`CudaExecutor`,
  `rotorcontact.studies.cuda_batch`), whose results agree with the others to
  rounding rather than bit for bit.

Nothing waits on a cluster for ever: a scheduler must answer within
`CONNECT_TIMEOUT_S` and have a worker within as long again, and a study whose
cluster has had no worker for `NO_WORKERS_TIMEOUT_S` stops with an error.

Worker processes on this machine are at most as many as its cores
(`available_cores`): more would only share the cores and multiply the memory.
They are started with Ctrl-C (SIGINT) blocked, so that an interrupt, which a
terminal sends to every process of the command, reaches this process alone;
leaving an executor's ``with`` block by an exception (KeyboardInterrupt
included) ends its workers at once instead of letting them finish.

Chunks that depend on each other (a sweep with the state carried along) are
run in *waves*: a wave holds the chunks whose inputs are known.

A `ChunkStore` writes each finished chunk to its own file in a folder beside
the output, atomically (write, then rename). A study started again with the
same settings finds the finished chunks there, computes only the others, and
produces the same result.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import os
import queue
import re
import signal
import sys
import tempfile
import threading
import time
import warnings
from concurrent.futures import CancelledError
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from collections.abc import Mapping, MutableMapping
from typing import Any, Iterable, Iterator

import numpy as np

from .batch import NSUM, BatchSettings, lane_arguments, run_lane_block, run_lanes
from .guided import GuidedLanes
from ..errors import ParameterError
from .netcdf import read_finished, umask_permissions, write_netcdf
from ..model.validation import check_bool, check_int, check_path, quoted

__all__ = ["BACKENDS", "ChunkTask", "ChunkStore", "CudaExecutor", "StoredChunks", "available_cores",
           "backend_manifest", "check_backend", "check_workers", "fitted_chunk_size", "local_workers", "make_executor",
           "progress_bar", "run_task", "study_digest", "write_netcdf", "read_finished", "check_chunk_size",
           "MAX_CHUNK_SIZE"]

#: Largest chunk size: the chunk files store it as a 32-bit integer. A chunk larger than the study is one
#: chunk of the whole study.
MAX_CHUNK_SIZE = 2**31 - 1


def check_chunk_size(value: Any) -> int:
    """``value`` as a chunk size, a whole number from 1 to `MAX_CHUNK_SIZE`; a `ParameterError` otherwise."""
    from ..model.validation import check_int

    return check_int("chunk_size", value, 1, MAX_CHUNK_SIZE)

STORE_FORMAT = 2

#: Seconds a Dask scheduler has to answer, and then to have its first worker.
CONNECT_TIMEOUT_S = 20.0
#: Seconds a study waits on a Dask cluster without workers before it stops.
NO_WORKERS_TIMEOUT_S = 60.0
#: Seconds between two looks at a cluster's workers while no chunk finishes.
_WORKER_POLL_S = 5.0
#: Chunks per worker that a study's default chunk size is cut down to give when the chunks run on worker
#: processes (`fitted_chunk_size`): each worker takes one chunk at a time, and while the last chunks finish
#: the other workers wait.
CHUNKS_PER_WORKER = 16
#: Fewest simulations a fitted chunk holds: below it a chunk's own cost (its file, its task) would weigh.
MIN_FITTED_CHUNK = 4
#: Lanes of one launch of the GPU backend (chunks are stacked up to about this many) ...
CUDA_LANES = 1 << 18
#: ... and bytes of results (sections and summaries) of one launch, on the GPU and here.
CUDA_RESULT_BYTES = 1 << 30
#: The backends of the batch kernel.
BACKENDS = ("cpu", "cuda")


@dataclass(frozen=True)
class ChunkTask:
    """One chunk of a study: lanes of steps for the batch kernel.

    Attributes
    ----------
    key : str
        Name of the chunk (also its file name in a `ChunkStore`).
    params : numpy.ndarray
        (n_lanes, n_steps, 7) parameter rows.
    u0, du0 : numpy.ndarray
        (n_lanes, n_steps) complex initial states.
    carry : bool
        Carry the state along each lane.
    settings : BatchSettings
        Transient and window.
    """

    key: str
    params: np.ndarray = field(repr=False)
    u0: np.ndarray = field(repr=False)
    du0: np.ndarray = field(repr=False)
    carry: bool
    settings: BatchSettings

    @property
    def n_items(self) -> int:
        """Number of simulations in the chunk."""
        return int(self.params.shape[0] * self.params.shape[1])


def run_task(task: ChunkTask, parallel: bool = False) -> dict[str, np.ndarray]:
    """Compute a chunk; returns its raw ``sections`` and ``summary`` arrays.

    A task of another kind (not a `ChunkTask`: a ``key``, ``n_items`` and a ``compute(parallel)`` method
    returning its arrays, such as the drop map's or the Lyapunov scan's) computes itself; every executor
    runs it the same way.

    Raises
    ------
    ParameterError
        For a task that is neither a `ChunkTask` nor has a ``compute`` method, or a ``parallel`` that is
        not True or False.
    """
    parallel = check_bool("parallel", parallel)
    if not isinstance(task, ChunkTask):
        if not callable(getattr(task, "compute", None)):
            raise ParameterError(f"task = {task!r} is invalid; allowed: a ChunkTask, or a task with a "
                                 "compute(parallel) method")
        return task.compute(parallel)
    sections, summary = run_lanes(task.params, task.u0, task.du0, task.settings, carry=task.carry,
                                  parallel=parallel)
    return {"sections": sections, "summary": summary}


def _indexed(index: int, task: ChunkTask) -> tuple[int, dict[str, np.ndarray]]:
    return index, run_task(task, parallel=False)


# ---------------------------------------------------------------------------
# executors
# ---------------------------------------------------------------------------


def available_cores() -> int:
    """The number of cores this process may run on (its CPU affinity where the system reports it)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - systems without sched_getaffinity
        return max(1, os.cpu_count() or 1)


#: -W option that silences the loky resource tracker's reports of resources it cleans up itself.
_TRACKER_QUIET = "ignore:resource_tracker:UserWarning"


@contextlib.contextmanager
def _interrupts_blocked() -> Iterator[None]:
    """Block SIGINT in this thread while worker processes are started, so that they inherit the block.

    Ctrl-C in a terminal signals every process of the command; workers that
    inherit the block never see it, and the parent, which does, ends them.
    The resource trackers of multiprocessing and loky unblock SIGINT when they
    start, so they are started first. A SIGINT that arrives meanwhile is
    delivered when the block is lifted.
    """
    if not hasattr(signal, "pthread_sigmask") or threading.current_thread() is not threading.main_thread():
        yield
        return
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()
    try:
        from joblib.externals.loky.backend import resource_tracker as loky_tracker
    except ImportError:  # pragma: no cover - joblib is a dependency
        pass
    else:
        # workers killed on an interrupt leave their registrations of the pool's semaphores behind;
        # the tracker unlinks them when the command ends but would warn on stderr about each: it
        # is started with those warnings off (it passes sys.warnoptions on as -W options)
        sys.warnoptions.append(_TRACKER_QUIET)
        try:
            loky_tracker.ensure_running()
        finally:
            sys.warnoptions.remove(_TRACKER_QUIET)
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _kill(processes: list[Any]) -> None:
    """Kill the given `psutil.Process` objects that still run (psutil checks the pid was not reused)."""
    import psutil

    for proc in processes:
        with contextlib.suppress(psutil.Error):
            proc.kill()
    psutil.wait_procs(processes, timeout=5)


class _Executor:
    name = "base"
    #: Worker processes (or threads of a cluster) that take chunks one at a time; None where the chunks run
    #: in this process.
    workers: int | None = None

    def run(self, tasks: list[ChunkTask]) -> Iterator[tuple[int, dict[str, np.ndarray]]]:  # pragma: no cover
        raise NotImplementedError

    def close(self, abort: bool = False) -> None:
        """Release the executor's resources; with ``abort``, end running work at once."""

    def __enter__(self) -> "_Executor":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        # an exception (an interrupt above all) ends the work at once instead of waiting for it
        self.close(abort=exc_type is not None)


class InProcessExecutor(_Executor):
    """Chunks in this process, over as many threads as numba has (`numba.get_num_threads`).

    On one thread the chunks run one after the other. On several, the threads share out the lanes of the
    whole wave by guided self-scheduling (`rotorcontact.studies.guided`): each claims a block of lanes of
    one chunk and runs it through the single-core kernel with the GIL released
    (`rotorcontact.studies.batch.run_lane_block`), then claims the next, so that no thread waits for another
    before the wave runs out. The results are those of any other executor, bit for bit. Tasks of another
    kind (`run_task`) compute themselves in this process, one after the other, before the chunks' lanes.
    """

    name = "in-process"

    def __init__(self) -> None:
        import numba

        self.threads = int(numba.get_num_threads())
        self._guided: GuidedLanes | None = None

    def run(self, tasks):
        if self.threads == 1:
            yield from _run_stacked(tasks, 1, lambda task: run_task(task, parallel=False))
            return
        for i, task in enumerate(tasks):
            if not _has_lanes(task):
                yield i, run_task(task, parallel=True)
        # the chunks that have lanes, their lanes shared out among the threads
        chunks = [(i, t) for i, t in enumerate(tasks) if _has_lanes(t)]
        jobs = [(t.params.shape[0], partial(lane_arguments, t.params, t.u0, t.du0, t.settings, carry=t.carry))
                for _, t in chunks]
        self._guided = GuidedLanes(jobs, run_lane_block, self.threads)
        for k, args in self._guided.run():
            yield chunks[k][0], {"sections": args[-2], "summary": args[-1]}

    def close(self, abort: bool = False) -> None:
        # a study left by an exception while this wave's generator is suspended keeps it alive (its traceback
        # holds it): its threads are stopped here rather than left to run the wave out
        guided, self._guided = self._guided, None
        if guided is not None:
            guided.stop()


def _has_lanes(task: Any) -> bool:
    return isinstance(task, ChunkTask) and task.params.shape[0] > 0


def _run_stacked(tasks: list, enough: int, compute) -> Iterator[tuple[int, dict[str, np.ndarray]]]:
    """Run consecutive stackable chunk tasks together, each call growing until it holds ``enough`` lanes.

    ``compute(task)`` runs one `ChunkTask` (a stack of several is one task); a task of another kind runs
    by itself in this process. Yields (index, arrays) for every task, in order.
    """
    i = 0
    while i < len(tasks):
        if not isinstance(tasks[i], ChunkTask):
            yield i, run_task(tasks[i], parallel=True)
            i += 1
            continue
        group = [i]
        lanes = tasks[i].params.shape[0]
        while (
            lanes < enough
            and group[-1] + 1 < len(tasks)
            and _stackable(tasks[group[0]], tasks[group[-1] + 1])
        ):
            group.append(group[-1] + 1)
            lanes += tasks[group[-1]].params.shape[0]
        if len(group) == 1:
            yield i, compute(tasks[i])
        else:
            sub = [tasks[j] for j in group]
            stacked = ChunkTask(
                key="stacked",
                params=np.concatenate([t.params for t in sub]),
                u0=np.concatenate([t.u0 for t in sub]),
                du0=np.concatenate([t.du0 for t in sub]),
                carry=sub[0].carry,
                settings=sub[0].settings,
            )
            res = compute(stacked)
            start = 0
            for j, t in zip(group, sub):
                n = t.params.shape[0]
                yield j, {name: arr[start : start + n] for name, arr in res.items()}  # views: no copy
                start += n
        i = group[-1] + 1


def _stackable(a: ChunkTask, b: ChunkTask) -> bool:
    if not isinstance(b, ChunkTask):
        return False
    return a.params.shape[1] == b.params.shape[1] and a.carry == b.carry and a.settings == b.settings


class CudaExecutor(_Executor):
    """Chunks on an NVIDIA GPU (`rotorcontact.studies.cuda_batch`), stacked into launches of `CUDA_LANES` lanes
    and `CUDA_RESULT_BYTES` of results at most (a launch may pass them by its last chunk).

    Items the GPU hands back (`rotorcontact.studies.cuda_batch`) are finished by the CPU kernel in this
    process (``handed_to_cpu`` counts them). Tasks of another kind run in this process.
    """

    name = "cuda"

    def __init__(self) -> None:
        from .cuda_batch import require_cuda

        require_cuda()
        self.items = 0
        self.handed_to_cpu = 0

    def _compute(self, task: ChunkTask) -> dict[str, np.ndarray]:
        from .cuda_batch import run_lanes_cuda

        sections, summary, deferred = run_lanes_cuda(task.params, task.u0, task.du0, task.settings,
                                                     carry=task.carry)
        self.items += task.n_items
        self.handed_to_cpu += int(np.where(deferred >= 0, task.params.shape[1] - deferred, 0).sum())
        return {"sections": sections, "summary": summary}

    def run(self, tasks):
        first = next((t for t in tasks if isinstance(t, ChunkTask)), None)
        lanes = CUDA_LANES
        if first is not None:
            steps = first.params.shape[1]
            per_lane = steps * (first.settings.keep * 4 + NSUM) * 8
            lanes = max(1, min(CUDA_LANES, CUDA_RESULT_BYTES // per_lane))
        yield from _run_stacked(tasks, lanes, self._compute)


class JoblibExecutor(_Executor):
    """Chunks in joblib worker processes (loky), one core each.

    The workers are started at once, with SIGINT blocked (`_interrupts_blocked`),
    and reused from wave to wave (loky's reusable pool). `close` with ``abort``
    kills them.
    """

    name = "joblib"

    def __init__(self, n_jobs: int) -> None:
        from joblib import Parallel, delayed

        self.n_jobs = n_jobs
        self.workers = n_jobs
        self._running = None
        self._parallel = None
        try:
            with _interrupts_blocked():
                # not a managed backend (no ``with Parallel``): joblib then ends the workers on an
                # exception instead of starting a fresh pool
                self._parallel = Parallel(n_jobs=n_jobs, backend="loky", return_as="generator_unordered")
                for _ in self._parallel(delayed(os.getpid)() for _ in range(n_jobs)):
                    pass
        except BaseException:
            self.close(abort=True)
            raise

    def run(self, tasks):
        from joblib import delayed

        self._running = self._parallel(delayed(_indexed)(i, t) for i, t in enumerate(tasks))
        try:
            # not ``yield from``: that would close joblib's generator itself when this one is left, and joblib
            # then writes a note on the tasks it cancels to stderr
            for item in self._running:
                yield item
        except BaseException:
            # left by an interrupt or an error, here or in the caller: the work ends at once, quietly
            self.close(abort=True)
            raise
        self._running = None

    def close(self, abort: bool = False) -> None:
        running, self._running = self._running, None
        if not abort:
            return
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if running is not None:
                with contextlib.suppress(Exception):
                    running.close()  # joblib aborts: the pool's workers are killed
            # whatever joblib left running (an interrupt between two waves, or during the start)
            with contextlib.suppress(Exception):
                from joblib.externals.loky import reusable_executor

                pool = getattr(reusable_executor, "_executor", None)
                if pool is not None:
                    pool.shutdown(wait=False, kill_workers=True)


def local_cluster(n_workers: int, processes: bool = True, **kwargs: Any) -> Any:
    """A `distributed.LocalCluster` of ``n_workers`` single-threaded workers, without a dashboard.

    Its scheduler serves Dask's HTTP routes on a free port of 127.0.0.1 rather than on 8787, which another
    cluster may hold (Dask would then warn on stderr and take another port). Dask's diagnosis of garbage
    collections, which its scheduler turns on in this process, is turned off again: its callback runs
    Python code at every collection, and a Ctrl-C that lands in it is lost (Python reports it as an
    exception ignored in the callback).

    Parameters
    ----------
    n_workers : int
        Workers.
    processes : bool
        Workers as processes (True) or as threads of this process.
    **kwargs
        Further arguments of `distributed.LocalCluster` (``protocol``, for example).
    """
    from distributed import LocalCluster

    cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=processes, dashboard_address=None,
                           scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, **kwargs)
    _gc_diagnosis_off()
    return cluster


def _gc_diagnosis_off() -> None:
    """Turn Dask's diagnosis of garbage collections off in this process (`local_cluster`)."""
    try:
        from distributed.gc import disable_gc_diagnosis
    except ImportError:  # distributed before 2024.2 keeps it in utils_perf
        try:
            from distributed.utils_perf import disable_gc_diagnosis
        except ImportError:  # pragma: no cover - a version without it has no callback to turn off
            return
    disable_gc_diagnosis(force=True)


class DaskExecutor(_Executor):
    """Chunks as tasks on a Dask distributed cluster.

    Parameters
    ----------
    scheduler : str or distributed.Client
        ``"local"`` starts a `distributed.LocalCluster` (``n_workers`` workers
        of one thread, closed again by `close`); an address such as
        ``"tcp://10.0.0.1:8786"`` connects to a running scheduler; a Client is used as it is.
    n_workers : int or None
        Workers of the local cluster (default: the number of cores).
    processes : bool
        Local workers as processes (True) or threads of this process.

    Notes
    -----
    Local worker processes start with SIGINT blocked (`_interrupts_blocked`);
    `close` with ``abort`` cancels the tasks, kills the local workers and
    closes the cluster without its shutdown messages. Workers of a remote
    cluster only lose their tasks.
    """

    name = "dask"

    def __init__(self, scheduler: Any, n_workers: int | None = None, processes: bool = True) -> None:
        try:
            from distributed import Client
        except ImportError:  # pragma: no cover - a declared dependency
            raise ParameterError("scheduler given but dask.distributed is not installed") from None
        self._cluster = None
        self._own_client = True
        self._futures: list[Any] = []
        self._workers: list[Any] = []
        self._where = repr(scheduler) if isinstance(scheduler, str) else "the client's cluster"
        self.client = None
        if isinstance(scheduler, Client):
            self.client = scheduler
            self._own_client = False
        elif scheduler == "local":
            n = n_workers or available_cores()
            try:
                with _interrupts_blocked():
                    self._cluster = local_cluster(n, processes=processes)
                    self.client = Client(self._cluster)
                    if processes:
                        import psutil

                        pids = self.client.run(os.getpid).values()
                        self._workers = [psutil.Process(pid) for pid in pids if pid != os.getpid()]
            except BaseException:
                self.close(abort=True)
                raise
        elif isinstance(scheduler, str) and "://" in scheduler:
            workers = _scheduler_workers(scheduler)
            try:
                self.client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S}s")
            except (OSError, TimeoutError) as exc:
                raise ParameterError(f"scheduler = {scheduler!r}: cannot connect ({exc})") from None
            try:
                if not workers:
                    _await_worker(self.client, scheduler)
                check_workers(self.client, self._where)
            except BaseException:
                self.close(abort=True)
                raise
        else:
            raise ParameterError(
                f"scheduler = {scheduler!r} is invalid; allowed: 'local' or an address such as tcp://host:8786"
            )
        if not self._own_client:
            check_workers(self.client, self._where)
        with contextlib.suppress(Exception):  # how many chunks run at once, for `fitted_chunk_size`
            self.workers = int(sum(self.client.nthreads().values())) or None

    def run(self, tasks):
        from distributed import KilledWorker

        futures = self.client.map(_indexed, range(len(tasks)), tasks, pure=False)
        self._futures = futures
        finished: queue.Queue = queue.Queue()
        for fut in futures:
            fut.add_done_callback(finished.put)
        for _ in range(len(futures)):
            fut = self._next_finished(finished)
            try:
                result = fut.result()
            except KilledWorker as exc:
                raise RuntimeError(
                    f"the Dask workers that ran a chunk died ({exc}); see their logs (memory limit, crash)"
                ) from None
            except CancelledError as exc:  # the scheduler was lost, or the tasks cancelled on the cluster
                raise RuntimeError(
                    f"the Dask cluster ({self._where}) cancelled the study's chunks ({exc}); the chunks already "
                    "written are resumed when the study is run again"
                ) from None
            # the caller writes the chunk away: the workers need not keep it (a wave would otherwise hold the
            # whole study's results on the cluster until its end)
            fut.release()
            yield result
        for fut in futures:
            fut.release()
        self._futures = []

    def _next_finished(self, finished: queue.Queue) -> Any:
        """The next future put in ``finished``; a `RuntimeError` once the cluster has had no workers for
        `NO_WORKERS_TIMEOUT_S` (one whose workers have all left, or never came, would keep the chunks for ever)."""
        no_workers_since = None
        while True:
            try:
                return finished.get(timeout=_WORKER_POLL_S)
            except queue.Empty:
                pass
            if _has_workers(self.client):
                no_workers_since = None
            elif no_workers_since is None:
                no_workers_since = time.monotonic()
            elif time.monotonic() - no_workers_since > NO_WORKERS_TIMEOUT_S:
                raise RuntimeError(
                    f"the Dask cluster ({self._where}) has had no workers for {NO_WORKERS_TIMEOUT_S:g} s: they left "
                    "or failed (see their logs); the chunks already written are resumed when the study is run again"
                )

    def close(self, abort: bool = False) -> None:
        if not abort:
            if self.client is not None and self._own_client:
                self.client.close()
            if self._cluster is not None:
                self._cluster.close()
            return
        # an interrupt or an error: no waiting for running tasks, and no shutdown chatter on stderr; a second
        # Ctrl-C meanwhile would cut the shutdown short and leave the cluster to its finalizers, which take
        # seconds at exit and report every worker's end: each step runs to its end, with Ctrl-C ignored
        quiet = logging.getLogger("distributed")
        level = quiet.level
        quiet.setLevel(logging.CRITICAL + 1)
        try:
            with warnings.catch_warnings(), _interrupts_ignored():
                warnings.simplefilter("ignore")
                with contextlib.suppress(BaseException):
                    if self.client is not None and self._futures:
                        self.client.cancel(self._futures, force=True)
                self._futures = []
                with contextlib.suppress(BaseException):
                    _kill(self._workers)
                if self.client is not None and self._own_client:
                    with contextlib.suppress(BaseException):
                        self.client.close(timeout=5)
                if self._cluster is not None:
                    with contextlib.suppress(BaseException):
                        self._cluster.close(timeout=10)
        finally:
            quiet.setLevel(level)


@contextlib.contextmanager
def _interrupts_ignored() -> Iterator[None]:
    """Ignore SIGINT (Ctrl-C) meanwhile, where this is the main thread (the only one that may set it)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _await_worker(client: Any, address: str) -> None:
    """Wait `CONNECT_TIMEOUT_S` for the first worker of the cluster at ``address``; a `ParameterError` if none joins."""
    try:
        client.wait_for_workers(1, timeout=CONNECT_TIMEOUT_S)
    except TimeoutError:
        raise ParameterError(
            f"scheduler = {address!r} has no workers (none joined within {CONNECT_TIMEOUT_S:g} s); "
            f"start them with: dask worker {address}"
        ) from None


def _has_workers(client: Any) -> bool:
    """Whether the cluster of ``client`` has a worker (False where its scheduler cannot be asked)."""
    try:
        return bool(client.nthreads())
    except OSError:
        return False


def _scheduler_identity(address: str, timeout: float) -> Any:
    """The answer of the Dask scheduler at ``address`` to ``identity``, within ``timeout`` seconds.

    Asked in a thread of its own, on an event loop of its own (the caller may
    run one, as a notebook does), and bounded as a whole: distributed's own
    connection waits for ever for the handshake of a service that accepts the
    connection but never answers (a dashboard's port, for example).
    """
    import asyncio

    from distributed.comm import connect
    from distributed.security import Security

    # the client's connection arguments (TLS certificates) from the Dask configuration, as Client takes them
    arguments = Security().get_connection_args("client")

    async def ask() -> Any:
        comm = await connect(address, timeout=timeout, **arguments)
        try:
            await comm.write({"op": "identity"})
            return await comm.read()
        finally:
            comm.abort()

    async def bounded() -> Any:
        # connect's own timeout (an OSError) covers a host that does not accept the connection,
        # this one a service that accepts it and does not answer
        return await asyncio.wait_for(ask(), timeout + 5.0)

    answer: queue.Queue = queue.Queue()

    def target() -> None:
        try:
            answer.put((True, asyncio.run(bounded())))
        except BaseException as exc:  # handed to the caller
            answer.put((False, exc))

    threading.Thread(target=target, name="rotorcontact-scheduler-identity", daemon=True).start()
    try:
        ok, value = answer.get(timeout=timeout + 10.0)
    except queue.Empty:
        raise TimeoutError(f"no answer within {timeout + 10.0:g} s") from None
    if not ok:
        raise value
    return value


def _scheduler_workers(address: str) -> int:
    """The number of workers of the Dask scheduler at ``address``; a `ParameterError` where none answers.

    Raises
    ------
    ParameterError
        On an address distributed cannot read, a host that cannot be
        reached, or a service that is not a Dask scheduler.
    """
    from distributed.comm.addressing import parse_address, parse_host_port
    from distributed.comm.registry import get_backend

    try:  # distributed's own reading of the address: a known scheme, and a port where it needs one
        scheme, location = parse_address(address)
        get_backend(scheme)
        if scheme in ("tcp", "tls"):
            parse_host_port(location)
    except ValueError as exc:
        raise ParameterError(
            f"scheduler = {address!r} is not a valid address ({exc}); allowed: 'local' or an address such as "
            "tcp://host:8786"
        ) from None
    try:
        identity = _scheduler_identity(address, CONNECT_TIMEOUT_S)
    except TimeoutError:
        raise ParameterError(
            f"scheduler = {address!r}: it accepts connections but does not answer as a Dask "
            "scheduler (the scheduler listens on 8786 by default; 8787 is its dashboard)"
        ) from None
    except OSError as exc:
        raise ParameterError(f"scheduler = {address!r}: cannot connect ({exc})") from None
    except Exception as exc:  # an answer in another protocol cannot be decoded, in any of many ways
        raise ParameterError(
            f"scheduler = {address!r} is not a Dask scheduler (its answer could not be read: {type(exc).__name__})"
        ) from None
    kind = identity.get("type") if isinstance(identity, dict) else None
    if kind != "Scheduler":
        what = f"a Dask {kind.lower()}" if kind in ("Worker", "Nanny") else "not a Dask scheduler"
        raise ParameterError(f"scheduler = {address!r} is {what}, not a Dask scheduler; give the scheduler's address")
    return len(identity.get("workers") or ())


def _worker_version() -> str:
    """The version of rotorcontact in a worker (run there by `check_workers`)."""
    from .. import __version__

    return __version__


def check_workers(client: Any, where: str) -> None:
    """Check that every worker of ``client`` runs this version of rotorcontact.

    A worker without the package would fail on its first chunk and leave
    the study waiting; one with another version could compute other results.

    Raises
    ------
    ParameterError
        Naming the workers concerned and their version, or the error of those
        that cannot import the package.
    """
    from .. import __version__

    try:
        versions = client.run(_worker_version)
    except Exception as exc:  # a worker that cannot import rotorcontact (or cannot run it)
        raise ParameterError(
            f"scheduler = {where}: its workers cannot run rotorcontact ({type(exc).__name__}: {exc}); "
            f"install rotorcontact {__version__} on every worker"
        ) from None
    other = {worker: version for worker, version in versions.items() if version != __version__}
    if other:
        listed = ", ".join(f"{worker} has {version}" for worker, version in sorted(other.items()))
        raise ParameterError(
            f"scheduler = {where}: its workers must run rotorcontact {__version__}, as this process does: {listed}"
        )


def _check_n_jobs(n_jobs: Any) -> int:
    whole = not isinstance(n_jobs, (bool, np.bool_)) and isinstance(n_jobs, (int, np.integer))
    if not (whole and (n_jobs >= 1 or n_jobs == -1)):
        raise ParameterError(f"n_jobs = {n_jobs!r} is invalid; allowed: an integer >= 1, or -1 for all cores")
    return int(n_jobs)


def local_workers(n_jobs: int) -> tuple[int, bool]:
    """The number of local worker processes for ``n_jobs``: at most `available_cores`.

    Parameters
    ----------
    n_jobs : int
        Workers asked for; -1 means one per core.

    Returns
    -------
    n : int
        Workers to start.
    capped : bool
        True when ``n_jobs`` asked for more workers than there are cores.

    Raises
    ------
    ParameterError
        Unless ``n_jobs`` is an integer >= 1 or -1.
    """
    n_jobs = _check_n_jobs(n_jobs)
    cores = available_cores()
    if n_jobs == -1:
        return cores, False
    return min(int(n_jobs), cores), int(n_jobs) > cores


def fitted_chunk_size(n_items: int, default: int, workers: int | None) -> int:
    """A study's default chunk size, cut down so that ``workers`` get at least `CHUNKS_PER_WORKER` chunks each,
    but not below `MIN_FITTED_CHUNK` simulations.

    Parameters
    ----------
    n_items : int
        Simulations of the study.
    default : int
        The study's default chunk size.
    workers : int or None
        Workers that take chunks one at a time (`_Executor.workers`); None (chunks in this process,
        whose threads share out each chunk's lanes) keeps ``default``.

    Returns
    -------
    int
        At most ``default``, and at least ``min(default, MIN_FITTED_CHUNK)``.

    Raises
    ------
    ParameterError
        Unless ``n_items`` is an integer >= 0, ``default`` >= 1 and ``workers`` None or >= 1.
    """
    n_items = check_int("n_items", n_items, 0)
    default = check_int("default", default, 1)
    if workers is not None:
        workers = check_int("workers", workers, 1)
    if workers is None or workers < 2:
        return default
    return min(default, max(MIN_FITTED_CHUNK, n_items // (CHUNKS_PER_WORKER * workers)))


def make_executor(n_jobs: int | None = None, scheduler: Any = None, *, processes: bool = True,
                  backend: str = "cpu") -> _Executor:
    """The executor for ``n_jobs`` / ``scheduler`` / ``backend`` (see the module docstring).

    Local workers (joblib, or ``scheduler="local"``) are at most as many as
    the cores (`local_workers`); asking for more gives that many, with a
    `RuntimeWarning`. ``backend="cuda"`` runs the chunks on this machine's GPU
    (`CudaExecutor`), in this process.

    Raises
    ------
    ParameterError
        On an invalid ``n_jobs``, ``scheduler`` or ``backend``, or ``backend="cuda"`` where no GPU can
        be used.
    """
    check_backend(backend)
    processes = check_bool("processes", processes)
    if backend == "cuda":
        if n_jobs is not None or scheduler is not None:
            raise ParameterError(
                f"backend = 'cuda' runs in this process on its GPU; n_jobs = {n_jobs!r} and scheduler = "
                f"{scheduler!r} are invalid with it; allowed: neither"
            )
        return CudaExecutor()
    if n_jobs is not None:
        n_jobs = _check_n_jobs(n_jobs)
        local = scheduler is None or (isinstance(scheduler, str) and scheduler == "local")
        if local:
            n, capped = local_workers(int(n_jobs))
            if capped:
                warnings.warn(
                    f"n_jobs = {int(n_jobs)} is more than the {n} cores available; using {n} workers",
                    RuntimeWarning,
                    stacklevel=2,
                )
            n_jobs = n
        else:
            n_jobs = int(n_jobs) if n_jobs > 0 else None
    if scheduler is not None:
        return DaskExecutor(scheduler, n_workers=n_jobs, processes=processes)
    if n_jobs is None:
        return InProcessExecutor()
    return JoblibExecutor(n_jobs)


def backend_manifest(backend: str) -> dict[str, str]:
    """The entry a study's manifest gets for its backend: none for the CPU (whose results do not depend on the
    executor), ``{"backend": "cuda"}`` for the GPU, whose results differ in rounding."""
    return {} if check_backend(backend) == "cpu" else {"backend": backend}


def check_backend(backend: Any) -> str:
    """Return ``backend`` if it is one of `BACKENDS`, else raise `ParameterError`."""
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise ParameterError(f"backend = {backend!r} is invalid; allowed: {', '.join(map(repr, BACKENDS))}")
    return backend


# ---------------------------------------------------------------------------
# chunk files
# ---------------------------------------------------------------------------


def _canonical(obj: Any) -> Any:
    """JSON-ready data with floats written exactly (hex), for comparing settings."""
    if isinstance(obj, dict):
        return {str(k): _canonical(v) for k, v in sorted(obj.items())}
    if isinstance(obj, (list, tuple)):
        return [_canonical(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_canonical(v) for v in obj.tolist()]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj).hex()
    if isinstance(obj, (complex, np.complexfloating)):
        return [float(obj.real).hex(), float(obj.imag).hex()]
    if obj is None or isinstance(obj, str):
        return obj
    # str() of another object may hold an address, or leave out what tells two studies apart
    raise ParameterError(f"a study's settings hold {quoted(obj)} of type {type(obj).__name__}; allowed in them: "
                         "dicts, lists, tuples, arrays, numbers, text and None")


def study_digest(manifest: dict[str, Any]) -> str:
    """A fingerprint of everything that defines a study (its ``manifest``), exact in every float."""
    text = json.dumps({"format": STORE_FORMAT, "study": _canonical(manifest)}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


#: The names of chunks (`ChunkStore` keys): one file name each, inside the store's folder.
CHUNK_KEY = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_-]{0,127}")


class ChunkStore:
    """Finished chunks of one study, one ``.npz`` file each, in a folder.

    Parameters
    ----------
    folder : path
        The folder (created if missing).
    manifest : dict
        Everything that defines the study. A folder holding chunks of a study
        with another manifest is refused rather than mixed in.
    resume : bool
        Reuse the chunks found in the folder (default); False deletes them first.
    layout : dict, optional
        How the study is cut into chunks (for example ``{"chunk_size": 20}``).
        It decides which files are written, not the results, so a folder
        written with another layout is resumed with its own: `layout` is then
        the layout found in the folder, and `layout_changed` is True.

    Attributes
    ----------
    digest : str
        `study_digest` of the manifest.
    layout : dict
        The layout to use.
    layout_changed : bool
        The folder's layout replaced the one asked for.

    Raises
    ------
    ParameterError
        If the folder holds chunks of a different study, or anything but a chunk store's files: a store
        deletes only its own files, never a folder of other files that happens to have its name.
    """

    def __init__(self, folder: str | Path, manifest: dict[str, Any], resume: bool = True,
                 layout: dict[str, int] | None = None) -> None:
        self.folder = check_path("folder", folder)
        resume = check_bool("resume", resume)
        self.layout = dict(layout or {})
        self.layout_changed = False
        study = {"format": STORE_FORMAT, "study": _canonical(manifest)}
        self.digest = study_digest(manifest)
        path = self.folder / "manifest.json"
        self._check_folder()
        if self.folder.exists() and not resume:
            self._clear()
        if path.exists():
            try:
                old = json.loads(path.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                old = None
            same = isinstance(old, dict) and {k: old.get(k) for k in study} == json.loads(json.dumps(study))
            if not same and not any(self.folder.glob("*.npz")):
                # a study that stopped before its first chunk (for example, no cluster to connect to)
                # left nothing to resume: start this one afresh
                self._write_manifest(path, study)
            elif not same:
                raise ParameterError(
                    f"{self.folder} holds partial results of a different study; delete it, "
                    "start afresh (resume=False, --no-resume) or write to another file"
                )
            elif isinstance(old.get("layout"), dict) and old["layout"] != self.layout:
                if any(self.folder.glob("*.npz")):
                    self.layout = dict(old["layout"])  # resume the chunks as they were cut
                    self.layout_changed = True
                else:
                    self._write_manifest(path, study)
        else:
            self.folder.mkdir(parents=True, exist_ok=True)
            self._write_manifest(path, study)

    def _own_files(self) -> list[Path]:
        return [e for e in self.folder.iterdir() if e.is_file() and _store_file(e.name)]

    def _check_folder(self) -> None:
        """Refuse a path that is not a folder, and a folder holding anything a store does not write, or
        store files without a manifest."""
        if not self.folder.exists():
            return
        if not self.folder.is_dir():
            raise ParameterError(f"folder = {str(self.folder)!r} is a file, not a folder of chunks; allowed: a chunk "
                                 "folder, or a path that does not exist yet")
        entries = list(self.folder.iterdir())
        others = [e.name for e in entries if not (e.is_file() and _store_file(e.name))]
        if others or (entries and not (self.folder / "manifest.json").is_file()):
            shown = ", ".join(sorted(others)[:5]) or "no manifest.json"
            raise ParameterError(f"folder = {str(self.folder)!r} holds files that are not chunks of a study ({shown}); "
                                 "allowed: a chunk folder (manifest.json and .npz chunks), or a path that does not "
                                 "exist yet; write to another file")

    def _clear(self) -> None:
        for e in self._own_files():
            e.unlink(missing_ok=True)

    def _write_manifest(self, path: Path, study: dict[str, Any]) -> None:
        _atomic_write_text(path, json.dumps({**study, "layout": self.layout}, sort_keys=True, indent=1))

    def _file(self, key: str) -> Path:
        """The chunk file of ``key``: a name of letters, digits, ``-`` and ``_`` (no folder, no leading dot)."""
        if not (isinstance(key, str) and CHUNK_KEY.fullmatch(key)):
            raise ParameterError(f"key = {key!r} is invalid; allowed: a chunk name of letters, digits, '-' and '_'")
        return self.folder / f"{key}.npz"

    def done(self, key: str) -> bool:
        """True when the chunk ``key`` is finished."""
        return self._file(key).exists()

    def save(self, key: str, arrays: dict[str, np.ndarray]) -> None:
        """Write a finished chunk (atomically)."""
        target = self._file(key)
        fd, tmp = tempfile.mkstemp(prefix=f".{key}.", suffix=".npz.part", dir=self.folder)
        try:
            with os.fdopen(fd, "wb") as fh:
                np.savez(fh, **arrays)
                fh.flush()
                os.fsync(fh.fileno())
            umask_permissions(tmp)
            os.replace(tmp, target)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise

    def load(self, key: str) -> dict[str, np.ndarray]:
        """Read a finished chunk."""
        with np.load(self._file(key)) as data:
            return {name: data[name] for name in data.files}

    def count(self) -> int:
        """Number of finished chunks in the folder."""
        return sum(1 for _ in self.folder.glob("*.npz"))

    def remove(self) -> None:
        """Delete the store: its files, then the folder once empty (a file put there meanwhile is kept)."""
        if not self.folder.is_dir():
            return
        self._clear()
        try:
            self.folder.rmdir()
        except OSError:
            pass


def _store_file(name: str) -> bool:
    """A file a `ChunkStore` writes: its manifest, a chunk, or one being written (a ``.part``)."""
    return name == "manifest.json" or name.endswith(".npz") or (name.startswith(".") and name.endswith(".part"))


def _atomic_write_text(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        fh.write(text)
    umask_permissions(tmp)
    os.replace(tmp, path)


def chunk_folder(out: str | Path) -> Path:
    """The folder of chunk files that goes with the output file ``out`` (``out`` + ``.chunks``)."""
    out = Path(out)
    return out.with_name(out.name + ".chunks")


# ---------------------------------------------------------------------------
# progress
# ---------------------------------------------------------------------------


def progress_bar(total: int, desc: str, enabled: bool, unit: str = "sim"):
    """A tqdm progress bar on stderr (a silent one when not ``enabled``)."""
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, disable=not enabled, dynamic_ncols=True,
                mininterval=0.5, smoothing=0.1)


class StoredChunks(Mapping):
    """The finished chunks of a `ChunkStore` as a read-only mapping, read from their files when asked for.

    The sink of `run_waves` where a study has a store: its results are on disk, and memory holds only
    those a wave is being built from.
    """

    def __init__(self, store: ChunkStore, keys: Iterable[str] = ()) -> None:
        self.store = store
        self._keys = list(keys)

    def __getitem__(self, key: str) -> dict[str, np.ndarray]:
        if not self.store.done(key):
            raise KeyError(key)
        return self.store.load(key)

    def __iter__(self):
        return (k for k in self._keys if self.store.done(k))

    def __len__(self) -> int:
        return sum(1 for _ in self)


def run_waves(
    executor: _Executor,
    waves: Iterable[list[ChunkTask]],
    store: ChunkStore | None,
    bar,
    sink: MutableMapping[str, dict[str, np.ndarray]] | StoredChunks,
) -> int:
    """Run waves of chunks, skipping finished ones; results go to ``store``, else to ``sink``.

    ``waves`` may be a generator that builds each wave from ``sink`` (the
    chunks of the previous waves): a dict without a store, a `StoredChunks`
    view of the store with one, so that a study's results are held in memory
    once at most. Returns the number of chunks computed.
    """
    computed = 0
    for wave in waves:
        todo = []
        for task in wave:
            if store is not None and store.done(task.key):
                bar.update(task.n_items)
            else:
                todo.append(task)
        for index, result in executor.run(todo):
            task = todo[index]
            if store is not None:
                store.save(task.key, result)
            else:
                sink[task.key] = result
            computed += 1
            bar.update(task.n_items)
    return computed
