"""The compliant contact law (MODEL.md §8) against closed forms, its asymptotics and the rigid kernel."""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from rotorcontact import Machine, ParameterError, reference_machine
from rotorcontact.model.machine_model import elastic_impact_duration, hertz_rebound, restitution_damping
from rotorcontact.simulation.drop import COMPLIANT_FIELDS, IMPACT_FIELDS
from rotorcontact.simulation.drop_run import RPM, drop, levitated_state, run_general

COL = {name: i for i, name in enumerate(IMPACT_FIELDS)}
KC = 1e10  # N/m^1.5


def machine(**changes):
    return Machine(**{**reference_machine().as_dict(), **changes})


def isolated(d, v0, n=1.5, kc=KC, tol=1e-10):
    """One radial impact at v0 (m/s): no gravity, unbalance or friction, the bearing failed at t = 0."""
    m = machine(eccentricity=0.0, friction=0.0, restitution=d, contact="compliant", contact_stiffness=kc,
                contact_exponent=n)
    # reaches the wall at c_r / v0; the episode lasts less than 10 delta_max / v0 (3 delta_max / v0 elastic)
    dmax = ((n + 1.0) * m.mass * v0**2 / (2.0 * kc)) ** (1.0 / (n + 1.0))
    t_end = (m.clearance + 10.0 * dmax) / v0
    r = run_general(m, 0j, complex(v0, 0.0), m.speed, 0.0, t_end, tol=tol)
    # (a fast impact may reach the opposite wall within t_end: the first episode is the one)
    assert len(r.impacts) >= 1 and r.t_stop == t_end and r.impacts[0, COL["duration_s"]] < 10.0 * dmax / v0
    return m, r.impacts[0]


@pytest.mark.parametrize("d", [0.3, 0.6, 0.9, 0.95])
@pytest.mark.parametrize("v0", [0.01, 0.1, 1.0])
def test_isolated_impact_rebounds_with_the_restitution_at_every_speed(d, v0):
    m, row = isolated(d, v0)
    assert row[COL["rebound_ratio"]] == pytest.approx(d, rel=1e-8)
    assert row[COL["normal_velocity_m_per_s"]] == pytest.approx(v0, rel=1e-12)
    # the velocity after, and the energy the damping dissipated (integrated with the motion)
    assert row[COL["vx_plus"]] == pytest.approx(-d * v0, rel=1e-8)
    assert row[COL["energy_lost_J"]] == pytest.approx(0.5 * m.mass * v0**2 * (1.0 - d * d), rel=1e-7)
    # the normal impulse is the change of momentum
    assert row[COL["normal_impulse_Ns"]] == pytest.approx(m.mass * (1.0 + d) * v0, rel=1e-8)
    assert row[COL["tangential_impulse_Ns"]] == 0.0


@pytest.mark.parametrize("d", [0.5, 0.9])
def test_linear_law_rebounds_with_the_restitution(d):
    _m, row = isolated(d, 0.1, n=1.0, kc=1e8)
    assert row[COL["rebound_ratio"]] == pytest.approx(d, rel=1e-8)


def _hertz(m, v0, kc, n):
    """delta_max, F_max and the duration of an undamped Hertz impact: the duration by mpmath's quadrature of
    dt = d delta / sqrt(v0^2 - 2 K_c delta^(n+1) / ((n+1) m)) (tanh-sinh handles the end's singularity)."""
    mp.mp.dps = 30
    dmax = ((n + 1) * m * v0**2 / (2.0 * kc)) ** (1.0 / (n + 1))
    # with delta = delta_max u: v0^2 - 2 K_c delta^(n+1) / ((n+1) m) = v0^2 (1 - u^(n+1))
    p = mp.mpf(n) + 1
    integral = mp.quad(lambda u: 1 / mp.sqrt(1 - u**p), [0, 1])
    assert integral == pytest.approx(float(mp.beta(1 / p, mp.mpf(1) / 2) / p), rel=1e-20)
    return dmax, kc * dmax**n, float(2 * integral) * dmax / v0


