"""How evenly the threads share a sweep: the cost of each value, and the idle share of ways of sharing lanes.

Problem: the gamma sweep of sweep.py (``--n`` values; with ``--every k``, every k-th of them, a sweep of
n/k values over the same range), each value run alone on one core
(`rotorcontact.studies.batch.simulate_batch`, ``parallel=False``). From the measured costs it computes,
for ``--threads`` threads, the share of the threads' time spent waiting for the slowest, where

* the threads claim blocks of lanes of the sweep's chunks (``--chunk`` values each, the sweep's default) as
  they finish the last (the present scheduling, `rotorcontact.studies.guided`, whose own claims are
  replayed against the costs), or, over kernel calls
  of C lanes each ending when its slowest thread does (earlier versions),
* the lanes of a call go in contiguous blocks (numba's static schedule of a ``prange`` over lanes), or
* in turn, lane i to thread i mod T (under a static schedule).

Prints the costs' spread, the guided idle share and one line per call size; the last line ``json: {...}``.

Run: python benchmarks/lane_costs.py [--n 4000] [--every 1] [--threads 16]
"""

from __future__ import annotations

import argparse
import heapq
import json
import time

import numpy as np

import rotorcontact as rc
from rotorcontact.studies.batch import simulate_batch
from rotorcontact.studies.guided import GuidedLanes
from rotorcontact.studies.sweep import DEFAULT_CHUNK_INDEPENDENT, sweep_values
from sweep_problem import add_problem_options


def idle_share(cost: np.ndarray, threads: int, call: int, dealt: bool) -> float:
    """Share of ``threads`` threads' time spent waiting, over calls of ``call`` consecutive lanes."""
    wall = 0.0
    for start in range(0, cost.size, call):
        lanes = cost[start:start + call]
        parts = [lanes[t::threads] for t in range(threads)] if dealt else np.array_split(lanes, threads)
        wall += max(part.sum() for part in parts)
    return 1.0 - cost.sum() / (threads * wall)


def guided_idle_share(cost: np.ndarray, threads: int, chunk: int) -> float:
    """Share of ``threads`` threads' time spent waiting when they claim blocks of the lanes
    (`GuidedLanes.claim`) as they finish, in chunks of ``chunk`` lanes (the in-process executor's jobs, a
    block never crossing a chunk's end), each block costing the sum of its lanes."""
    starts = range(0, cost.size, chunk)
    guided = GuidedLanes([(min(chunk, cost.size - a), lambda: None) for a in starts], lambda *_: None, threads)
    free = [(0.0, t) for t in range(threads)]  # (time the thread is free, thread)
    while (block := guided.claim()) is not None:
        at, t = heapq.heappop(free)
        first = starts[block[0]] + block[1]
        heapq.heappush(free, (at + cost[first:first + block[2] - block[1]].sum(), t))
    return 1.0 - cost.sum() / (threads * max(at for at, _ in free))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_problem_options(ap, n=4000)
    ap.add_argument("--every", type=int, default=1, help="take every k-th value")
    ap.add_argument("--threads", type=int, default=16)
    ap.add_argument("--chunk", type=int, default=DEFAULT_CHUNK_INDEPENDENT,
                    help="values per chunk of the sweep in process (default: the sweep's)")
    args = ap.parse_args()
    p = rc.Parameters.reference()
    values = sweep_values(args.lo, args.hi, args.n)
    timed = values[:: args.every]
    simulate_batch(p, n_transient=10, n_record=10, parallel=False)  # load the kernel first
    cost = np.empty(timed.size)
    for i, g in enumerate(timed):
        item = p.replace(gamma=float(g))
        t0 = time.perf_counter()
        simulate_batch(item, n_transient=args.transient, n_record=args.record, parallel=False)
        cost[i] = time.perf_counter() - t0
    print(f"{timed.size} of {values.size} values timed: {1e3 * cost.mean():.2f} ms on average, "
          f"{1e3 * cost.min():.2f} to {1e3 * cost.max():.2f} ms (sd {1e3 * cost.std():.2f} ms)")
    guided = guided_idle_share(cost, args.threads, args.chunk)
    print(f"claimed in guided blocks by {args.threads} threads, chunks of {args.chunk}: idle {100 * guided:5.1f} %")
    rows = []
    for call in (64, 128, 256, 512, 1024, timed.size):
        blocks = idle_share(cost, args.threads, call, dealt=False)
        dealt = idle_share(cost, args.threads, call, dealt=True)
        rows.append(dict(call_lanes=call, idle_blocks=round(blocks, 4), idle_dealt=round(dealt, 4)))
        print(f"calls of {call:5d} lanes on {args.threads} threads: idle {100 * blocks:5.1f} % in contiguous "
              f"blocks, {100 * dealt:5.1f} % dealt in turn")
    print("json: " + json.dumps(dict(n=args.n, every=args.every, threads=args.threads,
                                     mean_ms=round(1e3 * cost.mean(), 3), idle_guided=round(guided, 4), runs=rows)))


if __name__ == "__main__":
    main()
