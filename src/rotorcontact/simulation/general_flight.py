"""Exact flights of the general machine per axis and the guaranteed location of their next impact.

A flight (MODEL.md §7) is stored as one record per axis, in lengths of clearances c_r and times in
seconds: ``[gamma, w2, h2, Re H, Im H, p0, p1, p2, h0, dh0]`` with the harmonic response H, the
polynomial p0 + p1 s + p2 s^2/2 of the constant force and the homogeneous motion (h0, dh0) at s = 0
(`rotorcontact.model.machine_model`). Every derivative is exact at any s.

A stator on springs (MODEL.md §8) flies too, freely on its support: its records (`make_stator_flight`) have
no harmonic or polynomial part, and the gap is that of the rotor relative to it, Z = z - z_s.

Impact location follows `rotorcontact.simulation.roots`: safe steps on f(s) = |Z(s)|^2 - 1 from bounds
on |Z^(n)| over a window ahead (`crossing_free_step`), |Z^(n)| <= |z^(n)| + |z_s^(n)| with a moving stator.
Over [s, s + W] each part is bounded on its own:
|Re(H (i Omega)^n e^{i Omega s})| <= |H| Omega^n; the polynomial by its Taylor terms; the homogeneous
part, h^(n)(s + u) = e^{-gamma u/2}(C(u) h^(n)(s) + S(u)(gamma h^(n)(s)/2 + h^(n+1)(s))), by
`window_bounds`. No step crosses the wall, so a grazing impact is never missed.

Its functions are compiled kernels for the event loops and take their arguments unchecked (NaN gives NaN;
text is a numba typing error): `rotorcontact.simulate`, `drop` and `run_general` are the checked entry
points.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..model.flow import scaled_cs
from ..model.machine_model import constant_response, harmonic_response, unbalance_amplitudes
from .roots import (
    CROSSING,
    EPS,
    ITERATION_LIMIT,
    MAX_STEPS,
    NO_CROSSING,
    STUCK,
    crossing_free_step,
    nearest_root_step,
    window_bounds,
)

__all__ = ["make_flight", "make_stator_flight", "NO_STATOR", "flight_state", "next_impact", "flight_window"]

NDER = 7  # derivatives 0..6 of each axis


@njit(cache=True)
def _axis(gamma, w2, amplitude, b, spin, pos, vel):
    rec = np.empty(10)
    hh = harmonic_response(gamma, w2, spin, amplitude)
    p0, p1, p2 = constant_response(gamma, w2, b)
    rec[0] = gamma
    rec[1] = w2
    rec[2] = 0.25 * gamma * gamma - w2
    rec[3] = hh.real
    rec[4] = hh.imag
    rec[5] = p0
    rec[6] = p1
    rec[7] = p2
    rec[8] = pos - hh.real - p0
    rec[9] = vel - (1j * spin * hh).real - p1
    return rec


@njit(cache=True)
def make_flight(z, v, spin, psi, gamma_x, w2_x, gamma_y, w2_y, b_y, ecc):
    """The flight from (z, v) (clearances, clearances/s) with unbalance angle psi and constant spin.

    ``ecc`` is e/c_r, ``b_y`` the constant force per unit mass along y in clearances/s^2.
    Returns a (2, 10) array: the x and y records.
    """
    fx, fy = unbalance_amplitudes(ecc, spin, psi)
    out = np.empty((2, 10))
    out[0] = _axis(gamma_x, w2_x, fx, 0.0, spin, z.real, v.real)
    out[1] = _axis(gamma_y, w2_y, fy, b_y, spin, z.imag, v.imag)
    return out


@njit(cache=True)
def make_stator_flight(z, v, gamma_x, w2_x, gamma_y, w2_y):
    """The free flight of a stator on springs from (z, v) (clearances, clearances/s): a (2, 10) array of x and
    y records whose motion is homogeneous (damping gamma and stiffness w2 per unit mass of each axis)."""
    out = np.empty((2, 10))
    out[0] = _axis(gamma_x, w2_x, 0j, 0.0, 0.0, z.real, v.real)
    out[1] = _axis(gamma_y, w2_y, 0j, 0.0, 0.0, z.imag, v.imag)
    return out


#: The stator records of a fixed stator (no rows).
NO_STATOR = np.zeros((0, 10))


@njit(cache=True)
def _axis_derivatives(rec, spin, s, der):
    """Derivatives 0..NDER-1 at s into der[0] (total) and der[1] (homogeneous part)."""
    gamma, w2, h2 = rec[0], rec[1], rec[2]
    hh = complex(rec[3], rec[4])
    c, sn = scaled_cs(s, gamma, h2)
    h0, dh0 = rec[8], rec[9]
    g2 = 0.5 * gamma
    der[1, 0] = c * h0 + sn * (g2 * h0 + dh0)
    der[1, 1] = c * dh0 + sn * (-w2 * h0 - g2 * dh0)
    for n in range(2, NDER):
        der[1, n] = -gamma * der[1, n - 1] - w2 * der[1, n - 2]
    rot = hh * complex(math.cos(spin * s), math.sin(spin * s))
    fac = 1.0 + 0j
    for n in range(NDER):
        der[0, n] = der[1, n] + (fac * rot).real
        fac *= 1j * spin
    der[0, 0] += rec[5] + rec[6] * s + 0.5 * rec[7] * s * s
    der[0, 1] += rec[6] + rec[7] * s
    der[0, 2] += rec[7]


@njit(cache=True)
def _axis_bounds(rec, spin, s, der, width, out):
    """out[n] >= |a^(n)| on [s, s + width], n = 0..5 (der from `_axis_derivatives` at s)."""
    gamma, h2 = rec[0], rec[2]
    cmax, smax = window_bounds(gamma, h2, width)
    harm = abs(complex(rec[3], rec[4]))
    p1s = rec[6] + rec[7] * s
    p0s = rec[5] + rec[6] * s + 0.5 * rec[7] * s * s
    fac = harm
    for n in range(6):
        hom = cmax * abs(der[1, n]) + smax * abs(0.5 * gamma * der[1, n] + der[1, n + 1])
        out[n] = hom + fac
        fac *= spin
    out[0] += abs(p0s) + abs(p1s) * width + 0.5 * abs(rec[7]) * width * width
    out[1] += abs(p1s) + abs(rec[7]) * width
    out[2] += abs(rec[7])


@njit(cache=True)
def _bounds(flight, spin, s, dx, dy, width, bx, by, stator, sx, sy, bsx, bsy):
    """bx, by >= |x^(n)|, |y^(n)| of Z = z - z_s on [s, s + width], n = 0..5 (derivatives from `_surface`)."""
    _axis_bounds(flight[0], spin, s, dx, width, bx)
    _axis_bounds(flight[1], spin, s, dy, width, by)
    if stator.shape[0]:
        _axis_bounds(stator[0], 0.0, s, sx, width, bsx)
        _axis_bounds(stator[1], 0.0, s, sy, width, bsy)
        bx += bsx
        by += bsy


@njit(cache=True)
def flight_state(flight, spin, s):
    """(z, v) of the flight at time s, in clearances and clearances/s."""
    dx = np.empty((2, NDER))
    dy = np.empty((2, NDER))
    _axis_derivatives(flight[0], spin, s, dx)
    _axis_derivatives(flight[1], spin, s, dy)
    return complex(dx[0, 0], dy[0, 0]), complex(dx[0, 1], dy[0, 1])


@njit(cache=True)
def _surface(flight, spin, s, dx, dy, stator, sx, sy):
    """f = |Z|^2 - 1 and its derivatives 1..4 at s; dx[0], dy[0] become those of Z = z - z_s (dx[1], dy[1]
    keep the rotor's homogeneous part, sx, sy the stator's derivatives)."""
    _axis_derivatives(flight[0], spin, s, dx)
    _axis_derivatives(flight[1], spin, s, dy)
    if stator.shape[0]:
        _axis_derivatives(stator[0], 0.0, s, sx)
        _axis_derivatives(stator[1], 0.0, s, sy)
        for n in range(NDER):
            dx[0, n] -= sx[0, n]
            dy[0, n] -= sy[0, n]
    x = dx[0]
    y = dy[0]
    f = x[0] * x[0] + y[0] * y[0] - 1.0
    fp = 2.0 * (x[0] * x[1] + y[0] * y[1])
    fpp = 2.0 * (x[1] * x[1] + y[1] * y[1] + x[0] * x[2] + y[0] * y[2])
    f3 = 6.0 * (x[1] * x[2] + y[1] * y[2]) + 2.0 * (x[0] * x[3] + y[0] * y[3])
    f4 = 6.0 * (x[2] * x[2] + y[2] * y[2]) + 8.0 * (x[1] * x[3] + y[1] * y[3]) + 2.0 * (x[0] * x[4] + y[0] * y[4])
    return f, fp, fpp, f3, f4


@njit(cache=True)
def flight_window(flight, spin, z, v, stator) -> float:
    """A window width (s) of the order of the flight's fastest time scale (bounds are taken over it)."""
    rate = max(abs(spin), abs(v), 1e-300)
    for a in range(2):
        rate = max(rate, math.sqrt(flight[a, 1]), flight[a, 0], math.sqrt(abs(flight[a, 7])))
    for a in range(stator.shape[0]):
        rate = max(rate, math.sqrt(stator[a, 1]), stator[a, 0])
    return 1.0 / rate


