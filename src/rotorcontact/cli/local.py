"""``rotorcontact local``: first-order analysis of the small orbits born at the boundary equilibrium."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ..errors import ParameterError
from ..model.params import Machine
from ..model.si import parameter_si, times_si
from .options import (
    MAX_PERIOD,
    add_parameter_options,
    ignored_keys,
    json_result,
    parameters_from_args,
    parse_t_max,
    print_json,
    renamed,
)

if TYPE_CHECKING:
    from ..analysis.local import LocalAnalysis


def register(sub) -> None:
    p = sub.add_parser(
        "local",
        description=(
            "Local analysis at the boundary equilibrium gamma* (MODEL.md §6, docs/local.md): for each zero "
            "T0 of F1 on (0, T_max] at gamma*, the slopes d(rdot-)/d eps, d(thetadot-)/d eps and "
            "d(theta)/d eps of the small orbit at eps = gamma - gamma* = 0. --gamma is not used "
            "(it is replaced by gamma*)."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--t-max", dest="t_max", default="12", metavar="T", help="largest period searched (default 12)")
    p.add_argument("--json", action="store_true", help="print the slopes as JSON on stdout")
    p.set_defaults(func=run)


def _num(x, fmt: str = ".8g") -> str:
    return "-" if x is None else format(x, fmt)


def _side(side: int) -> str:
    return {1: "gamma > gamma*", -1: "gamma < gamma*"}.get(side, "-")


def _table(gamma_star: float, analysis: LocalAnalysis, machine: Machine | None = None) -> list[str]:
    damping = ""
    if machine is not None:
        damping = f" (damping {parameter_si(machine, 'gamma', gamma_star)['damping_Ns_per_m']:.6g} N s/m)"
    lines = [
        f"gamma* = {gamma_star:.10g}{damping}, impact angle at gamma*: Psi = {analysis.psi:.10g}",
        f"equilibrium shift z1 = {analysis.z1:.6g} (radial {analysis.radial_shift:.6g}, "
        f"tangential {analysis.tangential_shift:.6g}); x_R admissible for {_side(analysis.equilibrium_side)}",
    ]
    if not analysis.orbits:
        return lines + ["no zero of F1 with T in (0, T_max]: no small one-impact orbit"]
    si_head = f" {'T0 ms':>10}" if machine is not None else ""
    head = (f"{'orbit':<6} {'T0':>14}{si_head} {'rdot slope':>14} {'thetadot slope':>15} {'theta slope':>14} "
            f"{'admissible for'}")
    lines += [head, "-" * (len(head) + 8)]
    for o in analysis.orbits:
        si = f" {1e3 * times_si(machine, T=o.T)['T_s']:>10.6g}" if machine is not None else ""
        lines.append(
            f"{o.label:<6} {_num(o.T):>14}{si} {_num(o.rdot_slope):>14} {_num(o.thetadot_slope):>15} "
            f"{_num(o.theta_slope):>14} {_side(o.side)}"
        )
    return lines


def run(args: argparse.Namespace) -> int:
    from ..analysis.equilibria import boundary_gamma
    from ..analysis.local import LinearImpactingSystem, local_analysis

    params, machine = parameters_from_args(args)
    t_max = parse_t_max(args.t_max, MAX_PERIOD)
    system = LinearImpactingSystem.from_parameters(params)
    gamma_star = boundary_gamma(params)
    try:
        analysis = local_analysis(system, t_max)
    except ParameterError as exc:
        raise renamed(exc, {"t_max": "--t-max"}) from None
    if args.json:
        orbits = [o.to_dict() for o in analysis.orbits]
        data: dict[str, Any] = {"gamma_star": gamma_star, "orbits": orbits}
        if machine is not None:
            data.update(damping_star_Ns_per_m=parameter_si(machine, "gamma", gamma_star)["damping_Ns_per_m"])
            for row, o in zip(orbits, analysis.orbits):
                row.update(times_si(machine, T=o.T))
        # the analysis is made at gamma = gamma*, whatever --gamma says
        print_json(json_result(params.replace(gamma=gamma_star), data, machine, ignored=ignored_keys(args)))
    else:
        for line in _table(gamma_star, analysis, machine):
            print(line)
    return 0
