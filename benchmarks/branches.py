"""Time to compute all one-impact branches and their events at the reference parameters.

Problem: `rotorcontact.continuation.branches.orbit_branches` at the reference machine's
parameters over gamma in [-0.6, 0.25] (periods up to T = 12, the defaults):
every branch B_n,a..d that crosses one of the 41 seed values, continued
through its folds, with all events located to 1e-10 in gamma. The target is
under 10 s on 2 cores (the computation runs on one core).

Run: python benchmarks/branches.py [--from -0.6] [--to 0.25] [--t-max 12] [--repeat 3]

Prints the wall and CPU time of each repeat, the number of curves, points and
events, and the event list. A warm-up run on a short range is made first, so
that the timings exclude the one-off compilation of the numba kernels.
"""

from __future__ import annotations

import argparse
import os
import time

from rotorcontact import Parameters
from rotorcontact.continuation.branches import orbit_branches
from rotorcontact.interpreted import compiled_only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--from", dest="start", type=float, default=-0.6)
    ap.add_argument("--to", dest="stop", type=float, default=0.25)
    ap.add_argument("--t-max", dest="t_max", type=float, default=12.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    p = Parameters.reference()
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        orbit_branches(p, "gamma", 0.1, 0.12, t_max=4.0, n_seeds=2)  # warm-up (numba compilation)
    walls = []
    for i in range(args.repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        b = orbit_branches(p, "gamma", args.start, args.stop, t_max=args.t_max)
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        walls.append(wall)
        n_points = sum(len(c.values) for c in b.curves)
        print(f"run {i + 1}: wall {wall:.3f} s, cpu {cpu:.3f} s, {len(b.curves)} curves, {n_points} points, "
              f"{len(b.events)} events, load average {os.getloadavg()[0]:.2f}")
    print(f"best wall time {min(walls):.3f} s (target < 10 s)")
    print("events:")
    for e in b.events:
        print(f"  {e.type:<16} gamma = {e.value:+.10f}  {', '.join(e.orbits):<12} T = {e.T:.6f}  {e.detail}")


if __name__ == "__main__":
    main()
