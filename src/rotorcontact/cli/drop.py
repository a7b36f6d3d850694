"""``rotorcontact drop``: the magnetic bearing fails and the spinning rotor drops onto its touchdown bearing."""

from __future__ import annotations

import argparse
import math
import sys

from ..errors import ParameterError
from ..model.params import load_machine
from ..model.units import quantity_in
from .outputs import check_plot_path
from .options import parse_int, print_json, renamed

#: Default and largest --max-events.
DEFAULT_MAX_EVENTS = 1_000_000
MAX_EVENTS = 10_000_000


def register(sub) -> None:
    p = sub.add_parser(
        "drop",
        description="Levitate the machine in its steady whirl at --speed, fail the magnetic bearing at "
                    "--fail-at and follow the drop exactly (MODEL.md §7) to --t-end. With contact = 'compliant' "
                    "the touchdown bearing is compliant, optionally on springs (stator_mass; MODEL.md §8).",
    )
    p.add_argument("machine", metavar="M.toml", help="machine file, or 'reference'")
    p.add_argument("--speed", default=None, metavar="SPEED",
                   help="spin speed at the start, with units (12000rpm, 1250 rad/s; default: the machine's)")
    p.add_argument("--fail-at", dest="fail_at", default="0s", metavar="T", help="failure time (default 0s)")
    p.add_argument("--t-end", dest="t_end", default="2s", metavar="T", help="final time (default 2s)")
    p.add_argument("--max-events", dest="max_events", default=str(DEFAULT_MAX_EVENTS), metavar="N",
                   help=f"largest number of flights (default {DEFAULT_MAX_EVENTS})")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write a three-panel figure")
    p.set_defaults(func=run)


def parse_time(option: str, text: str, *, low_open: bool = False, high: float | None = None) -> float:
    """A time option in seconds: a bare number, or a quantity with units ("0.5s", "20 ms").

    Parameters
    ----------
    option : str
        The option's name without the leading dashes (``"t-end"``).
    text : str
        The text given.
    low_open : bool
        Whether 0 itself is refused (the time must be > 0, else >= 0).
    high : float, optional
        Largest time allowed, s.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        For a malformed or non-finite time or one out of range, naming the option, the text and what is
        allowed.
    """
    try:
        value = float(text)
    except ValueError:
        value = quantity_in(f"--{option}", text, "s")
    allowed = f"{'(' if low_open else '['}0, {'inf)' if high is None else f'{high:g}]'} s"
    if not math.isfinite(value):
        raise ParameterError(f"--{option} = {text!r} is not finite; allowed: {allowed}")
    if value < 0.0 or (low_open and value == 0.0) or (high is not None and value > high):
        raise ParameterError(f"--{option} = {text!r} ({value:g} s) is out of range; allowed: {allowed}")
    return value


def parse_drop_times(args: argparse.Namespace) -> tuple[float, float]:
    """``--fail-at`` and ``--t-end`` of ``drop`` and ``drop-map``, s: 0 <= fail_at < t_end <=
    `rotorcontact.simulation.drop_run.MAX_T_END`."""
    from ..simulation.drop_run import MAX_T_END, check_failure_before_end

    fail_at = parse_time("fail-at", args.fail_at)
    t_end = parse_time("t-end", args.t_end, low_open=True, high=MAX_T_END)
    try:
        check_failure_before_end(fail_at, t_end)
    except ParameterError as exc:
        raise renamed(exc, {"fail_at": "--fail-at", "t_end": "--t-end"}) from None
    return fail_at, t_end


def warn_deep_contact(machine, result, command: str) -> None:
    """One warning line on stderr where a compliant contact pressed more than `MAX_START_DEPTH` clearances into
    the touchdown bearing: beyond the compliant law's range (the rotor's centre that far out is no longer a
    contact of two surfaces), so the run's forces there are the law's, not the machine's."""
    import numpy as np

    from ..simulation.drop_run import MAX_START_DEPTH

    if not machine.compliant or not len(result.impacts):
        return
    deepest = result.column("max_penetration_m")
    deepest = float(np.nanmax(deepest)) / machine.clearance if np.any(np.isfinite(deepest)) else 0.0
    if deepest > MAX_START_DEPTH:
        print(f"rotorcontact {command}: warning: a contact pressed {deepest:.3g} clearances into the touchdown "
              f"bearing, beyond the compliant law's range ({MAX_START_DEPTH:g}): its forces there are the law's, "
              "not a bearing's; a stiffer contact_stiffness keeps the contact shallow", file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    from ..simulation.drop_run import RPM, check_drop_speed, drop

    machine = load_machine(args.machine)
    fail_at, t_end = parse_drop_times(args)
    speed = None  # the machine's own speed, checked by `drop` under its key's name
    if args.speed is not None:
        speed = check_drop_speed(machine, args.speed, "--speed")  # the text: its errors show it
    max_events = parse_int("max-events", args.max_events, 1, MAX_EVENTS)
    if args.plot is not None:
        check_plot_path(args.plot)
    result = drop(machine, speed, fail_at, t_end, max_events=max_events)
    warn_deep_contact(machine, result, "drop")
    if args.plot is not None:
        from ..plotting.drop import save_drop_figure

        save_drop_figure(result, args.plot)
    if args.json:
        print_json(result.to_dict())
    else:
        s = result.to_dict()["summary"]
        print(result.message)
        print(f"regime: {s['regime']}, spin {result.speed / RPM:.6g} -> {s['final_spin_rpm']:.6g} rpm, "
              f"energy dissipated {s['energy_dissipated_J']:.6g} J")
        if args.plot:
            print(f"figure written to {args.plot}")
    if result.status == "failed":
        print(f"rotorcontact drop: failed: {result.message}", file=sys.stderr)
        return 1
    return 0