@pytest.mark.parametrize("v0,n,kc", [(0.01, 1.5, KC), (0.3, 1.5, KC), (0.1, 1.5, 1e12), (0.1, 1.0, 1e8)])
def test_elastic_impact_peak_force_penetration_and_duration_are_hertz(v0, n, kc):
    m, row = isolated(1.0, v0, n=n, kc=kc)
    dmax, fmax, duration = _hertz(m.mass, v0, kc, n)
    assert row[COL["max_penetration_m"]] == pytest.approx(dmax, rel=1e-9)
    assert row[COL["max_force_N"]] == pytest.approx(fmax, rel=1e-8)
    assert row[COL["duration_s"]] == pytest.approx(duration, rel=1e-9)
    # the closed form the kernel uses to tell lasting contact from impacts
    assert elastic_impact_duration(m.mass, v0, kc, n) == pytest.approx(duration, rel=1e-13)
    assert row[COL["rebound_ratio"]] == pytest.approx(1.0, rel=1e-8)
    assert row[COL["energy_lost_J"]] == 0.0  # no damping part, no friction


def test_damping_factor_tends_to_the_small_damping_limit():
    # to first order in chi the impact loses chi * 2/3 of its energy's worth of velocity: 1 - d = (2/3) chi
    # for every n (the integral of u^n u'^2 over the elastic impact is 2/3); chi = 3 (1 - d) / 2 as d -> 1
    for n in (1.0, 1.5, 2.0):
        ratios = [restitution_damping(d, n) / (1.5 * (1.0 - d)) for d in (0.99, 0.999, 0.9999)]
        errors = [abs(r - 1.0) for r in ratios]
        assert errors[2] < 2e-4
        assert errors[1] / errors[0] == pytest.approx(0.1, rel=0.1)  # the error is O(1 - d)
    assert restitution_damping(1.0, 1.5) == 0.0
    # the solved chi reproduces d through an independent evaluation at a tighter tolerance
    for d in (0.3, 0.95):
        assert hertz_rebound(restitution_damping(d, 1.5), 1.5, rtol=1e-13) == pytest.approx(d, rel=1e-10)


def test_restitution_damping_refuses_zero():
    with pytest.raises(ValueError, match="restitution"):
        restitution_damping(0.0, 1.5)


def _drop_from_centre(kc, t_end=0.05, **changes):
    base = dict(eccentricity=0.0, gravity=9.81, polar_inertia=0.04, restitution=0.9)
    base.update(changes)
    m = machine(**base) if kc is None else machine(**base, contact="compliant", contact_stiffness=kc)
    return run_general(m, 0j, 0j, 3000 * RPM, 0.0, t_end)


def test_rigid_limit_converges_at_the_rate_of_the_contact_duration():
    # the episode lasts T_c ~ K_c^(-1/(n+1)); the next impact time and the state after the first episode
    # differ from the rigid kernel's by O(T_c): tenfold K_c divides the differences by 10^(2/5)
    rigid = _drop_from_centre(None)
    assert len(rigid.impacts) == 3
    diffs = []
    for kc in (1e11, 1e12, 1e13):
        r = _drop_from_centre(kc)
        assert len(r.impacts) == len(rigid.impacts)
        row, ref = r.impacts[0], rigid.impacts[0]
        diffs.append((abs(r.impacts[1, 0] - rigid.impacts[1, 0]),
                      abs(complex(row[COL["vx_plus"]], row[COL["vy_plus"]])
                          - complex(ref[COL["vx_plus"]], ref[COL["vy_plus"]])),
                      abs(row[COL["spin_after"]] - ref[COL["spin_after"]]),
                      row[COL["duration_s"]]))
        assert row[COL["tangential_impulse_Ns"]] == pytest.approx(ref[COL["tangential_impulse_Ns"]], rel=0.05)
    diffs = np.array(diffs)
    rate = 10.0 ** -0.4
    for k in range(4):
        ratios = diffs[1:, k] / diffs[:-1, k]
        assert ratios == pytest.approx([rate, rate], rel=0.02)
    # the differences are of the order of the duration of the contact
    assert np.all(diffs[:, 0] < diffs[:, 3])


def _energy(m, state):
    """m |v|^2/2 + I_p Omega^2/2 + I_b Omega_b^2/2 + m g y + the elastic energy K_c delta^(n+1)/(n+1)."""
    x, y, vx, vy, spin, race = state[1:7]
    delta = max(math.hypot(x, y) - m.clearance, 0.0)
    elastic = m.contact_stiffness * delta ** (m.exponent + 1.0) / (m.exponent + 1.0)
    race_energy = 0.5 * m.race_inertia * race**2 if m.has_race else 0.0
    return (0.5 * m.mass * (vx * vx + vy * vy) + 0.5 * m.polar_inertia * spin**2 + race_energy + m.mass * m.g * y
            + elastic)


