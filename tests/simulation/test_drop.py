"""The general machine's kernel (MODEL.md §7) against closed forms, mpmath and today's simulator."""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.optimize import brentq

from rotorcontact import Machine, ParameterError, reference_machine
from rotorcontact.model.machine_model import effective_mass_factor
from rotorcontact.simulation.drop import drop_kernel
from rotorcontact.simulation.drop_run import CHATTER_RELATIVE, REST_FRACTION, RPM, drop, levitated_state, run_general
from rotorcontact.simulation.simulator import simulate

CR = 0.7e-3
G = 9.81


def run(machine, z0, v0, spin, t_end, t_fail=0.0, chatter_v=1e-9, max_events=100_000, follow_contact=False):
    """The kernel's impacts, status, stop time and final state (contact phases: see the tests below)."""
    m = machine
    race = (m.race_inertia, m.race_drag_torque, m.race_drag_coefficient) if m.has_race else (0.0, 0.0, 0.0)
    impacts, _contacts, status, t_stop, state = drop_kernel(
        m.mass, m.clearance, m.eccentricity, m.rotor_radius, m.friction, m.restitution, m.kx, m.ky, m.cx, m.cy,
        m.fs, m.g, m.polar_inertia or 0.0, *race, complex(z0), complex(v0), m.unbalance_phase, spin, 0.0, t_fail,
        t_end, max_events, chatter_v, follow_contact)
    return impacts, status, t_stop, state


def machine(**changes):
    return Machine(**{**reference_machine().as_dict(), **changes})


@pytest.mark.parametrize("d", [0.5, 0.9])
def test_free_fall_from_the_centre_closed_form(d):
    m = machine(eccentricity=0.0, gravity=G, restitution=d)
    impacts, status, _t, _s = run(m, 0j, 0j, 0.0, 5.0)
    t1 = math.sqrt(2.0 * CR / G)
    v1 = G * t1
    n = len(impacts)
    assert status == 1 and n > 20  # impacts accumulate (chatter)
    k = np.arange(n)
    # t_n = t1 + sum_{j=1}^{n} 2 d^j v1 / g, the bounces of a ball
    expected = t1 + 2.0 * v1 / G * d * (1.0 - d**k) / (1.0 - d)
    assert impacts[:, 0] == pytest.approx(expected, rel=1e-11, abs=1e-13)
    assert impacts[:, 2] == pytest.approx(v1 * d**k, rel=1e-9, abs=1e-11 * v1)  # location to rounding of f
    assert np.all(impacts[:, 1] == pytest.approx(-math.pi / 2, abs=1e-12))
    t_acc = t1 + 2.0 * v1 * d / (G * (1.0 - d))  # the accumulation time
    last = impacts[-1, 0]
    assert last < t_acc and t_acc - last == pytest.approx(2.0 * v1 * d**n / (G * (1.0 - d)), rel=1e-6, abs=1e-12)
    np.testing.assert_allclose(np.diff(impacts[:8, 0]), 2.0 * v1 * d ** np.arange(1, 8) / G, rtol=1e-10)


def _mp_impacts(m, spin, count):
    """The spinning drop without unbalance in mpmath: exact parabolas and the impact law of MODEL.md §7."""
    mp.mp.dps = 40
    g, c, mass, d, mu, r = (mp.mpf(x) for x in (m.g, m.clearance, m.mass, m.restitution, m.friction, m.rotor_radius))
    ip = mp.mpf(m.polar_inertia)
    x = y = vx = vy = mp.mpf(0)
    om = mp.mpf(spin)
    t = mp.mpf(0)
    out = []
    on_wall = False
    for _ in range(count):
        def f(s):
            return (x + vx * s) ** 2 + (y + vy * s - g * s * s / 2) ** 2 - c * c
        # bracket the first root: sample finely, then bisect in mpmath
        lo = mp.mpf(0) if not on_wall else mp.mpf("1e-30")
        hi = lo
        step = mp.mpf("1e-6")
        while f(hi + step) < 0:
            hi += step
        s = mp.findroot(f, (hi, hi + step), solver="anderson")
        t += s
        x, y = x + vx * s, y + vy * s - g * s * s / 2
        vy = vy - g * s
        nx, ny = x / c, y / c
        vn = vx * nx + vy * ny
        vt = -vx * ny + vy * nx
        vrel = vt + r * om
        kappa = 1 + mass * r * r / ip
        pn = (1 + d) * vn
        qt = -vrel / kappa if abs(vrel) / kappa <= mu * pn else -mp.sign(vrel) * mu * pn
        vn, vt = -d * vn, vt + qt
        om_before = om
        om = om + mass * r * qt / ip
        vx, vy = vn * nx - vt * ny, vn * ny + vt * nx
        out.append((t, mp.atan2(y, x), pn * mass, qt * mass, om_before, om))
        on_wall = True
    return out


