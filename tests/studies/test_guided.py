"""Guided self-scheduling of lanes among threads: every lane run once, by claims that shrink as the work
runs out; errors raised to the caller; no thread left running."""

from __future__ import annotations

import itertools
import signal
import threading
import time

import numpy as np
import pytest

from rotorcontact.errors import ParameterError
from rotorcontact.studies.guided import GUIDED_SHARES, GuidedLanes


def _lane_threads() -> list:
    return [t for t in threading.enumerate() if t.name.startswith("rotorcontact-lanes-")]


def _counting_jobs(lanes: list[int]) -> tuple[list, list]:
    """Jobs whose prepared state counts how often each lane was run."""
    counts = [np.zeros(n, int) for n in lanes]
    return [(n, (lambda k=k: counts[k])) for k, n in enumerate(lanes)], counts


def _count(prepared, first, end) -> None:
    prepared[first:end] += 1


@pytest.mark.parametrize("threads", [1, 2, 3, 8, 64])
def test_every_lane_of_every_job_is_run_once_and_every_job_is_handed_back_once(threads):
    lanes = [10, 3, 200, 1, 60]
    jobs, counts = _counting_jobs(lanes)
    done = list(GuidedLanes(jobs, _count, threads).run())
    assert sorted(k for k, _ in done) == list(range(len(lanes)))
    for k, prepared in done:
        assert prepared is counts[k]
    assert all(np.all(c == 1) for c in counts)
    assert not _lane_threads()