RACE = dict(race_inertia=2e-4, race_drag_torque=0.1, race_drag_coefficient=1e-4)


@pytest.mark.parametrize("t_end, race", [(0.02, {}), (0.0421, {}), (0.0421, RACE), (0.3, RACE)])
def test_dissipated_energy_is_the_fall_of_the_mechanical_energy(t_end, race):
    # with a race: friction spins it up, its drag (static torque held at rest, and viscous) dissipates
    r = _drop_from_centre(1e10, t_end=t_end, **race)
    m = r.machine
    if race:
        assert r.final_state[6] != 0.0
    start = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 3000 * RPM, 0.0])
    lost = _energy(m, start) - _energy(m, r.final_state)
    assert r.energy_dissipated > 0.0
    assert r.energy_dissipated == pytest.approx(lost, rel=1e-8)


def test_elastic_frictionless_drop_conserves_energy():
    r = _drop_from_centre(1e10, t_end=0.0421, restitution=1.0, friction=0.0)
    m = r.machine
    assert len(r.impacts) >= 2
    start = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 3000 * RPM, 0.0])
    assert r.energy_dissipated == 0.0
    assert _energy(m, r.final_state) == pytest.approx(_energy(m, start), abs=1e-10 * m.mass * 9.81 * m.clearance)


def tolerance_pair(m, speed, min_impacts):
    """A 0.05 s drop of ``m`` from its levitated whirl at ``speed`` at the default tolerance and at 1e-12, with
    every episode's time, duration, peak force and penetration, spin and impulse checked to agree; returns both
    runs."""
    z0, v0 = levitated_state(m, speed)
    loose = run_general(m, z0, v0, speed, 0.0, 0.05, tol=1e-10)
    tight = run_general(m, z0, v0, speed, 0.0, 0.05, tol=1e-12)
    assert len(loose.impacts) == len(tight.impacts) >= min_impacts
    np.testing.assert_allclose(loose.column("t_s"), tight.column("t_s"), rtol=0, atol=1e-9)
    for name in ("duration_s", "max_force_N", "max_penetration_m", "spin_after", "normal_impulse_Ns"):
        np.testing.assert_allclose(loose.column(name), tight.column(name), rtol=1e-7)
    return loose, tight


def test_results_do_not_depend_on_the_tolerance():
    tolerance_pair(machine(gravity=9.81, polar_inertia=0.04, contact="compliant", contact_stiffness=KC),
                   12000 * RPM, 5)


def test_rigid_runs_keep_their_table_and_contract():
    m = machine(gravity=9.81, polar_inertia=0.04)
    r = drop(m, 12000 * RPM, 0.0, 0.02)
    assert len(r.impacts) > 0
    for name in COMPLIANT_FIELDS:
        assert np.all(np.isnan(r.column(name)))
    row = r.to_dict()["impacts"][0]
    assert not set(COMPLIANT_FIELDS) & set(row)


def test_compliant_drop_contract():
    m = machine(gravity=9.81, polar_inertia=0.04, contact="compliant", contact_stiffness=KC)
    r = drop(m, 12000 * RPM, 0.0, 0.05)
    out = r.to_dict()
    assert out["machine"]["contact"] == "compliant"
    rows = out["impacts"]
    assert len(rows) == len(r.impacts) >= 5
    for row, raw in zip(rows, r.impacts):
        for name in COMPLIANT_FIELDS[:-1]:
            value = raw[COL[name]]
            assert row[name] == (float(value) if math.isfinite(value) else None)
        assert row["kind"] == ("sliding-forward", "rolling", "sliding-backward")[int(raw[COL["kind"]])]
    # every finished episode has a rebound; the peak force is K_c delta^n at most (the damping part adds
    # while penetrating, so it may exceed K_c delta_max^n, never the force at the deepest point by much)
    assert all(row["rebound_ratio"] is not None for row in rows[:-1])
    assert out["summary"]["max_contact_force_N"] == pytest.approx(r.column("max_force_N").max(), rel=0)
    assert all(row["duration_s"] > 0.0 and row["max_force_N"] > 0.0 for row in rows)


