"""Options shared by the long-running subcommands: parallel execution, chunks, progress."""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import ParameterError


def parse_int(name: str, text: str, low: int) -> int:
    """Parse an integer >= ``low`` from a command-line string."""
    try:
        value = int(text)
    except (TypeError, ValueError):
        raise ParameterError(f"--{name} = {text!r} is not an integer") from None
    if value < low:
        raise ParameterError(f"--{name} = {value} is out of range; allowed: an integer >= {low}")
    return value


def add_scale_options(parser: argparse.ArgumentParser, default_chunk: str) -> None:
    """Add --n-jobs, --scheduler, --chunk-size, --no-resume, --keep-chunks, --no-progress."""
    g = parser.add_argument_group("execution")
    g.add_argument("--n-jobs", dest="n_jobs", default=None, metavar="N",
                   help="joblib worker processes (-1: one per core); default: this process, all cores")
    g.add_argument("--scheduler", default=None, metavar="ADDR",
                   help="run on Dask: 'local' starts a LocalCluster (--n-jobs workers), or a scheduler address "
                        "such as tcp://10.0.0.1:8786 (its workers need rotorcontact installed)")
    g.add_argument("--chunk-size", dest="chunk_size", default=None, metavar="K",
                   help=f"simulations per chunk written to disk (default {default_chunk}); results do not depend on "
                        "it, and an interrupted run resumes with the chunk size it was started with")
    g.add_argument("--no-resume", dest="resume", action="store_false",
                   help="discard partial results of an interrupted run instead of continuing from them, and "
                        "compute afresh an output file that already holds the finished study")
    g.add_argument("--keep-chunks", dest="keep_chunks", action="store_true",
                   help="keep the folder of chunk files after writing the NetCDF file")
    g.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar on stderr")


def scale_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    """Keyword arguments of `sweep` / `basins` from the execution options."""
    n_jobs = None
    if args.n_jobs is not None:
        n_jobs = parse_int("n-jobs", args.n_jobs, -1)
        if n_jobs == 0:
            raise ParameterError("--n-jobs = 0 is invalid; allowed: an integer >= 1, or -1 for one per core")
    out: dict[str, Any] = dict(n_jobs=n_jobs, scheduler=args.scheduler, resume=args.resume,
                               keep_chunks=args.keep_chunks, progress=args.progress)
    if args.chunk_size is not None:
        out["chunk_size"] = parse_int("chunk-size", args.chunk_size, 1)
    return out

