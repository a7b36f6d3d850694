"""Scaling of a study over cores: one sweep on 1, 2, 4, ... threads, then on joblib and Dask workers.

Problem: the gamma sweep of sweep.py, every value from rest (``independent``),
``--n`` values (default 4000: about a minute of single-core work on the 2-core
machine of the README) of 4000 transient and 1000 recorded impacts. The sweep
runs in this process on each thread count of ``--threads`` (default 1, 2, 4,
... up to the cores this process may use), and with ``--executors`` also with
``--n-jobs T`` (joblib) and ``--scheduler local --n-jobs T`` (a Dask
LocalCluster), T the largest thread count, with their workers' start-up
included; then joblib again on the workers it has started, and a Dask cluster that was started, and whose
workers have run a chunk, before the timing (the case of the README's worked example on an existing
cluster). Every run's dataset is compared bit for bit with the first run's.

With ``--ceiling``, it first measures what the machine allows: the same
single-core piece of the sweep (``--ceiling-values`` values) in one process
alone, then in T processes at once; T times the ratio of the two is the
speed-up that T fully independent single-core runs reach on this machine
(shared caches, memory bandwidth, clock speed under load, a virtual machine's
neighbours), the ceiling for any threads or workers.

Prints numba's version and threading layer (which the studies' threads, Python threads, do not use), then,
per run: wall time, speed-up over the first run (one thread by
default), parallel efficiency, impacts per second, the CPU time of this
process's threads in user and in system (kernel) mode and its minor page
faults (time spent in the kernel, on page faults or locks, grows with
contention between threads); the executors' wall times
against the in-process run on the same cores; the load average; and a last
line ``json: {...}`` with the same figures. Targets (issue: start-up and
speed): at least 13x over one core on 16 cores; executors within 15 % of the
in-process threads.

``--executors joblib,dask-local`` (any of joblib, dask-local, joblib-warm, dask-running) runs only those;
joblib-warm reuses the workers that the joblib run started.

Run: python benchmarks/scaling.py [--n 4000] [--transient 4000] [--record 1000]
     [--threads 1,2,4,8,16] [--executors [RUNS]] [--ceiling] [--ceiling-values 200]
The kernels must be compiled beforehand (``rotorcontact warmup --only studies``,
or any earlier run); a short run loads them first so that no timing includes it.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import multiprocessing
import os
import queue
import resource
import time

import numba
import numpy as np

import rotorcontact as rc
from rotorcontact.studies.execution import available_cores
from rotorcontact.studies.sweep import sweep, sweep_values
from memory import print_peak
from sweep_problem import add_problem_options


def default_threads(cores: int) -> list[int]:
    """1, 2, 4, ... below ``cores``, then ``cores`` itself."""
    counts = [1]
    while counts[-1] * 2 < cores:
        counts.append(counts[-1] * 2)
    if cores > 1:
        counts.append(cores)
    return counts


def same_bits(a, b) -> bool:
    """Whether two sweep datasets hold the same variables and coordinates, bit for bit."""
    names = sorted(a.variables)
    if names != sorted(b.variables):
        return False
    return all(
        a[n].shape == b[n].shape and a[n].dtype == b[n].dtype
        and np.ascontiguousarray(a[n].values).tobytes() == np.ascontiguousarray(b[n].values).tobytes()
        for n in names
    )


#: The executor runs of ``--executors``.
EXECUTOR_RUNS = ("joblib", "dask-local", "joblib-warm", "dask-running")


def run_options(transient: int, record: int) -> dict:
    """The sweep's options: every value from rest, no progress bar."""
    return dict(mode="independent", n_transient=transient, n_record=record, progress=False)


def load_kernels(p, values) -> None:
    """Short sweeps on one thread and on all, so that no timing includes loading (or compiling) the kernels."""
    threads = numba.get_num_threads()
    for t in sorted({1, threads}):
        numba.set_num_threads(t)
        sweep(p, "gamma", values[:4], **run_options(10, 10))


