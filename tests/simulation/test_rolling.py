"""Rolling on a fixed stator integrated in the whirl angle (`simulation.rolling`) against the time
integrator of the contact equations (`general_contact.contact_phase`)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact.model.machine_model import contact_accelerations, rolling_fixed_coefficients
from rotorcontact.simulation.drop import _contact_params
from rotorcontact.simulation.general_contact import C_END, contact_phase
from rotorcontact.simulation.rolling import _S, _W, _X, fast_rolling_applies, rolling_fixed_phase

M, CR, ECC, R, MU, G, I_P = 50.0, 0.7e-3, 0.3e-3, 0.04, 0.15, 9.81, 0.04


def params(mu=MU, ecc=ECC, kx=0.0):
    return _contact_params(M, CR, ecc, R, mu, kx, 0.0, 0.0, 0.0, -G, 1.0 / I_P, 0.0, 0.0, 0.0)


def test_the_quadrature_is_exact_for_polynomials_below_its_degree():
    for k in range(_X.size):
        # int_{-1}^{x} t^k dt = (x^{k+1} - (-1)^{k+1}) / (k + 1), at every node; and the weights
        np.testing.assert_allclose(_S @ _X**k, (_X ** (k + 1) - (-1.0) ** (k + 1)) / (k + 1), atol=1e-13)
        assert _W @ _X**k == pytest.approx((1 - (-1.0) ** (k + 1)) / (k + 1), abs=1e-14)


@pytest.mark.parametrize("seed", range(5))
def test_the_reduced_coefficients_are_the_rolling_contact_equations(seed):
    """2 theta'' of `contact_accelerations` (rolling, fixed stator, Omega = -(c_r/R) theta') is P + Q theta'^2."""
    rng = np.random.default_rng(seed)
    theta, psi = rng.uniform(-math.pi, math.pi, 2)
    thd = rng.uniform(-3e4, 3e4)
    om = -CR / R * thd
    delta = psi - theta
    unb = ECC * om * om
    f_n = -G * math.sin(theta) + unb * math.cos(delta)
    f_t = -G * math.cos(theta) + unb * math.sin(delta)
    sd, cd = math.sin(delta), math.cos(delta)
    thdd = contact_accelerations(f_n, f_t, sd, cd, ECC, CR, thd, MU, 1.0, True, M, R, 1 / I_P, R + CR, 0.0, 0.0)[0]
    p, q = rolling_fixed_coefficients(math.cos(theta), sd, cd, -G, ECC, CR, M, R, 1 / I_P)
    assert 2.0 * thdd == pytest.approx(p + q * thd * thd, rel=1e-12)


def _rolling_state(spin_rpm, theta=-1.2, psi=0.4):
    om = spin_rpm * math.pi / 30.0
    return np.array([theta, -R / CR * om, psi, om, 0.0, 0.0])


@pytest.mark.parametrize("spin_rpm", [500.0, 11_000.0])
def test_rolling_in_theta_follows_the_time_integrator(spin_rpm):
    p = params()
    assert fast_rolling_applies(p) and not fast_rolling_applies(params(kx=1e5))
    y0 = _rolling_state(spin_rpm)
    t_end = 0.02
    code_a, t_a, y_a, n_a = rolling_fixed_phase(y0, 0.0, t_end, p, 0.0)
    code_b, t_b, y_b, n_b = contact_phase(y0, 0.0, t_end, p, True, 1.0, 0.0)
    assert code_a == code_b == C_END and t_a == t_b == t_end
    turns = abs(y_b[0] - y0[0]) / (2 * math.pi)
    assert turns > (1.0 if spin_rpm < 1000 else 100.0)
    # the whirl angle to 1e-7 rad after hundreds of turns, the whirl rate and the spin to 1e-9 relative
    # (the time integrator's tolerance 1e-11 per step, over thousands of steps)
    assert y_a[0] == pytest.approx(y_b[0], abs=1e-7)
    assert y_a[1] == pytest.approx(y_b[1], rel=1e-9)
    assert y_a[2] == pytest.approx(y_b[2], abs=1e-7)
    assert y_a[3] == pytest.approx(y_b[3], rel=1e-9)
    # still rolling on the fixed stator
    assert CR * y_a[1] + R * y_a[3] == pytest.approx(0.0, abs=1e-12 * R * abs(y_a[3]))
    # the largest normal force, found between the nodes of the one and the steps of the other (it varies by
    # g sin(theta) and the unbalance round the wall, and samples 0.1 rad from its top miss it by 5e-3 g)
    assert n_a == pytest.approx(n_b, rel=1e-10)


def test_the_end_of_rolling_is_located_by_the_time_integrator():
    """A slow roll with little friction slips: both paths find the same switch."""
    p = params(mu=0.02)
    y0 = _rolling_state(50.0)
    code_a, t_a, y_a, _ = rolling_fixed_phase(y0, 0.0, 1.0, p, 0.0)
    code_b, t_b, y_b, _ = contact_phase(y0, 0.0, 1.0, p, True, 1.0, 0.0)
    assert code_a == code_b != C_END
    assert t_a == pytest.approx(t_b, rel=1e-9)
    np.testing.assert_allclose(y_a[:4], y_b[:4], rtol=1e-8, atol=1e-9)


@pytest.mark.parametrize("past_half_turn", [8e-4, None])
def test_a_maximum_just_before_the_hand_off_to_the_time_integrator_is_located(past_half_turn):
    """A slow roll started just short of the top: its first half turn ends just past the bottom, where the
    force is largest, between the panel's last node and its end. With t_end inside the next half turn that
    panel is handed to the time integrator, which starts at the end: the maximum is located all the same."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    from rotorcontact.simulation.general_contact import contact_rates

    p = params(mu=MU, ecc=0.0)
    om = 60.0 * math.pi / 30.0
    y0 = np.array([math.pi / 2 - 0.008, -R / CR * om, 0.4, om, 0.0, 0.0])
    sol = solve_ivp(lambda t, y: contact_rates(y, p, True, 1.0)[0], (0.0, 0.03), y0, method="DOP853", rtol=1e-13,
                    atol=1e-13, dense_output=True)
    t_bottom = brentq(lambda t: sol.sol(t)[0] + math.pi / 2, 0.0, 0.03, xtol=1e-16)
    n_bottom = contact_rates(sol.sol(t_bottom), p, True, 1.0)[1]  # the largest force: at the bottom
    t_half = brentq(lambda t: sol.sol(t)[0] - (y0[0] - math.pi), 0.0, 0.03, xtol=1e-16)  # the first panel's end
    t_end = 0.02 if past_half_turn is None else t_half + past_half_turn
    _code, t1, _y1, n_max = rolling_fixed_phase(y0, 0.0, t_end, p, 0.0)
    assert t1 > t_bottom
    assert n_max == pytest.approx(n_bottom, rel=1e-11)
