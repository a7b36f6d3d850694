"""A drop of the reference machine (MODEL.md §7): exact kernel against solve_ivp with events.

Problem: the reference rig with gravity 9.81 m/s^2 and polar inertia 0.04 kg m^2, levitated at
36,000 rpm, the magnetic bearing failing at t = 0; the drop runs to 10 s, to rest, or until the impacts
accumulate into continuous contact (followed as sliding and rolling).

The second script integrates the same model with scipy's solve_ivp (DOP853, rtol 1e-10, atol 1e-13 m)
between impacts, locating each impact as a terminal event |z| = c_r and applying the same impact law
(`impact_with_spin`), over the same number of impacts. It prints both times and the largest difference
of the impact times over the first impacts.

The third part drops the same machine with the compliant bearing of MODEL.md §8 (K_c =
``--contact-stiffness`` N/m^1.5, n = 1.5) and the rigid one, each for ``--compliant-t-end`` s, and prints
both run times and the peak forces of the first touchdowns.

Run: python benchmarks/drop.py [--speed-rpm 36000] [--t-end 10] [--compare 100] [--contact-stiffness 1e10]
[--compliant-t-end 1]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from rotorcontact import Machine, reference_machine
from rotorcontact.model.machine_model import impact_with_spin
from rotorcontact.simulation.drop_run import RPM, drop, levitated_state
from rotorcontact.interpreted import compiled_only


def solve_ivp_drop(m: Machine, speed: float, n_impacts: int) -> np.ndarray:
    """Impact times of the same drop by solve_ivp with events (failure at t = 0)."""
    z, v = levitated_state(m, speed)
    state = [z.real, z.imag, v.real, v.imag]
    psi = m.unbalance_phase
    spin = speed
    t = 0.0
    times = []
    cr = m.clearance

    for _ in range(n_impacts):
        def rhs(s, y, spin=spin, psi=psi):
            a = m.eccentricity * spin * spin
            return [y[2], y[3], a * math.cos(psi + spin * s), a * math.sin(psi + spin * s) - m.g]

        def wall(s, y):
            return y[0] * y[0] + y[1] * y[1] - cr * cr

        wall.terminal = True
        wall.direction = 1.0
        # leave the wall first: the event must not fire at s = 0
        sol = solve_ivp(rhs, (0.0, 10.0), state, method="DOP853", rtol=1e-10, atol=1e-13, events=wall,
                        first_step=1e-9)
        if not sol.t_events[0].size:
            break
        s = float(sol.t_events[0][0])
        y = sol.y_events[0][0]
        t += s
        psi += spin * s
        zc = complex(y[0], y[1])
        zc *= cr / abs(zc)
        v_plus, spin, _race, v_n, *_ = impact_with_spin(zc, complex(y[2], y[3]), spin, 0.0, m.mass,
                                                        m.restitution, m.friction, m.rotor_radius,
                                                        1.0 / m.polar_inertia, m.race_radius, 0.0)
        times.append(t)
        state = [zc.real, zc.imag, v_plus.real, v_plus.imag]
        if v_n < 1e-6 * math.sqrt(m.g * cr):
            break
    return np.array(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed-rpm", type=float, default=36000.0)
    ap.add_argument("--t-end", type=float, default=10.0)
    ap.add_argument("--compare", type=int, default=100, help="impacts integrated by solve_ivp")
    ap.add_argument("--contact-stiffness", type=float, default=1e10, help="K_c of the compliant drop, N/m^1.5")
    ap.add_argument("--compliant-t-end", type=float, default=1.0)
    args = ap.parse_args()
    m = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
    speed = args.speed_rpm * RPM
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        drop(m, speed, 0.0, 1e-3)  # compile
    t0 = time.perf_counter()
    result = drop(m, speed, 0.0, args.t_end)
    wall = time.perf_counter() - t0
    n = len(result.impacts)
    phases = result.contact_intervals()
    print(f"exact kernel: {n} impacts and {len(phases)} contact phases to t = {result.t_stop:.6g} s "
          f"({result.status}) in {wall * 1e3:.2f} ms; spin {args.speed_rpm:g} -> {result.final_state[5] / RPM:.6g} rpm")
    for ph in phases:
        print(f"  {ph['kind']}: {ph['t_start_s']:.6g} s to {ph['t_end_s']:.6g} s, whirl {ph['whirl_frequency_hz']:.6g} Hz, "
              f"largest normal force {ph['max_normal_force_N']:.4g} N")
    # the impacts alone (to the accumulation into contact)
    last = result.column("t_s")[-1] if n else 0.0
    t0 = time.perf_counter()
    drop(m, speed, 0.0, last)
    wall_imp = time.perf_counter() - t0
    print(f"  of which the impacts to t = {last:.6g} s: {wall_imp * 1e3:.2f} ms ({n / wall_imp:.3g} impacts/s)")
    k = min(args.compare, n)
    t0 = time.perf_counter()
    ref = solve_ivp_drop(m, speed, k)
    wall_ivp = time.perf_counter() - t0
    k = min(k, len(ref))
    diff = np.abs(ref[:k] - result.column("t_s")[:k]).max() if k else float("nan")
    print(f"solve_ivp with events: {k} impacts in {wall_ivp:.3g} s ({k / wall_ivp:.3g} impacts/s); "
          f"largest difference of impact times over them {diff:.3g} s")
    compliant_drop(m, speed, args.contact_stiffness, args.compliant_t_end)


def compliant_drop(m: Machine, speed: float, stiffness: float, t_end: float) -> None:
    """The same drop with the compliant bearing of MODEL.md §8 beside the rigid one, both to t_end."""
    mc = Machine(**{**m.as_dict(), "contact": "compliant", "contact_stiffness": stiffness})
    with compiled_only():  # a cold cache: compiled here, not run interpreted
        drop(mc, speed, 0.0, 1e-3)  # compile (and solve chi(d, n) once)
    t0 = time.perf_counter()
    rc = drop(mc, speed, 0.0, t_end)
    wall_c = time.perf_counter() - t0
    t0 = time.perf_counter()
    rr = drop(m, speed, 0.0, t_end)
    wall_r = time.perf_counter() - t0
    print(f"compliant bearing (K_c = {stiffness:g} N/m^1.5) to t = {rc.t_stop:.6g} s ({rc.status}): "
          f"{len(rc.impacts)} contact episodes in {wall_c:.3g} s; rigid bearing: {len(rr.impacts)} impacts and "
          f"{len(rr.contacts)} contact phases in {wall_r:.3g} s")
    for row in rc.to_dict()["impacts"][:5]:
        rebound = "-" if row["rebound_ratio"] is None else f"{row['rebound_ratio']:.4g}"
        print(f"  t = {row['t_s']:.6g} s: v_n = {row['normal_velocity_m_per_s']:.4g} m/s, peak force "
              f"{row['max_force_N']:.4g} N, penetration {row['max_penetration_m'] * 1e6:.4g} um, "
              f"duration {row['duration_s'] * 1e3:.4g} ms, rebound {rebound}")


if __name__ == "__main__":
    main()
