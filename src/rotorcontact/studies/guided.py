"""Lanes shared out among threads by guided self-scheduling.

The lanes of a batch are independent and cost unequally (a lane that rubs, chatters or settles early costs
more or less than its neighbours). Threads that each take a fixed share wait, at the end, for the one
whose share cost most. Here every thread instead *claims* a block of lanes, runs it, and claims the
next: a block is the lanes still unclaimed divided by `GUIDED_SHARES` times the threads (at least one
lane, at most the rest of its job), so the blocks are large while much is left, which keeps the claims
few, and shrink to single lanes as the work runs out, so that the threads finish within about a lane of
each other.

The work is a list of *jobs* (a kernel call's lanes: one for `rotorcontact.studies.batch.run_lanes`, the
chunks of a wave for the in-process executor), each prepared when its first block is claimed, so that
the results of a long list are not all allocated at once. The blocks run in Python threads through a
compiled single-core kernel that releases the GIL; a block writes only its own rows of its job's results,
so which thread runs which block changes nothing in them.
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Callable, Iterator
from typing import Any

from ..model.validation import check_int

__all__ = ["GUIDED_SHARES", "GuidedLanes"]

#: A claim takes the unclaimed lanes divided by this many times the threads.
GUIDED_SHARES = 4
#: Seconds between checks, while waiting for a finished job, that the threads still run.
_POLL_S = 1.0


class GuidedLanes:
    """Jobs of lanes run by ``threads`` threads that claim blocks of lanes.

    Parameters
    ----------
    jobs : list of (int, callable)
        Each job's number of lanes (>= 1) and a function of no arguments that prepares the job (its kernel
        arguments, results included), called once, when its first block is claimed.
    run_block : callable
        ``run_block(prepared, first, end)`` runs lanes ``first`` to ``end`` (excluded) of a prepared job
        into its results; it should release the GIL.
    threads : int
        Threads to run the blocks (at most one per lane is started).

    Raises
    ------
    ParameterError
        For a lane count or ``threads`` that is not an integer >= 1.
    """

    def __init__(self, jobs: list[tuple[int, Callable[[], Any]]], run_block: Callable[[Any, int, int], None],
                 threads: int) -> None:
        self.jobs = [(check_int("lanes", n, 1), prepare) for n, prepare in jobs]
        self.run_block = run_block
        self.threads = check_int("threads", threads, 1)
        self.lanes_left = sum(n for n, _ in self.jobs)
        self.lock = threading.Lock()
        self.finished: queue.Queue = queue.Queue()
        self.stopped = threading.Event()  # no more claims (set without the lock: see `stop`)
        self.started = False
        self.workers: list[threading.Thread] = []
        self.current = 0  # the job whose lanes are being claimed ...
        self.next_lane = 0  # ... and its first lane not yet claimed
        self.prepared: dict[int, Any] = {}  # the jobs under way
        self.lanes_done: dict[int, int] = {}

    def claim(self) -> tuple[int, int, int] | None:
        """(job, first lane, end) of the next block, or None when none is left or the work was stopped.

        Called under `lock` by the threads; prepares a job at its first block.
        """
        if self.stopped.is_set() or self.current >= len(self.jobs):
            return None
        k = self.current
        n_lanes, prepare = self.jobs[k]
        if self.next_lane == 0:
            try:
                self.prepared[k] = prepare()
            except BaseException:
                self.stopped.set()  # before the lock is let go: no other thread prepares it again
                raise
            self.lanes_done[k] = 0
        first = self.next_lane
        size = min(n_lanes - first, max(1, -(-self.lanes_left // (GUIDED_SHARES * self.threads))))
        self.next_lane += size
        self.lanes_left -= size
        if self.next_lane == n_lanes:
            self.current += 1
            self.next_lane = 0
        return k, first, first + size

    def _work(self) -> None:
        try:
            while True:
                with self.lock:
                    block = self.claim()
                if block is None:
                    return
                k, first, end = block
                self.run_block(self.prepared[k], first, end)
                with self.lock:
                    self.lanes_done[k] += end - first
                    if self.lanes_done[k] == self.jobs[k][0]:
                        self.finished.put(k)
        except BaseException as exc:  # handed to the thread that collects the results, which raises it
            self.stopped.set()
            self.finished.put(exc)

    def run(self) -> Iterator[tuple[int, Any]]:
        """Yields (job index, prepared job) for every job, as each is finished.

        An error in a thread is raised here. Leaving the iteration early (an error, an interrupt, or the
        caller's own choice) stops the claims; the blocks under way finish before it returns. A caller that
        leaves it without closing it (an exception raised while it is suspended keeps it alive) calls `stop`.

        Raises
        ------
        RuntimeError
            When run a second time (the work is done once), or if the threads all end with jobs unfinished.
        """
        if self.started:
            raise RuntimeError("GuidedLanes.run was called again; its work is run once")
        self.started = True
        if not self.jobs:
            return
        try:
            for n in range(min(self.threads, self.lanes_left)):
                worker = threading.Thread(target=self._work, name=f"rotorcontact-lanes-{n}", daemon=True)
                worker.start()
                self.workers.append(worker)
            for _ in range(len(self.jobs)):
                k = self._next_finished()
                if isinstance(k, BaseException):
                    raise k
                with self.lock:
                    prepared = self.prepared.pop(k)
                yield k, prepared
        finally:
            self.stop()

    def stop(self) -> None:
        """Stop the claims and wait for the blocks under way; the threads have ended when it returns.

        Called in one of the threads themselves (a generator let go in a reference cycle is closed by the
        garbage collector wherever a collection starts, possibly in a thread that holds `lock`), it only
        stops the claims: the other threads may be waiting for that lock, and the threads end by themselves.
        """
        self.stopped.set()  # no lock: see above
        if threading.current_thread() in self.workers:
            return
        for worker in self.workers:
            worker.join()

    def _next_finished(self) -> Any:
        """The next finished job (or a thread's error); an error if every thread ended without one."""
        while True:
            try:
                return self.finished.get(timeout=_POLL_S)
            except queue.Empty:
                if not any(worker.is_alive() for worker in self.workers) and self.finished.empty():
                    raise RuntimeError("the threads ended with jobs unfinished") from None