@pytest.mark.parametrize("changes,match", [
    (dict(contact="soft"), "contact = 'soft'"),
    (dict(contact="compliant"), "contact_stiffness = None"),
    (dict(contact_stiffness=1e10), "contact_stiffness = 10000000000.0 with contact = None"),
    (dict(contact_exponent=1.0), "contact_exponent = 1.0"),
    (dict(contact="compliant", contact_stiffness=1e10, restitution=0.0), "restitution = 0.0"),
    (dict(contact="compliant", contact_stiffness=-1.0), "contact_stiffness = -1.0"),
    (dict(contact="compliant", contact_stiffness=1e10, contact_exponent=0.0), "contact_exponent = 0.0"),
])
def test_bad_contact_keys_are_refused(changes, match):
    with pytest.raises(ParameterError, match=match):
        machine(**changes)


def test_compliant_machine_file_with_units(tmp_path):
    path = tmp_path / "m.toml"
    from tests.reference_parameters import REF_MACHINE_TOML

    path.write_text(REF_MACHINE_TOML + 'contact = "compliant"\ncontact_stiffness = "1 kN/mm**1.5"\n'
                    'contact_exponent = 1.5\n')
    from rotorcontact import load_machine

    m = load_machine(path)
    assert m.compliant and m.contact_stiffness == pytest.approx(1e3 / 1e-3**1.5, rel=1e-14)
    # an exponent out of range is refused under its own name, not through the unit of K_c it would give
    for bad in ("0", "-1.5", "11"):
        path.write_text(REF_MACHINE_TOML + 'contact = "compliant"\ncontact_stiffness = "1e10 N/m**1.5"\n'
                        f"contact_exponent = {bad}\n")
        with pytest.raises(ParameterError, match=f"contact_exponent = {float(bad)!r} is out of range"):
            load_machine(path)
    assert m.needs_general_model
    rigid = load_machine("reference")
    assert rigid.contact is None and not rigid.compliant and rigid.as_dict() == reference_machine().as_dict()


def test_force_history_of_an_elastic_impact_is_hertz():
    # the undamped Hertz impact in closed form: t(delta) = int_0^delta dx / sqrt(v0^2 - 2 K_c x^(n+1)/((n+1) m))
    v0, n = 0.1, 1.5
    m = machine(eccentricity=0.0, friction=0.0, restitution=1.0, contact="compliant", contact_stiffness=KC)
    t_wall = m.clearance / v0
    dmax, fmax, duration = _hertz(m.mass, v0, KC, n)
    mp.mp.dps = 20
    deltas = np.linspace(0.1, 0.95, 6) * dmax
    elapsed = [float(mp.quad(lambda x: 1 / mp.sqrt(v0**2 - 2 * KC * x ** (n + 1) / ((n + 1) * m.mass)), [0, dl]))
               for dl in deltas]
    from rotorcontact.simulation.drop_run import contact_force_history

    times = np.concatenate((t_wall + np.array(elapsed), [t_wall * 0.5, t_wall + duration * 1.01]))
    forces = contact_force_history(m, m.speed, 0.0, times, start=(0j, complex(v0, 0.0)))
    np.testing.assert_allclose(forces[:6], KC * deltas**n, rtol=1e-7)
    assert forces[6] == 0.0 and forces[7] == 0.0
    with pytest.raises(ParameterError, match="contact = None"):
        contact_force_history(machine(), 184.2, 0.0, [0.1])
    # a speed is checked before it is used: with units without a start, in rad/s with one
    rpm = m.speed * 30.0 / math.pi
    by_rpm = contact_force_history(m, f"{rpm!r} rpm", 0.0, [t_wall])
    assert by_rpm == pytest.approx(contact_force_history(m, m.speed, 0.0, [t_wall]), rel=1e-9)
    for speed in ("fast", None, math.inf):
        with pytest.raises(ParameterError, match=r"^speed = "):
            contact_force_history(m, speed, 0.0, times, start=(0j, complex(v0, 0.0)))


@pytest.mark.parametrize("spin, kind", [(0.125, 1.0), (100.0, 0.0), (-100.0, 2.0)])
def test_episode_kind_and_coulomb_impulse(spin, kind):
    # a radial impact at 0.1 m/s with the speed held: v_rel = R Omega. Sliding throughout, the friction
    # impulse is exactly -mu sgn(v_rel) P_n; a slow spin is stopped early (the rigid law would stick:
    # R |Omega| < mu (1 + d) v0) and the surfaces roll for most of the episode
    m = machine(eccentricity=0.0, contact="compliant", contact_stiffness=KC)
    v0 = 0.1
    r = run_general(m, 0j, complex(v0, 0.0), spin, 0.0, m.clearance / v0 + 5e-3)
    row = r.impacts[0]
    assert row[COL["kind"]] == kind
    p_n, p_t = row[COL["normal_impulse_Ns"]], row[COL["tangential_impulse_Ns"]]
    if kind != 1.0:
        assert p_t == pytest.approx(-m.friction * math.copysign(p_n, spin), rel=1e-12)
    else:
        assert m.rotor_radius * spin < m.friction * (1.0 + m.restitution) * v0
        assert abs(p_t) < m.friction * p_n
        assert r.to_dict()["impacts"][0]["kind"] == "rolling"


