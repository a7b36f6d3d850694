"""The GPU backend on the basins of basins.py: its speed against the CPU, and how far the two agree.

Problem: the reference machine at gamma = 0.1 (basins.py): a 400 x 400 grid of velocity kicks from the
contact-free whirl (``shock``) and of initial displacements (``plane``), 300 transient events in segments
of 25 and 50 recorded events per point.

For each grid it runs:

* the grid's states through the backend's two parts (`rotorcontact.studies.cuda_batch`): the GPU kernel
  (`launch_lanes`, transfers included), and the CPU kernel on the points it hands back, if any
  (`complete_deferred`), each timed, with the share of points handed back;
* the whole study, ``basins(backend="cuda")`` (twice) and ``basins(backend="cpu")`` (numba's threads over
  all cores), each timed from the call to the returned result;
* the agreement of the two: the share of points with the same attractor label, and of the points the
  GPU finished itself, those with the same number of impacts, and the largest difference in the period of
  periodic points. The GPU's libdevice rounds sin, cos and exp differently in the last bit, so points on
  a basin boundary or in chaotic motion may part ways; everything else must agree.

The CPU kernels are compiled (or loaded) first, as ``rotorcontact warmup --only studies`` does, so that
no study step runs in numba's interpreted tier (`rotorcontact.interpreted`); the first GPU call compiles
the GPU kernel, timed separately. Needs an NVIDIA GPU and numba-cuda.

Run: python benchmarks/cuda_basins.py [--n 400] [--gamma 0.1] [--grids shock,plane]
Prints one line per grid, and a last line ``json: {...}`` with the same figures.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time

import numba
import numpy as np

import rotorcontact as rc
from rotorcontact.studies.basins import basin_settings, basins, displacement_grid, shock_grid
from rotorcontact.studies.batch import parameter_array
from rotorcontact.studies.cuda_batch import complete_deferred, launch_lanes, require_cuda, run_lanes_cuda
from rotorcontact.studies.warmup import warm_up


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=400, help="points per axis")
    ap.add_argument("--gamma", type=float, default=0.1)
    ap.add_argument("--grids", default="shock,plane")
    args = ap.parse_args()
    require_cuda()
    from numba import cuda

    name = cuda.get_current_device().name if hasattr(cuda, "get_current_device") else "CUDA simulator"
    name = name.decode() if isinstance(name, bytes) else str(name)
    print(f"GPU: {name}; cores: {os.cpu_count()}, "
          f"numba threads: {numba.get_num_threads()}; numba {numba.__version__}, numpy {np.__version__}")
    p = rc.Parameters.reference().replace(gamma=args.gamma)
    settings = basin_settings()
    tiny = displacement_grid((-0.5, 0.5, 4), (-0.5, 0.5, 4))
    t0 = time.perf_counter()
    warm_up(["studies"])
    print(f"CPU kernels compiled or loaded (warmup --only studies): {time.perf_counter() - t0:.1f} s")
    t0 = time.perf_counter()
    basins(p, tiny, progress=False, backend="cuda")
    compile_s = time.perf_counter() - t0
    print(f"first GPU call (compiles the kernel): {compile_s:.1f} s")
    grids = {
        "shock": shock_grid((0.0, 1.0, args.n), (-math.pi, math.pi, args.n)),
        "plane": displacement_grid((-1.0, 1.0, args.n), (-1.0, 1.0, args.n)),
    }
    report = {"gpu": name, "compile_s": compile_s, "grids": {}}
    row = parameter_array(p)
    for name in args.grids.split(","):
        grid = grids[name]
        u0, du0, inside = grid.initial_states(p)
        idx = np.flatnonzero(inside.ravel())
        n = idx.size
        params = np.broadcast_to(row, (n, 1, row.size)).copy()
        u = u0.ravel()[idx].reshape(n, 1).copy()
        du = du0.ravel()[idx].reshape(n, 1).copy()
        run_lanes_cuda(params[:64], u[:64], du[:64], settings, carry=False)
        t0 = time.perf_counter()
        sections, summary, deferred, start_u, start_du = launch_lanes(params, u, du, settings, carry=False)
        kernel_s = time.perf_counter() - t0
        t0 = time.perf_counter()
        complete_deferred(params, u, du, settings, False, sections, summary, deferred, start_u, start_du)
        handed_back_s = time.perf_counter() - t0
        gpu_runs = []
        for _ in range(2):
            t0 = time.perf_counter()
            gpu = basins(p, grid, progress=False, backend="cuda")
            gpu_runs.append(time.perf_counter() - t0)
        gpu_s = min(gpu_runs)
        t0 = time.perf_counter()
        cpu = basins(p, grid, progress=False)
        cpu_s = time.perf_counter() - t0
        same_label = float(np.mean(gpu.image[inside] == cpu.image[inside]))
        # the points the GPU finished itself
        own = deferred < 0
        g_imp = gpu.dataset["n_impacts"].values.ravel()[idx][own]
        c_imp = cpu.dataset["n_impacts"].values.ravel()[idx][own]
        same_impacts = float(np.mean(g_imp == c_imp))
        g_per = gpu.dataset["period"].values.ravel()[idx][own]
        c_per = cpu.dataset["period"].values.ravel()[idx][own]
        both = np.isfinite(g_per) & np.isfinite(c_per)
        dperiod = float(np.max(np.abs(g_per[both] - c_per[both]), initial=0.0))
        n_deferred = int(np.count_nonzero(~own))
        entry = {
            "points": int(n), "deferred_to_cpu": n_deferred, "gpu_kernel_s": kernel_s,
            "handed_back_cpu_s": handed_back_s, "basins_gpu_s": gpu_s, "basins_gpu_runs_s": gpu_runs,
            "basins_cpu_s": cpu_s, "speedup": cpu_s / gpu_s, "same_label": same_label,
            "same_impacts_of_gpu_finished": same_impacts, "max_period_difference": dperiod,
            "impacts": cpu.impacts_simulated,
        }
        report["grids"][name] = entry
        share = 100 * n_deferred / n
        print(f"{name:6s} {args.n}x{args.n}: {n} points, {n_deferred} ({share:.1f} %) deferred to the CPU; "
              f"GPU kernel {kernel_s:.2f} s, handed-back points on the CPU {handed_back_s:.2f} s; "
              f"basins GPU {' and '.join(f'{x:.2f}' for x in gpu_runs)} s, CPU ({numba.get_num_threads()} threads) "
              f"{cpu_s:.2f} s: {cpu_s / gpu_s:.1f}x (the faster GPU run); same label {100 * same_label:.3f} %, "
              f"same impacts "
              f"{100 * same_impacts:.3f} % of GPU-finished points, max period difference {dperiod:.2e}")
    print("json: " + json.dumps(report))


if __name__ == "__main__":
    main()
