"""Options shared by the subcommands: model parameters, initial state, JSON output."""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..params import Machine, Parameters, load_machine, reference_machine

PARAM_NAMES = ("gamma", "omega", "rho", "mu", "d", "phi", "r_ratio")


def add_parameter_options(parser: argparse.ArgumentParser) -> None:
    """Add --gamma ... --r-ratio and --machine to a subcommand."""
    group = parser.add_argument_group(
        "model parameters",
        "dimensionless parameters (MODEL.md §2); default: the reference machine. "
        "With --machine, the machine file gives the defaults and these options override them.",
    )
    for name in PARAM_NAMES:
        group.add_argument(f"--{name.replace('_', '-')}", dest=name, type=str, default=None, metavar="X")
    group.add_argument(
        "--machine",
        default=None,
        metavar="FILE.toml",
        help="take the parameters from a machine file (SI units), or 'reference'",
    )


def parse_float(name: str, text: str) -> float:
    """Parse a finite float from a command-line string."""
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(f"--{name.replace('_', '-')} = {text!r} is not a number") from None
    if not math.isfinite(value):
        raise ParameterError(f"--{name.replace('_', '-')} = {text!r} is not finite; a finite number is required")
    return value


def parse_complex(name: str, text: str) -> complex:
    """Parse ``RE,IM`` into a complex number."""
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"--{name} = {text!r} is malformed; expected RE,IM (for example --{name}=0.1,-0.2)")
    return complex(parse_float(name, parts[0]), parse_float(name, parts[1]))


def parameters_from_args(args: argparse.Namespace) -> tuple[Parameters, Machine | None]:
    """The Parameters selected by the options, and the machine if one was given."""
    machine = load_machine(args.machine) if args.machine is not None else None
    base = (machine or reference_machine()).parameters()
    changes = {
        name: parse_float(name, getattr(args, name)) for name in PARAM_NAMES if getattr(args, name) is not None
    }
    try:
        params = base.replace(**changes)
    except ParameterError as exc:
        raise ParameterError(f"--{str(exc).replace('_', '-')}") from None
    if changes and machine is not None:
        # overridden parameters no longer describe the machine
        print(
            f"note: {', '.join('--' + k.replace('_', '-') for k in changes)} override the machine's values; "
            "its SI outputs are left out",
            file=sys.stderr,
        )
        machine = None
    return params, machine


def renamed(exc: Exception, names: dict[str, str]) -> ParameterError:
    """The error ``exc`` with library argument names replaced by their options (whole words only)."""
    text = str(exc)
    for name, flag in names.items():
        text = re.sub(rf"(?<![\w-]){re.escape(name)}(?![\w-])", flag, text)
    return ParameterError(text)


def jsonable(obj: Any) -> Any:
    """Plain JSON data: complex as [re, im], non-finite numbers as null."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (complex, np.complexfloating)):
        return [jsonable(float(obj.real)), jsonable(float(obj.imag))]
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    return obj


def json_result(params: Parameters, data: dict[str, Any], machine: Machine | None = None) -> dict[str, Any]:
    """The object a subcommand prints with ``--json``: its ``"parameters"`` first, then ``data``.

    Parameters
    ----------
    params : Parameters
        The dimensionless parameters of the computation (``"parameters"``).
    data : dict
        The subcommand's own keys (a ``"parameters"`` key in it is replaced).
    machine : Machine, optional
        With ``--machine``: its SI values are added as ``"machine"``.

    Returns
    -------
    dict
    """
    out: dict[str, Any] = {"parameters": params.as_dict()}
    out.update((k, v) for k, v in data.items() if k != "parameters")
    if machine is not None:
        out["machine"] = machine.as_dict()
    return out


def print_json(data: Any) -> None:
    """Write ``data`` as JSON on stdout."""
    json.dump(jsonable(data), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")
