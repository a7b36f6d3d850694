"""``rotorcontact simulate``: one trajectory, as JSON, a figure or a short text summary."""

from __future__ import annotations

import argparse
import sys

from ..errors import ParameterError
from ..model.params import MAX_T_END
from .options import (
    add_parameter_options,
    ignored_keys,
    json_result,
    parameters_from_args,
    parse_complex,
    parse_float,
    parse_int,
    parse_velocity,
    print_json,
)
from .outputs import check_plot_path

#: Largest --max-events: each event keeps about 150 bytes, so 1e7 events need 1.5 GB.
MAX_EVENTS = 10_000_000
#: Default --max-events.
DEFAULT_MAX_EVENTS = 1_000_000
#: Impacts (and contact intervals) listed by --json without --all-impacts: the first and the last half.
JSON_ROWS = 1000


def register(sub) -> None:
    p = sub.add_parser(
        "simulate",
        description="Simulate the rotor exactly (closed-form flight, guaranteed impact location).",
    )
    add_parameter_options(p)
    p.add_argument("--u0", default="0,0", metavar="RE,IM", help="initial position U(0) (co-rotating, |U| <= 1)")
    p.add_argument("--du0", default="0,0", metavar="RE,IM", help="initial velocity U'(0) (co-rotating)")
    p.add_argument("--t-end", dest="t_end", default="500", metavar="T",
                   help=f"final dimensionless time (default 500, at most {MAX_T_END:g})")
    p.add_argument("--max-events", dest="max_events", default=str(DEFAULT_MAX_EVENTS), metavar="N",
                   help=f"stop with status max-events after N flights and contact phases "
                        f"(default {DEFAULT_MAX_EVENTS}, at most {MAX_EVENTS})")
    p.add_argument(
        "--on-chatter",
        dest="on_chatter",
        choices=("contact", "stop"),
        default="contact",
        help="at an accumulation of impacts, continue in continuous contact (default) or stop",
    )
    p.add_argument("--json", action="store_true",
                   help=f"print the result as JSON on stdout (past {JSON_ROWS} impacts, the first and last "
                        f"{JSON_ROWS // 2}, flagged as truncated)")
    p.add_argument("--all-impacts", dest="all_impacts", action="store_true",
                   help="with --json, list every impact and contact interval however many there are")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write a three-panel figure")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..simulation.simulator import simulate

    params, machine = parameters_from_args(args, general=True)
    u0 = parse_complex("u0", args.u0)
    du0 = parse_velocity("du0", args.du0)
    t_end = parse_float("t-end", args.t_end, low=0.0, high=MAX_T_END, low_open=True,
                        why="beyond it double precision cannot resolve the impact times")
    max_events = parse_int("max-events", args.max_events, 1, MAX_EVENTS,
                           why="each event is kept in memory, about 150 bytes each")
    if args.all_impacts and not args.json:
        raise ParameterError("--all-impacts lists every impact in the JSON output; allowed: with --json")
    if args.plot is not None:
        check_plot_path(args.plot)
    if machine is not None and machine.needs_general_model:
        return _run_general(args, machine, u0, du0, t_end, max_events)
    traj = simulate(params, u0, du0, t_end, on_chatter=args.on_chatter, max_events=max_events, machine=machine)
    if args.plot is not None:
        from ..plotting.trajectory import save_trajectory_figure

        save_trajectory_figure(traj, args.plot)
    if args.json:
        print_json(json_result(params, traj.to_dict(None if args.all_impacts else JSON_ROWS), machine,
                ignored=ignored_keys(args)))
    else:
        s = traj.summary
        print(traj.message)
        if traj.status == "failed":
            line = f"regime: none (the run failed after {s.n_impacts} impacts)"
        else:
            line = f"regime: {s.regime}, impacts: {s.motion}"
        if s.period is not None:
            line += f" ({s.impacts_per_period} impact(s) per period, T = {s.period:.10g})"
        print(line)
        if args.plot:
            print(f"figure written to {args.plot}")
    if traj.status == "failed":
        print(f"rotorcontact simulate: failed: {traj.message}", file=sys.stderr)
        return 1
    return 0


def _run_general(args: argparse.Namespace, machine, u0: complex, du0: complex, t_end: float, max_events: int) -> int:
    """The general machine of MODEL.md §7 with its bearing on, in SI (times s, positions m, spin rpm).

    The initial state is given as for the paper's model (co-rotating, in clearances, MODEL.md §2):
    z = c_r U, z' = c_r Omega (U' + i U) at t = 0, and t_end in units of 1/Omega.
    """
    import math

    from ..simulation.drop_run import run_general

    om = machine.speed
    result = run_general(machine, machine.clearance * u0, machine.clearance * om * (du0 + 1j * u0), om, math.inf,
                         t_end / om, max_events=max_events)
    if args.plot is not None:
        from ..plotting.drop import save_drop_figure

        save_drop_figure(result, args.plot)
    if args.json:
        out = result.to_dict()
        out["model"] = "general"
        print_json(out)
    else:
        print(result.message)
        print(f"regime: {result.regime} (general machine, MODEL.md §7)")
        if args.plot:
            print(f"figure written to {args.plot}")
    if result.status == "failed":
        print(f"rotorcontact simulate: failed: {result.message}", file=sys.stderr)
        return 1
    return 0