@njit(cache=True)
def _polish(flight, spin, s, f, fp, fpp, dx, dy, stator, sx, sy):
    s_safe = s
    for _ in range(8):
        h = nearest_root_step(f, fp, fpp)
        if h != h:
            return -1.0
        s_new = max(s + h, s_safe)
        if s_new == s:
            break
        s = s_new
        f, fp, fpp, _f3, _f4 = _surface(flight, spin, s, dx, dy, stator, sx, sy)
        if fp <= 0.0:
            return -1.0
        if abs(h) <= 4.0 * EPS * s:
            break
    return s


@njit(cache=True)
def next_impact(flight, spin, horizon, on_boundary, liftoff, stator):
    """First s in (0, horizon] where |Z(s)| reaches 1 (one clearance) while increasing.

    Z = z - z_s: ``stator`` holds the records of a stator on springs (`make_stator_flight`), or no rows
    (`NO_STATOR`) for a fixed one.

    ``liftoff``: the start is a lift-off from continuous contact (f = f' = f'' = 0 to the event
    tolerance); the flight leaves when f3 = f''' < 0, and with M4 >= |f''''| ahead, f <= f3 s^3/6 + M4 s^4/24
    stays negative on (0, -4 f3/M4): half of it is the first step.

    Returns
    -------
    code, s : int, float
        ``CROSSING`` and the time; ``NO_CROSSING`` and ``horizon``; ``STUCK`` when starting on the
        wall with no inward velocity and outward acceleration (impacts accumulate); ``ITERATION_LIMIT``.
    """
    dx = np.empty((2, NDER))
    dy = np.empty((2, NDER))
    sx = np.zeros((2, NDER))
    sy = np.zeros((2, NDER))
    bx = np.empty(6)
    by = np.empty(6)
    bsx = np.zeros(6)
    bsy = np.zeros(6)
    moving = stator.shape[0] > 0
    z0, v0 = flight_state(flight, spin, 0.0)
    if moving:
        v0 -= flight_state(stator, 0.0, 0.0)[1]
    window = flight_window(flight, spin, z0, v0, stator)
    s = 0.0
    for _ in range(MAX_STEPS):
        f, fp, fpp, f3, f4 = _surface(flight, spin, s, dx, dy, stator, sx, sy)
        speed = abs(complex(dx[0, 1], dy[0, 1]))
        reach = abs(complex(dx[0, 0], dy[0, 0]))
        ftol = 16.0 * EPS * (reach * reach + 1.0)
        # f' = 2 Re(conj(Z) Z') within its rounding error is no slope: the wall is touched, not hit (as at a
        # lift-off, where f = O(s^3))
        slope_tol = 16.0 * EPS * (1.0 + reach) * speed
        if on_boundary and s == 0.0:
            f = 0.0
            if fp > -ftol * (1.0 + speed * window):
                if fpp >= -ftol / (window * window):
                    if not liftoff or f3 >= 0.0:
                        return STUCK, 0.0
                    _bounds(flight, spin, s, dx, dy, window, bx, by, stator, sx, sy, bsx, bsy)
                    z_b = np.sqrt(bx * bx + by * by)
                    m4 = 6.0 * z_b[2] * z_b[2] + 8.0 * z_b[1] * z_b[3] + 2.0 * z_b[0] * z_b[4]
                    h = min(-2.0 * f3 / m4, window)
                    if h >= horizon:
                        return NO_CROSSING, horizon
                    s = h
                    continue
                fp = min(fp, 0.0)
        elif f >= -ftol:
            if fp > slope_tol:
                root = _polish(flight, spin, s, f, fp, fpp, dx, dy, stator, sx, sy)
                if root >= 0.0:
                    return CROSSING, root
            f = -ftol  # a tangency within rounding of the wall that does not reach it: walk past
        width = min(window, horizon - s)
        _bounds(flight, spin, s, dx, dy, width, bx, by, stator, sx, sy, bsx, bsy)
        z_b = np.sqrt(bx * bx + by * by)
        h = min(crossing_free_step(f, fp, fpp, f3, f4, z_b[0], z_b[1], z_b[2], z_b[3], z_b[4], z_b[5]), width)
        if s + h == s:
            if fp > slope_tol:
                root = _polish(flight, spin, s, f, fp, fpp, dx, dy, stator, sx, sy)
                if root >= 0.0:
                    return CROSSING, root
            h = 4.0 * EPS * abs(s) + 1e-300
        if s + h >= horizon:
            return NO_CROSSING, horizon
        s += h
    return ITERATION_LIMIT, s