def _piece(values, transient: int, record: int, barrier, results) -> None:
    """One single-core piece of the sweep, timed after every process has loaded the kernels."""
    numba.set_num_threads(1)
    p = rc.Parameters.reference()
    run = run_options(transient, record)
    load_kernels(p, values)
    barrier.wait(timeout=600)
    t0 = time.perf_counter()
    sweep(p, "gamma", values, **run)
    results.put(time.perf_counter() - t0)


def ceiling(values, transient: int, record: int, processes: int) -> tuple[float, float, float]:
    """Seconds of one piece alone and (mean over) ``processes`` at once, and the speed-up they allow."""
    ctx = multiprocessing.get_context("spawn")
    times = []
    for count in (1, processes):
        barrier, results = ctx.Barrier(count), ctx.Queue()
        procs = [ctx.Process(target=_piece, args=(values, transient, record, barrier, results))
                 for _ in range(count)]
        for proc in procs:
            proc.start()
        got, deadline = [], time.monotonic() + 3600
        while len(got) < count:
            try:
                got.append(results.get(timeout=1.0))
            except queue.Empty:
                if time.monotonic() > deadline or any(proc.exitcode not in (None, 0) for proc in procs):
                    for proc in procs:
                        proc.kill()
                    raise SystemExit("--ceiling: a process failed or ran past an hour") from None
        for proc in procs:
            proc.join()
        times.append(got)
    alone, together = times[0][0], float(np.mean(times[1]))
    return alone, together, processes * alone / together


