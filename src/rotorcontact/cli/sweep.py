"""``rotorcontact sweep``: a brute-force orbit diagram against one parameter, to NetCDF."""

from __future__ import annotations

import argparse
import time

from ..continuation.limits import MAX_DOUBLINGS
from ..errors import ParameterError
from .options import (
    add_parameter_options,
    ignored_keys,
    json_result,
    parameter_value,
    parameters_from_args,
    parse_complex,
    parse_float,
    parse_int,
    parse_velocity,
    print_json,
    renamed,
)
from .outputs import check_output_file, check_plot_path, note_reuse
from .scale import add_scale_options, backend_summary, batch_settings, check_study_size, scale_kwargs

#: Largest --n: values of the swept parameter (a thousand take seconds at the default transient, a
#: hundred thousand minutes).
MAX_VALUES = 100_000

DESCRIPTION = """\
Brute-force orbit diagram: for each value of one parameter the rotor runs through
a transient, then the impacts of a recorded window are kept (impact angle theta,
rdot and thetadot just before each impact). Sweeping up and down carries the
state from value to value, so coexisting attractors show as hysteresis.

The result is a NetCDF file (xarray Dataset) with the model parameters, the
settings and the units as attributes. While the sweep runs, each finished chunk
of values is written to FILE.nc.chunks/; run the same command again after an
interruption and it continues from there.

examples:
  rotorcontact sweep --param gamma --from 0.08 --to 0.2 --n 200 --out sweep.nc --plot sweep.png
  rotorcontact sweep --param omega --from 0.6 --to 0.9 --n 100 --gamma 0.1 --out w.nc --n-jobs 4
  rotorcontact sweep --param gamma --from 0.085 --to 0.17 --n 100 --start B1,d --out b.nc --scheduler local
"""


