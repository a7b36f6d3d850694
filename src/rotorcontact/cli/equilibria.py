"""``rotorcontact equilibria``: regular, pseudo- and boundary equilibria, as JSON, text or a figure."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError
from ..model.params import BRANCH_PARAMETERS, Machine
from ..model.si import equilibria_si, parameter_si
from ..model.validation import MAX_EQUILIBRIUM_POINTS
from .options import (
    add_parameter_options,
    ignored_keys,
    json_result,
    parameter_value,
    parameters_from_args,
    parse_float,
    parse_int,
    print_json,
)
from .outputs import check_plot_path

if TYPE_CHECKING:
    from ..analysis.equilibria import Equilibria, EquilibriumBranches

#: --points: the default and the largest.
DEFAULT_POINTS = "401"
MAX_POINTS = MAX_EQUILIBRIUM_POINTS


def register(sub) -> None:
    p = sub.add_parser(
        "equilibria",
        description=(
            "Equilibria of the rotor (MODEL.md §4): the regular equilibrium x_R, the pseudo-equilibria "
            "x_P1 and x_P2 (rub on the stator), and the boundary equilibrium x_B at gamma* with the type "
            "of its bifurcation (non-smooth fold or persistence). With --from/--to, also the events "
            "along a parameter range; with --plot, a figure of r against that parameter."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write r of x_R and x_P against --param")
    p.add_argument(
        "--param",
        default="gamma",
        metavar="NAME",
        help=f"parameter of the branches: {', '.join(BRANCH_PARAMETERS)} (default gamma)",
    )
    p.add_argument("--from", dest="start", default=None, metavar="A", help="start of the parameter range")
    p.add_argument("--to", dest="stop", default=None, metavar="B", help="end of the parameter range")
    p.add_argument("--points", default=None, metavar="N",
                   help=f"grid points bracketing the events (default 401, at most {MAX_POINTS})")
    p.set_defaults(func=run)


def _branches(args: argparse.Namespace, params) -> EquilibriumBranches | None:
    from ..analysis.equilibria import equilibrium_branches

    if args.param not in BRANCH_PARAMETERS:
        raise ParameterError(
            f"--param = {args.param!r} is not a branch parameter; allowed: {', '.join(BRANCH_PARAMETERS)}"
        )
    if args.start is None and args.stop is None:
        if args.plot is not None:
            raise ParameterError("--plot needs a parameter range; give --from A --to B")
        if args.points is not None:
            raise ParameterError(f"--points = {args.points!r} sets the grid of a parameter range; allowed: with "
                                 "--from A --to B")
        return None
    if args.start is None or args.stop is None:
        raise ParameterError("--from and --to go together; give both")
    start = parameter_value("from", params, args.param, parse_float("from", args.start))
    stop = parameter_value("to", params, args.param, parse_float("to", args.stop))
    points = parse_int("points", DEFAULT_POINTS if args.points is None else args.points, 2, MAX_POINTS,
                       why="events are located between grid points, so a finer grid mostly costs time")
    try:
        return equilibrium_branches(params, args.param, start, stop, points)
    except ParameterError as exc:
        raise ParameterError(f"--from/--to: {exc}") from None


def _text(eq: Equilibria, branches: EquilibriumBranches | None, machine: Machine | None = None) -> list[str]:
    def num(x: Any, fmt: str = ".8g") -> str:
        return "-" if x is None else format(x, fmt)

    si = equilibria_si(machine, eq) if machine is not None else None

    lines = []
    reg = eq.regular
    if reg.exists:
        state = "admissible" if reg.admissible else "virtual"
        amplitude = "" if si is None else f" ({num(si['regular']['amplitude_um'], '.5g')} um)"
        lines.append(
            f"x_R : r = {num(reg.r)}{amplitude}, theta = {num(reg.theta)}, {state}, "
            f"{'stable' if reg.stable else 'unstable'}"
        )
    else:
        lines.append(f"x_R : does not exist ({reg.reason})")
    for i, pe in enumerate(eq.pseudo):
        if pe.exists:
            force = "" if si is None else f" ({num(si['pseudo'][i]['normal_force_N'], '.5g')} N)"
            lines.append(
                f"x_{pe.name}: theta = {num(pe.theta)}, N = {num(pe.normal_force)}{force}, "
                f"{'admissible' if pe.admissible else 'virtual'}, {'stable' if pe.stable else 'unstable'}"
            )
        else:
            lines.append(f"x_{pe.name}: does not exist ({pe.reason})")
    b = eq.boundary
    if b.gamma_star is None:
        lines.append(f"x_B : none ({b.reason})")
    else:
        kind = b.kind if b.kind is not None else f"unclassified ({b.reason})"
        partner = f" with x_{b.partner}" if b.partner else ""
        damping = "" if si is None else f" (damping {num(si['boundary']['damping_star_Ns_per_m'], '.5g')} N s/m)"
        lines.append(f"x_B : gamma* = {num(b.gamma_star)}{damping}, theta = {num(b.theta)}, {kind}{partner}")
    if branches is not None:
        lines.append(f"events for {branches.param} in [{branches.values[0]:g}, {branches.values[-1]:g}]:")
        if not branches.events:
            lines.append("  none")
        for e in branches.events:
            extra = f" (meets x_{e.partner})" if e.partner else ""
            lines.append(f"  {e.param} = {e.value:.12g}: {e.branch} {e.kind}, {e.before} -> {e.after}{extra}")
    return lines


def run(args: argparse.Namespace) -> int:
    from ..analysis.equilibria import equilibria

    params, machine = parameters_from_args(args)
    if args.plot is not None:
        check_plot_path(args.plot)
    branches = _branches(args, params)
    eq = equilibria(params)
    if args.plot:
        from ..plotting.equilibria import plot_equilibrium_branches
        from ..plotting.style import save_figure

        fig, ax = plot_equilibrium_branches(branches)
        ax.set_title(
            ", ".join(f"{n}={getattr(params, n):.4g}" for n in BRANCH_PARAMETERS if n != args.param), fontsize=9
        )
        save_figure(fig, args.plot)
    if args.json:
        data = eq.to_dict()
        if machine is not None:
            si = equilibria_si(machine, eq)
            data["regular"].update(si["regular"])
            for row, extra in zip(data["pseudo"], si["pseudo"]):
                row.update(extra)
            data["boundary"].update(si["boundary"])
        if branches is not None:
            events = [e.to_dict() for e in branches.events]
            if machine is not None:
                for row, e in zip(events, branches.events):
                    row.update(parameter_si(machine, e.param, e.value))
            data["branches"] = {
                "param": branches.param,
                "from": float(branches.values[0]),
                "to": float(branches.values[-1]),
                "events": events,
            }
        print_json(json_result(params, data, machine, ignored=ignored_keys(args)))
    else:
        for line in _text(eq, branches, machine):
            print(line)
        if args.plot:
            print(f"figure written to {args.plot}")
    return 0
