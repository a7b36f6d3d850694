"""Time of a 200-speed design map of the reference machine (1000 to 6000 rpm).

Run: python benchmarks/design_map.py
"""

from __future__ import annotations

import time

import numpy as np

from rotorcontact import reference_machine
from rotorcontact.studies.design_map import speed_map
from rotorcontact.interpreted import compiled_only


def main() -> None:
    machine = reference_machine()
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        speed_map(machine, [1500.0, 2500.0])  # compile outside the timing
    t0 = time.perf_counter()
    dmap = speed_map(machine, np.linspace(1000.0, 6000.0, 200))
    wall = time.perf_counter() - t0
    counts = {r: sum(pt.regime == r for pt in dmap.points) for r in ("safe", "bistable", "contact-certain")}
    print(f"200-speed map: {wall:.3f} s ({counts})")
    t0 = time.perf_counter()
    dmap = speed_map(machine, np.linspace(1000.0, 6000.0, 40), shock=0.02)
    wall = time.perf_counter() - t0
    print(f"40-speed map with recovery probabilities (shock 20 mm/s, 24 directions): {wall:.3f} s")


if __name__ == "__main__":
    main()
