"""``rotorcontact lyapunov``: the Lyapunov spectrum of a trajectory, as JSON or text."""

from __future__ import annotations

import argparse

from ..errors import ParameterError
from ..model.params import check_range
from ..model.si import rate_scale, scaled_list, times_si
from .options import (
    add_parameter_options,
    ignored_keys,
    json_result,
    parameter_values,
    parameters_from_args,
    parse_complex,
    parse_float,
    parse_velocity,
    print_json,
)
from .outputs import check_output_file, note_reuse
from .scale import add_scale_options, scale_kwargs, scale_options_given

#: Largest --t-end: tangent propagation through contact costs about 3 ms per unit of time, so 1e5 is
#: minutes of computation.
MAX_T_END = 1e5
#: Largest --n of a scan: each value is one run of --t-end.
MAX_SCAN_VALUES = 10_000


def register(sub) -> None:
    p = sub.add_parser(
        "lyapunov",
        description=(
            "Simulate the rotor and compute the full Lyapunov spectrum of the state (Re U, Im U, Re U', Im U'), "
            "largest first, with exact tangent propagation in free flight, saltation matrices at every impact "
            "and the transitions into and out of continuous contact. Directions annihilated by the dynamics "
            "(on entering contact, at sticking impacts, while rolling) have exponent -inf, printed as null."
        ),
    )
    add_parameter_options(p)
    p.add_argument("--u0", default="0,0", metavar="RE,IM", help="initial position U(0) (co-rotating, |U| <= 1)")
    p.add_argument("--du0", default="0,0", metavar="RE,IM", help="initial velocity U'(0) (co-rotating)")
    p.add_argument("--t-end", dest="t_end", default="2000", metavar="T",
                   help=f"length of the run (default 2000, at most {MAX_T_END:g})")
    p.add_argument(
        "--t-transient",
        dest="t_transient",
        default=None,
        metavar="T",
        help="initial time left out of the averages (default: a quarter of --t-end)",
    )
    p.add_argument(
        "--qr-interval",
        dest="qr_interval",
        default="1",
        metavar="T",
        help="longest time between re-orthonormalisations (default 1)",
    )
    s = p.add_argument_group("scan against a parameter")
    s.add_argument("--param", default=None, metavar="NAME",
                   help="compute the spectrum at --n values of this model parameter (or, with --machine, machine "
                        "quantity such as speed) from --from to --to, on the chunked study driver")
    s.add_argument("--from", dest="start_value", default=None, metavar="A", help="first value (units allowed)")
    s.add_argument("--to", dest="stop_value", default=None, metavar="B", help="last value (units allowed)")
    s.add_argument("--n", dest="n_values", default=None, metavar="N",
                   help=f"number of values, A and B included (at most {MAX_SCAN_VALUES})")
    s.add_argument("--out", default=None, metavar="FILE.nc", help="with --param: also write the scan to NetCDF")
    add_scale_options(p, default_chunk="4 values")
    p.add_argument("--json", action="store_true", help='print {"exponents": [...]} as JSON on stdout')
    p.add_argument(
        "--details",
        action="store_true",
        help="with --json, also print the averaging window, the number of impacts and the run's status",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..analysis.lyapunov import COORDINATES, lyapunov_spectrum

    params, machine = parameters_from_args(args)
    u0 = parse_complex("u0", args.u0)
    du0 = parse_velocity("du0", args.du0)
    t_end = parse_float("t-end", args.t_end, low=0.0, high=MAX_T_END, low_open=True,
                        why="longer runs in contact take more than minutes")
    t_transient = None
    if args.t_transient is not None:
        t_transient = check_range(
            "--t-transient", parse_float("t-transient", args.t_transient), low=0.0, high=t_end, high_open=True
        )
    qr_interval = check_range("--qr-interval", parse_float("qr-interval", args.qr_interval), low=0.0, low_open=True)
    if args.details and not args.json:
        raise ParameterError("--details adds fields to the JSON output; allowed: with --json")
    scan_options = [o for o, v in (("--from", args.start_value), ("--to", args.stop_value), ("--n", args.n_values),
                                   ("--out", args.out)) if v is not None] + scale_options_given(args)
    if args.param is not None:
        if args.details:
            raise ParameterError("--details adds the fields of one spectrum to the JSON output; allowed: without "
                                 "--param")
        return run_scan(args, params, machine, u0, du0, t_end, t_transient, qr_interval)
    if scan_options:
        raise ParameterError(f"{', '.join(scan_options)} need --param (a scan against a parameter)")
    res = lyapunov_spectrum(params, u0, du0, t_end, t_transient=t_transient, qr_interval=qr_interval)
    data = res.to_dict()
    if machine is not None:
        data["exponents_per_s"] = scaled_list(data["exponents"], rate_scale(machine))
        data.update(times_si(machine, time=res.time, t_start=res.t_start, t_stop=res.t_stop))
        if res.final_exponents is not None:
            data["final_exponents_per_s"] = scaled_list(data["final_exponents"], rate_scale(machine))
        if res.regime_start is not None:
            data.update(times_si(machine, regime_start=res.regime_start))
    if res.regime_change:
        warn_regime_change(res)
    if args.json:
        if not args.details:
            keep = {"exponents", "exponents_per_s", "errors", "regime_change"}
            if res.regime_change:
                keep |= {"final_regime", "regime_start", "regime_start_s", "final_exponents", "final_exponents_per_s",
                         "final_errors"}
            data = {k: v for k, v in data.items() if k in keep}
        print_json(json_result(params, data, machine, ignored=ignored_keys(args)))
        return 0
    print(f"Lyapunov spectrum of ({', '.join(COORDINATES)}), largest first"
          f"{' (per unit time; per second)' if machine is not None else ''}:")
    for x, err in zip(res.exponents, res.errors):
        si = f"  {x * rate_scale(machine):+.6g} /s" if machine is not None and x != float("-inf") else ""
        print(f"  {x:+.10g} +- {err:.2g}{si}" if x != float("-inf") else "  -inf (annihilated direction)")
    if res.regime_change:
        finals = ", ".join(f"{x:+.10g} +- {err:.2g}" if x != float("-inf") else "annihilated"
                           for x, err in zip(res.final_exponents or (), res.final_errors or ()))
        print(f"final regime ({res.final_regime}, from t = {res.regime_start:.10g}): {finals}")
    window = "impact to impact" if res.aligned else "time window"
    print(
        f"averaged over t in [{res.t_start:.10g}, {res.t_stop:.10g}] ({window}), {res.n_impacts} impacts; "
        f"run status: {res.trajectory.status}"
    )
    return 0


def warn_regime_change(res) -> None:
    """One line on stderr: the window holds a change of regime, and the final regime's largest exponent."""
    import sys

    top = res.final_exponents[0] if res.final_exponents else None
    final = f"; the final regime's largest exponent is {top:+.6g}" if top is not None else ""
    print(f"rotorcontact lyapunov: warning: the motion changed regime inside the averaging window: it settled "
          f"into {res.final_regime} motion at t = {res.regime_start:.6g} (window from t = {res.t_start:.6g}), so the "
          f"exponents average over two regimes{final}", file=sys.stderr)


def run_scan(args, params, machine, u0, du0, t_end, t_transient, qr_interval) -> int:
    """``--param``: the spectrum at each value of a parameter (`rotorcontact.studies.lyapunov_scan`)."""
    import math
    import sys
    import time

    from ..analysis.lyapunov import COORDINATES
    from ..studies.lyapunov_scan import FINAL_NAMES, lyapunov_scan

    missing = [o for o, v in (("--from", args.start_value), ("--to", args.stop_value), ("--n", args.n_values))
               if v is None]
    if missing:
        raise ParameterError(f"--param needs {', '.join(missing)}")
    unit, values = parameter_values(args, params, machine, MAX_SCAN_VALUES, why="each value is a run of --t-end")
    n_values = values.size
    if args.out is not None:
        check_output_file("--out", args.out, (".nc",))
    execution = scale_kwargs(args)
    t0 = time.perf_counter()
    res = lyapunov_scan(params, args.param, values, u0=u0, du0=du0, t_end=t_end, t_transient=t_transient,
                        qr_interval=qr_interval, out=args.out, machine=machine, **execution)
    elapsed = time.perf_counter() - t0
    if args.out is not None:
        note_reuse(res, execution.get("chunk_size"))
    ds = res.dataset

    def rows(name):
        return [[float(x) if math.isfinite(x) else None for x in row] for row in ds[name].values]

    change = res.regime_change
    final = [FINAL_NAMES[c] if c >= 0 else None for c in ds["final_regime"].values]
    starts = [float(t) if math.isfinite(t) else None for t in ds["regime_start"].values]
    if change.any():
        where = ", ".join(f"{v:.6g}" for v in res.values[change])
        print(f"rotorcontact lyapunov: warning: the motion changed regime inside the averaging window at "
              f"{args.param} = {where}; final_exponents hold the final regime's spectrum there", file=sys.stderr)
    data = {
        "param": args.param,
        "unit": unit,
        "values": [float(v) for v in res.values],
        "exponents": rows("exponents"),
        "errors": rows("errors"),
        "regime_change": [bool(c) for c in change],
        "final_regime": final,
        "regime_start": starts,
        "final_exponents": rows("final_exponents"),
        "final_errors": rows("final_errors"),
        "failed": [bool(f) for f in ds["failed"].values],
        "out": None if res.path is None else str(res.path),
        "chunks_computed": res.chunks_computed,
        "chunks_reused": res.chunks_reused,
        "seconds": elapsed,
    }
    if machine is not None:
        from ..studies.design_map import rad_s_to_rpm
        from ..studies.parameter_path import machine_at

        # the time scale is that of each value: 1 / Omega changes along a path in the speed
        data["exponents_per_s"] = [scaled_list(r, rate_scale(machine_at(machine, args.param, v)))
                                   for r, v in zip(data["exponents"], res.values)]
        if args.param == "speed":
            data["values_rpm"] = [float(v) for v in rad_s_to_rpm(res.values)]
    if args.json:
        print_json(json_result(params, data, machine, ignored=ignored_keys(args)))
        return 0
    print(f"Lyapunov spectrum of ({', '.join(COORDINATES)}) against {args.param}, largest first:")
    for v, ex, err, ch in zip(res.values, res.exponents, res.errors, change):
        cells = " ".join(f"{x:+.5g}+-{e:.1g}" if math.isfinite(x) else "-inf" for x, e in zip(ex, err))
        print(f"  {v:12.6g}  {cells}{'  (regime change)' if ch else ''}")
    print(f"  {n_values} values in {elapsed:.1f} s" + (f"; written to {res.path}" if res.path else ""))
    return 0
