"""Impacts per second of brute-force orbit diagrams (`rotorcontact.studies.sweep`).

Problem: a gamma sweep at the reference parameters, 1000 values of gamma in
[0.085, 0.145] (where the rotor settles on the impacting orbit B1,d from rest),
5000 impacts per value: 4000 of transient and 1000 recorded. Three layouts:

* ``independent``: every value from rest, the values in parallel over the cores;
* ``up``: one direction with the state carried from value to value (a chain:
  one core);
* ``both``: up and down, the two chains in parallel.

Run: python benchmarks/sweep.py [--n 1000] [--transient 4000] [--record 1000]
     [--modes independent,up,both] [--n-jobs N] [--threads N]
Prints the wall time, the CPU time of this process (all its threads; with
--n-jobs the workers' time is not included), the impacts computed, impacts
per second of wall time and per CPU second, and the load average of the
machine (other processes sharing the cores slow the wall time down; with
``both`` and ``independent`` the work is spread evenly, so CPU time / 2 is the
wall time on 2 free cores). The target is under 30 s on 2 cores for each
layout. The first run of a fresh
installation also compiles the kernels (cached afterwards); a short warm-up
run is made first so that the timings exclude it.
"""

from __future__ import annotations

import argparse
import os
import time

import numba
import numpy as np

import rotorcontact as rc
from rotorcontact.studies.sweep import sweep, sweep_values
from memory import print_peak
from sweep_problem import add_problem_options
from rotorcontact.interpreted import compiled_only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_problem_options(ap, n=1000)
    ap.add_argument("--modes", default="independent,up,both")
    ap.add_argument("--n-jobs", type=int, default=None, help="joblib workers (default: in-process threads)")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: all cores)")
    args = ap.parse_args()
    if args.threads:
        numba.set_num_threads(args.threads)
    p = rc.Parameters.reference()
    values = sweep_values(args.lo, args.hi, args.n)
    print(f"cores: {os.cpu_count()}, numba threads: {numba.get_num_threads()}, n_jobs: {args.n_jobs}")
    print(f"gamma in [{args.lo}, {args.hi}], {args.n} values, {args.transient} + {args.record} impacts per value")
    # warm-up (loads or compiles the kernels)
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        sweep(p, "gamma", values[:4], mode="both", n_transient=10, n_record=10, progress=False, n_jobs=args.n_jobs)
        sweep(p, "gamma", values[:4], mode="independent", n_transient=10, n_record=10, progress=False,
              n_jobs=args.n_jobs)
    for mode in args.modes.split(","):
        t0, c0 = time.perf_counter(), time.process_time()
        load0 = os.getloadavg()[0]
        res = sweep(p, "gamma", values, mode=mode, n_transient=args.transient, n_record=args.record,
                    n_jobs=args.n_jobs, progress=False)
        dt, cpu = time.perf_counter() - t0, time.process_time() - c0
        load = max(load0, os.getloadavg()[0])
        ds = res.dataset
        regimes = {}
        for d in ds.direction.values:
            names, counts = np.unique(res.regimes(str(d)), return_counts=True)
            regimes[str(d)] = dict(zip(names.tolist(), counts.tolist()))
        print(
            f"{mode:12s} wall {dt:7.2f} s  cpu {cpu:7.2f} s  {res.impacts_simulated:>10d} impacts  "
            f"{res.impacts_simulated / dt:10.0f} impacts/s (wall)  {res.impacts_simulated / cpu:10.0f} per cpu-s  "
            f"load {load:.1f}  regimes: {regimes}"
        )


if __name__ == "__main__":
    main()
    print_peak()
