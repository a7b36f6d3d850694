"""``rotorcontact codim2``: fold, DIB and grazing curves in a plane of two parameters."""

from __future__ import annotations

import argparse
from dataclasses import replace
from typing import TYPE_CHECKING

from ..errors import ParameterError
from ..model.params import BRANCH_PARAMETERS
from .options import (
    MAX_CONTINUATION_PERIOD,
    add_parameter_options,
    ignored_keys,
    json_result,
    parameter_value,
    parameters_from_args,
    parse_float,
    parse_int,
    parse_t_max,
    print_json,
    renamed,
)
from .outputs import check_plot_path

if TYPE_CHECKING:
    from ..continuation.codim2 import Codim2Diagram

#: Largest fold index of --folds, and most curves of --folds and of --grazing: each is a continuation.
MAX_FOLD = 100
MAX_CURVES = 20


def register(sub) -> None:
    p = sub.add_parser(
        "codim2",
        description=(
            "Continue in a plane of two parameters the fold curve of the one-impact orbits (F1 has a double "
            "zero), the boundary-equilibrium (NSFH/DIB) curve |k| = 1 and the grazing curve of a chosen "
            "orbit, and locate their intersections (fold-dib, grazing-dib, fold-grazing)."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--params", default="gamma,omega", metavar="P1,P2",
                   help=f"the plane, two of {', '.join(BRANCH_PARAMETERS)} (default gamma,omega)")
    p.add_argument("--from", dest="start", default=None, metavar="A1,A2",
                   help="lower corner of the box (default: gamma 0, omega 0.6, rho 0.05, mu 0, d 0.5)")
    p.add_argument("--to", dest="stop", default=None, metavar="B1,B2",
                   help="upper corner of the box (default: gamma 0.5, omega 1.25, rho 1, mu 0.5, d 1)")
    p.add_argument("--folds", default="1", metavar="N[,N...]", help="pairs whose fold curves are drawn (default 1)")
    p.add_argument("--grazing", action="append", default=None, metavar="ORBIT",
                   help="orbit whose grazing curve is drawn, e.g. B1,d (default); repeat for more; 'none' for none")
    p.add_argument("--curves", action="append", default=None, metavar="SPEC",
                   help="more curves (repeatable): 'coalescence' (the a-c and b-d coalescence curves of the pair 1), "
                        "'pd:ORBIT', 'ns:ORBIT', 'fold:ORBIT' or 'grazing:ORBIT' (period-doubling, Neimark-Sacker, "
                        "fold or grazing curve of ORBIT, B<n>,<m> or M<p>-<j> at the base parameters; seeded along "
                        "the first parameter)")
    p.add_argument("--t-max", dest="t_max", default="12", metavar="T", help="largest period considered (default 12)")
    p.add_argument("--json", action="store_true", help="print the curves and points as JSON on stdout")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write the diagram with regions R1-R4")
    p.set_defaults(func=run)


def _pair(name: str, text: str) -> tuple[float, float]:
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"--{name} = {text!r} is malformed; expected two numbers A,B (e.g. --{name}=0,0.6)")
    return parse_float(name, parts[0]), parse_float(name, parts[1])


def _plane(text: str) -> tuple[str, str]:
    names = tuple(s.strip() for s in text.split(","))
    if len(names) != 2 or names[0] == names[1] or any(n not in BRANCH_PARAMETERS for n in names):
        raise ParameterError(
            f"--params = {text!r} is invalid; allowed: two different names of {', '.join(BRANCH_PARAMETERS)}, "
            "e.g. gamma,omega"
        )
    return names  # type: ignore[return-value]


def _folds(text: str) -> tuple[int, ...]:
    out = []
    for part in text.split(","):
        try:
            out.append(parse_int("folds", part, 1, MAX_FOLD))
        except ParameterError:
            raise ParameterError(
                f"--folds = {text!r} is invalid ({part!r}); allowed: integers from 1 to {MAX_FOLD}, e.g. 1,2"
            ) from None
    folds = tuple(dict.fromkeys(out))
    if len(folds) > MAX_CURVES:
        raise ParameterError(f"--folds = {text!r} names {len(folds)} fold curves; allowed: at most {MAX_CURVES}")
    return folds


def _text(d: Codim2Diagram) -> list[str]:
    p1, p2 = d.params
    lines = [f"curves in the ({p1}, {p2}) plane, {p1} in [{d.ranges[0][0]:g}, {d.ranges[0][1]:g}], "
             f"{p2} in [{d.ranges[1][0]:g}, {d.ranges[1][1]:g}]:"]
    for name, c in d.curves.items():
        n = sum(len(x) for x in c.pieces)
        lines.append(f"  {name:<14} {len(c.pieces)} piece(s), {n} points")
    lines.append(f"{len(d.points)} intersection point(s):")
    for pt in d.points:
        lines.append(f"  {pt.type:<13} {p1} = {pt.values[0]:.12g}, {p2} = {pt.values[1]:.12g}")
    return lines


def run(args: argparse.Namespace) -> int:
    from ..continuation.codim2 import DEFAULT_RANGES, codim2_diagram
    from ..continuation.codim2_orbits import CURVE_SPECS, extra_curves

    params, machine = parameters_from_args(args)
    plane = _plane(args.params)
    lo = _pair("from", args.start) if args.start is not None else tuple(DEFAULT_RANGES[n][0] for n in plane)
    hi = _pair("to", args.stop) if args.stop is not None else tuple(DEFAULT_RANGES[n][1] for n in plane)
    for option, corner in (("from", lo), ("to", hi)):
        for name, value in zip(plane, corner):
            parameter_value(option, params, name, value)
    ranges = ((lo[0], hi[0]), (lo[1], hi[1]))
    folds = _folds(args.folds)
    grazing = ["B1,d"] if args.grazing is None else [g for g in args.grazing if g.lower() != "none"]
    if len(grazing) > MAX_CURVES:
        raise ParameterError(f"--grazing is given {len(grazing)} times; allowed: at most {MAX_CURVES} orbits")
    t_max = parse_t_max(args.t_max, MAX_CONTINUATION_PERIOD)
    if args.plot is not None:
        check_plot_path(args.plot)
    specs = args.curves or []
    if len(specs) > MAX_CURVES:
        raise ParameterError(f"--curves is given {len(specs)} times; allowed: at most {MAX_CURVES} curves")
    for spec in specs:
        kind, _, label = spec.partition(":")
        if spec != "coalescence" and (kind not in ("pd", "ns", "fold", "grazing") or not label):
            raise ParameterError(f"--curves = {spec!r} is invalid; allowed: {', '.join(CURVE_SPECS)}")
    try:
        diagram = codim2_diagram(params, plane, ranges, folds=folds, grazing=grazing, t_max=t_max)
        if specs:
            more = extra_curves(params, plane, ranges, specs, t_max=t_max)
            diagram = replace(diagram, curves={**diagram.curves, **more})
    except ParameterError as exc:
        raise renamed(exc, {"t_max": "--t-max"}) from None
    if args.plot:
        from ..plotting.codim2 import plot_codim2
        from ..plotting.style import save_figure

        fig, _ = plot_codim2(params, diagram=diagram, t_max=t_max)
        save_figure(fig, args.plot)
    if args.json:
        print_json(json_result(params, diagram.to_dict(), machine, ignored=ignored_keys(args)))
    else:
        for line in _text(diagram):
            print(line)
        if args.plot:
            print(f"figure written to {args.plot}")
    return 0
