"""Basins of attraction: grid points and impacts per second (`rotorcontact.studies.basins`).

Problem: the reference machine at gamma = 0.1, where the rotor either settles on
the impacting orbit B1,d, rubs, or returns to contact-free whirl. Two 400 x 400
grids:

* ``shock``: velocity kicks from the contact-free whirl x_R, amplitude in [0, 1]
  and direction in [-pi, pi] from the outward radial direction (160 000 points);
* ``plane``: initial displacements in [-1, 1]^2 at zero velocity (the 124 980
  points inside the clearance are simulated).

Each point runs up to 300 events of transient (in segments of 25, ended early
once the impacts repeat or the rotor can no longer touch the stator) and 50
recorded events.

Run: python benchmarks/basins.py [--n 400] [--gamma 0.1] [--grids shock,plane]
     [--n-jobs N] [--threads N] [--out-dir DIR]
Prints the wall time, the CPU time of this process (all its threads; with
--n-jobs the workers' time is not included), the load average of the machine,
points and impacts per second, and the fraction of each class. Other processes
sharing the cores slow the wall time down; the points are spread evenly over
the threads, so CPU time / 2 is the wall time on 2 free cores. The target is
under 60 s on 2 cores for a 400 x 400 grid.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numba

import rotorcontact as rc
from rotorcontact.studies.basins import basins, displacement_grid, shock_grid
from memory import print_peak
from rotorcontact.interpreted import compiled_only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=400, help="points per axis")
    ap.add_argument("--gamma", type=float, default=0.1)
    ap.add_argument("--grids", default="shock,plane")
    ap.add_argument("--n-jobs", type=int, default=None, help="joblib workers (default: in-process threads)")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: all cores)")
    ap.add_argument("--out-dir", default=None, help="also write NetCDF files and figures here")
    args = ap.parse_args()
    if args.threads:
        numba.set_num_threads(args.threads)
    p = rc.Parameters.reference().replace(gamma=args.gamma)
    print(f"cores: {os.cpu_count()}, numba threads: {numba.get_num_threads()}, n_jobs: {args.n_jobs}")
    # warm-up (loads or compiles the kernels)
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        basins(p, displacement_grid((-0.5, 0.5, 4), (-0.5, 0.5, 4)), progress=False, n_jobs=args.n_jobs)
    grids = {
        "shock": shock_grid((0.0, 1.0, args.n), (-3.141592653589793, 3.141592653589793, args.n)),
        "plane": displacement_grid((-1.0, 1.0, args.n), (-1.0, 1.0, args.n)),
    }
    if args.out_dir is not None:
        Path(args.out_dir).mkdir(parents=True, exist_ok=True)
    for name in args.grids.split(","):
        out = None if args.out_dir is None else Path(args.out_dir) / f"basins_{name}.nc"
        t0, c0 = time.perf_counter(), time.process_time()
        load0 = os.getloadavg()[0]
        res = basins(p, grids[name], n_jobs=args.n_jobs, progress=False, out=out)
        dt, cpu = time.perf_counter() - t0, time.process_time() - c0
        load = max(load0, os.getloadavg()[0])
        points = int(res.dataset["inside"].values.sum())
        fr = ", ".join(f"{k} {100 * v:.2f}%" for k, v in res.fractions.items())
        print(
            f"{name:6s} {args.n}x{args.n}: wall {dt:7.2f} s  cpu {cpu:7.2f} s  load {load:.1f}  {points} points "
            f"({points / dt:7.0f}/s)  {res.impacts_simulated} impacts ({res.impacts_simulated / dt:8.0f}/s wall, "
            f"{res.impacts_simulated / cpu:8.0f} per cpu-s)  [{fr}]"
        )
        if args.out_dir is not None:
            from rotorcontact.plotting.basins import save_basins_figure

            save_basins_figure(res.dataset, Path(args.out_dir) / f"basins_{name}.png")


if __name__ == "__main__":
    main()
    print_peak()
