"""``rotorcontact drop-map``: drops over a range of speeds (and friction coefficients), as a chunked study."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from ..errors import ParameterError
from ..model.params import load_machine
from .outputs import check_output_folder, note_reuse
from .options import parse_float, parse_int, print_json
from .scale import add_executor_options, executor_kwargs

MAX_N = 10_000


def register(sub) -> None:
    p = sub.add_parser(
        "drop-map",
        description="Regime after a magnetic-bearing failure, onset of backward whirl, peak impulse and "
                    "energy dissipated over speed (and friction), in parallel and resumable.",
    )
    p.add_argument("machine", metavar="M.toml", help="machine file, or 'reference'")
    p.add_argument("--speed", required=True, metavar="A:Brpm", help="speed range with units (3000:36000rpm)")
    p.add_argument("--friction", default=None, metavar="A:B", help="friction range (default: the machine's)")
    p.add_argument("--n", default="16", metavar="N", help="points per range (default 16)")
    p.add_argument("--fail-at", dest="fail_at", default="0s", metavar="T", help="failure time (default 0s)")
    p.add_argument("--t-end", dest="t_end", default="2s", metavar="T", help="final time of each drop (default 2s)")
    p.add_argument("--out", required=True, metavar="DIR", help="folder for drop_map.nc and drop_map.png")
    p.add_argument("--chunk-size", dest="chunk_size", default="16", metavar="N", help="drops per chunk")
    p.add_argument("--json", action="store_true", help="print the map as JSON on stdout")
    g = add_executor_options(p)
    g.add_argument("--no-resume", dest="resume", action="store_false",
                   help="compute afresh: neither a finished drop_map.nc nor the chunks of an interrupted run are "
                        "reused")
    g.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar on stderr")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..simulation.drop_run import check_drop_speed
    from ..studies.drop_map import REGIMES, drop_map, failed_points
    from .design_map import parse_range
    from .drop import parse_drop_times

    machine = load_machine(args.machine)
    n = parse_int("n", args.n, 1, MAX_N)
    if n < 2:
        raise ParameterError(f"--n = {args.n} would keep A of each range A:B alone; allowed: --n >= 2 (A and B "
                             "both included)")
    lo, hi = parse_range("speed", args.speed, "rad/s")
    speeds = np.linspace(lo, hi, n)
    for speed in speeds:
        check_drop_speed(machine, speed, "--speed")
    if args.friction is None:
        frictions = np.array([machine.friction])
    else:
        parts = args.friction.split(":")
        if len(parts) != 2:
            raise ParameterError(f"--friction = {args.friction!r} is not a range; allowed: A:B, such as 0.05:0.3")
        a = parse_float("friction", parts[0], low=0.0)
        b = parse_float("friction", parts[1], low=0.0)
        if not a < b:
            raise ParameterError(f"--friction = {args.friction!r}: the range must increase (A < B)")
        frictions = np.linspace(a, b, n)
    fail_at, t_end = parse_drop_times(args)
    chunk = parse_int("chunk-size", args.chunk_size, 1, 1_000_000)
    out = check_output_folder("--out", args.out)
    out.mkdir(parents=True, exist_ok=True)
    run_ = drop_map(machine, speeds, frictions, fail_at=fail_at, t_end=t_end, chunk_size=chunk,
                    out=Path(out) / "drop_map.nc", resume=args.resume, progress=args.progress and not args.json,
                    **executor_kwargs(args))
    note_reuse(run_, chunk)
    ds = run_.dataset
    from ..plotting.drop_map import save_drop_map_figure

    figure = save_drop_map_figure(ds, Path(out) / "drop_map.png")
    regime = ds["regime"].values.astype(int)
    if args.json:
        def grid(name):
            return [[None if not np.isfinite(v) else float(v) for v in row] for row in ds[name].values]

        print_json({
            "machine": machine.as_dict(),
            "speeds_rpm": ds["speed_rpm"].values.tolist(),
            "frictions": ds["friction"].values.tolist(),
            "regime": [[REGIMES[c] for c in row] for row in regime],
            "backward_whirl_onset_s": grid("backward_whirl_onset_s"),
            "max_normal_impulse_Ns": grid("max_normal_impulse_Ns"),
            "energy_dissipated_J": grid("energy_dissipated_J"),
            "final_spin_rpm": grid("final_spin_rpm"),
            "files": {"netcdf": str(run_.path), "figure": str(figure)},
        })
    else:
        counts = {name: int((regime == i).sum()) for i, name in enumerate(REGIMES)}
        print(f"{regime.size} drops: " + ", ".join(f"{k} {v}" for k, v in counts.items() if v))
        print(f"written {run_.path} and {figure}")
    failed = failed_points(ds)
    if failed:
        where = ", ".join(f"{speed:.6g} rpm and friction {mu:g}" for speed, mu in failed[:5])
        more = f" and {len(failed) - 5} more" if len(failed) > 5 else ""
        print(f"rotorcontact drop-map: failed: {len(failed)} of {regime.size} drops failed (at {where}{more}); "
              f"the map marks them \"failed\"", file=sys.stderr)
        return 1
    return 0
