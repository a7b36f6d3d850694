"""``rotorcontact basins``: basins of attraction on a grid of initial states, to NetCDF."""

from __future__ import annotations

import argparse
import time

from ..studies.grids import GRID_SYNTAX
from .options import (
    add_parameter_options,
    ignored_keys,
    json_result,
    parameters_from_args,
    parse_float,
    print_json,
)
from .outputs import check_output_file, check_plot_path, note_reuse
from .scale import add_scale_options, backend_summary, batch_settings, check_study_size, scale_kwargs

DESCRIPTION = f"""\
Basins of attraction: every initial state of a grid is simulated through a
transient and a recorded window, and the attractor reached is classified as
no-contact (the contact-free whirl x_R), a named one-impact orbit (B1,d, ...,
matched to the fixed points of the impact map), one-impact (unmatched),
multi-impact (p >= 2 impacts per period), forward-rub (continuous contact
sliding forward), backward-whirl (rolling round the stator), mixed (impacts and
contact), irregular, undetermined or failed. (forward-rub and backward-whirl were
formerly named rub and rolling.)
The image and the fraction of each class go to a NetCDF file; each finished
chunk is written to FILE.nc.chunks/ so that an interrupted run continues.

{GRID_SYNTAX}

examples:
  rotorcontact basins --gamma 0.1 --grid plane:200 --out plane.nc --plot plane.png
  rotorcontact basins --gamma 0.1 --grid "amplitude=0:1.5:300,direction=-pi:pi:300" --out shock.nc
  rotorcontact basins --gamma 0.12 --grid shock:400 --out s.nc --scheduler tcp://10.0.0.1:8786
"""


def register(sub) -> None:
    p = sub.add_parser(
        "basins",
        description=DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_parameter_options(p)
    g = p.add_argument_group("basins")
    g.add_argument("--grid", required=True, metavar="SPEC",
                   help="grid of initial states: x=X0:X1:NX,y=Y0:Y1:NY | amplitude=A0:A1:NA,direction=B0:B1:NB "
                        "| plane:N | shock:N (see above)")
    add_window_options(g)
    add_scale_options(p, default_chunk="2048 grid points; with --n-jobs or --scheduler, fewer, down to 4, so that "
                                       "each worker gets 16 chunks or more", backend=True)
    o = p.add_argument_group("output")
    o.add_argument("--out", required=True, metavar="FILE.nc", help="NetCDF file to write")
    o.add_argument("--plot", default=None, metavar="FILE.png", help="also draw the basin image")
    o.add_argument("--json", action="store_true", help="print the fractions and a summary as JSON")
    p.set_defaults(func=run)


def add_window_options(g) -> None:
    """--transient, --record, --t-transient, --t-record, --settle and --match-tol of a study of attractors."""
    g.add_argument("--transient", default="300", metavar="N", help="largest transient, in events (default 300)")
    g.add_argument("--record", default="50", metavar="N", help="events of the recorded window (default 50)")
    g.add_argument("--t-transient", dest="t_transient", default=None, metavar="T",
                   help="time limit of the transient (default 5 per event)")
    g.add_argument("--t-record", dest="t_record", default=None, metavar="T",
                   help="time limit of the recorded window (default 5 per event)")
    g.add_argument("--settle", default="25", metavar="K",
                   help="transient in segments of K events, ended once the motion repeats or can no longer touch "
                        "the stator (default 25; 0: the whole transient)")
    g.add_argument("--match-tol", dest="match_tol", default="1e-3", metavar="TOL",
                   help="largest difference between a periodic impact and the fixed point it is named after")


def run(args: argparse.Namespace) -> int:
    from ..studies.basins import basins, parse_grid

    params, machine = parameters_from_args(args)
    grid = parse_grid(args.grid, "--grid")
    settings = batch_settings(args, n_keep=1)
    rows, cols = grid.shape
    check_study_size(rows * cols, settings, f"--grid {cols} x {rows}")
    match_tol = parse_float("match-tol", args.match_tol, low=0.0, low_open=True)
    if args.plot is not None:
        check_plot_path(args.plot)
    check_output_file("--out", args.out, (".nc",))
    execution = scale_kwargs(args)
    t0 = time.perf_counter()
    res = basins(params, grid, settings=settings, match_tol=match_tol, out=args.out, machine=machine,
                 **execution)
    elapsed = time.perf_counter() - t0
    note_reuse(res, execution.get("chunk_size"))
    if args.plot is not None:
        from ..plotting.basins import save_basins_figure

        save_basins_figure(res.dataset, args.plot)
    rows, cols = grid.shape
    summary = {
        "out": str(res.path),
        "grid": grid.describe(),
        "kind": grid.kind,
        "shape": [rows, cols],
        "simulated": int(res.dataset["inside"].values.sum()),
        "fractions": res.fractions,
        "impacts": res.impacts_simulated,
        "chunks_computed": res.chunks_computed,
        "chunks_reused": res.chunks_reused,
        **backend_summary(res, execution),
        "seconds": elapsed,
        "plot": args.plot,
    }
    if args.json:
        print_json(json_result(params, summary, machine, ignored=ignored_keys(args)))
    else:
        print(f"wrote {res.path}: {grid.kind} grid {cols} x {rows} ({summary['simulated']} simulated)")
        for name, frac in res.fractions.items():
            print(f"  {name:14s} {100 * frac:6.2f} %")
        print(f"  {res.impacts_simulated} impacts in {elapsed:.1f} s; chunks computed {res.chunks_computed}, "
              f"reused {res.chunks_reused}")
        if args.plot:
            print(f"figure written to {args.plot}")
    return 0
