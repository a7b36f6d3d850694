"""``rotorcontact design-map``: where a real machine levitates safely, in rpm and controller gains."""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ParameterError
from ..model.params import load_machine
from ..model.units import option_quantity, quantity_in
from .options import ignored_keys, json_result, note_paper_model, parse_int, print_json
from .outputs import check_output_folder
from .scale import add_executor_options, executor_kwargs

if TYPE_CHECKING:
    from ..studies.design_map import DesignMap

_UNITS = {"speed": "rpm", "stiffness": "N/m", "damping": "N s/m"}


def register(sub) -> None:
    p = sub.add_parser(
        "design-map",
        description=(
            "Classify each setting of a machine as safe (contact-free whirl only), bistable (contact-free whirl "
            "and a stable impacting orbit or forward rub coexist) or contact-certain (no contact-free whirl). "
            "With --speed alone: a map against speed. With --speed and --stiffness (or --damping): a plane at "
            "the machine's other settings. With --stiffness and --damping: a plane at the machine's speed. "
            "Ranges are A:B with units after B (for example 1000:6000rpm, 2e5:2e6N/m, 0.5:2kN*s/m); "
            "plain numbers are N/m and N s/m, and a speed must carry its unit."
        ),
    )
    p.add_argument("machine_file", nargs="?", default=None, metavar="MACHINE.toml", help="machine file (SI or units)")
    p.add_argument("--machine", default=None, metavar="FILE|reference", help="machine file, or 'reference'")
    p.add_argument("--speed", default=None, metavar="A:Brpm", help="speed range with its unit (1000:6000rpm)")
    p.add_argument("--stiffness", default=None, metavar="A:B[unit]", help="bearing stiffness range (N/m)")
    p.add_argument("--damping", default=None, metavar="A:B[unit]", help="bearing damping range (N s/m)")
    p.add_argument("--n", default="200", metavar="N", help="points along each range (default 200; 60 for planes)")
    p.add_argument(
        "--shock",
        default=None,
        metavar="V",
        help="velocity disturbance for the recovery probability of bistable points, with its unit "
             "(for example 5mm/s or 0.005m/s; a number without a unit is refused)",
    )
    p.add_argument("--out", default=None, metavar="DIR", help="write map.png and map.nc here")
    p.add_argument("--json", action="store_true", help="print the map as JSON on stdout")
    g = add_executor_options(p)
    g.add_argument("--no-progress", dest="progress", action="store_false",
                   help="no progress bar on stderr (shown with --shock, whose recovery probabilities are simulated)")
    p.set_defaults(func=run)


def parse_range(option: str, text: str, unit: str) -> tuple[float, float]:
    """Parse ``A:B[unit]`` into two values in ``unit``; a unit written after B applies to A too."""
    parts = text.split(":")
    if len(parts) != 2 or not parts[0].strip() or not parts[1].strip():
        raise ParameterError(f"--{option} = {text!r} is malformed; expected a range A:B with its unit after B, e.g. "
                             "1000:6000rpm")
    a_text, b_text = parts[0].strip(), parts[1].strip()
    for end in (a_text, b_text):
        head = end.rstrip("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ/* ")
        if end.lower().startswith(("nan", "inf", "-inf", "+inf")) or head.lower() in ("nan", "inf", "-inf", "+inf"):
            raise ParameterError(f"--{option} = {text!r}: {end!r} is not finite; allowed: finite values")
    b = option_quantity(f"--{option}", b_text, unit)
    try:
        float(a_text)
        suffix = b_text.lstrip("0123456789.eE+- ")
        a_text = a_text + suffix
    except ValueError:
        pass
    a = option_quantity(f"--{option}", a_text, unit)
    if not a < b:
        raise ParameterError(f"--{option} = {text!r}: the range must increase (A < B)")
    low, strict = (0.0, option != "damping")
    if a < low or (strict and a == low):
        allowed = "> 0" if strict else ">= 0"
        raise ParameterError(f"--{option} = {text!r}: the range must lie at {allowed} (in {unit})")
    return a, b


def _machine(args: argparse.Namespace):
    if args.machine_file is not None and args.machine is not None:
        raise ParameterError("give the machine either as MACHINE.toml or as --machine, not both")
    source = args.machine_file or args.machine
    if source is None:
        raise ParameterError("no machine given; pass MACHINE.toml or --machine reference")
    return load_machine(source)


