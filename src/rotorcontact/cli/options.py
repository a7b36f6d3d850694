"""Options shared by the subcommands: model parameters, initial state, JSON output."""

from __future__ import annotations

import argparse
import math
import re
import sys
from typing import Any

from ..errors import ParameterError
from ..io.json import dump_json
from ..model.params import (
    Machine,
    Parameters,
    check_range,
    check_velocity,
    load_machine,
    reference_machine,
)

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


def parse_float(
    name: str,
    text: str,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    why: str | None = None,
) -> float:
    """Parse a finite float from a command-line string, optionally within bounds.

    Parameters
    ----------
    name : str
        Option name without the leading dashes (``"t-end"``).
    text : str
        The text given on the command line.
    low, high : float, optional
        Bounds of the allowed interval (None: unbounded on that side).
    low_open, high_open : bool
        Whether the bound itself is excluded.
    why : str, optional
        Reason for the upper bound, shown in the error of a value above it.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        If ``text`` is not a finite number or lies outside the bounds; the
        message names the option, the value and what is allowed.
    """
    option = f"--{name.replace('_', '-')}"
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(
            f"{option} = {text!r} is not a number; allowed: a plain number without units (the model's "
            "times and parameters are dimensionless: one forcing period is a time of 2 pi, MODEL.md)"
        ) from None
    if not math.isfinite(value):
        raise ParameterError(f"{option} = {text!r} is not finite; a finite number is required")
    if low is not None or high is not None:
        check_range(option, value, low=low, high=high, low_open=low_open, high_open=high_open, why=why)
    return value


def parse_int(name: str, text: str, low: int, high: int, *, why: str | None = None,
              allowed: str | None = None) -> int:
    """Parse an integer in [low, high] from a command-line string.

    Every count a subcommand takes (values, points, events, seeds, workers)
    goes through here, so that each has an upper bound that keeps the
    command's time and memory finite, and the error says what it is.

    Parameters
    ----------
    name : str
        Option name without the leading dashes (``"n-jobs"``).
    text : str
        The text given: an integer, or a float with an integer value (``1e5``).
    low, high : int
        Smallest and largest allowed values.
    why : str, optional
        Reason for the upper bound, shown in the error of a value above it.
    allowed : str, optional
        What the error says is allowed (default: the range), where only some values of the range are.

    Returns
    -------
    int

    Raises
    ------
    ParameterError
        If ``text`` is not an integer or lies outside [low, high].
    """
    option = f"--{name.replace('_', '-')}"
    allowed = allowed or f"an integer from {low} to {high}"
    try:
        value = int(text)
    except (TypeError, ValueError):
        try:
            number = float(text)
        except (TypeError, ValueError):
            number = math.nan
        if not (math.isfinite(number) and number.is_integer()):
            raise ParameterError(f"{option} = {text!r} is not an integer; allowed: {allowed}") from None
        value = int(number)
    if not low <= value <= high:
        reason = f" ({why})" if why and value > high else ""
        raise ParameterError(f"{option} = {value} is out of range; allowed: {allowed}{reason}")
    return value


#: Largest --t-max of ``orbits`` and ``local`` (about 160 forcing periods; the paper uses 12). The
#: number of orbits grows like T_max, and at small damping their search takes minutes past it.
MAX_PERIOD = 1000.0
#: Largest --t-max of ``branches`` and ``codim2``: every orbit found is continued, at a cost that
#: grows faster than T_max; 100 already takes minutes.
MAX_CONTINUATION_PERIOD = 100.0


def parse_t_max(text: str, high: float) -> float:
    """Parse --t-max, the largest period searched: in (0, ``high``]."""
    return parse_float("t-max", text, low=0.0, high=high, low_open=True,
                       why="the number of orbits, and the time to find them, grows with it")


def parse_complex(name: str, text: str) -> complex:
    """Parse ``RE,IM`` into a complex number."""
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"--{name} = {text!r} is malformed; expected RE,IM (for example --{name}=0.1,-0.2)")
    return complex(parse_float(name, parts[0]), parse_float(name, parts[1]))


def parse_velocity(name: str, text: str) -> complex:
    """Parse an initial velocity ``RE,IM``, at most `rotorcontact.model.params.MAX_VELOCITY` in magnitude."""
    return check_velocity(f"--{name}", parse_complex(name, text))


def parameter_value(option: str, params: Parameters, name: str, value: float) -> float:
    """Check that ``value`` is allowed for the model parameter ``name`` (the end of a range, say).

    Parameters
    ----------
    option : str
        The option that gave the value, without dashes (``"to"``).
    params : Parameters
        The other parameters.
    name : str
        The model parameter the value is for.
    value : float
        The value.

    Returns
    -------
    float
        ``value``.

    Raises
    ------
    ParameterError
        Naming the option, the value and the parameter's allowed range.
    """
    try:
        params.replace(**{name: value})
    except ParameterError as exc:
        raise ParameterError(f"--{option} = {value!r} is not a valid {name}: {exc}") from None
    return value


#: What the paper's model of MODEL.md §2 leaves out of a general machine (MODEL.md §7-8).
PAPER_MODEL = ("the paper's dimensionless model (MODEL.md §2: isotropic bearing, no gravity or static force, "
               "speed held, rigid impacts on a fixed stator)")


