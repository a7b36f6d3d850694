"""``rotorcontact warmup``: compile the kernels ahead, so that later commands and workers start at once."""

from __future__ import annotations

import argparse

from ..errors import ParameterError
from ..studies.warmup import WARMUP_GROUPS
from .options import print_json


def register(sub) -> None:
    p = sub.add_parser(
        "warmup",
        description=(
            "Compile the numerical kernels into numba's on-disk cache, where every later command and every "
            "worker process (joblib, Dask, on this machine or wherever the package's cache is shared) loads "
            "them instead of compiling. Prints the seconds each group took: its compile time the first time, "
            "its load time after."
        ),
    )
    p.add_argument("--only", default=None, metavar="G1,G2",
                   help="groups to compile, comma-separated (default all): "
                        + "; ".join(f"{name} ({uses})" for name, (uses, _f) in WARMUP_GROUPS.items()))
    p.add_argument("--json", action="store_true", help='print {"seconds": {group: s}} on stdout')
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..studies.warmup import warm_up

    groups = None if args.only is None else [g.strip() for g in args.only.split(",")]
    try:
        seconds = warm_up(groups)
    except ParameterError as exc:
        raise ParameterError(str(exc).replace("group = ", "--only = ", 1)) from None
    if args.json:
        print_json({"seconds": seconds})
    else:
        for name, s in seconds.items():
            print(f"{name:10s} {s:8.2f} s")
    return 0