def test_spinning_drop_first_impact_by_hand_and_later_ones_against_mpmath():
    ip = 0.04
    m = machine(eccentricity=0.0, gravity=G, polar_inertia=ip)
    spin = 12000 * RPM
    impacts, _status, _t, _s = run(m, 0j, 0j, spin, 0.2)
    # first impact, by hand: straight fall to the bottom, v_rel = R Omega > 0 slides forward
    t1 = math.sqrt(2.0 * CR / G)
    v1 = G * t1
    p_n = (1.0 + m.restitution) * m.mass * v1
    kappa = 1.0 + m.mass * m.rotor_radius**2 / ip
    p_t = -min(m.friction * p_n, m.mass * m.rotor_radius * spin / kappa)
    assert impacts[0, 0] == pytest.approx(t1, rel=1e-13)
    assert impacts[0, 1] == pytest.approx(-math.pi / 2, abs=1e-13)
    assert impacts[0, 3] == pytest.approx(p_n, rel=1e-12)
    assert impacts[0, 4] == pytest.approx(p_t, rel=1e-12)
    assert impacts[0, 6] == pytest.approx(spin + m.rotor_radius * p_t / ip, rel=1e-14)
    assert impacts[0, 10] == pytest.approx(p_t / m.mass, rel=1e-12)  # +theta at the bottom is +x
    ref = _mp_impacts(m, spin, 12)
    for row, (t, ang, pn, pt, _ob, om) in zip(impacts[:12], ref):
        assert row[0] == pytest.approx(float(t), rel=1e-11)
        assert row[1] == pytest.approx(float(ang), abs=1e-9)
        assert row[3] == pytest.approx(float(pn), rel=1e-8)
        assert row[4] == pytest.approx(float(pt), rel=1e-8)
        assert row[6] == pytest.approx(float(om), rel=1e-12)


def test_paper_machine_through_the_general_model_equals_the_simulator():
    # a damping where the rotor settles on a persistent impacting orbit (no accumulation of impacts)
    m = machine(damping=800.0)
    p = m.parameters()
    u0, du0 = 0.3 + 0.2j, 0.8 + 0.4j
    traj = simulate(p, u0, du0, 1500.0, on_chatter="stop")
    om = m.speed
    # inertial state Z = U e^{it}, Z' = (U' + i U) e^{it} at t = 0, in metres and seconds (MODEL.md §2)
    impacts, status, _t, _s = run(m, CR * u0, CR * om * (du0 + 1j * u0), om, 1500.0 / om, t_fail=math.inf)
    n = len(traj.impacts)
    assert traj.status == "completed" and status == 0 and n >= 400
    t_ref = np.asarray(traj.impacts.t)
    assert len(impacts) == n
    np.testing.assert_allclose(impacts[:n, 0] * om, t_ref, rtol=1e-12, atol=0)


def test_the_levitated_state_is_the_steady_whirl_and_must_fit():
    m = machine(gravity=G, stiffness_x=6e5, damping_y=2000.0)
    z, v = levitated_state(m, m.speed)
    impacts, status, t_stop, state = run(m, z, v, m.speed, 0.05, t_fail=math.inf)
    # started on its steady state, the levitated rotor whirls without impact and returns to it
    assert len(impacts) == 0 and status == 0
    z_end, v_end = levitated_state(Machine(**{**m.as_dict(), "unbalance_phase": m.unbalance_phase + m.speed * t_stop}),
                                   m.speed)
    assert complex(state[1], state[2]) == pytest.approx(z_end, abs=1e-12 * CR)
    with pytest.raises(ParameterError, match="speed"):
        levitated_state(machine(eccentricity=2e-3), 184.2)


def test_drop_result_contract_and_rolling_free_bounds():
    m = machine(gravity=G, polar_inertia=0.04)
    r = drop(m, speed=12000 * RPM, t_end=0.5)
    d = r.to_dict()
    assert set(d) >= {"machine", "speed_rpm", "status", "message", "impacts", "contact_intervals", "summary"}
    assert set(d["impacts"][0]) == {"t_s", "angle_rad", "normal_velocity_m_per_s", "normal_impulse_Ns",
                                    "tangential_impulse_Ns", "spin_rpm_before", "spin_rpm_after", "race_rpm_after"}
    assert set(d["summary"]) == {"regime", "backward_whirl_onset_s", "max_normal_impulse_Ns", "max_contact_force_N",
                                 "final_spin_rpm", "energy_dissipated_J", "time_to_rest_s", "stator_final"}
    assert d["speed_rpm"] == pytest.approx(12000.0, rel=1e-14)
    spins = [row["spin_rpm_after"] for row in d["impacts"]]
    assert all(-math.pi < row["angle_rad"] <= math.pi for row in d["impacts"])
    # friction only slows the spin here (v_rel > 0 at every impact of this drop) and never reverses v_rel
    assert all(b <= a for a, b in zip([12000.0] + spins, spins))
    assert d["summary"]["energy_dissipated_J"] > 0.0
    assert effective_mass_factor(m.mass, m.rotor_radius, 1 / 0.04, m.race_radius, 0.0) > 1.0
    with pytest.raises(ParameterError, match="t_end"):
        drop(m, t_end=0.0)


