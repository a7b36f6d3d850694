"""Options shared by the long-running subcommands: parallel execution, chunks, progress."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ..errors import ParameterError
from .options import parse_float, parse_int

__all__ = ["add_scale_options", "backend_summary", "batch_settings", "check_study_size", "parse_int",
           "scale_kwargs"]

#: Limits of the options of the batch studies (sweep, basins). The batch kernel runs of the order
#: of a million events per second per core; these keep each simulation within seconds and each
#: study's arrays within a few GiB. The Python API (`rotorcontact.studies.sweep`, `rotorcontact.studies.basins`)
#: takes larger values.
MAX_TRANSIENT = 1_000_000  # --transient, --settle: events of transient per simulation
MAX_RECORD = 100_000  # --record: events recorded per simulation
MAX_TIME = 1e7  # --t-transient, --t-record: dimensionless time
MAX_CHUNK = 1_000_000  # --chunk-size
MAX_JOBS = 1_000_000  # --n-jobs as written; local workers are then capped at the cores
MAX_STUDY_EVENTS = 10_000_000_000  # simulations x (transient + record): hours of work on one machine
MAX_KEPT_EVENTS = 50_000_000  # simulations x kept events: 32 bytes each, 1.6 GB of sections


def add_executor_options(parser: argparse.ArgumentParser) -> argparse._ArgumentGroup:
    """Add the group "execution" with --n-jobs and --scheduler, and return it."""
    g = parser.add_argument_group("execution")
    g.add_argument("--n-jobs", dest="n_jobs", default=None, metavar="N",
                   help="joblib worker processes (-1: one per core); default: this process, all cores")
    g.add_argument("--scheduler", default=None, metavar="ADDR",
                   help="run on Dask: 'local' starts a LocalCluster (--n-jobs workers), or a scheduler address "
                        "such as tcp://10.0.0.1:8786 (its workers need rotorcontact installed)")
    return g


#: --backend's values (`rotorcontact.studies.execution.BACKENDS`, not imported here to keep --help fast).
BACKEND_CHOICES = ("cpu", "cuda")


def add_scale_options(parser: argparse.ArgumentParser, default_chunk: str, *, backend: bool = False) -> None:
    """Add --n-jobs, --scheduler, --chunk-size, --no-resume, --keep-chunks, --no-progress (and --backend)."""
    g = add_executor_options(parser)
    if backend:
        g.add_argument("--backend", default="cpu", choices=BACKEND_CHOICES,
                       help="'cuda' runs the simulations on this machine's NVIDIA GPU (needs numba-cuda: "
                            "pip install 'rotorcontact[cuda]'), contact phases included; a rare simulation "
                            "whose contact phases end out of order by rounding is finished on the CPU. It pays "
                            "with many independent simulations (basins, attractors, independent sweeps), not for "
                            "a sweep that carries its state (it keeps two GPU threads busy). Default: cpu")
    g.add_argument("--chunk-size", dest="chunk_size", default=None, metavar="K",
                   help=f"simulations per chunk written to disk (default {default_chunk}); results do not depend on "
                        "it, and an interrupted run resumes with the chunk size it was started with")
    g.add_argument("--no-resume", dest="resume", action="store_false",
                   help="discard partial results of an interrupted run instead of continuing from them, and "
                        "compute afresh an output file that already holds the finished study")
    g.add_argument("--keep-chunks", dest="keep_chunks", action="store_true",
                   help="keep the folder of chunk files after writing the NetCDF file")
    g.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar on stderr")


def scale_options_given(args: argparse.Namespace) -> list[str]:
    """The options of `add_scale_options` given on the command line (for a command that runs no study)."""
    given = [(args.n_jobs is not None, "--n-jobs"), (args.scheduler is not None, "--scheduler"),
             (getattr(args, "backend", "cpu") != "cpu", "--backend"), (args.chunk_size is not None, "--chunk-size"),
             (not args.resume, "--no-resume"), (args.keep_chunks, "--keep-chunks"),
             (not args.progress, "--no-progress")]
    return [option for is_given, option in given if is_given]


def batch_settings(args: argparse.Namespace, n_keep: int | None = None):
    """The `BatchSettings` of --transient, --record, --t-transient, --t-record and --settle, within their limits."""
    from ..studies.batch import BatchSettings

    n_transient = parse_int("transient", args.transient, 0, MAX_TRANSIENT,
                            why="a transient of more events per simulation would take minutes each")
    n_record = parse_int("record", args.record, 1, MAX_RECORD,
                         why="every recorded event of every simulation is kept in memory")

    def time_limit(name: str, text: str | None) -> float | None:
        if text is None:
            return None
        return parse_float(name, text, low=0.0, high=MAX_TIME, low_open=True,
                           why="beyond it double precision cannot resolve the impact times")

    return BatchSettings(
        n_transient=n_transient,
        n_record=n_record,
        t_transient=time_limit("t-transient", args.t_transient),
        t_record=time_limit("t-record", args.t_record),
        settle=parse_int("settle", args.settle, 0, MAX_TRANSIENT),
        n_keep=n_keep,
    )


def check_study_size(simulations: int, settings, what: str) -> None:
    """Refuse a study whose total work or kept data exceeds `MAX_STUDY_EVENTS` or `MAX_KEPT_EVENTS`.

    Parameters
    ----------
    simulations : int
        Number of simulations of the study.
    settings : BatchSettings
        Events per simulation.
    what : str
        How the simulations are counted, for the message (``"--n 200 values x 2 directions"``).

    Raises
    ------
    ParameterError
        Naming the options, their product and its limit.
    """
    events = simulations * (settings.n_transient + settings.n_record)
    if events > MAX_STUDY_EVENTS:
        raise ParameterError(
            f"{what} = {simulations} simulations of --transient {settings.n_transient} + --record "
            f"{settings.n_record} events make {events:.3g} events; allowed: at most {MAX_STUDY_EVENTS:.0e} "
            "events per study (hours of computation on one machine); reduce them or split the study"
        )
    keep = settings.n_keep if settings.n_keep is not None else settings.n_record
    if simulations * keep > MAX_KEPT_EVENTS:
        raise ParameterError(
            f"{what} = {simulations} simulations keeping --record {keep} events each make "
            f"{simulations * keep:.3g} kept events; allowed: at most {MAX_KEPT_EVENTS:.0e} "
            f"({MAX_KEPT_EVENTS * 32 / 2**30:.1f} GiB of sections); reduce them or split the study"
        )


def executor_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    """``n_jobs`` and ``scheduler`` from --n-jobs and --scheduler (`add_executor_options`).

    More local workers than cores (--n-jobs, for joblib or ``--scheduler local``)
    are capped at the cores, with a note on stderr.
    """
    from ..studies.execution import local_workers

    n_jobs = None
    if args.n_jobs is not None:
        allowed = f"an integer from 1 to {MAX_JOBS}, or -1 for one per core"
        n_jobs = parse_int("n-jobs", args.n_jobs, -1, MAX_JOBS, allowed=allowed)
        if n_jobs == 0:
            raise ParameterError(f"--n-jobs = 0 is out of range; allowed: {allowed}")
        if args.scheduler is None or args.scheduler == "local":
            n, capped = local_workers(n_jobs)
            if capped:
                print(f"note: --n-jobs {n_jobs} is more than the {n} cores available; using {n} workers",
                      file=sys.stderr)
            n_jobs = n if n_jobs != -1 else -1
    return {"n_jobs": n_jobs, "scheduler": args.scheduler}


def backend_summary(result: Any, execution: dict[str, Any]) -> dict[str, Any]:
    """The JSON keys of a study run on the GPU (none on the CPU): ``backend`` and ``handed_to_cpu``.

    Also notes on stderr how many simulations the GPU handed to the CPU, when it handed any.
    """
    if execution.get("backend", "cpu") == "cpu":
        return {}
    if not result.reused_file and result.handed_to_cpu > 0:
        print(f"note: {result.handed_to_cpu} simulations were computed on the CPU: the GPU's summary of their "
              "window could not be exact (in a carried chain, from that step on)", file=sys.stderr)
    return {"backend": execution["backend"], "handed_to_cpu": int(result.handed_to_cpu)}


def scale_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    """Keyword arguments of `sweep` / `basins` from the execution options (`add_scale_options`)."""
    out: dict[str, Any] = dict(executor_kwargs(args), resume=args.resume, keep_chunks=args.keep_chunks,
                               progress=args.progress)
    backend = getattr(args, "backend", "cpu")
    if backend != "cpu":
        if args.n_jobs is not None or args.scheduler is not None:
            raise ParameterError(
                f"--backend {backend} runs in this process on its GPU; --n-jobs and --scheduler are invalid with "
                "it; allowed: one or the other"
            )
        from ..studies.cuda_batch import require_cuda

        require_cuda(f"--backend {backend}")
        out["backend"] = backend
    if args.chunk_size is not None:
        out["chunk_size"] = parse_int("chunk-size", args.chunk_size, 1, MAX_CHUNK)
    return out
