"""The impact law with spin and effective mass (MODEL.md §7): today's law in the limit, conservation laws."""

from __future__ import annotations

import cmath
import math

import numpy as np
import mpmath as mp
import pytest

from rotorcontact.model.impact_law import apply_reset
from rotorcontact.model.machine_model import (
    angular_momentum,
    constant_response,
    harmonic_response,
    impact_with_spin,
    kinetic_energy,
    race_spin,
)

M, CR, R = 50.0, 0.7e-3, 0.04
RB = R + CR


def _states(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        theta = rng.uniform(-math.pi, math.pi)
        e = cmath.exp(1j * theta)
        v_n = rng.uniform(1e-3, 1.0)
        v_t = rng.uniform(-2.0, 2.0)
        spin = rng.uniform(-400.0, 400.0)
        race = rng.uniform(-400.0, 400.0)
        yield CR * e, e * complex(v_n, v_t), spin, race


@pytest.mark.parametrize("mu", [0.0, 0.15, 3.0])
def test_held_speed_is_todays_law_in_si(mu):
    """1/I_p = 0 and a fixed stator: the law of MODEL.md §2 in units of c_r Omega."""
    d = 0.8
    for z, v, spin, _race in _states(200, 1):
        spin = abs(spin) + 1.0
        v_plus, spin_plus, race_plus, v_n, v_rel, p_n, p_t = impact_with_spin(z, v, spin, 0.0, M, d, mu, R, 0.0,
                                                                              RB, 0.0)
        u = z / CR
        # the co-rotating dimensionless velocity at t = 0: U' = Z' - i Z, with Z' = v / (c_r Omega)
        du = v / (CR * spin) - 1j * u
        du_plus, rd, _td, _rdp, _tdp, vrel, pn, pt = apply_reset(u, du, d, mu, R / CR)
        assert spin_plus == spin and race_plus == 0.0
        assert v_plus / (CR * spin) - 1j * u == pytest.approx(du_plus, rel=1e-12, abs=1e-12)
        assert v_rel == pytest.approx(vrel * CR * spin, rel=1e-12, abs=1e-12 * CR * spin)
        assert p_n == pytest.approx(M * CR * spin * pn, rel=1e-12)
        assert p_t == pytest.approx(M * CR * spin * pt, rel=1e-12, abs=1e-12 * M * CR * spin)


def test_elastic_frictionless_impacts_conserve_energy():
    for z, v, spin, race in _states(200, 2):
        v_plus, s_p, r_p, *_ = impact_with_spin(z, v, spin, race, M, 1.0, 0.0, R, 1 / 0.04, RB, 1 / 2e-4)
        before = kinetic_energy(M, v, 0.04, spin, 2e-4, race)
        after = kinetic_energy(M, v_plus, 0.04, s_p, 2e-4, r_p)
        assert after == pytest.approx(before, rel=1e-13)


@pytest.mark.parametrize("race_inertia", [0.0, 2e-4])
@pytest.mark.parametrize("mu", [0.15, 5.0])
def test_friction_impacts_keep_the_angular_momentum_about_the_stator_centre(mu, race_inertia):
    """The contact impulses act at the contact point: L = m z x v + I_p Omega + I_b Omega_b is unchanged."""
    assert R + CR == RB  # the race's surface is at the contact point
    ip = 0.04
    inv_race = 1 / race_inertia if race_inertia else 0.0
    lost = 0
    for z, v, spin, race in _states(300, 3):
        race = race if race_inertia else 0.0
        v_plus, s_p, r_p, v_n, v_rel, p_n, p_t = impact_with_spin(z, v, spin, race, M, 0.7, mu, R, 1 / ip, RB, inv_race)
        before = angular_momentum(M, z, v, ip, spin, race_inertia, race)
        after = angular_momentum(M, z, v_plus, ip, s_p, race_inertia, r_p)
        scale = M * CR * abs(v) + ip * abs(spin) + race_inertia * abs(race)
        # with a race the stator's part is the race's; a fixed stator takes the moment R_b P_t of the impulse
        gained = 0.0 if race_inertia else RB * p_t
        assert after == pytest.approx(before + gained, abs=1e-13 * scale)
        # the slip never reverses and the impact never gains energy
        v_rel_after = (np.conj(z / CR) * v_plus).imag + R * s_p - RB * r_p
        assert v_rel_after * v_rel >= -1e-12 * abs(v_rel)
        e0 = kinetic_energy(M, v, ip, spin, race_inertia, race)
        e1 = kinetic_energy(M, v_plus, ip, s_p, race_inertia, r_p)
        assert e1 <= e0 * (1 + 1e-13)
        lost += abs(v_rel_after) <= 1e-9 * abs(v_rel)
    assert lost > 0  # some impacts end rolling (the slip bound acts), some slide


def test_particular_solutions_solve_their_equations():
    gamma, w2, om, amp = 28.0, 1.96e4, 184.2, 0.3 + 0.1j
    h = harmonic_response(gamma, w2, om, amp)
    # a = Re(H e^{i om s}): a'' + gamma a' + w2 a = Re(amp e^{i om s}) as complex identity
    assert h * (w2 - om * om + 1j * gamma * om) == pytest.approx(amp, rel=1e-14)
    for gamma_, w2_, b in [(28.0, 1.96e4, -9.81), (28.0, 0.0, -9.81), (0.0, 0.0, -9.81)]:
        p0, p1, p2 = constant_response(gamma_, w2_, b)
        for s in (0.0, 0.3, 2.0):
            # P'' + gamma P' + w2 P = b with P = p0 + p1 s + p2 s^2 / 2
            assert p2 + gamma_ * (p1 + p2 * s) + w2_ * (p0 + p1 * s + p2 * s * s / 2) == pytest.approx(b, rel=1e-14)


def test_race_drag_closed_form_against_solve_ivp():
    from scipy.integrate import solve_ivp

    ib, torque, coef = 2e-4, 0.05, 1e-4
    sol = solve_ivp(lambda t, w: [(-torque - coef * w[0]) / ib], (0.0, 0.3), [300.0], rtol=1e-12, atol=1e-12,
                    dense_output=True)
    for s in (0.0, 0.1, 0.25):
        assert race_spin(300.0, s, ib, torque, coef) == pytest.approx(sol.sol(s)[0], rel=1e-9)
        assert race_spin(-300.0, s, ib, torque, coef) == pytest.approx(-sol.sol(s)[0], rel=1e-9)
    # it stops and stays at rest (linear decay without viscous drag)
    assert race_spin(10.0, 1.0, ib, torque, 0.0) == 0.0
    assert race_spin(10.0, 0.02, ib, torque, 0.0) == pytest.approx(10.0 - torque * 0.02 / ib, rel=1e-14)


def test_rolling_whirl_rate_fixed_stator_and_race():
    from rotorcontact import reference_machine
    from rotorcontact.model.machine_model import rolling_whirl_rate

    m = reference_machine()
    rate = rolling_whirl_rate(m.rotor_radius, m.clearance, m.speed, m.race_radius, 0.0)
    assert rate == pytest.approx(-(m.rotor_radius / m.clearance) * m.speed, rel=1e-15)  # rounding order only
    assert rate / (2 * math.pi) == pytest.approx(-1675.0, abs=0.5)  # -1675 Hz on the reference rig
    # with a race at Omega_b the surfaces roll when c_r Theta' + R Omega - R_b Omega_b = 0
    race = 120.0
    rate_b = rolling_whirl_rate(m.rotor_radius, m.clearance, m.speed, m.race_radius, race)
    assert m.clearance * rate_b + m.rotor_radius * m.speed - m.race_radius * race == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("rolling", [False, True])
@pytest.mark.parametrize("inv_polar, inv_race", [(0.0, 0.0), (1 / 0.04, 0.0), (1 / 0.04, 1 / 2e-4)])
def test_contact_accelerations_solve_the_contact_equations(rolling, inv_polar, inv_race):
    """Against the five linear equations of MODEL.md §7 solved by numpy: tangential and normal balance,
    spin, race and the friction law (sliding) or v_rel' = 0 (rolling)."""
    from rotorcontact.model.machine_model import contact_accelerations

    rng = np.random.default_rng(7)
    mu, e = 0.2, 0.3e-3
    for _ in range(50):
        f_n, f_t = rng.uniform(-20.0, 20.0, 2)
        delta, thetadot = rng.uniform(-math.pi, math.pi), rng.uniform(-500.0, 500.0)
        sgn = rng.choice([-1.0, 1.0])
        drag = rng.uniform(0.0, 0.2)
        got = contact_accelerations(f_n, f_t, math.sin(delta), math.cos(delta), e, CR, thetadot, mu, sgn, rolling, M, R, inv_polar, RB,
                                    inv_race, drag)
        a, b = M * R * inv_polar, M * RB * inv_race
        # unknowns: theta'', Omega', Omega_b', n, q
        A = np.array([
            [CR, e * math.cos(delta), 0.0, 0.0, -1.0],
            [0.0, -e * math.sin(delta), 0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0, 0.0, -a],
            [0.0, 0.0, 1.0, 0.0, b],
            [CR, R, -RB, 0.0, 0.0] if rolling else [0.0, 0.0, 0.0, mu * sgn, 1.0],
        ])
        rhs = np.array([f_t, f_n + CR * thetadot**2, 0.0, -drag * inv_race, 0.0])
        ref = np.linalg.solve(A, rhs)
        np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-10 * np.abs(ref).max())