def test_claims_start_at_a_share_of_the_work_shrink_to_single_lanes_and_stay_within_a_job():
    lanes, threads = [10, 3, 200, 1, 60], 3
    jobs, _ = _counting_jobs(lanes)
    guided = GuidedLanes(jobs, _count, threads)
    claims = []
    while (claim := guided.claim()) is not None:
        claims.append(claim)
        assert len(claims) <= sum(lanes)
    covered = [np.zeros(n, int) for n in lanes]
    for k, first, end in claims:
        assert 0 <= first < end <= lanes[k]
        covered[k][first:end] += 1
    assert all(np.all(c == 1) for c in covered)
    # the first block is the whole work over GUIDED_SHARES times the threads (272 / 12, rounded up), cut
    # at its job's end; the blocks of one job never grow; the last ones are single lanes
    assert GUIDED_SHARES == 4
    assert claims[0] == (0, 0, 10)
    assert claims[2] == (2, 0, -(-(sum(lanes) - 13) // 12))
    big = [end - first for k, first, end in claims if k == 2]
    assert big == sorted(big, reverse=True) and big[0] > 1
    assert [end - first for _, first, end in claims[-3:]] == [1, 1, 1]


def test_a_job_is_prepared_when_its_first_block_is_claimed():
    prepared = []

    def job(k):
        def prepare():
            prepared.append(k)
            return np.zeros(4, int)
        return 4, prepare

    guided = GuidedLanes([job(0), job(1), job(2)], _count, 1)
    assert prepared == []
    guided.claim()
    assert prepared == [0]
    while guided.claim() is not None:
        pass
    assert prepared == [0, 1, 2]


def test_an_error_in_a_thread_is_raised_to_the_caller_and_stops_the_claims():
    blocks = itertools.count()

    def failing(prepared, first, end):
        if next(blocks) == 1:  # the second block claimed, whichever thread runs it
            raise FloatingPointError("the second block")

    jobs, _ = _counting_jobs([50, 50])
    guided = GuidedLanes(jobs, failing, 3)
    with pytest.raises(FloatingPointError, match="the second block"):
        list(guided.run())
    assert guided.stopped.is_set() and guided.claim() is None
    assert not _lane_threads()


def test_leaving_early_stops_the_claims_and_ends_the_threads():
    jobs, counts = _counting_jobs([1] + [5] * 40)
    guided = GuidedLanes(jobs, _count, 2)
    results = guided.run()
    next(results)
    results.close()
    assert guided.stopped.is_set() and guided.claim() is None
    assert not _lane_threads()
    # no lane run twice, whatever was left undone
    assert all(np.all(c <= 1) for c in counts)


def test_a_job_is_handed_back_only_once_all_its_blocks_have_run():
    # blocks that take their time, so that a job whose last block is claimed is not yet run
    def slow(prepared, first, end):
        time.sleep(0.002 * (end - first))
        prepared[first:end] += 1

    jobs, counts = _counting_jobs([30, 7, 30])
    for k, prepared in GuidedLanes(jobs, slow, 4).run():
        assert np.all(prepared == 1), k


def test_a_failing_preparation_is_raised_once_and_never_repeated():
    calls = []

    def prepare():
        calls.append(1)
        time.sleep(0.01)  # the other threads wait on the claim meanwhile
        raise MemoryError("no room for the results")

    guided = GuidedLanes([(40, prepare)], _count, 4)
    with pytest.raises(MemoryError, match="no room"):
        list(guided.run())
    assert len(calls) == 1
    assert not _lane_threads()


def test_the_work_is_run_once_and_a_second_run_is_refused_rather_than_waiting():
    jobs, counts = _counting_jobs([5, 5])
    guided = GuidedLanes(jobs, _count, 2)
    assert len(list(guided.run())) == 2
    with pytest.raises(RuntimeError, match="run once"):
        list(guided.run())
    assert all(np.all(c == 1) for c in counts)


def test_threads_that_cannot_all_be_started_stop_the_work(monkeypatch):
    starts = itertools.count()
    real = threading.Thread.start

    def start(thread):
        if next(starts) == 1:
            raise RuntimeError("can't start new thread")
        real(thread)

    monkeypatch.setattr(threading.Thread, "start", start)
    jobs, counts = _counting_jobs([200])

    def slow(prepared, first, end):
        time.sleep(0.001)
        _count(prepared, first, end)

    guided = GuidedLanes(jobs, slow, 3)
    with pytest.raises(RuntimeError, match="can't start new thread"):
        list(guided.run())
    monkeypatch.undo()
    assert guided.stopped.is_set() and not _lane_threads()
    assert counts[0].max() <= 1


@pytest.mark.skipif(not hasattr(signal, "pthread_kill"), reason="POSIX signals to a thread")
def test_an_interrupt_of_the_waiting_thread_stops_the_claims_and_ends_the_threads():
    # Ctrl-C in a Python session: SIGINT, and so KeyboardInterrupt, in the main thread, which waits for
    # the results; about a second of work, interrupted at its third block
    assert threading.current_thread() is threading.main_thread()
    blocks = itertools.count()

    def interrupting(prepared, first, end):
        if next(blocks) == 2:
            signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)
        time.sleep(0.001 * (end - first))
        _count(prepared, first, end)

    jobs, counts = _counting_jobs([2000])
    guided = GuidedLanes(jobs, interrupting, 2)
    with pytest.raises(KeyboardInterrupt):
        for _ in guided.run():
            pass
    assert guided.stopped.is_set() and not _lane_threads()
    # the claims stopped: far from every lane was run, none twice
    assert counts[0].max() <= 1 and counts[0].sum() < 2000


def test_a_generator_collected_in_a_thread_that_holds_the_lock_does_not_deadlock():
    # the run() generator is left in a reference cycle; the garbage collector closes it in a thread that
    # prepares a job (under the lock) while the other thread waits for that lock: stop() must not join it
    import gc

    dropped = threading.Event()

    def prepare_collect():
        gc.collect()
        return 2

    def block(prepared, first, end):
        if prepared == 1:
            dropped.wait(5)
            time.sleep(0.1 if first == 0 else 0.3)

    was_enabled = gc.isenabled()
    gc.disable()
    try:
        guided = GuidedLanes([(1, lambda: 0), (2, lambda: 1), (1, prepare_collect)], block, 2)
        results = guided.run()
        assert next(results)[0] == 0

        class Cycle:
            pass

        cycle = Cycle()
        cycle.self, cycle.results = cycle, results
        del results, cycle
        dropped.set()
        for worker in list(guided.workers):
            worker.join(timeout=30)
        assert not any(worker.is_alive() for worker in guided.workers)
        assert guided.stopped.is_set()
    finally:
        if was_enabled:
            gc.enable()


def test_no_jobs_is_no_work():
    assert list(GuidedLanes([], _count, 4).run()) == []


@pytest.mark.parametrize("jobs, threads, name", [
    ([(0, lambda: None)], 2, "lanes"),
    ([(1.5, lambda: None)], 2, "lanes"),
    ([(3, lambda: None)], 0, "threads"),
    ([(3, lambda: None)], True, "threads"),
])
def test_lane_counts_and_threads_are_whole_numbers_of_at_least_one(jobs, threads, name):
    with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid"):
        GuidedLanes(jobs, _count, threads)