def note_paper_model(machine: Machine | None, command: str, args: argparse.Namespace | None = None) -> tuple[str, ...]:
    """Say on stderr that ``command`` computes on the paper's model, ignoring the machine's keys of MODEL.md §7-8.

    Parameters
    ----------
    machine : Machine or None
        The machine given (None: nothing to say).
    command : str
        The subcommand, as the note names it.
    args : argparse.Namespace, optional
        The parsed options: the keys ignored are kept in ``args.ignored_machine_keys`` for `ignored_keys`.

    Returns
    -------
    tuple of str
        The machine's keys the computation ignores (`Machine.general_keys`); empty when it ignores none.
    """
    keys = () if machine is None else machine.general_keys
    if keys:
        print(f"note: rotorcontact {command} computes on {PAPER_MODEL}; the machine's {', '.join(keys)} "
              "are ignored", file=sys.stderr)
    if args is not None:
        args.ignored_machine_keys = keys
    return keys


def ignored_keys(args: argparse.Namespace) -> tuple[str, ...]:
    """The machine's keys the command's model ignores, as `note_paper_model` recorded them (empty if none)."""
    return tuple(getattr(args, "ignored_machine_keys", ()))


def parameters_from_args(args: argparse.Namespace, *, general: bool = False) -> tuple[Parameters, Machine | None]:
    """The Parameters selected by the options, and the machine if one was given.

    ``general``: the command runs a machine that needs it on the general model of MODEL.md §7 (as long as
    no option overrides the machine's values). Otherwise the command computes on the paper's model, and a
    note on stderr (`note_paper_model`) names the machine's keys it ignores.
    """
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
    if machine is not None and (changes or not general):
        note_paper_model(machine, getattr(args, "command", None) or "this command", args)
    if changes:
        machine = None
    return params, machine


def renamed(exc: Exception, names: dict[str, str]) -> ParameterError:
    """The error ``exc`` with library argument names replaced by their options (whole words only)."""
    text = str(exc)
    for name, flag in names.items():
        text = re.sub(rf"(?<![\w-]){re.escape(name)}(?![\w-])", flag, text)
    return ParameterError(text)


def json_result(params: Parameters, data: dict[str, Any], machine: Machine | None = None, *,
                ignored: tuple[str, ...] = ()) -> dict[str, Any]:
    """The object a subcommand prints with ``--json``: its ``"parameters"`` first, then ``data``.

    Parameters
    ----------
    params : Parameters
        The dimensionless parameters of the computation (``"parameters"``).
    data : dict
        The subcommand's own keys (a ``"parameters"`` key in it is replaced).
    machine : Machine, optional
        With ``--machine``: its SI values are added as ``"machine"``.
    ignored : tuple of str
        The machine's keys the computation's model ignores (`ignored_keys`); given, ``"model": "paper"`` and
        ``"ignored_machine_keys"`` are added.

    Returns
    -------
    dict
    """
    out: dict[str, Any] = {"parameters": params.as_dict()}
    out.update((k, v) for k, v in data.items() if k != "parameters")
    if machine is not None:
        out["machine"] = machine.as_dict()
    if ignored:
        out["model"] = "paper"
        out["ignored_machine_keys"] = list(ignored)
    return out


def print_json(data: Any) -> None:
    """Write ``data`` as JSON on stdout (`rotorcontact.io.json.dump_json`)."""
    dump_json(data, sys.stdout)


def parse_section_grid(text: str | None) -> tuple[int, int, int]:
    """``--grid NT,NR,ND``: the grid of impact states seeding orbits with several impacts (default `GRID_SHAPE`)."""
    from ..maps.multi_impact import GRID_SHAPE, MAX_GRID_POINTS

    if text is None:
        return GRID_SHAPE
    parts = text.split(",")
    if len(parts) != 3:
        raise ParameterError(f"--grid = {text!r} is invalid; allowed: three counts NT,NR,ND (theta, rdot-, thetadot-)")
    shape = tuple(parse_int("grid", q.strip(), 1, MAX_GRID_POINTS) for q in parts)
    if shape[0] * shape[1] * shape[2] > MAX_GRID_POINTS:
        raise ParameterError(f"--grid = {text!r} has {shape[0] * shape[1] * shape[2]} points; allowed: at most "
                             f"{MAX_GRID_POINTS} (each is a Newton solve)")
    return shape  # type: ignore[return-value]


def parameter_values(args: argparse.Namespace, params: Parameters, machine: Machine | None, max_values: int,
                     why: str) -> tuple[str, Any]:
    """The unit of ``--param`` and its ``--n`` values from ``--from`` to ``--to`` (a numpy array, ends included).

    A model parameter is dimensionless; with ``--machine`` a machine quantity (speed, stiffness, ...)
    takes its ends with units (``3000rpm``), bare numbers being SI. Both ends must give valid parameters.

    Raises
    ------
    ParameterError
        For an unknown parameter, a machine quantity without ``--machine``, a bad count or range.
    """
    import numpy as np

    from ..model.units import option_quantity
    from ..studies.parameter_path import check_path_param, parameter_path

    param = check_path_param(args.param, machine, "--param", "--machine")
    if param in PARAM_NAMES:
        unit, a, b = "1", parse_float("from", args.start_value), parse_float("to", args.stop_value)
    else:
        unit = Machine.units()[param]
        a, b = option_quantity("--from", args.start_value, unit), option_quantity("--to", args.stop_value, unit)
    n_values = parse_int("n", args.n_values, 1, max_values, why=why)
    if n_values > 1 and not a < b:
        raise ParameterError(f"--from = {args.start_value} must be smaller than --to = {args.stop_value}")
    if n_values == 1 and a != b:
        raise ParameterError(f"--n = 1 is a single value, but --from = {args.start_value} and --to = "
                             f"{args.stop_value} differ; allowed: --n >= 2, or --from = --to")
    values = np.linspace(a, b, n_values)
    try:
        parameter_path(params, param, np.unique(values[[0, -1]]), machine)
    except ParameterError as exc:
        raise ParameterError(f"--from/--to: {exc}") from None
    return unit, values