def test_contact_keeps_the_angular_momentum_balance_without_unbalance():
    """Contact forces act at the contact point: d/dt (m c_r^2 Theta' + I_p Omega + I_b Omega_b) is the external
    tangential moment m c_r f_t less the race's drag."""
    from rotorcontact.model.machine_model import contact_accelerations

    ip, ib, drag = 0.04, 2e-4, 0.07
    for rolling in (False, True):
        thetadd, sd, rd, n, q = contact_accelerations(3.0, -4.0, math.sin(0.4), math.cos(0.4), 0.0, CR, -300.0, 0.2, 1.0, rolling, M, R,
                                                      1 / ip, RB, 1 / ib, drag)
        rate = M * CR * CR * thetadd + ip * sd + ib * rd
        assert rate == pytest.approx(M * CR * -4.0 - drag, rel=1e-12)


@pytest.mark.parametrize("polar", [0.0, 0.04, 1e12])
@pytest.mark.parametrize("v_rel", [25.0, 1e-4, -3.0])
def test_impact_dissipation_is_the_loss_of_kinetic_energy(polar, v_rel):
    """`impact_dissipation` against the kinetic energies before and after `impact_with_spin`, differenced in
    60-digit arithmetic (with the speed held, polar = 0, the motor's work -R Omega P_t counts in)."""
    from rotorcontact.model.machine_model import effective_mass_factor, impact_dissipation, impact_with_spin

    mass, radius, d, mu, spin = 15.0, 0.03, 0.8, 0.1, 3000.0
    inv_p = 1.0 / polar if polar else 0.0
    z = 2.5e-4 * cmath.exp(0.3j)
    v_n = 0.3
    v = z / abs(z) * complex(v_n, v_rel - radius * spin)
    v_plus, spin_plus, _race, vn, vrel, _pn, p_t = impact_with_spin(z, v, spin, 0.0, mass, d, mu, radius, inv_p,
                                                                 radius + 2.5e-4, 0.0)
    lost = impact_dissipation(mass, d, vn, vrel, p_t, effective_mass_factor(mass, radius, inv_p, 0.0, 0.0))
    with mp.workdps(60):
        m_, p_t_ = mp.mpf(mass), mp.mpf(p_t)
        v_t = mp.mpf(v_rel) - mp.mpf(radius) * spin
        before = m_ * (mp.mpf(v_n) ** 2 + v_t ** 2) / 2
        after = m_ * ((d * mp.mpf(v_n)) ** 2 + (v_t + p_t_ / m_) ** 2) / 2
        if polar:
            i_p = mp.mpf(polar)
            before += i_p * mp.mpf(spin) ** 2 / 2
            after += i_p * (mp.mpf(spin) + mp.mpf(radius) * p_t_ / i_p) ** 2 / 2
        else:
            after += mp.mpf(radius) * spin * p_t_  # the motor's work holding the speed
        expected = float(before - after)
    assert lost >= 0.0
    assert lost == pytest.approx(expected, rel=1e-12, abs=1e-15 * mass * v_n ** 2)


