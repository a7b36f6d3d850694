"""``rotorcontact branches``: branches of one-impact orbits against a parameter, with their events."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Any

from ..continuation.limits import MAX_DOUBLINGS
from ..errors import ParameterError
from ..model.params import BRANCH_PARAMETERS, Machine
from ..model.si import parameter_si, rate_scale, scaled_list, times_si, velocity_scale
from .options import (
    MAX_CONTINUATION_PERIOD,
    add_parameter_options,
    ignored_keys,
    json_result,
    parameters_from_args,
    parse_float,
    parse_int,
    parse_section_grid,
    parse_t_max,
    print_json,
    renamed,
)
from .outputs import check_plot_path

if TYPE_CHECKING:
    from ..continuation.branches import OrbitBranches
    from ..continuation.multi_impact_families import MultiImpactBranches

#: Largest --rdot-max: impact velocities of the model are of order one (clearances per unit time).
MAX_RDOT = 1e3

def register(sub) -> None:
    p = sub.add_parser(
        "branches",
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
    p.add_argument("--seeds", default=None, metavar="N",
                   help="parameter values at which orbits are searched to start branches (default: as dense as "
                        "41 over the default range, at least 41, at most 2000)")
    p.add_argument("--impacts", default=None, metavar="P",
                   help="follow the orbits with P impacts per period found at the base parameters (default: the "
                        "one-impact orbits B_n,m); P >= 2 seeds come from long simulations and a grid of impact "
                        "states, and the base value of --param must lie in the range")
    p.add_argument("--doublings", default="0", metavar="K",
                   help="follow the period-doubled branch born at each period doubling, K levels deep (default 0)")
    p.add_argument("--grid", default=None, metavar="NT,NR,ND",
                   help="grid of impact states (theta, rdot-, thetadot-) from which Newton's method seeds the "
                        "branches of --impacts P >= 2 (default 12,4,4)")
    p.add_argument("--json", action="store_true", help="print events and branches as JSON on stdout")
    p.add_argument("--plot", default=None, metavar="FILE.png",
                   help="write rdot- and thetadot- of B1,a..d against the parameter")
    p.set_defaults(func=run)


def _check_reach(args: argparse.Namespace, params, start: float, stop: float, t_max: float) -> None:
    """Refuse, naming the option that sets it, a range end where periods up to t_max cannot be computed.

    The flight grows or decays like e^{±growth T} (`rotorcontact.maps.impact_map.period_limit`); its rate is largest at
    an end of the range (it increases with |gamma| and decreases with omega).
    """
    from ..maps.impact_map import MAX_GROWTH, flight_growth, period_limit

    for option, given, value in (("to", args.stop, stop), ("from", args.start, start)):
        try:
            at = params.replace(**{args.param: value})
        except ParameterError as exc:
            raise ParameterError(f"--{option} = {value!r} is not a valid {args.param}: {exc}") from None
        limit = period_limit(at)
        if t_max <= limit:
            continue
        fix = f"a smaller --t-max (at most {limit:.6g} there)"
        if given is None:  # the default range end: only --t-max was given
            raise ParameterError(f"--t-max = {t_max:g} is too large at {args.param} = {value:g}, the default "
                                 f"--{option}; allowed: --t-max <= {limit:.6g}, or another --{option}")
        raise ParameterError(
            f"--{option} = {value:g} is out of reach: at {args.param} = {value:g} the free flight grows or decays "
            f"like e^{{±{flight_growth(at):.3g} T}}, too fast to follow periods up to --t-max = {t_max:g}; allowed: "
            f"a range where --t-max <= {MAX_GROWTH:g} / (|gamma| / 2 + sqrt(max(gamma^2 / 4 - omega^2, 0))), or {fix}"
        )


def _event_si(machine: Machine, param: str, value: float, T: float, rdot: float) -> dict[str, Any]:
    """SI values of an event: the parameter's SI value, the period and the impact velocity."""
    return {**parameter_si(machine, param, value), **times_si(machine, T=T),
            "rdot_m_per_s": scaled_list([rdot], velocity_scale(machine))[0]}


