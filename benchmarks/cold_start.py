"""Start-up: a cold command (empty numba cache), a warm one, ``--help`` and ``import rotorcontact``.

Each figure is the wall time of a fresh process. "Cold" runs with NUMBA_CACHE_DIR pointing at an empty
folder: the command runs its kernels interpreted (`rotorcontact.interpreted`) while they are not compiled.
"Cold, compiled" sets ROTORCONTACT_INTERPRET_S=0, so every kernel the command needs is compiled first;
"warm" runs again with that folder filled.

Run: python benchmarks/cold_start.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

COMMANDS = {
    "simulate --t-end 100": ["simulate", "--t-end", "100"],
    "drop reference --speed 12000rpm --t-end 0.5s": ["drop", "reference", "--speed", "12000rpm", "--t-end", "0.5s"],
    "orbits": ["orbits"],
}


def _wall(argv: list[str], env: dict[str, str]) -> float:
    start = time.perf_counter()
    subprocess.run(argv, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3, help="runs of each warm figure (the best is printed)")
    args = ap.parse_args()
    cli = [sys.executable, "-m", "rotorcontact.cli.main"]
    base = {k: v for k, v in os.environ.items() if k != "ROTORCONTACT_INTERPRET_S"}
    for name, command in COMMANDS.items():
        with tempfile.TemporaryDirectory() as cache:
            env = {**base, "NUMBA_CACHE_DIR": cache}
            cold = min(_wall([*cli, *command], env) for _ in range(args.repeat))
            compiled = _wall([*cli, *command], {**env, "ROTORCONTACT_INTERPRET_S": "0"})
            warm = min(_wall([*cli, *command], env) for _ in range(args.repeat))
        print(f"`rotorcontact {name}`: cold {cold:.2f} s (interpreted); cold, compiled {compiled:.2f} s; "
              f"warm {warm:.2f} s")
    with tempfile.TemporaryDirectory() as cache:
        env = {**base, "NUMBA_CACHE_DIR": cache}
        cold_warmup = _wall([*cli, "warmup"], env)
    print(f"cold `rotorcontact warmup` (every group): {cold_warmup:.2f} s")
    best = {name: min(_wall(argv, base) for _ in range(args.repeat)) for name, argv in {
        "import rotorcontact": [sys.executable, "-c", "import rotorcontact"],
        "rotorcontact --help": [*cli, "--help"],
        "rotorcontact simulate --help": [*cli, "simulate", "--help"],
    }.items()}
    for name, s in best.items():
        print(f"{name}: {s:.3f} s")


if __name__ == "__main__":
    main()