def _impact_dissipation(m, r, inv_polar):
    """Energy each impact dissipates, from its impulses alone: (1 - d^2) m v_n^2 / 2 by restitution, and the
    friction work |P_t| (|v_rel-| + |v_rel+|) / 2, v_rel changing linearly with P_t (kappa P_t / m)."""
    kappa = effective_mass_factor(m.mass, m.rotor_radius, inv_polar, m.race_radius,
                                  1.0 / m.race_inertia if m.has_race else 0.0)
    v_n = r.column("normal_velocity_m_per_s")
    p_t = r.column("tangential_impulse_Ns")
    v_rel = r.column("v_rel_before")
    return (0.5 * (1.0 - m.restitution ** 2) * m.mass * v_n ** 2
            + np.abs(p_t) * (np.abs(v_rel) + np.abs(v_rel + kappa * p_t / m.mass)) / 2.0)


def test_impacts_with_the_speed_held_dissipate_what_their_impulses_do():
    """The motor's work holding the speed enters the balance: no impact creates energy."""
    m = machine(gravity=G)
    r = drop(m, speed=12000 * RPM, t_end=0.05)
    assert len(r.impacts) >= 3
    expected = _impact_dissipation(m, r, 0.0)
    assert np.all(expected > 0.0)
    # the kernel differences kinetic energies as large as the largest loss: rounding at that scale
    np.testing.assert_allclose(r.column("energy_lost_J"), expected, rtol=1e-9, atol=1e-12 * expected.max())
    assert r.energy_dissipated >= r.column("energy_lost_J").sum() > 0.0


def _mechanical_energy(m, z, v, spin, race):
    """m |z'|^2 / 2 + I_p Omega^2 / 2 + I_b Omega_b^2 / 2 + m g y: the energy once the bearing has failed."""
    return (0.5 * m.mass * abs(v) ** 2 + 0.5 * m.polar_inertia * spin ** 2
            + 0.5 * (m.race_inertia if m.has_race else 0.0) * race ** 2 + m.mass * m.g * z.imag)


@pytest.mark.parametrize("race", [False, True])
def test_energy_balance_of_a_drop_with_free_spin(race):
    """After the failure the machine's energy falls by exactly what the touchdown bearing dissipates:
    impacts, friction in sliding contact and the race's drag (no unbalance, so no work by the motor)."""
    keys = dict(race_inertia=2e-4, race_drag_torque=0.05, race_drag_coefficient=1e-4) if race else {}
    m = machine(eccentricity=0.0, gravity=G, polar_inertia=0.04, restitution=0.5, **keys)
    speed = 3000 * RPM
    r = drop(m, speed=speed, t_end=0.4)
    assert len(r.impacts) >= 3 and len(r.contacts) >= 1
    z0, v0 = levitated_state(m, speed)
    _t, x, y, vx, vy, spin, race_end, dissipated = r.final_state[:8]
    e0 = _mechanical_energy(m, z0, v0, speed, 0.0)
    e1 = _mechanical_energy(m, complex(x, y), complex(vx, vy), spin, race_end)
    assert dissipated == r.energy_dissipated == r.to_dict()["summary"]["energy_dissipated_J"]
    assert dissipated == pytest.approx(e0 - e1, rel=1e-7)
    expected = _impact_dissipation(m, r, 1 / 0.04)
    np.testing.assert_allclose(r.column("energy_lost_J"), expected, rtol=1e-9, atol=1e-12 * e0)


def test_a_rotor_without_radius_drops_with_its_spin_untouched_and_its_energy_balanced():
    """R = 0: friction has no lever on the spin (Omega stays exactly), and the contact integrator, whose error
    scale of the spin divided by R, runs through the contact phases; the energy falls by what is dissipated."""
    m = machine(eccentricity=0.0, rotor_radius=0.0, gravity=G, polar_inertia=0.04, restitution=0.5)
    speed = 3000 * RPM
    r = drop(m, speed=speed, t_end=0.4)
    assert r.status in ("completed", "at-rest") and len(r.impacts) >= 3 and len(r.contacts) >= 1
    z0, v0 = levitated_state(m, speed)
    _t, x, y, vx, vy, spin, race_end, dissipated = r.final_state[:8]
    assert spin == speed
    e0 = _mechanical_energy(m, z0, v0, speed, 0.0)
    e1 = _mechanical_energy(m, complex(x, y), complex(vx, vy), spin, race_end)
    assert dissipated == pytest.approx(e0 - e1, rel=1e-7)