def register(sub) -> None:
    p = sub.add_parser(
        "sweep",
        description=DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_parameter_options(p)
    g = p.add_argument_group("sweep")
    g.add_argument("--param", required=True, metavar="NAME",
                   help="parameter to sweep: gamma, omega, rho, mu, d, phi or r_ratio")
    g.add_argument("--from", dest="start_value", required=True, metavar="A", help="first value")
    g.add_argument("--to", dest="stop_value", required=True, metavar="B", help="last value")
    g.add_argument("--n", dest="n_values", required=True, metavar="N", help="number of values (A and B included)")
    g.add_argument("--mode", default="both", choices=("both", "up", "down", "independent"),
                   help="directions with the state carried along (default both), or every value from the start")
    g.add_argument("--start", default=None, metavar="STATE",
                   help="initial state at the first value of each direction: rest (default), equilibrium (x_R), "
                        "or an admissible one-impact orbit such as B1,d")
    g.add_argument("--u0", default=None, metavar="RE,IM",
                   help="explicit initial position (instead of --start, not with it)")
    g.add_argument("--du0", default=None, metavar="RE,IM",
                   help="explicit initial velocity (instead of --start, not with it)")
    g.add_argument("--transient", default="4000", metavar="N",
                   help="events of transient per value (impacts in impacting motion; default 4000)")
    g.add_argument("--record", default="1000", metavar="N", help="events recorded per value (default 1000)")
    g.add_argument("--t-transient", dest="t_transient", default=None, metavar="T",
                   help="time limit of the transient (default 5 per event)")
    g.add_argument("--t-record", dest="t_record", default=None, metavar="T",
                   help="time limit of the recorded window (default 5 per event)")
    g.add_argument("--settle", default="0", metavar="K",
                   help="end the transient early in segments of K events once the motion repeats (default 0: off)")
    add_scale_options(p, default_chunk="20 values (carried), 64 (independent; with --n-jobs or --scheduler, "
                                       "fewer, down to 4, so that each worker gets 16 chunks or more)", backend=True)
    o = p.add_argument_group("output")
    o.add_argument("--out", required=True, metavar="FILE.nc", help="NetCDF file to write")
    o.add_argument("--plot", default=None, metavar="FILE.png", help="also draw the diagram")
    o.add_argument("--section", default=None, choices=("theta", "rdot", "thetadot"),
                   help="section variable of the figure (default theta)")
    o.add_argument("--no-overlay", dest="overlay", action="store_false",
                   help="do not overlay the one-impact orbits (continued branches, or the fixed points at each "
                        "value where the parameter cannot be continued) on the figure")
    o.add_argument("--overlay-impacts", dest="overlay_impacts", default=None, metavar="P",
                   help="also overlay the continued branches of the orbits with P >= 2 impacts per period found at "
                        "the middle of the range (every impact drawn), with --overlay-doublings K their period-"
                        "doubled branches and the doublings of the cascades marked")
    o.add_argument("--overlay-doublings", dest="overlay_doublings", default="0", metavar="K",
                   help="levels of period doubling followed for --overlay-impacts (default 0)")
    o.add_argument("--json", action="store_true", help="print a summary as JSON")
    p.set_defaults(func=run)


def _multi_overlay(args: argparse.Namespace, params, values):
    """The multi-impact branches over the swept range and their cascades (--overlay-impacts), or (None, ())."""
    if args.overlay_impacts is None:
        return None, ()
    from ..continuation.cascade import cascades_of
    from ..continuation.multi_impact_families import multi_impact_branches

    lo, hi = float(min(values)), float(max(values))
    if not lo < hi:
        raise ParameterError("--overlay-impacts needs a range of values; allowed: --n >= 2 with --from < --to")
    base = params.replace(**{args.param: 0.5 * (lo + hi)})
    family = multi_impact_branches(base, args.overlay_impacts, args.param, lo, hi, doublings=args.overlay_doublings)
    return family, cascades_of(family)


def run(args: argparse.Namespace) -> int:
    from ..maps.multi_impact import CONTINUATION_PARAMETERS
    from ..simulation.motion import MAX_PERIOD_IMPACTS
    from ..studies.sweep import MODES, SWEEP_PARAMETERS, sweep, sweep_values

    params, machine = parameters_from_args(args)
    if args.param not in SWEEP_PARAMETERS:
        raise ParameterError(f"--param = {args.param!r} is invalid; allowed: {', '.join(SWEEP_PARAMETERS)}")
    start_value = parameter_value("from", params, args.param, parse_float("from", args.start_value))
    stop_value = parameter_value("to", params, args.param, parse_float("to", args.stop_value))
    n_values = parse_int("n", args.n_values, 1, MAX_VALUES, why="split a longer sweep into ranges")
    try:
        values = sweep_values(start_value, stop_value, n_values)
    except ParameterError as exc:
        raise renamed(exc, {"start": "--from", "stop": "--to", "n": "--n"}) from None
    if args.start is not None and (args.u0 is not None or args.du0 is not None):
        raise ParameterError(f"--start = {args.start!r} and --u0/--du0 both give the initial state; allowed: one "
                             "of them")
    settings = batch_settings(args)
    directions = len(MODES[args.mode])
    check_study_size(n_values * directions, settings, f"--n {n_values} values x {directions} direction(s)")
    u0 = None if args.u0 is None else parse_complex("u0", args.u0)
    du0 = None if args.du0 is None else parse_velocity("du0", args.du0)
    if args.plot is not None:
        check_plot_path(args.plot)
    else:
        for given, option in ((args.section is not None, "--section"), (not args.overlay, "--no-overlay")):
            if given:
                raise ParameterError(f"{option} sets the figure; allowed: with --plot FILE.png")
    if args.overlay_impacts is not None:
        if args.plot is None:
            raise ParameterError("--overlay-impacts draws on the figure; allowed: with --plot FILE.png")
        if args.param not in CONTINUATION_PARAMETERS:
            raise ParameterError(f"--overlay-impacts follows orbits in {', '.join(CONTINUATION_PARAMETERS)}; "
                                 f"allowed: one of them as --param")
        args.overlay_impacts = parse_int("overlay-impacts", args.overlay_impacts, 2, MAX_PERIOD_IMPACTS,
                                         why="the longest period, in impacts, that is followed")
    args.overlay_doublings = parse_int("overlay-doublings", args.overlay_doublings, 0, MAX_DOUBLINGS,
                                       why="each level doubles the impacts per period")
    if args.overlay_doublings and args.overlay_impacts is None:
        raise ParameterError("--overlay-doublings follows the period doublings of the --overlay-impacts family; "
                             "allowed: with --overlay-impacts P")
    check_output_file("--out", args.out, (".nc",))
    execution = scale_kwargs(args)
    overlay_kind = None
    if args.plot is not None:
        # the figure's orbits first: what cannot be computed there is refused before the sweep runs
        from ..studies.sweep import overlay_for

        overlay, overlay_kind = overlay_for(params, args.param, values) if args.overlay else (None, None)
        family, found = _multi_overlay(args, params, values)
    t0 = time.perf_counter()
    res = sweep(params, args.param, values, mode=args.mode, start=args.start, u0=u0, du0=du0, settings=settings,
                out=args.out, machine=machine, **execution)
    elapsed = time.perf_counter() - t0
    note_reuse(res, execution.get("chunk_size"))
    ds = res.dataset
    regimes = res.regime_counts()
    if args.plot is not None:
        from ..plotting.sweep import save_sweep_figure

        layers = [x for x in (overlay, family) if x is not None]
        save_sweep_figure(ds, args.plot, args.section or "theta", overlay=layers or None, cascades=found)
    summary = {
        "out": str(res.path),
        "param": args.param,
        "values": int(values.size),
        "directions": [str(d) for d in ds.direction.values],
        "regimes": regimes,
        "impacts": res.impacts_simulated,
        "chunks_computed": res.chunks_computed,
        "chunks_reused": res.chunks_reused,
        **backend_summary(res, execution),
        "seconds": elapsed,
        "plot": args.plot,
        "overlay": overlay_kind,
    }
    if args.json:
        print_json(json_result(params, summary, machine, ignored=ignored_keys(args)))
    else:
        dirs = ", ".join(summary["directions"])
        print(f"wrote {res.path}: {args.param} sweep, {values.size} values, directions {dirs}")
        for d, counts in regimes.items():
            print(f"  {d}: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
        rate = res.impacts_simulated / elapsed if elapsed > 0 else float("nan")
        print(f"  {res.impacts_simulated} impacts in {elapsed:.1f} s ({rate:.0f} impacts/s); "
              f"chunks computed {res.chunks_computed}, reused {res.chunks_reused}")
        if args.plot:
            what = {"branches": "continued branches", "fixed-points": "fixed points at each value"}
            extra = f" (overlay: {what[overlay_kind]})" if overlay_kind else ""
            print(f"figure written to {args.plot}{extra}")
    return 0