def test_the_compliant_laws_functions_refuse_what_has_no_impact():
    import dataclasses
    import math

    from rotorcontact import ParameterError, reference_machine
    from rotorcontact.model.machine_model import (MAX_CHI, MIN_COMPLIANT_RESTITUTION, elastic_impact_duration,
                                                  hertz_rebound, impact_duration_factor, restitution_damping)

    # chi = 0 is elastic: the rebound is the impact speed, to the integration's tolerance
    assert hertz_rebound(0.0, 1.5) == pytest.approx(1.0, abs=1e-9)
    for args, name in (((math.nan, 1.5), "chi"), ((-1.0, 1.5), "chi"), ((2 * MAX_CHI, 1.5), "chi"),
                       ((0.5, 0.0), "exponent"), ((0.5, 11.0), "exponent"), ((0.5, "1.5"), "exponent"),
                       ((0.5, 1.5, 0.0), "rtol")):
        with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: a finite number"):
            hertz_rebound(*args)
    assert restitution_damping(MIN_COMPLIANT_RESTITUTION, 1.5) <= MAX_CHI  # the smallest restitution is taken
    for args, name in (((0.0, 1.5), "restitution"), ((MIN_COMPLIANT_RESTITUTION / 2, 1.5), "restitution"),
                       ((1.5, 1.5), "restitution"), ((0.5, -1.0), "exponent")):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            restitution_damping(*args)
    with pytest.raises(ParameterError, match=r"^exponent = -1.0 is invalid"):
        impact_duration_factor(-1.0)
    with pytest.raises(ParameterError, match=r"^stiffness = 0.0 is invalid"):
        elastic_impact_duration(1.0, 1.0, 0.0, 1.5)
    with pytest.raises(ParameterError, match=r"^restitution = 0.001 with contact = 'compliant'; allowed: \[0.002"):
        dataclasses.replace(reference_machine(), contact="compliant", contact_stiffness=1e9, restitution=0.001)
