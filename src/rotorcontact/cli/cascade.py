"""``rotorcontact cascade``: period-doubling cascades in a parameter range, with Feigenbaum's ratios."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..continuation.limits import MAX_DOUBLINGS
from ..errors import ParameterError
from ..model.params import BRANCH_PARAMETERS
from .branches import param_range
from .options import (
    MAX_CONTINUATION_PERIOD,
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
    from ..continuation.cascade import Cascade


def register(sub) -> None:
    p = sub.add_parser(
        "cascade",
        description=(
            "Follow each period doubling of the orbits with --impacts P impacts per period (default 1: B_n,m) in "
            "--from..--to: the doubled branch is followed to its own doubling, and so on --depth times. Prints "
            "the doublings of each cascade, the ratios of successive intervals (Feigenbaum's delta) and where it "
            "ends: an accumulation estimate, a grazing or a fold."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--param", default="gamma", metavar="NAME",
                   help=f"parameter varied: {', '.join(BRANCH_PARAMETERS)} (default gamma)")
    p.add_argument("--from", dest="start", default=None, metavar="A", help="start of the range")
    p.add_argument("--to", dest="stop", default=None, metavar="B", help="end of the range")
    p.add_argument("--impacts", default="1", metavar="P",
                   help="impacts per period of the orbits whose doublings start the cascades (default 1); for "
                        "P >= 2 the base value of --param must lie in the range")
    p.add_argument("--depth", default="5", metavar="K", help=f"doublings followed, 1..{MAX_DOUBLINGS} (default 5)")
    p.add_argument("--t-max", dest="t_max", default="12", metavar="T",
                   help="largest period of the one-impact orbits followed (default 12)")
    p.add_argument("--seeds", default=None, metavar="N",
                   help="seed values of the one-impact branches (default: as for branches, as dense as 41 over the "
                        "default range)")
    p.add_argument("--grid", default=None, metavar="NT,NR,ND",
                   help="grid of impact states seeding the orbits of --impacts P >= 2 (default 12,4,4)")
    p.add_argument("--json", action="store_true", help="print the cascades as JSON on stdout")
    p.set_defaults(func=run)


def _text(found: tuple[Cascade, ...], param: str) -> list[str]:
    if not found:
        return ["no period doubling found in the range"]
    lines = []
    for c in found:
        lines.append(f"cascade {' -> '.join((c.points[0].orbits[0],) + c.labels)}:")
        for k, e in enumerate(c.points):
            ratio = ""
            if 1 <= k <= len(c.ratios):
                delta = c.ratios[k - 1]
                ratio = "  delta undefined" if delta is None else f"  delta = {delta:.6g}"
            lines.append(f"  period-doubling {param} = {e.value:.12g}  {e.orbits[0]} ({e.impacts} impacts){ratio}")
        where = "" if c.end_value is None else f" at {param} = {c.end_value:.12g}"
        lines.append(f"  ends: {c.end}{where}")
    return lines


def run(args: argparse.Namespace) -> int:
    from ..continuation.branches import MAX_SEEDS
    from ..continuation.cascade import cascades
    from ..simulation.motion import MAX_PERIOD_IMPACTS

    params, machine = parameters_from_args(args)
    start, stop = param_range(args)
    p = parse_int("impacts", args.impacts, 1, MAX_PERIOD_IMPACTS, why="the longest period, in impacts, followed")
    depth = parse_int("depth", args.depth, 1, MAX_DOUBLINGS, why="each level doubles the impacts per period")
    t_max = parse_t_max(args.t_max, MAX_CONTINUATION_PERIOD)
    seeds = None if args.seeds is None else parse_int("seeds", args.seeds, 2, MAX_SEEDS,
                                                      why="each seed value is a search for orbits")
    grid = parse_section_grid(args.grid)
    try:
        found = cascades(params, args.param, start, stop, impacts=p, depth=depth, t_max=t_max, n_seeds=seeds,
                         grid=grid)
    except ParameterError as exc:
        raise renamed(exc, {"start": "--from", "stop": "--to", "t_max": "--t-max", "n_seeds": "--seeds",
                            "depth": "--depth", "impacts": "--impacts"}) from None
    if args.json:
        print_json(json_result(params, {"param": args.param, "impacts": p,
                                        "cascades": [c.to_dict() for c in found]}, machine, ignored=ignored_keys(args)))
    else:
        for line in _text(found, args.param):
            print(line)
    return 0
