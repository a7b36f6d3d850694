"""Time to compute the (gamma, omega) two-parameter diagram at the reference parameters.

Problem: `rotorcontact.continuation.codim2.codim2_diagram` with the defaults: the fold
curve gamma_F,1, the DIB curve and the grazing curve of B1,d in the box
gamma in [0, 0.5], omega in [0.6, 1.25], and their intersections; then the
classification of a 61 x 61 grid into the regions R1-R4 (as drawn in the
Fig. 6a figure). The target is under 60 s on 2 cores (the computation runs on
one core).

Run: python benchmarks/codim2.py [--repeat 3] [--grid 61]

Prints the wall and CPU time of the curves and of the region grid for each
repeat, and the intersection points. A small warm-up run is made first, so
that the timings exclude the one-off compilation of the numba kernels.
"""

from __future__ import annotations

import argparse
import os
import time

from rotorcontact import Parameters
from rotorcontact.continuation.codim2 import classify_plane, codim2_diagram
from rotorcontact.interpreted import compiled_only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--grid", type=int, default=61)
    args = ap.parse_args()
    p = Parameters.reference()
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        codim2_diagram(p, ("gamma", "omega"), ((0.1, 0.2), (0.7, 0.8)), n_seeds=2, n_scan=5)  # warm-up
    best = None
    for i in range(args.repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        d = codim2_diagram(p, ("gamma", "omega"))
        w1, c1 = time.perf_counter(), time.process_time()
        classify_plane(p, ("gamma", "omega"), None, (args.grid, args.grid))
        w2, c2 = time.perf_counter(), time.process_time()
        total = w2 - w0
        best = total if best is None else min(best, total)
        sizes = ", ".join(f"{name} {sum(len(x) for x in c.pieces)}" for name, c in d.curves.items())
        print(f"run {i + 1}: curves wall {w1 - w0:.3f} s (cpu {c1 - c0:.3f} s) [{sizes}]; "
              f"regions {args.grid}x{args.grid} wall {w2 - w1:.3f} s (cpu {c2 - c1:.3f} s); "
              f"load average {os.getloadavg()[0]:.2f}")
    print(f"best total wall time {best:.3f} s (target < 60 s)")
    for pt in d.points:
        print(f"  {pt.type:<12} gamma = {pt.values[0]:.10f}, omega = {pt.values[1]:.10f}")


if __name__ == "__main__":
    main()
