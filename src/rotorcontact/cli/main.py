"""The ``rotorcontact`` command line.

Each subcommand lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``func`` to a function
taking the parsed arguments and returning an exit status. Bad input raises
`ParameterError`; it is printed without a traceback and the exit status is 2.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from .. import __version__
from ..errors import ParameterError

#: The subcommands, each in its module of this package (``design-map`` in ``design_map``), with its summary.
SUBCOMMANDS: dict[str, str] = {
    "simulate": "simulate the rotor from an initial state",
    "drop": "drop a spinning rotor onto its touchdown bearing after a magnetic-bearing failure",
    "drop-map": "drops of a machine over a range of speeds and friction coefficients",
    "dry-whip": "the steady dry whip of a rotor on a touchdown bearing on springs",
    "equilibria": "regular and pseudo-equilibria, and the boundary equilibrium bifurcation",
    "orbits": "periodic orbits with one (or, with --impacts, p) impacts per period",
    "sweep": "brute-force orbit diagram against one parameter",
    "basins": "basins of attraction on a grid of initial states",
    "attractors": "attractors and their basin fractions followed across a parameter",
    "design-map": "classify a machine's speed range or controller gains: safe, bistable, contact-certain",
    "local": "first-order expansion of the small impacting orbits at the boundary equilibrium (NSFH)",
    "lyapunov": "Lyapunov spectrum of the 4-dimensional state along a simulated trajectory",
    "branches": "branches of one-impact orbits against a parameter, with folds, NSFH, grazing, stability changes",
    "cascade": "period-doubling cascades in a parameter range, with Feigenbaum's ratios and where they end",
    "codim2": "two-parameter diagram: fold, NSFH/DIB and grazing curves and their intersections",
    "reproduce": "compute the paper's Figures 2-7 and write report.json and report.html",
    "warmup": "compile the numerical kernels ahead, so that later commands and workers start at once",
}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # exit status 2, no traceback (argparse's own contract)
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The command-line parser.

    With ``argv``, only the module of the subcommand named there is loaded (the
    others are listed by name and summary), so that a command, and its
    ``--help``, loads nothing that other commands need; without, every module.
    """
    parser = _Parser(
        prog="rotorcontact",
        description="Rotor-stator contact: exact impacting simulation and bifurcation analysis.",
    )
    parser.add_argument("--version", action="version", version=f"rotorcontact {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    parser.set_defaults(_commands=sub.choices)
    # the top level has no option taking a value, so the first word that is not an option names the command
    named = None if argv is None else next((a for a in argv if not a.startswith("-")), "")
    for name, summary in SUBCOMMANDS.items():
        if named is None or name == named:
            importlib.import_module(f"{__package__}.{name.replace('-', '_')}").register(sub)
        else:
            sub.add_parser(name, help=summary)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status.

    0: done; 1: a computation could not complete (a failed simulation, memory
    exhausted), with one line on stderr; 2: bad input, with one line on stderr;
    130: interrupted (Ctrl-C), with one line on stderr, after every worker
    process has been ended.
    """
    command = "rotorcontact"
    # the commands write their figures to files and never show a window: no display is needed (a backend the
    # user chose with MPLBACKEND is kept); the Python API leaves matplotlib's choice alone
    os.environ.setdefault("MPLBACKEND", "Agg")
    try:
        argv = sys.argv[1:] if argv is None else list(argv)
        parser = build_parser(argv)
        args, unknown = parser.parse_known_args(argv)
        if unknown:  # refused by the subcommand's parser, whose usage and name the message then carries
            args._commands[args.command].error(f"unrecognized arguments: {' '.join(unknown)}")
        command = f"rotorcontact {args.command}"
        return _run(args, command)
    except KeyboardInterrupt:
        print(f"{command}: interrupted", file=sys.stderr)
        return 130


def check_numba_threads_variable() -> None:
    """Refuse a ``NUMBA_NUM_THREADS`` that is set but not a whole number >= 1 (numba itself fails to import
    with 0, and with text it warns and falls back to all cores)."""
    text = os.environ.get("NUMBA_NUM_THREADS")
    if text is None:
        return
    try:
        threads = int(text.strip())
    except ValueError:
        threads = 0
    if threads < 1:
        raise ParameterError(f"NUMBA_NUM_THREADS = {text!r} is invalid; allowed: a whole number >= 1 (the "
                             "threads of numba and of the studies in this process), or unset for one per core")


def _run(args: argparse.Namespace, command: str) -> int:
    try:
        check_numba_threads_variable()
        return int(args.func(args) or 0)
    except ParameterError as exc:
        print(f"{command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        if isinstance(exc, BrokenPipeError):  # output piped into a program that stopped reading
            sys.stderr.close()
            return 1
        # an output path that cannot be written: bad input, reported as such
        where = f" {exc.filename!r}" if getattr(exc, "filename", None) else ""
        print(f"{command}: error: cannot write{where}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        # a computation that could not complete (for example a simulation that failed)
        print(f"{command}: failed: {exc}", file=sys.stderr)
        return 1
    except MemoryError:
        print(f"{command}: failed: out of memory; use smaller sizes", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
