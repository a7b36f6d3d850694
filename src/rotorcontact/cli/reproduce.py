"""``rotorcontact reproduce``: the paper's figures, numbers and an HTML report in one command."""

from __future__ import annotations

import argparse

from .options import (
    PARAM_NAMES,
    add_parameter_options,
    parameters_from_args,
    print_json,
)
from .outputs import check_output_folder


def register(sub) -> None:
    p = sub.add_parser(
        "reproduce",
        description=(
            "Compute from scratch everything behind Figures 2 to 7 of Mora, Budd, Glendinning & Keogh (2015) "
            "and write each figure (PNG and SVG), report.json and a self-contained report.html. By default the "
            "paper's parameters; with parameter options, those instead (the paper column is then left empty). "
            "Progress goes to stderr."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--out", default="reproduction", metavar="DIR", help="output folder (default ./reproduction)")
    p.add_argument("--json", action="store_true", help="also print report.json on stdout")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..report.reproduce import paper_parameters, reproduce

    if args.machine is None and all(getattr(args, name) is None for name in PARAM_NAMES):
        params = paper_parameters()
    else:
        params, _machine = parameters_from_args(args)
    check_output_folder("--out", args.out)
    rep = reproduce(args.out, params, progress=True)
    if args.json:
        print_json(rep.report)
    else:
        print(f"wrote {len(rep.figures)} figures, report.json and report.html to {args.out}")
        for q in rep.quantities:
            paper = "" if q.paper is None else f" (paper {q.paper}{', agrees' if q.agrees else ', differs'})"
            ours = f"{q.ours:.6g}" if isinstance(q.ours, float) else str(q.ours)
            print(f"  {q.label}: {ours}{paper}")
    return 0
