"""The γ sweep that sweep.py and scaling.py measure: its command-line options, shared by both."""

from __future__ import annotations

import argparse


def add_problem_options(ap: argparse.ArgumentParser, n: int) -> None:
    """``--n`` values of gamma in ``[--from, --to]``, each ``--transient`` + ``--record`` impacts."""
    ap.add_argument("--n", type=int, default=n, help="number of gamma values")
    ap.add_argument("--from", dest="lo", type=float, default=0.085)
    ap.add_argument("--to", dest="hi", type=float, default=0.145)
    ap.add_argument("--transient", type=int, default=4000)
    ap.add_argument("--record", type=int, default=1000)
