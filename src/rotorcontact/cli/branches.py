"""``rotorcontact branches``: branches of one-impact orbits against a parameter, with their events."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..branches import BRANCH_PARAMETERS, OrbitBranches, orbit_branches
from ..errors import ParameterError
from .options import add_parameter_options, parameters_from_args, parse_float, print_json, renamed

#: Default range of each parameter.
DEFAULT_RANGES = {
    "gamma": (-0.6, 0.25),
    "omega": (0.6, 1.25),
    "rho": (0.05, 1.0),
    "mu": (0.0, 0.5),
    "d": (0.5, 1.0),
}


def register(sub) -> None:
    p = sub.add_parser(
        "branches",
        help="branches of one-impact orbits against a parameter, with folds, NSFH, grazing, stability changes",
        description=(
            "Follow every periodic orbit with one impact per period (B_n,a..d, MODEL.md §5) with period "
            "up to T_max as --param goes from --from to --to, by pseudo-arclength continuation through folds. "
            "Events located along the branches: fold, nsfh, grazing, branch-point, period-doubling, "
            "neimark-sacker, extrema-change, ac-coalescence."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--param", default="gamma", metavar="NAME",
                   help=f"parameter varied: {', '.join(BRANCH_PARAMETERS)} (default gamma)")
    p.add_argument("--from", dest="start", default=None, metavar="A",
                   help="start of the range (default: -0.6 for gamma; see the documentation for the others)")
    p.add_argument("--to", dest="stop", default=None, metavar="B", help="end of the range (default: 0.25 for gamma)")
    p.add_argument("--t-max", dest="t_max", default="12", metavar="T", help="largest period followed (default 12)")
    p.add_argument("--rdot-max", dest="rdot_max", default="5", metavar="V",
                   help="branches are followed while |rdot-| <= V (default 5)")
    p.add_argument("--seeds", default="41", metavar="N",
                   help="parameter values at which orbits are searched to start branches (default 41)")
    p.add_argument("--json", action="store_true", help="print events and branches as JSON on stdout")
    p.add_argument("--plot", default=None, metavar="FILE.png",
                   help="write rdot- and thetadot- of B1,a..d against the parameter")
    p.set_defaults(func=run)


def _int(name: str, text: str, low: int) -> int:
    try:
        value = int(text)
    except ValueError:
        raise ParameterError(f"--{name} = {text!r} is not an integer; allowed: an integer >= {low}") from None
    if value < low:
        raise ParameterError(f"--{name} = {value} is out of range; allowed: an integer >= {low}")
    return value


def _text(b: OrbitBranches) -> list[str]:
    lines = [f"one-impact orbits along {b.param} in [{b.start:g}, {b.stop:g}] (T <= {b.t_max:g}): "
             f"{', '.join(b.labels) or 'none'}"]
    lines.append(f"{len(b.events)} events:")
    for e in b.events:
        extra = f"  ({e.detail})" if e.detail else ""
        lines.append(f"  {e.type:<16} {b.param} = {e.value:<20.12g} {', '.join(e.orbits):<14} "
                     f"T = {e.T:.8g}, rdot = {e.rdot:.6g}{extra}")
    return lines


def run(args: argparse.Namespace) -> int:
    params, _machine = parameters_from_args(args)
    if args.param not in BRANCH_PARAMETERS:
        raise ParameterError(
            f"--param = {args.param!r} is not a branch parameter; allowed: {', '.join(BRANCH_PARAMETERS)}"
        )
    lo, hi = DEFAULT_RANGES[args.param]
    start = lo if args.start is None else parse_float("from", args.start)
    stop = hi if args.stop is None else parse_float("to", args.stop)
    t_max = parse_float("t-max", args.t_max)
    rdot_max = parse_float("rdot-max", args.rdot_max)
    seeds = _int("seeds", args.seeds, 2)
    if args.plot and Path(args.plot).suffix.lower() not in {".png", ".svg", ".pdf"}:
        raise ParameterError(f"--plot = {args.plot!r} has an unsupported suffix; allowed: .png, .svg, .pdf")
    try:
        branches = orbit_branches(params, args.param, start, stop, t_max=t_max, rdot_max=rdot_max,
                                  n_seeds=seeds)
    except ParameterError as exc:
        raise renamed(exc, {"t_max": "--t-max", "rdot_max": "--rdot-max", "start": "--from", "stop": "--to",
                            "n_seeds": "--seeds"}) from None
    if args.plot:
        import matplotlib.pyplot as plt

        from ..plotting.branches import B1, plot_branch_quantity
        from ..plotting.style import save_figure

        fig, axes = plt.subplots(2, 1, figsize=(7, 8), sharex=True)
        plot_branch_quantity(branches, "rdot", B1, ax=axes[0])
        plot_branch_quantity(branches, "thetadot", B1, ax=axes[1], legend=False)
        for ax in axes:
            ax.set_ylim(max(ax.get_ylim()[0], -rdot_max), min(ax.get_ylim()[1], rdot_max))
        axes[0].set_title(
            ", ".join(f"{n}={getattr(params, n):.4g}" for n in BRANCH_PARAMETERS if n != args.param), fontsize=9
        )
        save_figure(fig, args.plot)
    if args.json:
        print_json(branches.to_dict())
    else:
        for line in _text(branches):
            print(line)
        if args.plot:
            print(f"figure written to {args.plot}")
    return 0