@pytest.mark.parametrize("d", [0.5, 0.95])
def test_a_bouncing_rotor_settles_in_one_lasting_episode_at_the_static_penetration(d):
    # no spin: the bounces die out and the last episode lasts to the end, at m g = K_c delta^n
    m = machine(eccentricity=0.0, gravity=9.81, restitution=d, contact="compliant", contact_stiffness=KC)
    r = run_general(m, 0j, 0j, 0.0, 0.0, 1.0)
    assert r.status == "completed" and len(r.impacts) >= 2
    last = r.impacts[-1]
    assert last[COL["t_s"]] + last[COL["duration_s"]] == pytest.approx(1.0, rel=1e-14)
    assert math.isnan(last[COL["rebound_ratio"]]) and r.to_dict()["impacts"][-1]["rebound_ratio"] is None
    x, y = r.final_state[1:3]
    assert x == pytest.approx(0.0, abs=1e-15) and y < 0.0
    static = (m.mass * 9.81 / KC) ** (1.0 / 1.5)
    assert math.hypot(x, y) - m.clearance == pytest.approx(static, rel=1e-6)
    assert np.all(np.diff(r.column("t_s")) > 0.0) and np.all(r.impacts[:-1, COL["rebound_ratio"]] > 0.0)
    # the lasting episode, and it alone, is a contact interval: no whirl without spin
    (interval,) = r.contact_intervals()
    assert interval["t_start_s"] == last[COL["t_s"]] and interval["t_end_s"] == 1.0
    assert interval["max_normal_force_N"] == last[COL["max_force_N"]] >= m.mass * 9.81
    assert abs(interval["whirl_frequency_hz"]) < 1e-6
    assert r.regime == "contact"


def test_a_drop_ends_in_a_lasting_rolling_episode_listed_as_backward_whirl():
    m = machine(gravity=9.81, polar_inertia=0.04, contact="compliant", contact_stiffness=KC)
    speed = 12000 * RPM
    r = drop(m, speed, 0.0, 0.2)
    last = r.impacts[-1]
    assert len(r.impacts) >= 3 and last[COL["kind"]] == 1.0
    (interval,) = r.contact_intervals()
    assert interval["kind"] == "rolling" and interval["t_start_s"] == last[COL["t_s"]]
    assert interval["t_end_s"] == 0.2 and interval["max_normal_force_N"] == last[COL["max_force_N"]]
    # rolling on a fixed stator whirls backward at R Omega / (c_r + delta) with delta within [0, delta_max]
    whirl = -2.0 * math.pi * interval["whirl_frequency_hz"]
    spin_end = r.final_state[5]
    assert m.rotor_radius * spin_end / (m.clearance + last[COL["max_penetration_m"]]) <= whirl
    assert whirl <= m.rotor_radius * last[COL["spin_before"]] / m.clearance
    assert r.regime == "backward-whirl" and r.backward_whirl_onset <= interval["t_start_s"]
    assert r.to_dict()["contact_intervals"] == r.contact_intervals()


def _episode_p(stator=(0.0, 0.0, 0.0, 0.0, 0.0), n=1.5):
    from rotorcontact.simulation.drop import _episode_params

    return _episode_params(50.0, 0.7e-3, 0.0, 0.04, 0.3, 0.0, 0.0, 0.0, 0.0, -9.81, 1.0 / 0.04, 0.0, 0.0, 0.0,
                           KC, n, 0.0, 1e-10, 1.0, np.array(stator, dtype=float))


