"""Guaranteed location of the next impact: the first t > 0 with |U(t)| = 1, |U| increasing.

Method (safe stepping on f(t) = |U(t)|^2 - 1). At a point tau with f(tau) < 0,
Taylor's theorem gives, for every s in the interval of validity of a bound
M >= max |f''|,

    f(tau + s) <= f(tau) + f'(tau) s + M s^2 / 2,

so no crossing lies before the positive root h of the right-hand side. M comes
from rigorous bounds on |V|, |V'|, |V''| (V = U - k) along the exact flow of
`rotorcontact.flow`: with p_n = V^{(n)}(tau) and q_n = a p_n + p_{n+1},

    V^{(n)}(tau + s) = e^{-gamma s/2} e^{-is} [C(s) p_n + S(s) q_n],

so |V^{(n)}| <= sqrt(|p_n|^2 + |q_n|^2 / nu^2) for all s >= 0 when the flow is
underdamped with gamma >= 0, and |V^{(n)}| <= Cmax |p_n| + Smax |q_n| on a
finite window otherwise. Then |f''| <= 2 |V'|^2 + 2 (|k| + |V|) |V''|.

Stepping by h never crosses the surface; near a transversal crossing the steps
converge to it quadratically from below (like Newton), near a tangency that
stays below 1 they walk past it, and a crossing whose excursion above 1 is
tiny is still found because the steps can never jump over it.
"""

from __future__ import annotations

import math

from numba import njit

from .flow import propagate

NO_CROSSING = 0
CROSSING = 1
STUCK = 2
ITERATION_LIMIT = 3

MAX_STEPS = 200_000
EPS = 2.220446049250313e-16


@njit(cache=True)
def _window(gamma: float, h2: float, width: float) -> tuple[float, float]:
    """Bounds Cmax >= e^{-gamma s/2}|C(s)| and Smax >= e^{-gamma s/2}|S(s)| for s in [0, width]."""
    g2 = 0.5 * gamma
    if h2 > 0.0:
        kap = math.sqrt(h2)
        cmax = 0.5 * (max(1.0, math.exp((kap - g2) * width)) + max(1.0, math.exp((-kap - g2) * width)))
        return cmax, cmax * min(width, 1.0 / kap)
    cmax = max(1.0, math.exp(-g2 * width))
    if h2 < 0.0:
        return cmax, cmax * min(width, 1.0 / math.sqrt(-h2))
    return cmax, cmax * width


@njit(cache=True)
def _taylor_bounds(p0, p1, p2, p3, a, cmax, smax, sqrt_form, nu):
    """Bounds on |V|, |V'|, |V''| ahead of the current point."""
    q0 = a * p0 + p1
    q1 = a * p1 + p2
    q2 = a * p2 + p3
    if sqrt_form:
        b0 = math.sqrt(abs(p0) ** 2 + (abs(q0) / nu) ** 2)
        b1 = math.sqrt(abs(p1) ** 2 + (abs(q1) / nu) ** 2)
        b2 = math.sqrt(abs(p2) ** 2 + (abs(q2) / nu) ** 2)
    else:
        b0 = cmax * abs(p0) + smax * abs(q0)
        b1 = cmax * abs(p1) + smax * abs(q1)
        b2 = cmax * abs(p2) + smax * abs(q2)
    return b0, b1, b2


@njit(cache=True)
def _safe_root(f: float, fp: float, m: float) -> float:
    """Positive root of f + fp s + m s^2 / 2 = 0 for f < 0 (cancellation-free)."""
    if m <= 0.0:
        if fp > 0.0:
            return -f / fp
        return math.inf
    disc = math.sqrt(fp * fp - 2.0 * m * f)
    if fp >= 0.0:
        return -2.0 * f / (fp + disc)
    return (disc - fp) / m


@njit(cache=True)
def _safe_step(p0, p1, k_abs, f, fp, a, b, gamma, h2, horizon, window):
    """Largest step from the current point guaranteed free of crossings."""
    p2 = b * p0 - 2.0 * a * p1
    p3 = b * p1 - 2.0 * a * p2
    best = 0.0
    # infinite-horizon bound (decaying underdamped flow)
    if gamma >= 0.0 and h2 < 0.0:
        nu = math.sqrt(-h2)
        b0, b1, b2 = _taylor_bounds(p0, p1, p2, p3, a, 1.0, 1.0, True, nu)
        best = _safe_root(f, fp, 2.0 * b1 * b1 + 2.0 * (k_abs + b0) * b2)
    # finite window bound
    width = min(window, horizon)
    if best < width:
        cmax, smax = _window(gamma, h2, width)
        b0, b1, b2 = _taylor_bounds(p0, p1, p2, p3, a, cmax, smax, False, 1.0)
        h = min(_safe_root(f, fp, 2.0 * b1 * b1 + 2.0 * (k_abs + b0) * b2), width)
        if h > best:
            best = h
    return best


