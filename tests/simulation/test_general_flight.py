"""Per-axis exact flights of the general machine (MODEL.md §7) and the guaranteed location of their impacts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from rotorcontact.simulation.general_flight import NO_STATOR, flight_state, make_flight, next_impact
from rotorcontact.simulation.roots import CROSSING, NO_CROSSING

M, CR = 50.0, 0.7e-3
SPIN = 184.2


def _rhs(kx, ky, cx, cy, b_y, ecc, spin, psi0):
    def f(t, s):
        x, y, vx, vy = s
        psi = psi0 + spin * t
        ax = -cx / M * vx - kx / M * x + ecc * spin * spin * math.cos(psi)
        ay = -cy / M * vy - ky / M * y + ecc * spin * spin * math.sin(psi) + b_y
        return [vx, vy, ax, ay]
    return f


@pytest.mark.parametrize("kx, ky, cx, cy, b_y", [
    (6e5, 9.8e5, 1400.0, 2500.0, 3.0),        # anisotropic levitated, static force off balance
    (0.0, 0.0, 900.0, 300.0, -9.81),          # damping without stiffness
    (0.0, 0.0, 0.0, 0.0, -9.81),              # free fall after the failure
    (2e5, 2e5, 0.0, 0.0, 0.0),                # undamped spring
])
def test_flight_against_solve_ivp(kx, ky, cx, cy, b_y):
    ecc, psi0 = 0.3e-3, 0.21
    z0, v0 = (0.1 + 0.2j) * CR, (0.05 - 0.03j)
    fl = make_flight(z0 / CR, v0 / CR, SPIN, psi0, cx / M, kx / M, cy / M, ky / M, b_y / CR, ecc / CR)
    t_eval = np.linspace(0.0, 0.05, 11)
    sol = solve_ivp(_rhs(kx, ky, cx, cy, b_y, ecc, SPIN, psi0), (0.0, 0.05), [z0.real, z0.imag, v0.real, v0.imag],
                    rtol=1e-12, atol=1e-15, t_eval=t_eval, method="DOP853")
    for i, s in enumerate(t_eval):
        z, v = flight_state(fl, SPIN, s)
        scale_z = max(abs(sol.y[0]).max(), abs(sol.y[1]).max())
        scale_v = max(abs(sol.y[2]).max(), abs(sol.y[3]).max())
        assert abs(z * CR - complex(sol.y[0, i], sol.y[1, i])) <= 1e-9 * scale_z
        assert abs(v * CR - complex(sol.y[2, i], sol.y[3, i])) <= 1e-9 * scale_v


def _graze_flight(scale, kind):
    """A flight whose largest |z| over the first peak is ``scale`` (clearances), and the time of that peak."""
    if kind == "levitated":  # gravity balanced: the flight is linear in (z0, v0, e)
        args = (0.3 + 0.1j, (20.0 - 60.0j), SPIN, 0.4, 28.0, 1.2e4, 50.0, 2.0e4, 0.0, 0.2)
    else:
        # a vertical throw after the failure at x0 beside the centre: |z| peaks at the apex, where
        # y_max = y0 + vy^2 / (2 g) at t = vy / g; vy is set so that x0^2 + y_max^2 = scale^2 exactly
        g = 9.81 / CR
        x0, y0 = 0.3, -0.5
        vy = math.sqrt(2.0 * g * (math.sqrt(scale * scale - x0 * x0) - y0))
        return make_flight(complex(x0, y0), complex(0.0, vy), 0.0, 0.0, 0, 0, 0, 0, -g, 0), 0.0, vy / g
    fl = make_flight(*args)
    r = lambda s: -abs(flight_state(fl, SPIN, s)[0])
    grid = np.linspace(0.0, 0.02, 4001)
    vals = np.array([r(s) for s in grid])
    i = int(np.argmin(vals))
    res = minimize_scalar(r, bounds=(grid[max(i - 1, 0)], grid[i + 1]), method="bounded", options={"xatol": 1e-14})
    fac = scale / -res.fun
    a = list(args)
    a[0] *= fac
    a[1] *= fac
    a[9] *= fac
    return make_flight(*a), SPIN, res.x


@pytest.mark.parametrize("kind", ["levitated", "free-fall"])
@pytest.mark.parametrize("eps", [1e-6, 1e-9])
def test_near_tangent_flights_above_and_below_the_wall(kind, eps):
    above, spin, t_peak = _graze_flight(1.0 + eps, kind)
    code, s = next_impact(above, spin, 1.5 * t_peak, False, False, NO_STATOR)
    assert code == CROSSING and s <= t_peak * (1 + 1e-9)
    z, _v = flight_state(above, spin, s)
    assert abs(abs(z) - 1.0) <= 1e-13
    below, spin, t_peak = _graze_flight(1.0 - eps, kind)
    code, s = next_impact(below, spin, 1.5 * t_peak, False, False, NO_STATOR)
    assert code == NO_CROSSING and s == 1.5 * t_peak
