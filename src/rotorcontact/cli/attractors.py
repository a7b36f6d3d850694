"""``rotorcontact attractors``: the attractors and their basins followed across a parameter, to NetCDF."""

from __future__ import annotations

import argparse
import math
import time

from ..model.si import rate_scale, scaled_each
from ..studies.grids import GRID_SYNTAX
from .basins import add_window_options
from .options import (
    add_parameter_options,
    ignored_keys,
    json_result,
    parameter_values,
    parameters_from_args,
    parse_float,
    print_json,
)
from .outputs import check_output_file, check_plot_path, note_reuse
from .scale import add_scale_options, backend_summary, batch_settings, check_study_size, scale_kwargs

#: Largest --n (values of the parameter).
MAX_VALUES = 10_000
#: Largest --t-lyapunov: tangent propagation through contact costs about 3 ms per unit of time.
MAX_T_LYAPUNOV = 1e4

DESCRIPTION = f"""\
Attractors against a parameter: at each value the initial states of a grid (as
for `basins`) are simulated through a transient and a window, the attractor each
reaches is classified as `basins` does, and the attractors are given identities
that hold along the parameter: x_R (contact-free whirl), the labels of the
one-impact orbits (B1,d, ...), P1 and P2 (forward rub on a pseudo-equilibrium),
p-impact orbits, backward-whirl, mixed, irregular. For each attractor and value:
its basin fraction with a 95% Wilson confidence interval, its largest Lyapunov
exponent (from the end state of the first point that reached it) with an error
estimate, and a label periodic / quasi-periodic / chaotic / contact. Where each
attractor appears and disappears is reported.

--param is a model parameter (gamma, omega, rho, mu, d, phi, r_ratio), or with
--machine a machine quantity (speed, stiffness, damping, mass, eccentricity,
clearance, rotor_radius, unbalance_phase, friction, restitution) whose --from and
--to may carry units (3000rpm, 1.2MN/m); bare numbers are SI.

{GRID_SYNTAX}

examples:
  rotorcontact attractors --param gamma --from 0.06 --to 0.22 --n 33 --grid plane:30 --out a.nc --plot a.png
  rotorcontact attractors --machine reference --param speed --from 3000rpm --to 6000rpm --n 20 \\
      --grid plane:20 --out s.nc --json
"""


