"""Time to follow the orbits with several impacts per period: branches, branch switching, a cascade.

Problems, at the reference parameters:

* `multi_impact_branches` with p = 2, base gamma = 0.0818, gamma in [0.075, 0.09], one level of
  doublings (the `branches --impacts 2 --doublings 1` example of the README): seeds from simulations and
  the 12 x 4 x 4 grid, every branch continued both ways, the doubled branches;
* `cascades` with p = 2, base gamma = 0.0845, gamma in [0.0836, 0.0865], depth 4 (the M2-1 cascade up to
  32 impacts per period).

Run: python benchmarks/multi_impact.py [--repeat 3]

Prints the wall and CPU time of each for every repeat, the branches, and the doublings with their ratios.
A warm-up run (a grid seed search) is made first, so that the timings exclude the compilation of the
numba kernels.
"""

from __future__ import annotations

import argparse
import time

from rotorcontact import Parameters
from rotorcontact.continuation.cascade import cascades
from rotorcontact.continuation.multi_impact_families import multi_impact_branches
from rotorcontact.maps.multi_impact import orbits_from_grid
from rotorcontact.interpreted import compiled_only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    ref = Parameters.reference()
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        orbits_from_grid(ref.replace(gamma=0.083), 2, shape=(2, 2, 2))  # warm-up
    for i in range(args.repeat):
        w0, c0 = time.perf_counter(), time.process_time()
        fam = multi_impact_branches(ref.replace(gamma=0.0818), 2, "gamma", 0.075, 0.09, doublings=1)
        w1, c1 = time.perf_counter(), time.process_time()
        found = cascades(ref.replace(gamma=0.0845), "gamma", 0.0836, 0.0865, impacts=2, depth=4)
        w2, c2 = time.perf_counter(), time.process_time()
        print(f"repeat {i + 1}: branches --impacts 2 --doublings 1: {w1 - w0:.2f} s wall, {c1 - c0:.2f} s CPU "
              f"({len(fam.branches)} branches, {sum(len(b.values) for b in fam.branches)} points, "
              f"{len(fam.events)} events); cascade depth 4: {w2 - w1:.2f} s wall, {c2 - c1:.2f} s CPU")
    print("branches:", ", ".join(fam.labels))
    for c in found:
        print("cascade", " -> ".join(c.labels), "doublings", [f"{e.value:.10f}" for e in c.points],
              "ratios", [f"{r:.4f}" for r in c.ratios], "end", c.end, c.end_value)


if __name__ == "__main__":
    main()
