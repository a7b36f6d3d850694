"""The largest normal force of a contact phase of the general machine (`general_contact.contact_phase`) against
an independent integration: scipy's solve_ivp (DOP853) of the same contact equations, its dense output
searched for the largest force."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from rotorcontact.simulation.drop import _contact_params
from rotorcontact.simulation.general_contact import C_END, C_SWITCH, contact_phase, contact_rates

M, CR, R, G, I_P = 50.0, 0.7e-3, 0.04, 9.81, 0.04


def params(mu, kx=0.0, ky=0.0, cx=0.0, cy=0.0, ecc=0.0):
    return _contact_params(M, CR, ecc, R, mu, kx, ky, cx, cy, -G, 1.0 / I_P, 0.0, 0.0, 0.0)


def reference_max(y0, t1, p, rolling, sgn):
    """The largest normal force per unit mass over [0, t1] of the solve_ivp solution from y0, and whether it
    falls at t1."""
    sol = solve_ivp(lambda t, y: contact_rates(y, p, rolling, sgn)[0], (0.0, t1), y0, method="DOP853",
                    rtol=1e-13, atol=1e-13, dense_output=True)
    assert sol.success

    def force(t):
        return contact_rates(sol.sol(t), p, rolling, sgn)[1]

    grid = np.linspace(0.0, t1, 4001)
    n = np.array([force(t) for t in grid])
    k = int(np.argmax(n))
    best = float(n[k])
    if 0 < k < grid.size - 1:
        res = minimize_scalar(lambda t: -force(t), bounds=(grid[k - 1], grid[k + 1]), method="bounded",
                              options={"xatol": 1e-15 * t1 + 1e-18})
        best = max(best, -float(res.fun))
    return best, k == grid.size - 1


def phases(y0, p, kinds, t_end):
    """The contact phases of ``kinds`` ((rolling, sgn) each) from y0 at 0, each from where the one before ends:
    (start state, start time, code, end time, n_max) per phase."""
    out, y, t = [], y0, 0.0
    for rolling, sgn in kinds:
        code, t1, y1, n_max = contact_phase(y, t, t_end, p, rolling, sgn, 0.0)
        out.append((y, t, code, t1, n_max))
        y, t = y1, t1
    return out


def test_a_largest_force_at_the_phase_end_is_counted():
    """Rolling and slipping by turns at the bottom of the wall (mu = 0.06): the rolling phase that slips and
    the backward slide that sticks reach their largest force where they end, at the event."""
    theta, thd = -math.pi / 2, -0.2 / CR
    y0 = np.array([theta, thd, 0.0, -CR * thd / R, 0.0, 0.0])
    p = params(0.06)
    kinds = [(True, 1.0), (False, 1.0), (True, 1.0), (False, -1.0)]
    ends_at_max = 0
    for (y, t, code, t1, n_max), (rolling, sgn) in zip(phases(y0, p, kinds, 0.05), kinds):
        assert code == C_SWITCH
        ref, at_end = reference_max(y, t1 - t, p, rolling, sgn)
        ends_at_max += at_end
        assert n_max == pytest.approx(ref, rel=1e-9)
    assert ends_at_max >= 2


@pytest.mark.parametrize("spin_rpm", [600.0, 3000.0])
def test_the_largest_force_between_steps_is_located(spin_rpm):
    """Rolling for turns with the bearing on and anisotropic (the time integrator's case): the force varies by
    g and the bearing's pull round each turn, and its largest value falls between the integrator's steps."""
    p = params(0.6, kx=2e5, ky=3e6, cx=300.0, cy=5000.0, ecc=2e-6)
    om = spin_rpm * math.pi / 30.0
    y0 = np.array([-1.0, -R / CR * om, 0.3, om, 0.0, 0.0])
    t_end = 0.03
    code, t1, _y1, n_max = contact_phase(y0, 0.0, t_end, p, True, 1.0, 0.0)
    assert code == C_END and t1 == t_end
    ref, at_end = reference_max(y0, t_end, p, True, 1.0)
    assert not at_end
    assert n_max == pytest.approx(ref, rel=1e-9)


def _rolling_with_bearing():
    p = params(0.6, kx=2e5, ky=3e6, cx=300.0, cy=5000.0, ecc=2e-6)
    om = 600.0 * math.pi / 30.0
    return p, np.array([-1.0, -R / CR * om, 0.3, om, 0.0, 0.0])


def _peak(y0, p, t1):
    """The time and value of the largest force over [0, t1], by solve_ivp's dense output and a bounded search."""
    sol = solve_ivp(lambda t, y: contact_rates(y, p, True, 1.0)[0], (0.0, t1), y0, method="DOP853", rtol=1e-13,
                    atol=1e-13, dense_output=True)
    grid = np.linspace(0.0, t1, 2001)
    n = [contact_rates(sol.sol(t), p, True, 1.0)[1] for t in grid]
    k = int(np.argmax(n))
    res = minimize_scalar(lambda t: -contact_rates(sol.sol(t), p, True, 1.0)[1], bounds=(grid[k - 1], grid[k + 1]),
                          method="bounded", options={"xatol": 1e-18})
    return float(res.x), -float(res.fun), sol


@pytest.mark.parametrize("after", [3e-8, 2e-7, 7.4e-6])
def test_a_maximum_in_the_last_step_before_the_end_is_located(after):
    """The phase ends (t_end) just after a maximum of the force, inside its last step, so that no sample after
    the maximum lies below it but the end's."""
    p, y0 = _rolling_with_bearing()
    t_peak, n_peak, _sol = _peak(y0, p, 6e-4)
    code, t1, _y1, n_max = contact_phase(y0, 0.0, t_peak + after, p, True, 1.0, 0.0)
    assert code == C_END
    assert n_max == pytest.approx(n_peak, rel=1e-11)


@pytest.mark.parametrize("after", [5e-7, 1.5e-6, 6e-6])
def test_a_maximum_just_before_an_ending_event_is_located(after):
    """The rest event (its energy set from the reference) ends the phase just after a maximum of the force."""
    from rotorcontact.simulation.general_contact import C_REST, rotor_energy_above_rest

    p, y0 = _rolling_with_bearing()
    t_peak, n_peak, sol = _peak(y0, p, 6e-4)
    rest = rotor_energy_above_rest(sol.sol(t_peak + after), p)
    code, t1, _y1, n_max = contact_phase(y0, 0.0, 0.03, p, True, 1.0, rest)
    assert code == C_REST and t1 == pytest.approx(t_peak + after, abs=1e-9)
    assert n_max == pytest.approx(n_peak, rel=1e-11)
