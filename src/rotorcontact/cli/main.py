"""The ``rotorcontact`` command line.

Each subcommand lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``func`` to a function
taking the parsed arguments and returning an exit status. Bad input raises
`ParameterError`; it is printed without a traceback and the exit status is 2.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from .. import __version__
from ..errors import ParameterError

SUBCOMMANDS = ("simulate", "drop", "drop-map", "equilibria", "orbits", "sweep", "basins", "design-map", "local", "lyapunov", "branches", "codim2", "reproduce")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # exit status 2, no traceback (argparse's own contract)
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="rotorcontact",
        description="Rotor-stator contact: exact impacting simulation and bifurcation analysis.",
    )
    parser.add_argument("--version", action="version", version=f"rotorcontact {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for name in SUBCOMMANDS:
        importlib.import_module(f"{__package__}.{name.replace('-', '_')}").register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status.

    0: done; 1: a computation could not complete (a failed simulation, memory
    exhausted), with one line on stderr; 2: bad input, with one line on stderr;
    130: interrupted (Ctrl-C), with one line on stderr, after every worker
    process has been ended.
    """
    command = "rotorcontact"
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
        command = f"rotorcontact {args.command}"
        return _run(args, command)
    except KeyboardInterrupt:
        print(f"{command}: interrupted", file=sys.stderr)
        return 130


def _run(args: argparse.Namespace, command: str) -> int:
    try:
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
