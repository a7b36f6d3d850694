"""The steady dry whip (MODEL.md §8) against the equations of motion of each body and against the simulator."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

from rotorcontact import Machine, ParameterError, reference_machine
from rotorcontact.analysis.dry_whip import steady_dry_whip
from rotorcontact.simulation.drop_run import run_general

KC = 1e10  # N/m^1.5
STATOR = dict(stator_mass=20.0, stator_stiffness=4e6, stator_damping=400.0)


def machine(**changes):
    base = {**reference_machine().as_dict(), "contact": "compliant", "contact_stiffness": KC, "eccentricity": 0.0,
            "friction": 0.2, "speed": 100.0, **STATOR}
    return Machine(**{**base, **changes})


@pytest.mark.parametrize("failed", [True, False])
@pytest.mark.parametrize("damping", [400.0, 100.0])
def test_the_whip_satisfies_each_body_s_equation_of_motion(failed, damping):
    # written out from Newton's law for the circular whirl, not from G = A B / (A + B)
    m = machine(stator_damping=damping, damping=50.0)  # a whip exists on a lightly damped live bearing
    whip = steady_dry_whip(m, bearing_failed=failed)
    w, r, zeta = whip.whirl_rate, whip.rotor_orbit, whip.stator_orbit
    k, c = (0.0, 0.0) if failed else (m.stiffness, m.damping)
    gap = r - zeta
    n = gap / abs(gap)
    contact = (-whip.normal_force + 1j * whip.friction_force) * n  # on the rotor
    scale = whip.normal_force
    assert abs(-m.mass * w * w * r - (-(k + 1j * c * w) * r + contact)) <= 1e-10 * scale
    support = -(m.stator_stiffness + 1j * m.stator_damping * w) * zeta
    assert abs(-m.stator_mass * w * w * zeta - (support - contact)) <= 1e-10 * scale
    assert abs(gap) == pytest.approx(m.clearance + whip.penetration, rel=1e-14)
    assert whip.normal_force == pytest.approx(KC * whip.penetration**1.5, rel=1e-12)
    assert whip.friction_force == -m.friction * whip.normal_force
    assert whip.slip_velocity == pytest.approx(m.rotor_radius * m.speed + w * abs(gap), rel=1e-14)
    coupled = math.sqrt((k + m.stator_stiffness) / (m.mass + m.stator_mass))
    assert whip.coupled_frequency == pytest.approx(coupled, rel=1e-15)
    assert -coupled < w < 0.0


def test_the_whip_tends_to_the_coupled_natural_frequency_as_the_support_damping_vanishes():
    # (the orbit grows as the damping falls: a faster spin keeps the contact sliding)
    whips = [steady_dry_whip(machine(stator_damping=c, speed=1e4)) for c in (400.0, 100.0, 25.0, 5.0)]
    shifts = [1.0 + whip.whirl_rate / whip.coupled_frequency for whip in whips]
    assert 0.0 < shifts[3] < shifts[2] < shifts[1] < shifts[0] < 0.07
    assert shifts[3] < 1e-3


def test_of_several_roots_the_whip_is_the_one_closest_below_the_coupled_frequency():
    # a lightly damped live bearing adds a root near sqrt(k/m) below the whip, and one lies above the
    # stator's own frequency sqrt(k_s/m_s) (MODEL.md §8): located here by a dense scan of Im G - mu Re G
    m = machine(damping=50.0)
    whip = steady_dry_whip(m, bearing_failed=False)
    k, c, ks, cs = m.kx, m.cx, m.stator_stiffness, m.stator_damping
    w = -np.linspace(1.0, 3.0 * math.sqrt(ks / m.stator_mass), 400_001)
    a = k - m.mass * w**2 + 1j * c * w
    b = ks - m.stator_mass * w**2 + 1j * cs * w
    g = a * b / (a + b)
    residual = g.imag - m.friction * g.real
    roots = w[np.flatnonzero(np.sign(residual[1:]) != np.sign(residual[:-1]))]
    assert len(roots) == 3
    low, whip_root, high = sorted(roots, reverse=True)
    assert low == pytest.approx(-math.sqrt(k / m.mass), rel=0.05)
    assert high < -math.sqrt(ks / m.stator_mass)
    assert whip.whirl_rate == pytest.approx(whip_root, abs=2.0 * (w[0] - w[1]))


@pytest.mark.parametrize("damping, failed", [(400.0, True), (200.0, True), (400.0, False)])
def test_the_simulator_started_on_the_whip_stays_on_it(damping, failed):
    m = machine(stator_damping=damping, damping=50.0)
    whip = steady_dry_whip(m, bearing_failed=failed)
    z, v, zs, vs = whip.state(0.0)
    t_end = 0.2  # 7 whirl periods
    res = run_general(m, z, v, m.speed, 0.0 if failed else math.inf, t_end, stator_start=(zs, vs))
    assert res.status == "completed" and len(res.impacts) == 1
    z1, v1, zs1, _vs1 = whip.state(t_end)
    r = abs(whip.rotor_orbit)
    assert abs(complex(*res.final_state[1:3]) - z1) <= 1e-8 * r
    assert abs(complex(*res.final_state[3:5]) - v1) <= 1e-8 * abs(whip.whirl_rate) * r
    assert abs(complex(*res.final_state[8:10]) - zs1) <= 1e-8 * abs(whip.stator_orbit)
    (interval,) = res.contact_intervals()
    assert interval["kind"] == "sliding-forward" and interval["t_end_s"] == t_end
    assert interval["whirl_frequency_hz"] == pytest.approx(whip.whirl_frequency_hz, rel=1e-9)
    assert interval["max_normal_force_N"] == pytest.approx(whip.normal_force, rel=1e-8)
    # the whirl follows the coupled system, far below the rolling rate R Omega / rho of dry whirl
    rolling = m.rotor_radius * m.speed / (m.clearance + whip.penetration)
    assert rolling > 10.0 * abs(whip.whirl_rate)
    assert cmath.phase(complex(*res.final_state[8:10]) / complex(*res.final_state[1:3])) == pytest.approx(
        cmath.phase(whip.stator_orbit / whip.rotor_orbit), abs=1e-8)


@pytest.mark.parametrize("changes,match", [
    (dict(stator_mass=None, stator_stiffness=None, stator_damping=None), "stator_mass = None"),
    (dict(friction=0.0), "friction = 0.0"),
    (dict(stator_stiffness_x=3e6), "isotropic support"),
    (dict(speed=0.5), r"speed = 0.5 rad/s.*allowed: a speed above [0-9.]+ rad/s \([0-9.]+ rpm\)"),
    (dict(stator_damping=0.0), "stator_damping = 0.0 with no bearing damping"),
    (dict(polar_inertia=0.04, race_inertia=2e-4, race_drag_torque=0.0, race_drag_coefficient=1e-4), "race_inertia"),
])
def test_bad_machines_are_refused(changes, match):
    with pytest.raises(ParameterError, match=match):
        steady_dry_whip(machine(**changes))


def test_a_live_anisotropic_bearing_is_refused():
    with pytest.raises(ParameterError, match=r"anisotropic bearing \(stiffness 1000000.0, 980000.0 N/m"):
        steady_dry_whip(machine(stiffness_x=1e6), bearing_failed=False)


@pytest.mark.parametrize("machine", [None, "x"])
def test_what_is_not_a_machine_is_refused(machine):
    with pytest.raises(ParameterError, match=r"^machine = .* is not a Machine object"):
        steady_dry_whip(machine)


@pytest.mark.parametrize("flag", ["False", None, 0])
def test_a_bearing_failed_flag_that_is_not_a_bool_is_refused(flag):
    with pytest.raises(ParameterError, match=r"^bearing_failed = .* allowed: True or False$"):
        steady_dry_whip(reference_machine(), bearing_failed=flag)


@pytest.fixture(scope="module")
def whip():
    return steady_dry_whip(machine())


@pytest.mark.parametrize("t", [None, "1", [1.0], {}, math.nan, math.inf, True, 1j])
def test_the_time_of_a_state_is_a_finite_real_number(whip, t):
    with pytest.raises(ParameterError, match=r"^t = .* is invalid; allowed: a finite number$"):
        whip.state(t)


def test_a_time_where_the_whirl_angle_is_not_resolved_is_refused(whip):
    most = 1e7 / abs(whip.whirl_rate)
    assert all(map(math.isfinite, (abs(z) for z in whip.state(-0.999 * most))))
    for t in (1e300, -1.001 * most):
        with pytest.raises(ParameterError, match=r"^t = .* s is invalid: the whirl would turn by more than 1e\+07 rad, "
                                                 rf"where its angle is not resolved; allowed: \|t\| <= {most:.6g} s$"):
            whip.state(t)


def test_a_state_at_a_numpy_time_is_the_same(whip):
    want = whip.state(0.37)
    assert whip.state(np.float64(0.37)) == want and whip.state(np.array(0.37)) == want
    assert whip.state(np.int64(2)) == whip.state(2.0) and whip.state(0) == whip.state(0.0)


def test_a_rotor_without_radius_cannot_slide_forward():
    with pytest.raises(ParameterError, match=r"^rotor_radius = 0.0 m is invalid: the rotor's surface does not") as err:
        steady_dry_whip(machine(rotor_radius=0.0))
    assert "inf" not in str(err.value) and "nan" not in str(err.value)