@njit(cache=True)
def next_crossing(v0: complex, dv0: complex, k: complex, gamma: float, omega: float,
                  horizon: float, on_boundary: bool) -> tuple[int, float]:
    """First time tau in (0, horizon] where |k + V(tau)| reaches 1 while increasing.

    Parameters
    ----------
    v0, dv0 : complex
        V = U - k and V' at tau = 0.
    k : complex
        Regular equilibrium.
    gamma, omega : float
        Parameters of the flow.
    horizon : float
        Search up to this time.
    on_boundary : bool
        True when the start lies on |U| = 1 (just after an impact).

    Returns
    -------
    code, tau : int, float
        ``CROSSING`` and the time; ``NO_CROSSING`` and ``horizon``; ``STUCK``
        when starting on the boundary with no inward motion and outward
        acceleration (impacts accumulate); ``ITERATION_LIMIT``.
    """
    a = complex(0.5 * gamma, 1.0)
    b = complex(1.0 - omega * omega, -gamma)
    h2 = 0.25 * gamma * gamma - omega * omega
    k_abs = abs(k)
    window = 1.0
    tau = 0.0
    for _ in range(MAX_STEPS):
        v, dv = propagate(v0, dv0, tau, gamma, omega)
        u = k + v
        scale = (k_abs + abs(v)) ** 2 + 1.0
        f = (u.real * u.real + u.imag * u.imag) - 1.0
        fp = 2.0 * (u.real * dv.real + u.imag * dv.imag)
        ftol = 16.0 * EPS * scale
        if on_boundary and tau == 0.0:
            f = 0.0
            if fp > -ftol * (1.0 + abs(dv)):
                # no inward velocity: decide by the sign of f'' (third-order safe step)
                p2 = b * v - 2.0 * a * dv
                p3 = b * dv - 2.0 * a * p2
                p4 = b * p2 - 2.0 * a * p3
                fpp = 2.0 * abs(dv) ** 2 + 2.0 * (u.real * p2.real + u.imag * p2.imag)
                if fpp >= -ftol:
                    return STUCK, 0.0
                width = min(window, horizon)
                cmax, smax = _window(gamma, h2, width)
                b0 = cmax * abs(v) + smax * abs(a * v + dv)
                b1 = cmax * abs(dv) + smax * abs(a * dv + p2)
                b2 = cmax * abs(p2) + smax * abs(a * p2 + p3)
                b3 = cmax * abs(p3) + smax * abs(a * p3 + p4)
                m3 = 6.0 * b1 * b2 + 2.0 * (k_abs + b0) * b3
                h = min(1.5 * (-fpp) / m3, width)
                if h >= horizon:
                    return NO_CROSSING, horizon
                tau = h
                continue
        elif f >= -ftol:
            if fp > 0.0:
                # converged onto a transversal crossing from below: polish by Newton
                for _p in range(2):
                    step = f / fp
                    if abs(step) > 1e-9 * (1.0 + tau):
                        break
                    tau -= step
                    v, dv = propagate(v0, dv0, tau, gamma, omega)
                    u = k + v
                    f = (u.real * u.real + u.imag * u.imag) - 1.0
                    fp = 2.0 * (u.real * dv.real + u.imag * dv.imag)
                    if fp <= 0.0:
                        break
                return CROSSING, tau
            # tangency at rounding level, not moving outward: walk past it
            f = -ftol
        h = _safe_step(v, dv, k_abs, f, fp, a, b, gamma, h2, horizon - tau, window)
        if tau + h == tau:
            # the step is below the resolution of tau: we are on the crossing
            if fp > 0.0:
                return CROSSING, tau
            h = 4.0 * EPS * abs(tau)
        if tau + h >= horizon:
            return NO_CROSSING, horizon
        tau += h
    return ITERATION_LIMIT, tau