#: Largest --shock, in m/s.
MAX_SHOCK = 100.0
#: Largest --n: about half a millisecond per setting; with --shock, each bistable setting also
#: simulates 24 disturbances (about 20 ms), hence the smaller bound.
MAX_POINTS_SHOCK = 2_000


def _count(text: str, shock: bool = False) -> int:
    if shock:
        return parse_int("n", text, 2, MAX_POINTS_SHOCK,
                         why="with --shock every bistable setting runs 24 simulations")
    from ..studies.design_map import MAX_POINTS

    return parse_int("n", text, 2, MAX_POINTS)


def _shock(text: str) -> float:
    """The velocity disturbance of ``--shock`` in m/s; its unit must be written."""
    shock = quantity_in("--shock", text, "m/s", unit_required=True)
    if shock <= 0 or shock > MAX_SHOCK:
        raise ParameterError(
            f"--shock = {text!r} is out of range; allowed: a speed > 0 and at most {MAX_SHOCK:g} m/s, such as 5mm/s "
            "(touchdown disturbances are of mm/s to m/s)"
        )
    return shock


def _check_corners(machine, ranges: dict[str, tuple[float, float]], args: argparse.Namespace) -> None:
    """Refuse, naming the option, a range whose ends give parameters outside the model's range."""
    from dataclasses import replace

    from ..studies.design_map import rpm_to_rad_s

    names = list(ranges)
    for corner in itertools.product(*(ranges[name] for name in names)):
        values = {name: rpm_to_rad_s(v) if name == "speed" else v for name, v in zip(names, corner)}
        try:
            replace(machine, **values).parameters()
        except ParameterError as exc:
            where = ", ".join(f"{v:g} {_UNITS[name]}" for name, v in zip(names, corner))
            options = " and ".join(f"--{name} = {getattr(args, name)!r}" for name in names)
            raise ParameterError(f"{options}: at {where}, {exc}") from None


def build_map(args: argparse.Namespace) -> DesignMap:
    from ..studies.design_map import MAP_AXES, design_map

    machine = _machine(args)
    # the classification is that of the paper's dimensionless model (its equilibria and orbits, MODEL.md §2-5)
    note_paper_model(machine, "design-map", args)
    shock = _shock(args.shock) if args.shock is not None else None
    n = _count(args.n, shock is not None)
    ranges = {
        name: parse_range(name, getattr(args, name), _UNITS[name])
        for name in ("speed", "stiffness", "damping")
        if getattr(args, name) is not None
    }
    _check_corners(machine, ranges, args)
    if frozenset(ranges) not in MAP_AXES:
        raise ParameterError(
            "choose the map: --speed A:B; or --speed with --stiffness or --damping; or --stiffness with --damping"
        )
    progress = bool(getattr(args, "progress", True)) and shock is not None
    return design_map(machine, ranges, n, shock=shock, progress=progress, **executor_kwargs(args))


def _table(dmap: DesignMap) -> str:
    lines = [f"{'speed rpm':>10} {'k N/m':>11} {'c N s/m':>9} {'gamma':>8} {'omega':>8} {'regime':>16}  coexisting"]
    step = max(1, len(dmap.points) // 40)
    for pt in dmap.points[::step]:
        extra = "" if pt.recovery_probability is None else f"  (recovers {pt.recovery_probability:.0%})"
        lines.append(
            f"{pt.speed_rpm:10.1f} {pt.stiffness:11.4g} {pt.damping:9.4g} {pt.gamma:8.4f} {pt.omega:8.4f} "
            f"{pt.regime:>16}  {', '.join(pt.coexisting) or '-'}{extra}"
        )
    if len(dmap.axes) == 1:
        for speed, before, after in dmap.boundaries():
            lines.append(f"boundary near {speed:.1f} rpm: {before} -> {after}")
    lines.append("points: " + ", ".join(f"{r} {c}" for r, c in dmap.outcome_counts().items()))
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    if args.out is not None:
        check_output_folder("--out", args.out)
    dmap = build_map(args)
    if args.out is not None:
        from ..plotting.design import save_design_map

        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        save_design_map(dmap, out / "map.png")
        dmap.to_xarray().to_netcdf(out / "map.nc", engine="scipy")
    if args.json:
        print_json(json_result(dmap.machine.parameters(), dmap.to_dict(), dmap.machine, ignored=ignored_keys(args)))
    else:
        print(_table(dmap))
        if args.out is not None:
            print(f"wrote {Path(args.out) / 'map.png'} and {Path(args.out) / 'map.nc'}", file=sys.stderr)
    return 0