def _branches_dict(b: OrbitBranches, machine: Machine | None) -> dict[str, Any]:
    """The ``branches --json`` object; with a machine, SI values beside the dimensionless ones."""
    data = b.to_dict()
    if machine is None:
        return data
    for row, e in zip(data["events"], b.events):
        row.update(_event_si(machine, b.param, e.value, e.T, e.rdot))
    for arrays in data["branches"].values():
        rows = [parameter_si(machine, b.param, v) for v in arrays[b.param]]  # {} for mu, d
        for key in parameter_si(machine, b.param, 0.0):
            arrays[key] = [row[key] for row in rows]
        arrays["T_s"] = scaled_list(arrays["T"], machine.time_scale)
        arrays["rdot_m_per_s"] = scaled_list(arrays["rdot"], velocity_scale(machine))
        arrays["thetadot_rad_per_s"] = scaled_list(arrays["thetadot"], rate_scale(machine))
    return data


def _text(b: OrbitBranches, machine: Machine | None = None) -> list[str]:
    lines = [f"one-impact orbits along {b.param} in [{b.start:g}, {b.stop:g}] (T <= {b.t_max:g}): "
             f"{', '.join(b.labels) or 'none'}"]
    lines.append(f"{len(b.events)} events:")
    for e in b.events:
        extra = f"  ({e.detail})" if e.detail else ""
        si = ""
        if machine is not None:
            v = _event_si(machine, b.param, e.value, e.T, e.rdot)
            units = {"damping_Ns_per_m": "N s/m", "stiffness_N_per_m": "N/m", "eccentricity_m": "m",
                     "rotor_radius_m": "m"}
            si = "".join(f"{v[k]:.6g} {u}, " for k, u in units.items() if k in v)
            si = f"  [{si}T = {1e3 * v['T_s']:.6g} ms, rdot = {v['rdot_m_per_s']:.4g} m/s]"
        lines.append(f"  {e.kind:<16} {b.param} = {e.value:<20.12g} {', '.join(e.orbits):<14} "
                     f"T = {e.T:.8g}, rdot = {e.rdot:.6g}{extra}{si}")
    return lines


def _family_text(f: MultiImpactBranches) -> list[str]:
    lines = [f"orbits with {f.impacts} impact(s) per period along {f.param} in [{f.start:g}, {f.stop:g}]"
             + (" and their period doublings" if any(f.depth) else "") + f": {', '.join(f.labels) or 'none'}"]
    for b in f.branches:
        if b.orbits:
            lines.append(f"  {b.orbits[0].label:<16} {b.orbits[0].impacts} impacts, {f.param} in "
                         f"[{min(b.values):.10g}, {max(b.values):.10g}], ends: {b.status}")
    lines.append(f"{len(f.events)} events:")
    for e in f.events:
        extra = f"  ({e.detail})" if e.detail else ""
        period = "" if e.T is None else f"period = {e.T:.8g}"
        lines.append(f"  {e.kind:<16} {f.param} = {e.value:<20.12g} {', '.join(e.orbits):<22} {period}{extra}")
    return lines


def _run_impacts(args: argparse.Namespace, params, machine, start: float, stop: float, p: int, doublings: int,
                 one: OrbitBranches | None) -> int:
    """--impacts P (P >= 2), or the period-doubled branches of the one-impact ones (``one``)."""
    from ..continuation.multi_impact_families import multi_impact_branches

    grid = parse_section_grid(args.grid)
    names = {"start": "--from", "stop": "--to", "doublings": "--doublings", "impacts": "--impacts"}
    try:
        if one is None:
            fam = multi_impact_branches(params, p, args.param, start, stop, doublings=doublings, grid=grid)
        else:
            fam = multi_impact_branches(params.replace(**{args.param: start}), 1, args.param, start, stop,
                                        doublings=doublings, one_impact_events=one.events)
    except ParameterError as exc:
        raise renamed(exc, names) from None
    if one is None:
        data = fam.to_dict()
        lines = _family_text(fam)
    else:
        data = _branches_dict(one, machine)
        for row in data["events"]:
            row["impacts"] = 1
        for arrays in data["branches"].values():
            arrays["impacts"] = 1
        more = fam.to_dict()
        data["events"] = sorted(data["events"] + more["events"], key=lambda row: row["value"])
        data["branches"].update(more["branches"])
        data["impacts"] = 1
        lines = _text(one, machine) + (_family_text(fam)[:-1 - len(fam.events)] if fam.branches else [])
        if fam.events:
            lines.append(f"{len(fam.events)} events of the period-doubled branches:")
            lines.extend(_family_text(fam)[-len(fam.events):])
    if args.json:
        print_json(json_result(params, data, machine, ignored=ignored_keys(args)))
    else:
        for line in lines:
            print(line)
    return 0


