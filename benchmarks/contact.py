"""Chatter and continuous contact: run time of touchdown cases for several restitutions.

Each case starts the reference rig at gamma = 0.05 from U = 0.5, U' = 0.8 + 0.3i (a
touchdown that chatters into contact) and runs to t = 2000. Prints, for each d, the
wall time, the impacts, the contact time, and impacts and contact time per second.

Run: python benchmarks/contact.py
"""

from __future__ import annotations

import time

import rotorcontact as rc
from rotorcontact.interpreted import compiled_only

T_END = 2000.0


def main() -> None:
    base = rc.Parameters.reference().replace(gamma=0.05)
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        rc.simulate(base, 0.5, 0.8 + 0.3j, 5.0)  # compile outside the timing
    print(f"{'d':>5} {'status':>10} {'regime':>16} {'wall s':>9} {'impacts':>8} {'contact t':>10} "
          f"{'impacts/s':>11} {'contact t/s':>12}")
    for d in (0.0, 0.5, 0.95, 1.0):
        p = base.replace(d=d)
        t0 = time.perf_counter()
        traj = rc.simulate(p, 0.5, 0.8 + 0.3j, T_END)
        wall = time.perf_counter() - t0
        contact = sum(c.t_end - c.t_start for c in traj.contact_intervals)
        print(f"{d:5.2f} {traj.status:>10} {traj.summary.regime:>16} {wall:9.4f} {len(traj.impacts):8d} "
              f"{contact:10.1f} {len(traj.impacts) / wall:11.0f} {contact / wall:12.0f}")


if __name__ == "__main__":
    main()
