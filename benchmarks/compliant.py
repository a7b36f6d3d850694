"""Figures and timings of the compliant touchdown bearing (MODEL.md §8).

1. The force against time over the first touchdowns of the reference machine (g = 9.81 m/s^2,
   I_p = 0.04 kg m^2, K_c = ``--contact-stiffness`` N/m^1.5) dropped at ``--speed-rpm``.
2. The rigid limit: a drop from the centre without unbalance (3000 rpm, d = 0.9) with K_c from 1e9 to
   1e13 N/m^1.5 against the rigid kernel: the differences of the second impact time, of the velocity and
   of the spin after the first episode, relative to their scales, fall as K_c^(-2/5).
3. The run time of a compliant drop to ``--t-end`` beside the rigid one.
4. The same compliant drop with the touchdown bearing on springs (20 kg, 5 MN/m, 2 kN s/m), and the dry
   whip of that machine (`analysis.dry_whip`) held by the simulator for 0.2 s from its steady state, and its
   whirl frequency against the support's damping, analytic and simulated (figure compliant_dry_whip.png).

Run: python benchmarks/compliant.py [--speed-rpm 12000] [--contact-stiffness 1e10] [--t-end 1] [--out DIR]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from rotorcontact import Machine, reference_machine
from rotorcontact.analysis.dry_whip import steady_dry_whip
from rotorcontact.plotting.drop import plot_dry_whip, plot_rigid_limit, plot_touchdown_forces
from rotorcontact.plotting.style import save_figure
from rotorcontact.simulation.drop_run import RPM, drop, run_general
from rotorcontact.interpreted import compiled_only


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed-rpm", type=float, default=12000.0)
    ap.add_argument("--contact-stiffness", type=float, default=1e10)
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--out", default=".")
    args = ap.parse_args()
    out = Path(args.out)
    base = {**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04}
    rigid = Machine(**base)
    compliant = Machine(**base, contact="compliant", contact_stiffness=args.contact_stiffness)
    speed = args.speed_rpm * RPM
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        drop(compliant, speed, 0.0, 1e-3)  # compile
    t0 = time.perf_counter()
    rc = drop(compliant, speed, 0.0, args.t_end)
    wall_c = time.perf_counter() - t0
    t0 = time.perf_counter()
    rr = drop(rigid, speed, 0.0, args.t_end)
    wall_r = time.perf_counter() - t0
    print(f"{args.t_end:g} s drop at {args.speed_rpm:g} rpm: compliant {len(rc.impacts)} episodes in {wall_c:.3g} s; "
          f"rigid {len(rr.impacts)} impacts and {len(rr.contacts)} contact phases in {wall_r:.3g} s")
    for row in rc.to_dict()["impacts"][:4]:
        print(f"  t = {row['t_s']:.6g} s: peak force {row['max_force_N']:.4g} N, penetration "
              f"{row['max_penetration_m'] * 1e6:.4g} um, duration {row['duration_s'] * 1e3:.4g} ms")
    fig, _ = plot_touchdown_forces(rc)
    print("wrote", save_figure(fig, out / "compliant_touchdowns.png"))

    limit = {**reference_machine().as_dict(), "eccentricity": 0.0, "gravity": 9.81, "polar_inertia": 0.04,
             "restitution": 0.9}
    ref = run_general(Machine(**limit), 0j, 0j, 3000 * RPM, 0.0, 0.05).impacts
    stiffness = [1e9, 1e10, 1e11, 1e12, 1e13]
    rows = []
    for kc in stiffness:
        r = run_general(Machine(**limit, contact="compliant", contact_stiffness=kc), 0j, 0j, 3000 * RPM, 0.0,
                        0.05).impacts
        rows.append((abs(r[1, 0] - ref[1, 0]) / (ref[1, 0] - ref[0, 0]),
                     abs(complex(r[0, 10], r[0, 11]) - complex(ref[0, 10], ref[0, 11])) / abs(ref[0, 2]),
                     abs(r[0, 6] - ref[0, 6]) / abs(ref[0, 5] - ref[0, 6])))
        print(f"K_c = {kc:.0e}: differences {rows[-1][0]:.3e} {rows[-1][1]:.3e} {rows[-1][2]:.3e}")
    rows = np.array(rows)
    print("ratios per tenfold K_c (theory 10^-0.4 = 0.398):", np.round(rows[1:] / rows[:-1], 4).tolist())
    fig, _ = plot_rigid_limit(stiffness, rows, ["second impact time", "velocity after", "spin after"])
    print("wrote", save_figure(fig, out / "compliant_rigid_limit.png"))

    on_springs = Machine(**base, contact="compliant", contact_stiffness=args.contact_stiffness, stator_mass=20.0,
                         stator_stiffness=5e6, stator_damping=2e3)
    drop(on_springs, speed, 0.0, 1e-3)
    t0 = time.perf_counter()
    rs = drop(on_springs, speed, 0.0, args.t_end)
    wall_s = time.perf_counter() - t0
    print(f"{args.t_end:g} s drop on a stator on springs: {len(rs.impacts)} episodes, {len(rs.contacts)} lasting, "
          f"peak force {rs.column('max_force_N').max():.4g} N, in {wall_s:.3g} s")
    # the whip's machine: no unbalance or gravity, the speed held (the polar inertia left out)
    held = {key: value for key, value in on_springs.as_dict().items() if key != "polar_inertia"}
    whip_machine = Machine(**{**held, "eccentricity": 0.0, "gravity": 0.0})
    whip = steady_dry_whip(whip_machine)
    z, v, zs, vs = whip.state(0.0)
    t0 = time.perf_counter()
    rw = run_general(whip_machine, z, v, whip_machine.speed, 0.0, 0.2, stator_start=(zs, vs))
    wall_w = time.perf_counter() - t0
    z1 = whip.state(0.2)[0]
    print(f"dry whip at {whip_machine.speed / RPM:g} rpm: {whip.whirl_frequency_hz:.6g} Hz (coupled "
          f"{whip.coupled_frequency / (2 * np.pi):.6g} Hz), force {whip.normal_force:.4g} N; simulated 0.2 s in "
          f"{wall_w:.3g} s, whirl {rw.contact_intervals()[0]['whirl_frequency_hz']:.9g} Hz, "
          f"|z - z_whip| / r = {abs(complex(*rw.final_state[1:3]) - z1) / abs(whip.rotor_orbit):.2e}")
    dampings = np.geomspace(50.0, 5000.0, 25)
    whirl = [steady_dry_whip(Machine(**{**whip_machine.as_dict(), "stator_damping": c})).whirl_frequency_hz
             for c in dampings]
    held, simulated = [], []
    for c in dampings[::3]:
        mc = Machine(**{**whip_machine.as_dict(), "stator_damping": c})
        wc = steady_dry_whip(mc)
        z, v, zs, vs = wc.state(0.0)
        run = run_general(mc, z, v, mc.speed, 0.0, 0.2, stator_start=(zs, vs))
        (interval,) = run.contact_intervals()
        # the steady whip is not always stable: where the run leaves it, dry whirl (rolling) takes over
        off = abs(complex(*run.final_state[1:3]) - wc.state(0.2)[0]) / abs(wc.rotor_orbit)
        print(f"  c_s = {c:.4g} N s/m: whip {wc.whirl_frequency_hz:.6g} Hz, simulated 0.2 s from it: mostly "
              f"{interval['kind']} at {interval['whirl_frequency_hz']:.6g} Hz, ending {off:.2g} of the orbit off it")
        if off < 1e-6:
            held.append(c)
            simulated.append(interval["whirl_frequency_hz"])
    fig, _ = plot_dry_whip(dampings, whirl, whip.coupled_frequency / (2 * np.pi), (held, simulated))
    print("wrote", save_figure(fig, out / "compliant_dry_whip.png"))


if __name__ == "__main__":
    main()
