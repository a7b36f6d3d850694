"""``rotorcontact simulate``: one trajectory, as JSON, a figure or a short text summary."""

from __future__ import annotations

import argparse

from ..params import check_range
from ..simulate import simulate
from .outputs import check_plot_path
from .options import add_parameter_options, json_result, parameters_from_args, parse_complex, parse_float, print_json


def register(sub) -> None:
    p = sub.add_parser(
        "simulate",
        help="simulate the rotor from an initial state",
        description="Simulate the rotor exactly (closed-form flight, guaranteed impact location).",
    )
    add_parameter_options(p)
    p.add_argument("--u0", default="0,0", metavar="RE,IM", help="initial position U(0) (co-rotating, |U| <= 1)")
    p.add_argument("--du0", default="0,0", metavar="RE,IM", help="initial velocity U'(0) (co-rotating)")
    p.add_argument("--t-end", dest="t_end", default="500", metavar="T", help="final dimensionless time (default 500)")
    p.add_argument(
        "--on-chatter",
        dest="on_chatter",
        choices=("contact", "stop"),
        default="contact",
        help="at an accumulation of impacts, continue in continuous contact (default) or stop",
    )
    p.add_argument("--json", action="store_true", help="print the whole result as JSON on stdout")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write a three-panel figure")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    params, machine = parameters_from_args(args)
    u0 = parse_complex("u0", args.u0)
    du0 = parse_complex("du0", args.du0)
    t_end = check_range("--t-end", parse_float("t-end", args.t_end), low=0.0, low_open=True)
    if args.plot is not None:
        check_plot_path(args.plot)
    traj = simulate(params, u0, du0, t_end, on_chatter=args.on_chatter, machine=machine)
    if args.plot is not None:
        from ..plotting.trajectory import save_trajectory_figure

        save_trajectory_figure(traj, args.plot)
    if args.json:
        print_json(json_result(params, traj.to_dict(), machine))
    else:
        s = traj.summary
        print(traj.message)
        line = f"regime: {s.regime}, impacts: {s.motion}"
        if s.period is not None:
            line += f" ({s.impacts_per_period} impact(s) per period, T = {s.period:.10g})"
        print(line)
        if args.plot:
            print(f"figure written to {args.plot}")
    return 0