def param_range(args: argparse.Namespace) -> tuple[float, float]:
    """``--from``, ``--to`` of ``--param`` (its default range where not given), after checking ``--param``."""
    if args.param not in BRANCH_PARAMETERS:
        raise ParameterError(
            f"--param = {args.param!r} is not a branch parameter; allowed: {', '.join(BRANCH_PARAMETERS)}"
        )
    from ..continuation.branches import DEFAULT_RANGES

    lo, hi = DEFAULT_RANGES[args.param]
    start = lo if args.start is None else parse_float("from", args.start)
    stop = hi if args.stop is None else parse_float("to", args.stop)
    return start, stop


def run(args: argparse.Namespace) -> int:
    from ..continuation.branches import MAX_SEEDS, orbit_branches
    from ..simulation.motion import MAX_PERIOD_IMPACTS

    params, machine = parameters_from_args(args)
    start, stop = param_range(args)
    t_max = parse_t_max(args.t_max, MAX_CONTINUATION_PERIOD)
    rdot_max = parse_float("rdot-max", args.rdot_max, low=0.0, high=MAX_RDOT, low_open=True,
                           why="impact velocities of the model are of order one")
    seeds = None if args.seeds is None else parse_int("seeds", args.seeds, 2, MAX_SEEDS,
                                                      why="each seed value is a search for orbits")
    p = None if args.impacts is None else parse_int(
        "impacts", args.impacts, 1, MAX_PERIOD_IMPACTS, why="the longest period, in impacts, that is followed")
    doublings = parse_int("doublings", args.doublings, 0, MAX_DOUBLINGS,
                          why="each level doubles the impacts per period")
    if args.grid is not None and (p is None or p < 2):
        raise ParameterError(f"--grid = {args.grid!r} seeds the branches of --impacts P >= 2 only; allowed: with "
                             "--impacts P >= 2")
    if p is not None and p >= 2:
        if args.plot is not None:
            raise ParameterError("--plot draws one-impact branches; allowed: --plot without --impacts P >= 2")
        return _run_impacts(args, params, machine, start, stop, p, doublings, None)
    _check_reach(args, params, start, stop, t_max)
    if args.plot is not None:
        check_plot_path(args.plot)
    try:
        branches = orbit_branches(params, args.param, start, stop, t_max=t_max, rdot_max=rdot_max,
                                  n_seeds=seeds)
    except ParameterError as exc:
        raise renamed(exc, {"t_max": "--t-max", "rdot_max": "--rdot-max", "start": "--from", "stop": "--to",
                            "n_seeds": "--seeds"}) from None
    if args.plot:
        from ..plotting.branches import plot_velocities
        from ..plotting.style import save_figure

        fig, _ = plot_velocities(branches, rdot_max=rdot_max)
        save_figure(fig, args.plot)
    if p is not None or doublings:
        return _run_impacts(args, params, machine, start, stop, 1, doublings, branches)
    if args.json:
        print_json(json_result(params, _branches_dict(branches, machine), machine, ignored=ignored_keys(args)))
    else:
        for line in _text(branches, machine):
            print(line)
        if args.plot:
            print(f"figure written to {args.plot}")
    return 0