def test_a_rotor_rolling_on_a_race_comes_to_rest_and_the_run_stops_there():
    """The race's viscous drag takes the energy of the roll: the run stops where the rotor's energy above
    rest (kinetic, and potential above the bottom) falls to REST_FRACTION of its kinetic energy at the start."""
    m = machine(eccentricity=0.0, gravity=G, polar_inertia=0.04, restitution=0.5, race_inertia=2e-4,
                race_drag_torque=0.0, race_drag_coefficient=0.05)
    speed = 1000 * RPM
    r = drop(m, speed=speed, t_end=20.0)
    assert r.status == "at-rest" and r.time_to_rest == r.t_stop < 20.0
    assert r.to_dict()["summary"]["time_to_rest_s"] == r.t_stop
    z0, v0 = levitated_state(m, speed)
    _t, x, y, vx, vy, spin, race, _d = r.final_state[:8]
    above = (0.5 * m.mass * (vx * vx + vy * vy) + 0.5 * m.polar_inertia * spin * spin
             + m.mass * G * (y + m.clearance))
    start = 0.5 * m.mass * abs(v0) ** 2 + 0.5 * m.polar_inertia * speed ** 2
    assert above == pytest.approx(REST_FRACTION * start, rel=1e-3)
    # all the energy went into the bearing: the spin's, and the fall to the bottom
    assert r.energy_dissipated == pytest.approx(start + m.mass * G * (z0.imag + m.clearance)
                                                - 0.5 * m.race_inertia * race ** 2, rel=1e-7)


def test_a_rotor_let_fall_from_rest_without_spin_comes_to_rest_on_the_scale_of_its_fall():
    """With no kinetic energy at the start the rest threshold is REST_FRACTION of m g c_r, the weight's fall
    from the centre to the bottom (a zero threshold never stopped the run)."""
    m = machine(eccentricity=0.0, gravity=G, polar_inertia=0.04)
    r = run_general(m, 0j, 0j, 0.0, 0.0, 2.0)
    assert r.status == "at-rest" and r.time_to_rest == r.t_stop < 2.0
    _t, x, y, vx, vy, spin = r.final_state[:6]
    above = 0.5 * m.mass * (vx * vx + vy * vy) + 0.5 * m.polar_inertia * spin * spin + m.mass * G * (y + m.clearance)
    assert -1e-12 * m.mass * G * m.clearance <= above <= REST_FRACTION * m.mass * G * m.clearance
    assert r.energy_dissipated == pytest.approx(m.mass * G * m.clearance, rel=1e-7)


def test_a_rotor_rolling_to_and_fro_on_a_fixed_stator_never_rests():
    """Rolling dissipates nothing in the rigid model: the rotor swings at the bottom, its kinetic energy
    passing through zero at each turning point, and the run is not taken for rest there."""
    m = machine(eccentricity=0.0, gravity=G, polar_inertia=0.04, restitution=0.5)
    r = drop(m, speed=1000 * RPM, t_end=3.0)
    assert r.status == "completed" and r.time_to_rest is None
    # a held speed never comes to rest either
    held = drop(machine(eccentricity=0.0, gravity=G, restitution=0.5), speed=1000 * RPM, t_end=0.3)
    assert held.status == "completed" and held.time_to_rest is None


def test_the_failure_switch_starts_a_free_fall_from_the_levitated_whirl():
    m = machine(gravity=G)
    t_fail = 0.0137
    r = drop(m, fail_at=t_fail, t_end=0.1)
    # levitated until t_fail: the steady whirl there (its unbalance phase advanced by Omega t_fail)
    z_f, v_f = levitated_state(machine(gravity=G, unbalance_phase=m.unbalance_phase + m.speed * t_fail), m.speed)
    # then gravity and the unbalance alone (K = C = F_s = 0), integrated by hand:
    # x = x_f + A s + e (cos psi - cos(psi + Om s)), y = y_f + B s + e (sin psi - sin(psi + Om s)) - g s^2 / 2
    e, om = m.eccentricity, m.speed
    psi = m.unbalance_phase + om * t_fail
    a = v_f.real - e * om * math.sin(psi)
    b = v_f.imag + e * om * math.cos(psi)

    def gap(s):
        x = z_f.real + a * s + e * (math.cos(psi) - math.cos(psi + om * s))
        y = z_f.imag + b * s + e * (math.sin(psi) - math.sin(psi + om * s)) - G * s * s / 2
        return x * x + y * y - CR * CR

    grid = np.linspace(0.0, 0.05, 50001)
    vals = np.array([gap(s) for s in grid])
    i = int(np.argmax(vals > 0))
    s1 = brentq(gap, grid[i - 1], grid[i], xtol=1e-18, rtol=1e-15)
    assert r.column("t_s")[0] == pytest.approx(t_fail + s1, rel=1e-12)
    assert r.column("spin_after")[0] == m.speed  # no polar inertia: the speed stays held