@contextlib.contextmanager
def running_cluster(workers: int):
    """A Dask LocalCluster of single-threaded worker processes, started and given a chunk before any timing."""
    from distributed import Client

    from rotorcontact.studies.execution import local_cluster

    with local_cluster(workers) as cluster, \
            Client(cluster) as client:
        load = sweep_values(0.1, 0.12, 4 * workers)
        sweep(rc.Parameters.reference(), "gamma", load, scheduler=client, chunk_size=1, **run_options(10, 10))
        yield client


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_problem_options(ap, n=4000)
    ap.add_argument("--threads", default=None, help="comma-separated thread counts (default 1, 2, 4, ... cores)")
    ap.add_argument("--executors", nargs="?", const=",".join(EXECUTOR_RUNS), default=None,
                    help="also joblib and a Dask LocalCluster; optionally a comma-separated choice of "
                         f"{', '.join(EXECUTOR_RUNS)} (default: all)")
    ap.add_argument("--ceiling", action="store_true", help="first measure the machine's own ceiling")
    ap.add_argument("--ceiling-values", type=int, default=200, help="values of each process's piece")
    args = ap.parse_args()
    cores = available_cores()
    threads = [int(t) for t in args.threads.split(",")] if args.threads else default_threads(cores)
    threads = [t for t in threads if 1 <= t <= numba.config.NUMBA_NUM_THREADS]
    chosen = args.executors.split(",") if args.executors else []
    unknown = sorted(set(chosen) - set(EXECUTOR_RUNS))
    if unknown:
        raise SystemExit(f"--executors: {unknown[0]!r} is not one of {', '.join(EXECUTOR_RUNS)}")
    if "joblib-warm" in chosen and "joblib" not in chosen:
        raise SystemExit("--executors: joblib-warm reuses the workers of the joblib run; name joblib too")
    if not threads:
        raise SystemExit(f"--threads: no count between 1 and numba's {numba.config.NUMBA_NUM_THREADS} threads")
    p = rc.Parameters.reference()
    values = sweep_values(args.lo, args.hi, args.n)
    run = run_options(args.transient, args.record)
    print(f"cores: {cores} (os.cpu_count {os.cpu_count()}), numba threads at most {numba.config.NUMBA_NUM_THREADS}")
    print(f"gamma in [{args.lo}, {args.hi}], {args.n} values, {args.transient} + {args.record} impacts per value")
    load_kernels(p, values)
    try:
        layer = numba.threading_layer()  # known once a parallel kernel has run
    except ValueError:
        layer = "not started"
    print(f"numba {numba.__version__}, threading layer: {layer}")

    rows, first, base = [], None, None
    if args.ceiling:
        piece = sweep_values(args.lo, args.hi, args.ceiling_values)
        alone, together, allowed = ceiling(piece, args.transient, args.record, threads[-1])
        rows.append(dict(runner="processes", workers=threads[-1], alone_s=round(alone, 3),
                         together_s=round(together, 3), speedup=round(allowed, 2)))
        print(f"ceiling: one piece alone {alone:.2f} s, {threads[-1]} at once {together:.2f} s each: "
              f"{allowed:.2f}x is what {threads[-1]} independent single-core runs reach on this machine")
    for t in threads:
        numba.set_num_threads(t)
        t0, load0, use0 = time.perf_counter(), os.getloadavg()[0], resource.getrusage(resource.RUSAGE_SELF)
        res = sweep(p, "gamma", values, **run)
        wall = time.perf_counter() - t0
        use = resource.getrusage(resource.RUSAGE_SELF)
        identical = True if first is None else same_bits(first.dataset, res.dataset)
        if first is None:
            first, base = res, wall
        row = dict(runner="threads", workers=t, wall_s=round(wall, 3), speedup=round(base / wall, 2),
                   efficiency=round(base / wall * threads[0] / t, 3), impacts_per_s=round(res.impacts_simulated / wall),
                   load=round(max(load0, os.getloadavg()[0]), 1), identical=identical,
                   user_s=round(use.ru_utime - use0.ru_utime, 2), system_s=round(use.ru_stime - use0.ru_stime, 2),
                   minor_faults=use.ru_minflt - use0.ru_minflt)
        rows.append(row)
        print(f"threads {t:3d}  wall {wall:8.2f} s  speed-up {row['speedup']:6.2f}x  efficiency "
              f"{row['efficiency']:5.3f}  {row['impacts_per_s']:>10d} impacts/s  load {row['load']:.1f}  "
              f"cpu user {row['user_s']:.1f} s, system {row['system_s']:.1f} s, {row['minor_faults']} minor faults  "
              f"identical: {identical}")

    if args.executors:
        t = threads[-1]
        numba.set_num_threads(t)
        in_process = rows[-1]["wall_s"]
        runs = (("joblib", dict(n_jobs=t), "worker start-up included"),
                ("dask-local", dict(n_jobs=t, scheduler="local"), "cluster start-up included"),
                ("joblib-warm", dict(n_jobs=t), "the same workers again, started"),
                ("dask-running", "cluster", "a running cluster whose workers have run a chunk"))
        for runner, extra, how in runs:
            if runner not in chosen:
                continue
            with contextlib.ExitStack() as stack:
                if extra == "cluster":
                    extra = dict(scheduler=stack.enter_context(running_cluster(t)))
                t0 = time.perf_counter()
                res = sweep(p, "gamma", values, **run, **extra)
                wall = time.perf_counter() - t0
            identical = same_bits(first.dataset, res.dataset)
            rows.append(dict(runner=runner, workers=t, wall_s=round(wall, 3),
                             versus_threads=round(wall / in_process - 1.0, 3), identical=identical,
                             chunk_size=int(res.dataset.attrs["chunk_size"])))
            print(f"{runner:12s} {t:3d} workers  wall {wall:8.2f} s  {100 * (wall / in_process - 1):+6.1f} % "
                  f"against {t} threads in process ({how}; chunks of {rows[-1]['chunk_size']})  "
                  f"identical: {identical}")

    print("json: " + json.dumps(dict(cores=cores, threading_layer=layer, n=args.n, transient=args.transient,
                                     record=args.record, impacts=int(first.impacts_simulated), runs=rows)))


if __name__ == "__main__":
    main()
    print_peak()
