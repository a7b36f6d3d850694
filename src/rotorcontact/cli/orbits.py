"""``rotorcontact orbits``: periodic impacting orbits, as JSON or a table.

Without ``--impacts`` (or with ``--impacts 1``) it lists the orbits with one
impact per period (MODEL.md §5). With ``--impacts p`` (p >= 2) it lists the
orbits with p impacts per period of `rotorcontact.continuation.multi_impact_branches.multi_impact_orbits`:
each as {"label", "impacts", "period", "points", "multipliers", "stable",
"plausible"}, the points as {"theta", "rdot", "thetadot", "dt"} with dt the
time to the next impact.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..errors import ParameterError
from ..model.params import Machine
from ..model.si import orbit_si, rate_scale, times_si, velocity_scale
from .options import (
    MAX_PERIOD,
    add_parameter_options,
    ignored_keys,
    json_result,
    parameters_from_args,
    parse_int,
    parse_section_grid,
    parse_t_max,
    print_json,
    renamed,
)

if TYPE_CHECKING:
    from ..maps.impact_map import ImpactOrbit
    from ..maps.multi_impact import MultiImpactOrbit


def register(sub) -> None:
    p = sub.add_parser(
        "orbits",
        description=(
            "Every fixed point of the impact map with one impact per period and period T in (0, T_max] "
            "(MODEL.md §5): the orbits B_n,a..B_n,d from the zeros of F1, with admissibility, physical "
            "plausibility, the interior extrema of r, the multipliers and stability. With --impacts p >= 2: "
            "orbits with p impacts per period (fixed points of P_I^p), found from long simulations and, for "
            "p = 2, on the period-doubled branches of the one-impact orbits (labels B_n,m/PD, others M<p>-<j>)."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--t-max", dest="t_max", default="12", metavar="T", help="largest period searched (default 12)")
    p.add_argument(
        "--impacts",
        default="1",
        metavar="P",
        help="impacts per period (default 1: the one-impact orbits B_n,m)",
    )
    p.add_argument("--grid", default=None, metavar="NT,NR,ND",
                   help="with --impacts P >= 2, also the orbits that Newton's method finds from this grid of impact "
                        "states (theta, rdot-, thetadot-), unstable ones included (for example 12,4,4)")
    p.add_argument("--json", action="store_true", help="print the orbits as JSON on stdout")
    p.set_defaults(func=run)


def _num(x, fmt: str = ".8g") -> str:
    return "-" if x is None else format(x, fmt)


def _table(orbits: tuple[ImpactOrbit, ...], machine: Machine | None = None) -> list[str]:
    if not orbits:
        return ["no one-impact periodic orbit with T in (0, T_max]"]
    si_head = f" {'T ms':>10} {'impulse N s':>12} {'power W':>10}" if machine is not None else ""
    head = (
        f"{'orbit':<6} {'T':>14} {'theta':>14} {'rdot-':>14} {'thetadot-':>14} "
        f"{'state':<10} {'plausible':<9} {'friction':<9} {'r_max':>10} {'extrema':>7} {'max|mult|':>10} "
        f"{'stability':<9}{si_head}"
    ).rstrip()
    lines = [head, "-" * len(head)]
    for o in orbits:
        mult = "-" if o.multipliers is None else format(max(abs(m) for m in o.multipliers), ".6g")
        stability = "-" if o.stable is None else ("stable" if o.stable else "unstable")
        si = ""
        if machine is not None:
            v = orbit_si(machine, o)
            si = f" {1e3 * v['T_s']:>10.5g} {_num(v['normal_impulse_Ns'], '.5g'):>12} {_num(v['friction_power_W'], '.5g'):>10}"
        lines.append(
            f"{o.label:<6} {_num(o.T):>14} {_num(o.theta):>14} {_num(o.rdot):>14} {_num(o.thetadot):>14} "
            f"{'admissible' if o.admissible else 'virtual':<10} {'yes' if o.plausible else 'no':<9} "
            f"{'reverses' if o.friction_reverses else '-':<9} "
            f"{_num(o.r_max_interior, '.7g'):>10} {o.interior_extrema:>7} {mult:>10} {stability:<9}{si}".rstrip()
        )
    reversed_ = [o.label for o in orbits if o.friction_reverses]
    if reversed_:
        lines.append(
            f"friction reverses at the impact of {', '.join(reversed_)}: v_rel = r_ratio + 1 + thetadot- is at most "
            "mu (1 + d) rdot-, so the law of MODEL.md §5 would reverse the slip, which the simulator's friction "
            "never does; not an orbit of the simulator (not plausible, stability not claimed)"
        )
    return lines


def _impacts(text: str) -> int:
    from ..simulation.motion import MAX_PERIOD_IMPACTS

    return parse_int("impacts", text, 1, MAX_PERIOD_IMPACTS,
                     why="the longest period, in impacts, that the simulations recognise")


def _multi_table(orbits: tuple[MultiImpactOrbit, ...], p: int, machine: Machine | None = None,
                 grid: bool = False) -> list[str]:
    if not orbits:
        doubling = " or at a period doubling of a one-impact orbit" if p == 2 else ""
        how = f"from the grid of impact states, by simulation{doubling}" if grid else \
            (f"by simulation (stable orbits reached from its starts){doubling}; --grid NT,NR,ND also searches by "
             "Newton's method from a grid of impact states, unstable orbits included")
        return [f"no periodic orbit with {p} impacts per period found {how}"]
    lines = []
    for o in orbits:
        mult = format(max(abs(m) for m in o.multipliers), ".6g")
        period = f"period {o.period:.10g}"
        if machine is not None:
            period += f" ({1e3 * o.period * machine.time_scale:.6g} ms)"
        lines.append(
            f"{o.label}: {o.impacts} impacts, {period}, max|mult| {mult}, "
            f"{'stable' if o.stable else 'unstable'}, {'plausible' if o.plausible else 'not plausible'}"
        )
        head = f"  {'theta':>14} {'rdot-':>14} {'thetadot-':>14} {'dt':>14}"
        lines.append(head)
        for q in o.points:
            lines.append(f"  {q.theta:>14.8g} {q.rdot:>14.8g} {q.thetadot:>14.8g} {q.dt:>14.8g}")
    return lines


def _multi_dict(o: MultiImpactOrbit, machine: Machine | None) -> dict:
    out = o.to_dict()
    if machine is not None:
        out.update(times_si(machine, period=o.period))
        for row, q in zip(out["points"], o.points):
            row.update(times_si(machine, dt=q.dt))
            row["rdot_m_per_s"] = q.rdot * velocity_scale(machine)
            row["thetadot_rad_per_s"] = q.thetadot * rate_scale(machine)
    return out


def _orbit_dict(o: ImpactOrbit, machine: Machine | None) -> dict:
    out = o.to_dict()
    if machine is not None:
        out.update(orbit_si(machine, o))
    return out


def _run_multi(args: argparse.Namespace, params, machine, t_max: float, p: int) -> int:
    from ..continuation.multi_impact_branches import multi_impact_orbits

    grid = None if args.grid is None else parse_section_grid(args.grid)
    orbits = multi_impact_orbits(params, p, t_max=t_max, grid=grid)
    if args.json:
        print_json(json_result(params, {"orbits": [_multi_dict(o, machine) for o in orbits]}, machine,
                ignored=ignored_keys(args)))
    else:
        print(f"periodic orbits with {p} impacts per period at gamma = {params.gamma:g}, "
              f"omega = {params.omega:g}, rho = {params.rho:g}, mu = {params.mu:g}, d = {params.d:g}")
        for line in _multi_table(orbits, p, machine, grid is not None):
            print(line)
    return 0


def run(args: argparse.Namespace) -> int:
    from ..maps.impact_map import one_impact_orbits

    params, machine = parameters_from_args(args)
    t_max = parse_t_max(args.t_max, MAX_PERIOD)
    p = _impacts(args.impacts)
    if args.grid is not None and p < 2:
        raise ParameterError("--grid seeds orbits with several impacts; allowed: with --impacts P >= 2")
    if p >= 2:
        try:
            return _run_multi(args, params, machine, t_max, p)
        except ParameterError as exc:
            raise renamed(exc, {"t_max": "--t-max"}) from None
    try:
        orbits = one_impact_orbits(params, t_max)
    except ParameterError as exc:
        raise renamed(exc, {"t_max": "--t-max"}) from None
    if args.json:
        print_json(json_result(params, {"orbits": [_orbit_dict(o, machine) for o in orbits]}, machine,
                ignored=ignored_keys(args)))
    else:
        print(f"one-impact periodic orbits with T in (0, {t_max:g}] at gamma = {params.gamma:g}, "
              f"omega = {params.omega:g}, rho = {params.rho:g}, mu = {params.mu:g}, d = {params.d:g}, "
              f"r_ratio = {params.r_ratio:g}")
        for line in _table(orbits, machine):
            print(line)
    return 0