def test_chatter_into_rolling_contact_at_the_reference_speed_whirls_at_minus_r_over_cr_omega():
    """Held speed, gravity: the drop ends rolling on a fixed stator with Theta' = -(R/c_r) Omega (-1675 Hz)."""
    m = machine(gravity=G)
    r = drop(m, t_end=0.3)
    last = r.contact_intervals()[-1]
    assert r.status == "completed" and last["kind"] == "rolling" and last["t_end_s"] == 0.3
    expected = -(m.rotor_radius / m.clearance) * m.speed / (2 * math.pi)
    assert last["whirl_frequency_hz"] == pytest.approx(expected, rel=1e-9)
    assert expected == pytest.approx(-1675.0, abs=0.5)
    assert r.regime == "backward-whirl" and r.backward_whirl_onset is not None


def test_rolling_with_a_race_keeps_the_surfaces_together():
    m = machine(gravity=G, polar_inertia=0.04, race_inertia=2e-4, race_drag_torque=0.05, race_drag_coefficient=1e-4)
    r = drop(m, speed=12000 * RPM, t_end=0.2)
    last = r.contact_intervals()[-1]
    assert last["kind"] == "rolling"
    _t, x, y, vx, vy, spin, race = r.final_state[:7]
    theta_dot = (x * vy - y * vx) / (x * x + y * y)
    v_rel = m.clearance * theta_dot + m.rotor_radius * spin - m.race_radius * race
    assert abs(v_rel) <= 1e-8 * m.rotor_radius * abs(spin)
    # the race has been spun up by the rotor: the whirl is (R_b Omega_b - R Omega)/c_r
    assert race > 0.0
    assert r.to_dict()["impacts"][-1]["race_rpm_after"] is not None


def test_free_fall_accumulates_into_rest_at_the_bottom():
    m = machine(eccentricity=0.0, gravity=G, restitution=0.5)
    r = drop(m, speed=1e-9, t_end=0.1)
    _t, x, y, vx, vy, _spin, _race = r.final_state[:7]
    assert r.status == "completed" and r.contact_intervals()[-1]["t_end_s"] == 0.1
    # at the bottom, rolling with the held spin 1e-9 rad/s: the whirl -(R/c_r) Omega turns it by at most
    # (R/c_r) 1e-9 0.1 rad over the run
    assert y == pytest.approx(-CR, rel=1e-12) and abs(vx) + abs(vy) <= 1e-9
    assert abs(x) <= CR * (m.rotor_radius / CR) * 1e-9 * 0.1


def test_contact_phases_of_the_paper_machine_match_the_simulator():
    """Chatter into sliding, then rolling: the same phases as today's simulator's (MODEL.md §4).

    The two handle the end of an accumulation differently (the simulator extrapolates the tail from
    normal velocities 1e-5 c_r Omega; the general kernel drops velocities below 1e-6 c_r Omega), so the
    times agree to the length of a bounce tail, 2 d v / (N (1 - d)) < 1e-4 here (N of order one).
    """
    m = machine(damping=600.0)
    p = m.parameters()
    u0, du0 = 0.3 + 0.2j, 0.8 + 0.4j
    om = m.speed
    ref = simulate(p, u0, du0, 150.0).to_dict()["contact_intervals"]
    got = run_general(m, CR * u0, CR * om * (du0 + 1j * u0), om, math.inf, 150.0 / om).contact_intervals()
    assert [c["kind"] for c in got] == [c["kind"] for c in ref] == ["sliding-forward", "rolling"]
    for a, b in zip(got, ref):
        assert a["t_start_s"] * om == pytest.approx(b["t_start"], abs=1e-4)
        assert a["t_end_s"] * om == pytest.approx(b["t_end"], abs=1e-4)
    # rolling in the inertial frame: Theta' = -(R/c_r) Omega
    assert got[1]["whirl_frequency_hz"] * 2 * math.pi / om == pytest.approx(-p.r_ratio, rel=1e-9)


def test_forward_rub_of_the_paper_machine_follows_the_simulator():
    """A plastic impact (d = 0) into a forward rub: the general kernel's sliding phase against the simulator's
    dense output at the same times (inertial Z = U e^{it})."""
    m = machine(restitution=0.0)
    p = m.parameters()
    om = m.speed
    u0, du0 = 0.9 + 0j, 0.5j
    traj = simulate(p, u0, du0, 200.0)
    assert [c["kind"] for c in traj.to_dict()["contact_intervals"]] == ["sliding-forward"]
    for t in (100.0, 200.0):
        r = run_general(m, CR * u0, CR * om * (du0 + 1j * u0), om, math.inf, t / om)
        assert [c["kind"] for c in r.contact_intervals()] == ["sliding-forward"]
        z = complex(r.final_state[1], r.final_state[2]) / CR
        assert z == pytest.approx(complex(traj.Z(np.array([t]))[0]), abs=1e-8)


