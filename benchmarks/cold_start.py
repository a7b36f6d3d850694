"""Start-up: a cold command (empty numba cache), a warm one, ``--help`` and ``import rotorcontact``.

Each figure is the wall time of a fresh process. "Cold" runs with NUMBA_CACHE_DIR pointing at an empty
folder, so every kernel the command needs is compiled; "warm" runs again with that folder filled.

Run: python benchmarks/cold_start.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

SIMULATE = ["simulate", "--t-end", "100"]


def _wall(argv: list[str], env: dict[str, str]) -> float:
    start = time.perf_counter()
    subprocess.run(argv, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3, help="runs of each warm figure (the best is printed)")
    args = ap.parse_args()
    cli = [sys.executable, "-m", "rotorcontact.cli.main"]
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        cold = _wall([*cli, *SIMULATE], env)
        warm = min(_wall([*cli, *SIMULATE], env) for _ in range(args.repeat))
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        cold_warmup = _wall([*cli, "warmup"], env)
        after = min(_wall([*cli, *SIMULATE], env) for _ in range(args.repeat))
    env = dict(os.environ)
    best = {name: min(_wall(argv, env) for _ in range(args.repeat)) for name, argv in {
        "import rotorcontact": [sys.executable, "-c", "import rotorcontact"],
        "rotorcontact --help": [*cli, "--help"],
        "rotorcontact simulate --help": [*cli, "simulate", "--help"],
    }.items()}
    print(f"cold `rotorcontact {' '.join(SIMULATE)}` (empty cache): {cold:.2f} s")
    print(f"warm, the same command: {warm:.2f} s")
    print(f"cold `rotorcontact warmup` (every group): {cold_warmup:.2f} s; then the command: {after:.2f} s")
    for name, s in best.items():
        print(f"{name}: {s:.3f} s")


if __name__ == "__main__":
    main()