def register(sub) -> None:
    p = sub.add_parser(
        "attractors",
        description=DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_parameter_options(p)
    g = p.add_argument_group("attractors")
    g.add_argument("--param", required=True, metavar="NAME", help="model parameter, or machine quantity with --machine")
    g.add_argument("--from", dest="start_value", required=True, metavar="A", help="first value (units allowed)")
    g.add_argument("--to", dest="stop_value", required=True, metavar="B", help="last value (units allowed)")
    g.add_argument("--n", dest="n_values", required=True, metavar="N", help="number of values (A and B included)")
    g.add_argument("--grid", required=True, metavar="SPEC", help="grid of initial states, as for basins (see above)")
    add_window_options(g)
    g.add_argument("--t-lyapunov", dest="t_lyapunov", default="400", metavar="T",
                   help=f"length of the Lyapunov run from each attractor (default 400, at most {MAX_T_LYAPUNOV:g})")
    g.add_argument("--no-lyapunov", dest="lyapunov", action="store_false",
                   help="do not compute the largest exponents (labels of irregular motion are then undetermined)")
    add_scale_options(p, default_chunk="2048 simulations", backend=True)
    o = p.add_argument_group("output")
    o.add_argument("--out", required=True, metavar="FILE.nc", help="NetCDF file to write")
    o.add_argument("--plot", default=None, metavar="FILE.png", help="also draw fractions and exponents")
    o.add_argument("--json", action="store_true", help="print the attractors and a summary as JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..studies.attractors import attractors
    from ..studies.basins import parse_grid
    from ..studies.design_map import rad_s_to_rpm
    from ..studies.parameter_path import machine_at

    params, machine = parameters_from_args(args)
    unit, values = parameter_values(args, params, machine, MAX_VALUES, why="split a longer range")
    n_values = values.size
    grid = parse_grid(args.grid, "--grid")
    settings = batch_settings(args, n_keep=1)
    rows, cols = grid.shape
    check_study_size(n_values * rows * cols, settings, f"--n {n_values} x --grid {cols} x {rows}")
    match_tol = parse_float("match-tol", args.match_tol, low=0.0, high=math.pi, low_open=True,
                            why="a rubbing point is matched by its angle")
    t_lyapunov = parse_float("t-lyapunov", args.t_lyapunov, low=0.0, high=MAX_T_LYAPUNOV, low_open=True,
                             why="the tangent propagation through contact would take minutes per attractor")
    if args.plot is not None:
        check_plot_path(args.plot)
    check_output_file("--out", args.out, (".nc",))
    execution = scale_kwargs(args)
    t0 = time.perf_counter()
    res = attractors(params, args.param, values, grid, settings=settings, match_tol=match_tol,
                     lyapunov=args.lyapunov, t_lyapunov=t_lyapunov, out=args.out, machine=machine, **execution)
    elapsed = time.perf_counter() - t0
    note_reuse(res, execution.get("chunk_size"))
    if args.plot is not None:
        from ..plotting.attractors import save_attractors_figure

        save_attractors_figure(res.dataset, args.plot)
    items = [a.to_dict() for a in res.attractors]
    if machine is not None:
        # the time scale is that of each value: 1 / Omega changes along a path in the speed
        rates = [rate_scale(machine_at(machine, args.param, v)) for v in res.values]
        for item in items:
            item["exponent_per_s"] = scaled_each(item["exponent"], rates)
    summary = {
        "out": str(res.path),
        "param": args.param,
        "unit": unit,
        "values": [float(v) for v in res.values],
        "grid": grid.describe(),
        "simulated_per_value": int(res.dataset.attrs["simulated_per_value"]),
        "confidence": float(res.dataset.attrs["confidence"]),
        "attractors": items,
        "impacts": res.impacts_simulated,
        "chunks_computed": res.chunks_computed,
        "chunks_reused": res.chunks_reused,
        **backend_summary(res, execution),
        "seconds": elapsed,
        "plot": args.plot,
    }
    if args.param == "speed" and machine is not None:
        summary["values_rpm"] = [float(v) for v in rad_s_to_rpm(res.values)]
    if args.json:
        print_json(json_result(params, summary, machine, ignored=ignored_keys(args)))
        return 0
    span = f"{values[0]:.6g} to {values[-1]:.6g}" + ("" if unit == "1" else f" {unit}")
    print(f"wrote {res.path}: {len(res.attractors)} attractors over {args.param} from {span} ({n_values} values, "
          f"{summary['simulated_per_value']} initial states each)")
    for att in res.attractors:
        born = "from the start" if att.appears is None else f"appears at {att.appears:.6g}"
        dies = "to the end" if att.disappears is None else f"disappears at {att.disappears:.6g}"
        top = float(np.nanmax(att.fraction))
        lam = att.exponent[np.isfinite(att.exponent)]
        lam_txt = f"largest exponent {lam.min():+.3g} .. {lam.max():+.3g}" if lam.size else "no exponent"
        print(f"  {att.name:16s} {att.label:15s} {born}, {dies}; fraction up to {100 * top:.3g} %; {lam_txt}")
    rate = res.impacts_simulated / elapsed if elapsed > 0 else math.nan
    print(f"  {res.impacts_simulated} impacts in {elapsed:.1f} s ({rate:.0f} impacts/s); chunks computed "
          f"{res.chunks_computed}, reused {res.chunks_reused}")
    if args.plot:
        print(f"figure written to {args.plot}")
    return 0