def test_lift_off_where_the_normal_force_vanishes_then_a_ballistic_flight():
    """Sliding up the wall under gravity (speed held, v_rel > 0 throughout, no unbalance), the rotor lifts off
    where n = -g sin(theta) + c_r theta'^2 reaches 0 (MODEL.md §7), found here by solve_ivp on the equation
    c_r theta'' = -g cos(theta) - mu n; then it flies a parabola to its next impact."""
    from scipy.integrate import solve_ivp

    m = machine(eccentricity=0.0, gravity=G, friction=0.15)
    mu = m.friction
    thd0 = 5.0 * math.sqrt(G / CR)
    r = run_general(m, -1j * CR, thd0 * CR + 0j, m.speed, 0.0, 0.05)
    first = r.contact_intervals()[0]
    assert first["kind"] == "sliding-forward" and first["t_start_s"] == 0.0

    def rhs(_t, y):
        th, thd = y
        n = -G * math.sin(th) + CR * thd * thd
        return [thd, (-G * math.cos(th) - mu * n) / CR]

    def normal(_t, y):
        return -G * math.sin(y[0]) + CR * y[1] * y[1]

    normal.terminal = True
    normal.direction = -1
    sol = solve_ivp(rhs, (0.0, 0.05), [-math.pi / 2, thd0], method="DOP853", events=normal, rtol=1e-12,
                    atol=1e-14, dense_output=True)
    t_lift = sol.t_events[0][0]
    th, thd = sol.y_events[0][0]
    assert math.sin(th) > 0.0  # it lifts off on the upper half, after turning round the wall
    assert first["t_end_s"] == pytest.approx(t_lift, rel=1e-8)
    # the flight from there: z = c_r e^{i theta} + i c_r theta' e^{i theta} s - i g s^2 / 2
    z0 = CR * complex(math.cos(th), math.sin(th))
    v0 = 1j * CR * thd * complex(math.cos(th), math.sin(th))

    def gap(s):
        z = z0 + v0 * s - 0.5j * G * s * s
        return abs(z) ** 2 - CR * CR

    # gap = O(s^3) at lift-off (n = 0): the grid starts past rounding's reach
    grid = np.linspace(1e-5, 0.05, 20001)
    vals = np.array([gap(s) for s in grid])
    assert vals[0] < 0.0
    i = int(np.argmax(vals > 0))
    s1 = brentq(gap, grid[i - 1], grid[i], xtol=1e-18, rtol=1e-15)
    assert r.column("t_s")[0] == pytest.approx(t_lift + s1, rel=1e-7)


def test_impacts_of_a_rotor_sliding_round_the_wall_accumulate_into_contact():
    """At 36,000 rpm the bounces shrink until their normal velocity is 1e-6 of the centre's speed, where the
    run follows the contact (below that, a flight's |z|^2 - 1 is rounding): hundreds of impacts, not 10^5."""
    m = machine(gravity=G, polar_inertia=0.04)
    r = drop(m, speed=36000 * RPM, t_end=0.02)
    v_n = r.column("normal_velocity_m_per_s")
    speed = np.abs(r.column("vx_plus") + 1j * r.column("vy_plus"))
    assert len(r.impacts) < 1000
    assert v_n[-1] < CHATTER_RELATIVE * 1.01 * speed[-1] and np.all(v_n[:-1] >= CHATTER_RELATIVE * 0.99 * speed[:-1])
    first = r.contact_intervals()[0]
    assert first["t_start_s"] == r.column("t_s")[-1] and first["kind"] == "sliding-forward"


def _energy_change_mp(m, v_n, v_rel, spin, polar):
    """Loss of m |z'|^2/2 + I_p Omega^2/2 at one impact on a fixed stator, the impact law of MODEL.md §7
    redone in 60-digit arithmetic from the state before it."""
    with mp.workdps(60):
        mass, radius, d, mu = (mp.mpf(x) for x in (m.mass, m.rotor_radius, m.restitution, m.friction))
        v_n, v_rel, spin, polar = (mp.mpf(float(x)) for x in (v_n, v_rel, spin, polar))
        v_t = v_rel - radius * spin
        kappa = 1 + mass * radius ** 2 / polar
        slip = mu * (1 + d) * v_n
        q_t = -v_rel / kappa if abs(v_rel) / kappa <= slip else -mp.sign(v_rel) * slip
        before = mass * (v_n ** 2 + v_t ** 2) / 2 + polar * spin ** 2 / 2
        after = mass * ((d * v_n) ** 2 + (v_t + q_t) ** 2) / 2 + polar * (spin + mass * radius * q_t / polar) ** 2 / 2
        return float(before - after)


@pytest.mark.parametrize("polar", [0.04, 1e8, 1e12])
def test_energy_of_an_impact_of_a_heavy_spinning_rotor_is_exact(polar):
    """A spin energy of 1e18 J no longer swamps the impact's loss of a few joules."""
    m = machine(gravity=G, polar_inertia=polar)
    r = drop(m, speed=30000 * RPM, t_end=0.0125)  # a few impacts from 10 ms after the failure, no contact
    assert len(r.impacts) >= 1 and len(r.contacts) == 0
    expected = np.array([_energy_change_mp(m, row[2], row[13], row[5], polar) for row in r.impacts])
    assert np.all(expected > 1.0)
    np.testing.assert_allclose(r.column("energy_lost_J"), expected, rtol=1e-10)
    assert r.energy_dissipated == pytest.approx(expected.sum(), rel=1e-10)


