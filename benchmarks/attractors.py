"""Attractors against a parameter: initial states per second (`rotorcontact.studies.attractors`).

Problem: the reference machine with gamma from 0.06 to 0.22 (x_R virtual below gamma* = 0.0729, chaos and
backward whirl near 0.08, B1,d from its period doubling near 0.085 to its fold near 0.175, forward rub on P2
throughout), 100 values x a 114 x 114 plane of initial displacements (10,000 of its points lie inside the
clearance and are simulated at every value: a million simulations of up to 300 events of transient, in
segments of 25 ended once the impacts repeat or the rotor can no longer touch the stator, and 50 recorded
events), then the largest Lyapunov exponent of every attractor at every value (runs of t = 400).

Target: the whole study in under 5 minutes on 2 cores (``--n-jobs 2``).

Run: python benchmarks/attractors.py [--values 100] [--n 114] [--n-jobs N] [--t-lyapunov 400]
     [--no-lyapunov] [--out-dir DIR]
Prints the wall time, the CPU time of this process (with --n-jobs the workers' time is not included), the
load average, initial states per second, and each attractor with where it appears and disappears.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

import rotorcontact as rc
from rotorcontact.studies.attractors import attractors
from memory import print_peak
from rotorcontact.interpreted import compiled_only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--values", type=int, default=100, help="values of gamma")
    ap.add_argument("--n", type=int, default=114, help="grid points per axis of the plane of displacements")
    ap.add_argument("--n-jobs", type=int, default=None, help="joblib workers (default: in-process threads)")
    ap.add_argument("--t-lyapunov", type=float, default=400.0)
    ap.add_argument("--no-lyapunov", dest="lyapunov", action="store_false")
    ap.add_argument("--out-dir", default=None, help="also write the NetCDF file and the figure here")
    args = ap.parse_args()
    p = rc.Parameters.reference()
    values = np.linspace(0.06, 0.22, args.values)
    print(f"cores: {os.cpu_count()}, n_jobs: {args.n_jobs}")
    # warm-up (loads or compiles the kernels)
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        attractors(p, "gamma", [0.1, 0.12], "plane:4", progress=False, n_jobs=args.n_jobs, t_lyapunov=20.0)
    out = None if args.out_dir is None else Path(args.out_dir) / "attractors.nc"
    t0, c0 = time.perf_counter(), time.process_time()
    load0 = os.getloadavg()[0]
    res = attractors(p, "gamma", values, f"plane:{args.n}", n_jobs=args.n_jobs, progress=False, out=out,
                     lyapunov=args.lyapunov, t_lyapunov=args.t_lyapunov, resume=False)
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    load = max(load0, os.getloadavg()[0])
    per_value = int(res.dataset.attrs["simulated_per_value"])
    sims = per_value * values.size
    print(f"{values.size} values x {per_value} initial states = {sims} simulations "
          f"({'with' if args.lyapunov else 'without'} exponents): wall {dt:.1f} s  cpu {cpu:.1f} s  load {load:.1f}  "
          f"{sims / dt:.0f} simulations/s  {res.impacts_simulated} impacts ({res.impacts_simulated / dt:.0f}/s)")
    for a in res.attractors:
        print(f"  {a.name:16s} {a.label:15s} appears {a.appears}, disappears {a.disappears}, "
              f"largest fraction {a.fraction.max():.3f}")
    if args.out_dir is not None:
        from rotorcontact.plotting.attractors import save_attractors_figure

        save_attractors_figure(res.dataset, Path(args.out_dir) / "attractors.png")


if __name__ == "__main__":
    main()
    print_peak()