def _own_energy_above_rest(y, mass, cr, g, kc, n, ksx=0.0, ksy=0.0):
    """Kinetic and potential energy less their value at rest, written out: gravity, the contact's elasticity
    and the stator's springs, the rest found from the balance of the weight (no stator: ksy = 0)."""
    ke = 0.5 * mass * (y[2] ** 2 + y[3] ** 2) + 0.5 * 0.04 * y[5] ** 2
    if ksy > 0.0:
        ke += 0.5 * 2.0 * (y[13] ** 2 + y[14] ** 2)  # stator mass 2 kg
    delta = math.hypot(y[0] - y[11], y[1] - y[12]) - cr
    ds = (mass * g / kc) ** (1.0 / n)
    ys_rest = -mass * g / ksy if ksy > 0.0 else 0.0
    y_rest = ys_rest - (cr + ds)

    def potential(yy, d, xs, ys):
        return mass * g * yy + (kc * d ** (n + 1) / (n + 1) if d > 0 else 0.0) + 0.5 * (ksx * xs**2 + ksy * ys**2)

    return ke + potential(y[1], delta, y[11], y[12]) - potential(y_rest, ds, 0.0, ys_rest)


@pytest.mark.parametrize("stator", [None, (1.0 / 2.0, 2e6, 5e6, 0.0, 0.0)])
def test_the_energy_above_rest_is_zero_at_rest_and_the_written_out_energy_elsewhere(stator):
    from rotorcontact.simulation.compliant import NY, energy_above_rest

    mass, cr, g, n = 50.0, 0.7e-3, 9.81, 1.5
    p = _episode_p() if stator is None else _episode_p(stator)
    ksx, ksy = (0.0, 0.0) if stator is None else stator[1:3]
    ds = (mass * g / KC) ** (1.0 / n)
    ys = -mass * g / ksy if stator is not None else 0.0
    rest = np.zeros(NY)
    rest[1], rest[12] = ys - (cr + ds), ys
    scale = mass * g * cr
    assert abs(energy_above_rest(rest, p)) <= 1e-12 * scale
    rng = np.random.default_rng(3)
    for _ in range(20):
        y = rest.copy()
        angle = -math.pi / 2 + rng.uniform(-0.3, 0.3)
        radius = cr + rng.uniform(-0.5, 1.5) * ds
        y[11:13] = (rng.uniform(-1e-5, 1e-5, 2) if stator is not None else 0.0)
        y[0], y[1] = y[11] + radius * math.cos(angle), y[12] + radius * math.sin(angle)
        y[2], y[3], y[5] = rng.normal(0.0, 1e-3, 3)
        if stator is not None:
            y[13:15] = rng.normal(0.0, 1e-3, 2)
        own = _own_energy_above_rest(y, mass, cr, g, KC, n, ksx, ksy)
        assert own > 0.0
        assert energy_above_rest(y, p) == pytest.approx(own, rel=1e-9, abs=1e-12 * scale)


def test_a_compliant_rotor_rocking_at_the_bottom_rests_only_when_its_energy_above_rest_is_spent():
    """A rotor rolling to and fro at the bottom of a compliant wall passes through zero kinetic energy at each
    turning point; its rest is where its energy above rest, potential included, falls to 1e-8 of the kinetic
    energy at the start (as for the rigid law), not at a turning point of a swing."""
    from rotorcontact.simulation.drop_run import REST_FRACTION

    m = machine(eccentricity=0.0, gravity=9.81, polar_inertia=0.04, race_inertia=0.005, race_drag_torque=0.0,
                race_drag_coefficient=0.3, friction=0.3, contact="compliant", contact_stiffness=KC, restitution=0.9)
    cr, radius, amp, thd0 = m.clearance, m.rotor_radius, 0.3, -5.0
    ds = (m.mass * 9.81 * math.cos(amp) / KC) ** (1.0 / 1.5)
    speed = -cr * thd0 / radius
    th0 = -math.pi / 2 + amp
    z0 = (cr + ds) * complex(math.cos(th0), math.sin(th0))
    v0 = 1j * cr * thd0 * complex(math.cos(th0), math.sin(th0))
    r = run_general(m, z0, v0, speed, 0.0, 20.0)
    assert r.status == "at-rest"
    fs = r.final_state
    y = np.zeros(15)
    y[0], y[1], y[2], y[3], y[5] = fs[1], fs[2], fs[3], fs[4], fs[5]
    ke0 = 0.5 * m.mass * abs(v0) ** 2 + 0.5 * 0.04 * speed**2
    left = _own_energy_above_rest(y, m.mass, cr, 9.81, KC, 1.5)
    assert 0.0 <= left <= REST_FRACTION * ke0 * (1.0 + 1e-6)