def test_a_drop_refuses_a_speed_above_the_bound_whether_given_or_the_machines():
    from rotorcontact.model.params import MAX_SPEED
    from rotorcontact.simulation.drop_run import check_drop_speed

    m = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
    assert check_drop_speed(m, MAX_SPEED) == MAX_SPEED
    for speed in (2.0 * MAX_SPEED, 1e30 * RPM, -1.0, 0.0, math.nan):
        with pytest.raises(ParameterError, match="^speed = .*(allowed|required)"):
            drop(m, speed, 0.0, 0.01)
    with pytest.raises(ParameterError, match="^speed = .*allowed"):  # a machine's own speed has the same bound
        Machine(**{**m.as_dict(), "speed": 1e30 * RPM})
    with pytest.raises(ParameterError, match="^--speed = .*allowed"):
        check_drop_speed(m, 1e30 * RPM, "--speed")


def test_a_drops_speed_is_rad_per_s_or_a_string_with_its_unit():
    from rotorcontact.simulation.drop_run import check_drop_speed
    from rotorcontact.studies.drop_map import drop_map

    m = reference_machine()
    assert check_drop_speed(m, "12000 rpm") == check_drop_speed(m, 12000 * RPM) == 12000 * RPM
    a, b = drop(m, "12000 rpm", 0.0, 0.01), drop(m, 12000 * RPM, 0.0, 0.01)
    assert a.speed == b.speed and np.array_equal(a.impacts, b.impacts)
    with pytest.raises(ParameterError, match="^speed = '12000' has no unit"):
        drop(m, "12000", 0.0, 0.01)
    with pytest.raises(ParameterError, match=r"^speeds\[1\] = '12000' has no unit"):  # before any drop
        drop_map(m, ["6000 rpm", "12000"])
    with pytest.raises(ParameterError, match=r"^frictions\[0\] = 'x' is text, not a number"):
        drop_map(m, ["6000 rpm"], ["x"])


def test_a_drop_whose_bearing_fails_after_the_end_is_refused():
    from rotorcontact.studies.drop_map import drop_map

    m = reference_machine()
    with pytest.raises(ParameterError, match="^fail_at = 1.0 s is not before t_end = 0.05 s"):
        drop(m, 1000.0, 1.0, 0.05)
    with pytest.raises(ParameterError, match="^fail_at = 0.05 s is not before t_end = 0.05 s"):
        drop_map(m, [1000.0], fail_at=0.05, t_end=0.05)


def test_a_failed_drop_has_the_regime_failed_never_levitated(failing_drops):
    m = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
    r = drop(m, 9000 * RPM, 0.0, 0.001)  # no impact yet: it would be "levitated" had it not failed
    assert r.status == "failed" and len(r.impacts) == 0 and len(r.contacts) == 0
    assert r.regime == "failed" and r.to_dict()["summary"]["regime"] == "failed"


@pytest.mark.parametrize("fail_at", [300.0, 1000.0])
def test_a_bearing_failing_after_a_long_levitated_run_drops_as_from_that_phase_of_the_whirl(fail_at):
    """A levitated whirl of thousands of periods is longer than one impact search's step budget: the flight
    goes on from where the search stopped. After the failure at T the drop is the one of a failure at 0 with
    the unbalance phase advanced by Omega T (the steady whirl at T), shifted by T."""
    m = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
    speed = 9000 * RPM
    late = drop(m, speed, fail_at, fail_at + 0.02)
    phase = math.remainder(m.unbalance_phase + speed * fail_at, 2.0 * math.pi)
    early = drop(Machine(**{**m.as_dict(), "unbalance_phase": phase}), speed, 0.0, 0.02)
    assert late.status == early.status == "completed" and len(late.impacts) == len(early.impacts) >= 2
    # the phase of the whirl at T holds the rounding of Omega T (about 1e-16 Omega T rad)
    np.testing.assert_allclose(late.column("t_s") - fail_at, early.column("t_s"), rtol=0, atol=1e-9)
    np.testing.assert_allclose(late.column("normal_impulse_Ns"), early.column("normal_impulse_Ns"), rtol=1e-5)


def test_a_drop_needs_a_machine():
    with pytest.raises(ParameterError, match="^machine = None is not a Machine object; allowed: rotorcontact.Machine$"):
        drop(None, 1000.0, 0.0, 0.05)


