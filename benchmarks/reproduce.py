"""Wall time of the full paper reproduction (`rotorcontact reproduce`), with its per-stage timings.

Run: python benchmarks/reproduce.py [--out DIR]
The first call in a fresh environment also compiles the numba kernels; run twice to see both.
"""

from __future__ import annotations

import argparse
import tempfile
import time

from rotorcontact.report.reproduce import reproduce


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    out = args.out or tempfile.mkdtemp(prefix="rotorcontact-reproduce-")
    t0 = time.perf_counter()
    rep = reproduce(out, progress=False)
    wall = time.perf_counter() - t0
    for stage, seconds in rep.timings.items():
        print(f"{stage:>24}: {seconds:7.2f} s")
    print(f"{'total':>24}: {wall:7.2f} s  (target < 120 s, aim 30 s)")


if __name__ == "__main__":
    main()