@pytest.mark.parametrize("machine", [None, "x"])
def test_the_drop_functions_refuse_what_is_not_a_machine(machine):
    from rotorcontact.simulation.drop_run import contact_force_history

    for call in (lambda: levitated_state(machine, 300.0), lambda: run_general(machine, 0j, 0j, 300.0, 0.0, 0.1),
                 lambda: contact_force_history(machine, 300.0, 0.0, [0.01]), lambda: drop(machine)):
        with pytest.raises(ParameterError, match=r"^machine = .* is not a Machine object"):
            call()


@pytest.mark.parametrize("call, match", [
    (lambda m: levitated_state(m, -1.0), r"^speed = -1.0 is out of range"),
    (lambda m: levitated_state(m, True), r"^speed = True is a bool"),
    (lambda m: run_general(m, 0j, 0j, 1e300, 0.0, 0.05), r"^speed = 1e\+300 is out of range"),
    (lambda m: run_general(m, 0j, 0j, "100", 0.0, 0.05), r"^speed = '100' is text"),
    (lambda m: run_general(m, "x", 0j, 100.0, 0.0, 0.05), r"^z0 = 'x' is text"),
    (lambda m: run_general(m, 0j, None, 100.0, 0.0, 0.05), r"^v0 = None"),
    (lambda m: run_general(m, 0j, 0j, 100.0, -1.0, 0.05), r"^fail_at = -1.0 is out of range"),
    (lambda m: run_general(m, 0j, 0j, 100.0, 0.0, 1e300),
     r"^t_end = 1e\+300 is out of range; allowed: \(0, 100000\] s"),
    (lambda m: run_general(m, 0j, 0j, 0.0, 0.0, 1e300), r"^t_end = 1e\+300 is out of range; allowed: \(0, 10000\] s"),
    (lambda m: run_general(m, 0j, 0j, 100.0, 0.0, 0.05, stator_start=0j), r"^stator_start = "),
    (lambda m: run_general(m, 0j, 0j, 100.0, 0.0, 0.05, max_events=0), r"^max_events = 0 is invalid"),
    (lambda m: run_general(m, 0j, 0j, 100.0, 0.0, 0.05, max_events="x"), r"^max_events = 'x' is invalid"),
    (lambda m: drop(m, None, 0.0, 1e300), r"^t_end = 1e\+300 is out of range; allowed: \(0, 10000\]"),
    (lambda m: run_general(m, 0j, 1e30, 100.0, 0.0, 0.01), r"^v0 = \(1e\+30\+0j\) m/s is too fast .* allowed: \|v0\| "
                                                          r"<= 1000 m/s$"),
])
def test_the_drop_functions_refuse_bad_speeds_states_and_times_by_name(call, match):
    with pytest.raises(ParameterError, match=match):
        call(reference_machine())


def test_a_run_whose_bearing_never_fails_is_a_run_with_fail_at_inf():
    r = run_general(reference_machine(), 0j, 0j, 100.0, math.inf, 0.05)
    assert r.status == "completed"


def test_the_velocity_scale_of_a_backward_spin_is_positive():
    from rotorcontact.simulation.drop_run import _velocity_scale

    m = reference_machine()
    weightless = Machine(**{**m.as_dict(), "gravity": 0.0}) if m.g > 0.0 else m
    assert weightless.g == 0.0
    assert _velocity_scale(weightless, -100.0) == _velocity_scale(weightless, 100.0) == weightless.clearance * 100.0


def test_a_compliant_start_deeper_than_a_clearance_and_bad_force_times_are_refused():
    from rotorcontact.simulation.drop_run import contact_force_history

    m = Machine(**{**reference_machine().as_dict(), "contact": "compliant", "contact_stiffness": 1e9})
    with pytest.raises(ParameterError, match=r"^z0 = \(1\+0j\) m lies .* m inside the stator; allowed: "
                                             r"\|z0 - z_s\| <= 2 c_r"):
        run_general(m, 1.0, 0j, 100.0, 0.0, 0.001)
    # a start just inside the stator is an episode at once, as documented
    assert run_general(m, 1.001 * m.clearance, 0j, 100.0, 0.0, 1e-4).status != "failed"
    for times in ([], [0.0], [math.nan], ["0.01"], np.full(1001, 0.01), [[0.01, 0.02]]):
        with pytest.raises(ParameterError, match=r"^times = .* is invalid; allowed: 1 to 1000 finite times > 0"):
            contact_force_history(m, 100.0, 0.0, times)
    with pytest.raises(ParameterError, match=r"^start = .* is invalid; allowed: \(z0, v0\)"):
        contact_force_history(m, 100.0, 0.0, [0.01], start=0j)



def test_a_drop_results_column_is_one_of_its_fields():
    from rotorcontact.simulation.drop import IMPACT_FIELDS

    r = run_general(reference_machine(), 0j, 0j, 100.0, 0.0, 0.01)
    assert r.column(IMPACT_FIELDS[0]).shape == (len(r.impacts),)
    for bad in ("x", None, 0):
        with pytest.raises(ParameterError, match=r"^name = .* is invalid; allowed: 't_s', "):
            r.column(bad)
