"""The impact map P_I, its analytic Jacobian, and the orbits with one impact per period (MODEL.md §5).

The impact map
--------------
P_I acts on Sigma = {r = 1}. Its state is x = (theta, rdot-, thetadot-), the
angle and polar velocities just before an impact. From x the reset
(`rotorcontact.model.impact_law.apply_reset`) gives the velocity just after the impact;
the free flight is evaluated exactly (`rotorcontact.model.flow.propagate`) and the
next impact is located with the simulator's own guaranteed method
(`rotorcontact.simulation.roots.next_crossing`). P_I returns the state just before that
impact and the flight time T, so it reproduces the simulator step for step.

Its Jacobian is analytic. With V = U - k, w = (V, V') and Phi = e^{AT}:

* the state on Sigma maps to (U, U') by U = e^{i theta},
  U'- = e^{i theta} (rdot + i thetadot); the reset acts on (rdot, thetadot)
  (saltation): rdot+ = -d rdot, and thetadot+ = thetadot - s mu (1 + d) rdot
  while slipping (s = sgn v_rel), thetadot+ = -(r_ratio + 1) while the
  friction impulse is capped and the contact sticks;
* the flight is complex-linear: (dV, dV') = Phi (dV0, dV0+);
* the impact time moves by dT = -(grad h . dw) / (grad h . f) with
  h = |U|^2 - 1, i.e. dT = -Re(conj(U) dV) / Re(conj(U) U');
* the state on Sigma is recovered from dU = dV + U' dT, dU' = dV' + U'' dT:
  dtheta = Im(conj(U) dU), d(rdot + i thetadot) = conj(dU) U' + conj(U) dU'.

F1 and the fixed points
-----------------------
With m = -(gamma/2 + i), h^2 = gamma^2/4 - omega^2, C = cosh(hT),
S = sinh(hT)/h, the flow of flow.py gives e^{AT} = e^{mT}[C I + S (A - m I)]
and, exactly,

    a = (e^{-AT} - I)^{-1} = [[C - mS - e^{mT}, S], [b S, C + mS - e^{mT}]] / D,
    D = 2 (cosh(mT) - C) = 4 sinh(lambda+ T/2) sinh(lambda- T/2),

with b = 1 - omega^2 - i gamma the (2,1) entry of A. So
F1(T) = 1 + Re(q a22) = Re((D + q P) conj(D)) / |D|^2 with P = C + mS - e^{mT}.
Both D and P vanish to second order at T = 0; with D~ = D/T^2, P~ = P/T^2 (a
power series near 0, closed forms elsewhere) the function

    g(T) = Re((D~ + q P~) conj(D~)) = |D~|^2 F1(T)

is smooth on [0, inf), g(0) = |omega^2 - 1 + i gamma|^2 (1 - d)/2, and has the
zeros of F1 on (0, inf) for gamma != 0 (D has no real zero but T = 0 then).

Why no zero of F1 is missed
---------------------------
All zeros are isolated by safe stepping on g (the method of `rotorcontact.simulation.roots`
applied to F1). For T in a window [tau, tau + w], rigorous bounds on |D~^(j)|,
|P~^(j)| (j = 0, 1, 2) follow from

* D^(n)(u) = 2 (m^n cosh_n(mu) - h^n cosh_n(hu)), P^(n) likewise, with
  |cosh(mu)|, |sinh(mu)| <= cosh(gamma u/2) and |cosh(hu)|, |sinh(hu)| <=
  cosh(Re(h) u) (h is real or imaginary);
* X~^(j)(T) = int_0^1 (1 - s) s^j X^(j+2)(sT) ds (valid down to T = 0), or
  Leibniz on X T^{-2} away from 0; the smaller bound is used.

This gives M >= max |g''| on the window. From a point where sigma g(tau) > 0,

    sigma g(tau + s) >= sigma g(tau) + sigma g'(tau) s - M s^2 / 2 > 0

for s below the positive root h of the right-hand side (and within the
window), so the step to tau + h cannot pass a zero. The steps converge onto each transversal zero from
its own side (quadratically, like Newton); the zero is polished by Newton and
left on the other side through the monotone neighbourhood |s| < |g'|/M (a
single zero there). Two zeros about to merge are therefore both found however
close they are: the search stops at the first one, leaves it and steps towards
the second one from the negative side. A local minimum of F1 that stays
positive is walked past (no zero); the only undecidable case is a minimum
within rounding of 0 (|g| below the evaluation error and |g'| below
2 sqrt(2 M tol)), which is reported as a double zero (a merged pair, the smooth
fold itself).

The zeros alternate in sign change. F1 > 0 near T = 0 for d < 1, so the n-th
zero where F1 turns negative is T0,n,a and the next zero, where F1 turns
positive again, is T0,n,b (for d = 1, F1(0) = 0 and the sign just after 0 is
that of gamma - 2 mu). At gamma = 0 exactly F1 has poles at the resonances
(D = 0), which are the limits of zeros as gamma -> 0; g vanishes there too.
Such points keep their place in the labelling but give no orbit.

The fixed points
----------------
From the reset and the flow, a fixed point satisfies (MODEL.md §5, checked
here): w-(0) = -a (0, q rdot U0), i.e. U0 (1 + q a12 rdot) = k,
rdot F1(T) = 0 and thetadot = -Im(q a22) rdot. |U0| = 1 gives
|q a12|^2 rdot^2 + 2 Re(q a12) rdot + 1 - |k|^2 = 0; its smaller root is orbit
a (at T0,n,a) or b (at T0,n,b), its larger root c (at T0,n,a) or d (at T0,n,b).
Where the roots are complex there is no real orbit and none is reported; a
double root gives a = c (or b = d), reported twice.

These are the orbits of the impact law with slipping friction of positive
sign (q = (1 + d)(1 + i mu)). An orbit is `slipping` when the slip-bounded law
of `rotorcontact.model.impact_law` gives the same impact, i.e. v_rel = r_ratio + 1 +
thetadot > mu (1 + d) rdot; only then is it a fixed point of the simulator,
and only then can it be plausible.

Plausibility and the extrema of r
---------------------------------
The interior extrema of r are the zeros of r rdot = Re(conj(U) U') on (0, T),
isolated by the same safe stepping with a rigorous bound on its second
derivative along the exact flow (bounds on |V^(n)| from the closed form, as in
`rotorcontact.simulation.roots`). Each is polished to rounding, so r_max_interior is
exact. An admissible orbit starts inwards (rdot+ = -d rdot- < 0) and arrives
outwards, so r < 1 on (0, T) exactly when every interior maximum is below 1.
This is cross-checked with the simulator's impact location: the first impact
after the reset must be the one at T.
"""

from __future__ import annotations

import cmath
import math
import re
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
from numba import njit

from ..model.angles import wrap_angle
from ..errors import ParameterError
from ..interpreted import call_kernel, complex_quotient, int_power
from ..model.flow import (
    flight_coefficients,
    half_discriminant,
    has_regular_equilibrium,
    period_closed_form,
    propagate,
    scaled_cs,
)
from ..model.params import MAX_VELOCITY, Parameters, check_finite, check_range, check_velocity
from ..model.validation import check_bool, check_choice, check_params, complex_array, real_array
from ..model.impact_law import (
    apply_reset,
    ideal_reset,
    impact_q,
    polar_velocity,
    relative_velocity,
    reset_jacobian,
    slides_forward,
)
from ..simulation.roots import CROSSING, STUCK, next_crossing, window_bounds

__all__ = [
    "ORBIT_LABEL",
    "check_orbit_label",
    "IDEAL",
    "SLIP_BOUNDED",
    "ImpactMapResult",
    "F1Zero",
    "IsolationLimit",
    "FlightExtrema",
    "ImpactOrbit",
    "impact_map",
    "impact_map_jacobian",
    "post_impact_state",
    "a_matrix",
    "a_derivatives",
    "f1",
    "f1_derivative",
    "f1_zeros",
    "rdot_roots",
    "stable_quadratic_roots",
    "label_f1_zeros",
    "root_branches",
    "BRANCH_LETTERS",
    "fixed_point_residual",
    "flight_extrema",
    "flight_growth",
    "period_limit",
    "searchable_t_max",
    "admissible_orbits",
    "check_growth",
    "one_impact_orbits",
    "orbit_stability",
]

#: Impact laws: the slip-bounded law of the simulator, and the law of MODEL.md §5
#: (U'+ = U'- - q rdot- U, friction always slipping with v_rel > 0).
SLIP_BOUNDED = "slip-bounded"
IDEAL = "ideal"
_LAWS = {SLIP_BOUNDED: 0, IDEAL: 1}

EPS = 2.220446049250313e-16
N_SERIES = 30
MAX_STEPS = 1_000_000
BOUND_SAFETY = 1.0 + 1e-9

# isolation status
ISO_OK = 0
ISO_ITERATION_LIMIT = 1

# kinds of function for the generic isolator
_KIND_G = 0  # g(T) = |D~|^2 F1(T)
_KIND_F = 1  # f(t) = Re(conj(U) U') = r rdot along a flight

# reset branches
_SLIP = 0
_STICK = 1


class IsolationLimit(ParameterError):
    """``t_max`` holds more zeros of F1 than the isolation follows within its `MAX_STEPS` steps."""


def _check_law(law: str) -> int:
    if not isinstance(law, str) or law not in _LAWS:
        raise ParameterError(f"law = {law!r} is not an impact law; allowed: {', '.join(_LAWS)}")
    return _LAWS[law]


# ---------------------------------------------------------------------------
# D~, P~ and F1
# ---------------------------------------------------------------------------


@njit(cache=True)
def _cs(t: float, h2: float) -> tuple[float, float]:
    """C = cosh(h t) and S = sinh(h t)/h for h^2 = h2 (real): `flow.scaled_cs` without damping."""
    return scaled_cs(t, 0.0, h2)


@njit(cache=True)
def _series_limit(gamma: float, h2: float) -> float:
    """Largest T evaluated by the power series of D~ and P~."""
    mabs = math.sqrt(0.25 * gamma * gamma + 1.0)
    return 0.5 / max(1.0, mabs, math.sqrt(abs(h2)))


@njit(cache=True)
def _dp_tilde(t: float, gamma: float, h2: float):
    """D~ = D/T^2, P~ = P/T^2 and their first two T-derivatives, and rounding scales.

    Returns
    -------
    d0, d1, d2, p0, p1, p2 : complex
    sd, sp : float
        Sums of the magnitudes of the terms (rounding scales of d0 and p0).
    """
    m = complex(-0.5 * gamma, -1.0)
    if t <= _series_limit(gamma, h2):
        # X~ = sum_j c_j T^j, c_j = X^(j+2)(0) / (j+2)!
        # D^(n)(0) = 2 (m^n - h^n) (n even), 0 (n odd)
        # P^(n)(0) = h^n - m^n (n even), m h^(n-1) - m^n (n odd)
        d0 = 0j
        d1 = 0j
        d2 = 0j
        p0 = 0j
        p1 = 0j
        p2 = 0j
        sd = 0.0
        sp = 0.0
        mp = m * m
        h2p = h2  # h2^(n // 2)
        fact = 2.0
        tj = 1.0
        tj1 = 0.0
        tj2 = 0.0
        for j in range(N_SERIES):
            n = j + 2
            if n % 2 == 0:
                cd = complex_quotient(2.0 * (mp - h2p), fact)
                cp = complex_quotient(h2p - mp, fact)
            else:
                cd = 0j
                cp = complex_quotient(m * h2p - mp, fact)
            d0 += cd * tj
            d1 += j * cd * tj1
            d2 += j * (j - 1) * cd * tj2
            p0 += cp * tj
            p1 += j * cp * tj1
            p2 += j * (j - 1) * cp * tj2
            sd += abs(cd) * tj
            sp += abs(cp) * tj
            tj2 = tj1
            tj1 = tj
            tj *= t
            mp *= m
            fact *= n + 1
            if (n + 1) % 2 == 0:
                h2p *= h2
        return d0, d1, d2, p0, p1, p2, sd, sp
    c, s, em, chm, dd0, dd1, dd2, pp0, pp1, pp2 = period_closed_form(t, gamma, h2)
    i2 = 1.0 / (t * t)
    i3 = i2 / t
    i4 = i3 / t
    d0 = dd0 * i2
    d1 = dd1 * i2 - 2.0 * dd0 * i3
    d2 = dd2 * i2 - 4.0 * dd1 * i3 + 6.0 * dd0 * i4
    p0 = pp0 * i2
    p1 = pp1 * i2 - 2.0 * pp0 * i3
    p2 = pp2 * i2 - 4.0 * pp1 * i3 + 6.0 * pp0 * i4
    sd = 2.0 * (abs(chm) + abs(c)) * i2
    sp = (abs(c) + abs(m) * abs(s) + abs(em)) * i2
    return d0, d1, d2, p0, p1, p2, sd, sp


@njit(cache=True)
def _g_eval(t: float, gamma: float, h2: float, q: complex):
    """g = |D~|^2 F1, g', g'' at T = t and the rounding tolerance of g."""
    d0, d1, d2, p0, p1, p2, sd, sp = _dp_tilde(t, gamma, h2)
    e0 = d0 + q * p0
    e1 = d1 + q * p1
    e2 = d2 + q * p2
    g0 = (e0 * d0.conjugate()).real
    g1 = (e1 * d0.conjugate() + e0 * d1.conjugate()).real
    g2 = (e2 * d0.conjugate() + 2.0 * e1 * d1.conjugate() + e0 * d2.conjugate()).real
    tol = 64.0 * EPS * (sd * (abs(e0) + abs(d0)) + abs(q) * sp * abs(d0))
    return g0, g1, g2, tol


@njit(cache=True)
def _g_bound(t0: float, t1: float, gamma: float, h2: float, qabs: float) -> float:
    """A bound M >= max |g''(T)| over T in [t0, t1] (0 <= t0 < t1)."""
    mabs = math.sqrt(0.25 * gamma * gamma + 1.0)
    habs = math.sqrt(abs(h2))
    ch = math.cosh(math.sqrt(h2) * t1) if h2 > 0.0 else 1.0
    chm = math.cosh(0.5 * gamma * t1)
    e_int = max(1.0, math.exp(-0.5 * gamma * t1))

    # integral form: |X~^(j)| <= max_{[0, t1]} |X^(j+2)| / ((j+1)(j+2))
    bd = np.empty(3)
    bp = np.empty(3)
    for j in range(3):
        n = j + 2
        dn = 2.0 * (int_power(mabs, n) * chm + int_power(habs, n) * ch)
        pn = int_power(habs, n) * ch + mabs * int_power(habs, n - 1) * ch + int_power(mabs, n) * e_int
        den = (j + 1.0) * (j + 2.0)
        bd[j] = dn / den
        bp[j] = pn / den
    if t0 > 0.0:
        e_dir = max(math.exp(-0.5 * gamma * t0), math.exp(-0.5 * gamma * t1))
        sabs = ch * (min(t1, 1.0 / habs) if habs > 0.0 else t1)
        dx0 = 2.0 * (chm + ch)
        dx1 = 2.0 * (mabs * chm + habs * ch)
        dx2 = 2.0 * (mabs * mabs * chm + habs * habs * ch)
        px0 = ch + mabs * sabs + e_dir
        px1 = habs * ch + mabs * ch + mabs * e_dir
        px2 = habs * habs * ch + mabs * habs * ch + mabs * mabs * e_dir
        i2 = 1.0 / (t0 * t0)
        i3 = i2 / t0
        i4 = i3 / t0
        bd[0] = min(bd[0], dx0 * i2)
        bd[1] = min(bd[1], dx1 * i2 + 2.0 * dx0 * i3)
        bd[2] = min(bd[2], dx2 * i2 + 4.0 * dx1 * i3 + 6.0 * dx0 * i4)
        bp[0] = min(bp[0], px0 * i2)
        bp[1] = min(bp[1], px1 * i2 + 2.0 * px0 * i3)
        bp[2] = min(bp[2], px2 * i2 + 4.0 * px1 * i3 + 6.0 * px0 * i4)
    be0 = bd[0] + qabs * bp[0]
    be1 = bd[1] + qabs * bp[1]
    be2 = bd[2] + qabs * bp[2]
    return (be2 * bd[0] + 2.0 * be1 * bd[1] + be0 * bd[2]) * BOUND_SAFETY


@njit(cache=True)
def _coefficients(t: float, gamma: float, omega: float):
    """a11, a12, a21, a22 of (e^{-AT} - I)^{-1} and da12/dT, da22/dT (t > 0)."""
    h2 = half_discriminant(gamma, omega)
    m = complex(-0.5 * gamma, -1.0)
    _, b = flight_coefficients(gamma, omega)
    d0, d1, d2, p0, p1, p2, sd, sp = _dp_tilde(t, gamma, h2)
    c, s = _cs(t, h2)
    # D = T^2 D~, D' = 2T D~ + T^2 D~'
    dfull = t * t * d0
    dfull1 = 2.0 * t * d0 + t * t * d1
    a12 = complex_quotient(s, dfull)
    a22 = complex_quotient(p0, d0)
    a11 = a22 - complex_quotient(2.0 * m * s, dfull)
    a21 = complex_quotient(b * s, dfull)
    da12 = complex_quotient(c * dfull - s * dfull1, dfull * dfull)
    da22 = complex_quotient(p1 * d0 - p0 * d1, d0 * d0)
    return a11, a12, a21, a22, da12, da22


@njit(cache=True)
def _f1_many(t: np.ndarray, gamma: float, omega: float, q: complex):
    h2 = half_discriminant(gamma, omega)
    out = np.empty(t.shape[0])
    der = np.empty(t.shape[0])
    for i in range(t.shape[0]):
        d0, d1, d2, p0, p1, p2, sd, sp = _dp_tilde(t[i], gamma, h2)
        a22 = complex_quotient(p0, d0)
        da22 = complex_quotient(p1 * d0 - p0 * d1, d0 * d0)
        out[i] = 1.0 + (q * a22).real
        der[i] = (q * da22).real
    return out, der


# ---------------------------------------------------------------------------
# r rdot along a flight (for the interior extrema of r)
# ---------------------------------------------------------------------------


@njit(cache=True)
def _f_eval(t: float, gamma: float, omega: float, k: complex, v0: complex, dv0: complex):
    """f = Re(conj(U) U') (= r rdot), f', f'' at time t of the flight, and its rounding tolerance."""
    a, b = flight_coefficients(gamma, omega)
    v, dv = propagate(v0, dv0, t, gamma, omega)
    u = k + v
    p2 = b * v - 2.0 * a * dv
    p3 = b * dv - 2.0 * a * p2
    f0 = (u.conjugate() * dv).real
    speed = abs(dv)
    f1 = speed * speed + (u.conjugate() * p2).real
    f2 = 3.0 * (dv.conjugate() * p2).real + (u.conjugate() * p3).real
    scale = (1.0 + abs(k) + abs(v) + abs(v0)) * (abs(dv) + abs(dv0) + abs(v0) + 1e-300)
    return f0, f1, f2, 64.0 * EPS * scale


@njit(cache=True)
def _f_bound(t: float, w: float, gamma: float, omega: float, k: complex, v0: complex, dv0: complex) -> float:
    """A bound M >= max |f''| on [t, t + w] from the exact flow started at t."""
    a, b = flight_coefficients(gamma, omega)
    h2 = half_discriminant(gamma, omega)
    v, dv = propagate(v0, dv0, t, gamma, omega)
    p2 = b * v - 2.0 * a * dv
    p3 = b * dv - 2.0 * a * p2
    p4 = b * p2 - 2.0 * a * p3
    cmax, smax = window_bounds(gamma, h2, w)
    b0 = cmax * abs(v) + smax * abs(a * v + dv)
    b1 = cmax * abs(dv) + smax * abs(a * dv + p2)
    b2 = cmax * abs(p2) + smax * abs(a * p2 + p3)
    b3 = cmax * abs(p3) + smax * abs(a * p3 + p4)
    return (3.0 * b1 * b2 + (abs(k) + b0) * b3) * BOUND_SAFETY


# ---------------------------------------------------------------------------
# Generic guaranteed isolation of the zeros of g or f
# ---------------------------------------------------------------------------


@njit(cache=True)
def _eval(kind, t, rp, cp):
    if kind == _KIND_G:
        return _g_eval(t, rp[0], rp[2], cp[0])
    return _f_eval(t, rp[0], rp[1], cp[0], cp[1], cp[2])


@njit(cache=True)
def _bound(kind, t, w, rp, cp):
    if kind == _KIND_G:
        return _g_bound(t, t + w, rp[0], rp[2], abs(cp[0]))
    return _f_bound(t, w, rp[0], rp[1], cp[0], cp[1], cp[2])


@njit(cache=True)
def _safe_root(f: float, fp: float, m: float) -> float:
    """Positive root of f + fp s - m s^2 / 2 = 0 for f > 0 (cancellation-free)."""
    if m <= 0.0:
        if fp < 0.0:
            return -f / fp
        return math.inf
    disc = math.sqrt(fp * fp + 2.0 * m * f)
    if fp <= 0.0:
        return 2.0 * f / (disc - fp)
    return (fp + disc) / m


@njit(cache=True)
def _push(zt, zd, zf, n, t, direction, flag):
    if n == zt.shape[0]:
        zt2 = np.empty(2 * n)
        zd2 = np.empty(2 * n, dtype=np.int64)
        zf2 = np.empty(2 * n, dtype=np.int64)
        zt2[:n] = zt[:n]
        zd2[:n] = zd[:n]
        zf2[:n] = zf[:n]
        zt, zd, zf = zt2, zd2, zf2
    zt[n] = t
    zd[n] = direction
    zf[n] = flag
    return zt, zd, zf, n + 1


@njit(cache=True)
def _isolate(kind, rp, cp, t_start, t_end, sigma0, w0):
    """All zeros of the function `kind` on (t_start, t_end), in order, by safe stepping.

    Returns
    -------
    times : float array
    directions : int array
        Sign of the function just after each zero (+1: it turns positive).
    flags : int array
        0 for a transversal zero, 1 for one half of a double zero (tangency
        within rounding; reported as two consecutive entries at one time).
    sigma_start : int
        Sign of the function just after t_start.
    status : int
    """
    zt = np.empty(16)
    zd = np.empty(16, dtype=np.int64)
    zf = np.empty(16, dtype=np.int64)
    nz = 0
    tau = t_start
    v, v1, v2, tol = _eval(kind, tau, rp, cp)
    if abs(v) > tol:
        sigma = 1 if v > 0.0 else -1
    elif v1 != 0.0:
        sigma = 1 if v1 > 0.0 else -1
    else:
        sigma = sigma0
    sigma_start = sigma
    fresh = True  # leaving a zero that is not to be recorded again
    band = False  # inside a tangency that is within rounding
    band_t = tau
    band_v = math.inf
    w = w0
    finished = False
    for _ in range(MAX_STEPS):
        if tau >= t_end:
            finished = True
            break
        v, v1, v2, tol = _eval(kind, tau, rp, cp)
        ww = min(w, t_end - tau)
        mb = _bound(kind, tau, ww, rp, cp)
        thr = 2.0 * math.sqrt(2.0 * mb * tol)
        sv = sigma * v
        sv1 = sigma * v1
        if sv > tol:
            if band and not fresh:
                zt, zd, zf, nz = _push(zt, zd, zf, nz, band_t, -sigma, 1)
                zt, zd, zf, nz = _push(zt, zd, zf, nz, band_t, sigma, 1)
            band = False
            fresh = False
            h = min(_safe_root(sv, sv1, mb), ww)
        elif sv < -tol:
            # the sign changed inside a rounding band (a crossing with a tiny slope)
            if not fresh:
                zt, zd, zf, nz = _push(zt, zd, zf, nz, band_t if band else tau, -sigma, 0)
            sigma = -sigma
            band = False
            continue
        elif sv1 < -thr:
            # a transversal zero here: polish it in its monotone neighbourhood
            reach = abs(v1) / mb
            z = tau
            for _p in range(6):
                fz, fz1, fz2, tz = _eval(kind, z, rp, cp)
                if fz1 == 0.0:
                    break
                step = fz / fz1
                znew = min(max(z - step, tau - reach), tau + reach)
                if abs(znew - z) <= 4.0 * EPS * abs(z):
                    z = znew
                    break
                z = znew
            zt, zd, zf, nz = _push(zt, zd, zf, nz, z, -sigma, 0)
            sigma = -sigma
            band = False
            fresh = True
            # leave through the monotone neighbourhood of the zero
            fz, fz1, fz2, tz = _eval(kind, z, rp, cp)
            ww = min(max(w, 1e-3), t_end - z)
            if ww <= 0.0:
                finished = True
                break
            mb = _bound(kind, z, ww, rp, cp)
            h = min(abs(fz1) / mb, ww)
            tau = max(z + h, tau + 4.0 * EPS * abs(tau) + 1e-300)
            w = max(2.0 * h, 1e-6)
            continue
        elif sv1 > thr:
            # at the noise level, moving into the sigma side: unless this is the zero
            # just left, the function came down to rounding level and turns back
            if not fresh:
                t_touch = band_t if band else tau
                zt, zd, zf, nz = _push(zt, zd, zf, nz, t_touch, -sigma, 1)
                zt, zd, zf, nz = _push(zt, zd, zf, nz, t_touch, sigma, 1)
                fresh = True
            band = False
            h = min(sv1 / mb, ww)
        else:
            # |g| and |g'| both at the rounding level: a tangency; walk past it
            if not band:
                band = True
                band_t = tau
                band_v = abs(v)
            elif abs(v) < band_v:
                band_t = tau
                band_v = abs(v)
            h = min(_safe_root(tol, sv1, mb), ww)
        if not h > 0.0 or tau + h == tau:
            h = 4.0 * EPS * abs(tau) + 1e-300
        if h >= 0.5 * ww:
            w = 2.0 * ww
        else:
            w = max(2.0 * h, 1e-6)
        tau += h
    status = ISO_OK if finished else ISO_ITERATION_LIMIT
    return zt[:nz].copy(), zd[:nz].copy(), zf[:nz].copy(), sigma_start, status


@njit(cache=True)
def _f1_zeros_kernel(gamma, omega, d, mu, t_max):
    h2 = half_discriminant(gamma, omega)
    q = impact_q(d, mu)
    rp = np.array([gamma, omega, h2])
    cp = np.array([q, 0j, 0j])
    # sign of F1 just after 0 when F1(0) = (1 - d)/2 vanishes: F1 ~ (1 + d)(gamma - 2 mu) T / 12
    sigma0 = 1 if (gamma - 2.0 * mu) >= 0.0 else -1
    return _isolate(_KIND_G, rp, cp, 0.0, t_max, sigma0, min(0.25, t_max))


@njit(cache=True)
def _flight_extrema_kernel(gamma, omega, k, v0, dv0, t_end):
    rp = np.array([gamma, omega, 0.0])
    cp = np.array([k, v0, dv0])
    zt, zd, zf, s0, status = _isolate(_KIND_F, rp, cp, 0.0, t_end, 1, min(0.25, t_end))
    radii = np.empty(zt.shape[0])
    for i in range(zt.shape[0]):
        v, dv = propagate(v0, dv0, zt[i], gamma, omega)
        radii[i] = abs(k + v)
    return zt, zd, zf, radii, status


# ---------------------------------------------------------------------------
# The impact map and its Jacobian
# ---------------------------------------------------------------------------


@njit(cache=True)
def _reset(theta, rdot, thetadot, d, mu, r_ratio, law):
    """Post-impact velocity and the reset Jacobian d(rdot+, thetadot+)/d(rdot, thetadot)."""
    e = complex(math.cos(theta), math.sin(theta))
    du = e * complex(rdot, thetadot)
    if law == 1:
        du_plus = ideal_reset(e, du, rdot, impact_q(d, mu))
        r11, r12, r21, r22, stuck = reset_jacobian(relative_velocity(r_ratio, thetadot), 0.0, d, mu, True)
        return du_plus, r11, r12, r21, r22, _SLIP
    du_plus, rd, td, rdp, tdp, v_rel, p_n, p_t = apply_reset(e, du, d, mu, r_ratio)
    r11, r12, r21, r22, stuck = reset_jacobian(v_rel, mu * p_n, d, mu, False)
    return du_plus, r11, r12, r21, r22, (_STICK if stuck else _SLIP)


@njit(cache=True)
def _jacobian_kernel(gamma, omega, k, d, mu, r_ratio, theta, rdot, thetadot, tau, law):
    """Next pre-impact state after a flight of length tau and the analytic Jacobian of P_I.

    Returns
    -------
    x1 : (3,) array
    jac : (3, 3) array
    dtau : (3,) array
        Gradient of the flight time.
    branch : int
        Reset branch (slip or stick).
    """
    a, b = flight_coefficients(gamma, omega)
    e = complex(math.cos(theta), math.sin(theta))
    du_plus, r11, r12, r21, r22, branch = _reset(theta, rdot, thetadot, d, mu, r_ratio, law)
    w_plus = du_plus * e.conjugate()  # rdot+ + i thetadot+
    v0 = e - k
    v, dv = propagate(v0, du_plus, tau, gamma, omega)
    u1 = k + v
    e1 = complex_quotient(u1, abs(u1))
    ddv = b * v - 2.0 * a * dv
    rd1, td1 = polar_velocity(e1, dv)
    x1 = np.empty(3)
    x1[0] = math.atan2(e1.imag, e1.real)
    if x1[0] <= -math.pi:
        x1[0] += 2.0 * math.pi
    x1[1] = rd1
    x1[2] = td1
    # Phi = e^{A tau} column by column (the flow is complex-linear)
    phi11, phi21 = propagate(1.0 + 0j, 0j, tau, gamma, omega)
    phi12, phi22 = propagate(0j, 1.0 + 0j, tau, gamma, omega)
    hdot = (e1.conjugate() * dv).real  # grad h . f / 2 on |U| = 1
    jac = np.empty((3, 3))
    dtau = np.empty(3)
    for j in range(3):
        dth = 1.0 if j == 0 else 0.0
        drd = 1.0 if j == 1 else 0.0
        dtd = 1.0 if j == 2 else 0.0
        drp = r11 * drd + r12 * dtd
        dtp = r21 * drd + r22 * dtd
        dv0 = 1j * e * dth
        ddv0 = 1j * e * w_plus * dth + e * complex(drp, dtp)
        dvt = phi11 * dv0 + phi12 * ddv0
        ddvt = phi21 * dv0 + phi22 * ddv0
        dt = -(e1.conjugate() * dvt).real / hdot
        du = dvt + dv * dt
        ddu = ddvt + ddv * dt
        dw = du.conjugate() * dv + e1.conjugate() * ddu
        jac[0, j] = (e1.conjugate() * du).imag
        jac[1, j] = dw.real
        jac[2, j] = dw.imag
        dtau[j] = dt
    return x1, jac, dtau, branch


@njit(cache=True)
def _impact_map_kernel(gamma, omega, k, d, mu, r_ratio, theta, rdot, thetadot, horizon, law):
    e = complex(math.cos(theta), math.sin(theta))
    du_plus = _reset(theta, rdot, thetadot, d, mu, r_ratio, law)[0]
    code, tau = next_crossing(e - k, du_plus, k, gamma, omega, horizon, True)
    return code, tau


# ---------------------------------------------------------------------------
# Public API: impact map
# ---------------------------------------------------------------------------


def _params_tuple(params: Parameters):
    check_params(params)
    if not has_regular_equilibrium.py_func(params.gamma, params.omega):
        raise ParameterError(
            "omega = 1 with gamma = 0 has no regular equilibrium (k is infinite); "
            "allowed: omega != 1 or gamma != 0"
        )
    return params.gamma, params.omega, params.k, params.d, params.mu, params.r_ratio


def _state(state) -> tuple[float, float, float]:
    arr = real_array(state)
    if arr is None:
        raise ParameterError(f"state = {state!r} is not (theta, rdot, thetadot), three real numbers")
    arr = arr.reshape(-1)
    if arr.shape != (3,):
        raise ParameterError(f"state = {state!r} is not (theta, rdot, thetadot): need 3 numbers")
    names = ("theta", "rdot", "thetadot")
    theta, rdot, thetadot = (check_finite(n, x) for n, x in zip(names, arr))
    check_velocity("(rdot, thetadot)", complex(rdot, thetadot))
    return theta, rdot, thetadot


@dataclass(frozen=True)
class ImpactMapResult:
    """One application of the impact map P_I.

    Attributes
    ----------
    status : str
        ``"impact"``; ``"no-impact"`` (no impact within the horizon);
        ``"stuck"`` (after the impact the rotor stays on the boundary: impacts
        accumulate); ``"failed"`` (the impact location did not converge).
    state : numpy.ndarray or None
        Next pre-impact state (theta, rdot-, thetadot-), theta in (-pi, pi].
    time : float or None
        Flight time T to the next impact.
    jacobian : numpy.ndarray or None
        3x3 Jacobian d state / d state0 (when requested).
    time_gradient : numpy.ndarray or None
        Gradient dT / d state0 (when requested).
    sticking : bool
        True when the friction impulse is capped (the contact point sticks).
    """

    status: str
    state: np.ndarray | None
    time: float | None
    jacobian: np.ndarray | None = field(default=None, repr=False)
    time_gradient: np.ndarray | None = field(default=None, repr=False)
    sticking: bool = False


def post_impact_state(params: Parameters, state, *, law: str = SLIP_BOUNDED) -> tuple[complex, complex]:
    """(U, U') just after the impact at the pre-impact state (theta, rdot-, thetadot-).

    This is the initial condition that starts `rotorcontact.simulation.simulator` just
    after the impact.
    """
    g, w, k, d, mu, rr = _params_tuple(params)
    theta, rdot, thetadot = _state(state)
    du_plus = call_kernel(_reset, theta, rdot, thetadot, d, mu, rr, _check_law(law))[0]
    return complex(math.cos(theta), math.sin(theta)), complex(du_plus)


def impact_map(
    params: Parameters,
    state,
    *,
    horizon: float = 1000.0,
    law: str = SLIP_BOUNDED,
    jacobian: bool = False,
) -> ImpactMapResult:
    """Apply the impact map P_I to a pre-impact state on Sigma = {r = 1}.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    state : array_like
        (theta, rdot-, thetadot-) just before an impact; rdot- > 0 for a real impact.
    horizon : float
        Longest flight searched for the next impact.
    law : {"slip-bounded", "ideal"}
        Impact law: the simulator's (friction capped at v_rel = 0) or the
        law of MODEL.md §5 (U'+ = U'- - q rdot- U).
    jacobian : bool
        Also return the analytic Jacobian and the gradient of the flight time.

    Returns
    -------
    ImpactMapResult
    """
    g, w, k, d, mu, rr = _params_tuple(params)
    theta, rdot, thetadot = _state(state)
    horizon = check_range("horizon", horizon, low=0.0, low_open=True)
    lw = _check_law(law)
    jacobian = check_bool("jacobian", jacobian)
    code, tau = call_kernel(_impact_map_kernel, g, w, k, d, mu, rr, theta, rdot, thetadot, horizon, lw)
    sticking = call_kernel(_reset, theta, rdot, thetadot, d, mu, rr, lw)[5] == _STICK
    if code != CROSSING:
        status = "stuck" if code == STUCK else ("no-impact" if tau >= horizon else "failed")
        return ImpactMapResult(status, None, None, sticking=sticking)
    x1, jac, dtau, branch = call_kernel(_jacobian_kernel, g, w, k, d, mu, rr, theta, rdot, thetadot, tau, lw)
    if not jacobian:
        jac, dtau = None, None
    return ImpactMapResult("impact", x1, float(tau), jac, dtau, sticking)


def impact_map_jacobian(
    params: Parameters, state, time: float, *, law: str = SLIP_BOUNDED
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Image and analytic Jacobian of P_I at a state whose next impact is known to be at ``time``.

    No impact search is made: the flight of length ``time`` is taken to end
    on |U| = 1 (as at a fixed point, or on a continuation branch).

    Returns
    -------
    state1 : numpy.ndarray
        (theta, rdot-, thetadot-) after the flight.
    jacobian : numpy.ndarray
        3x3 Jacobian of P_I.
    time_gradient : numpy.ndarray
        dT / d state.
    """
    g, w, k, d, mu, rr = _params_tuple(params)
    theta, rdot, thetadot = _state(state)
    time = _check_period(params, "time", time)
    x1, jac, dtau, branch = call_kernel(_jacobian_kernel, g, w, k, d, mu, rr, theta, rdot, thetadot, time,
                                        _check_law(law))
    return x1, jac, dtau


# ---------------------------------------------------------------------------
# Public API: F1 and a_ij
# ---------------------------------------------------------------------------


def _check_times(params: Parameters, name: str, t) -> np.ndarray:
    """``t``, a period or an array of periods, each in (0, period_limit(params)]."""
    if not isinstance(t, (list, tuple, np.ndarray)) or (isinstance(t, np.ndarray) and t.ndim == 0):
        return np.asarray(_check_period(params, name, t[()] if isinstance(t, np.ndarray) else t))
    arr = real_array(t)
    if arr is None:
        raise ParameterError(f"{name} = {t!r} is not a number or an array of numbers; allowed: {name} > 0")
    if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise ParameterError(f"{name} must be finite and > 0; got {t!r}")
    _check_period_limit(params, f"max({name})", float(arr.max()))
    return arr


def a_matrix(params: Parameters, T: float) -> np.ndarray:
    """[a_ij(T)] = (e^{-AT} - I)^{-1} (MODEL.md §5).

    Parameters
    ----------
    params : Parameters
        Model parameters.
    T : float
        Period, > 0 (at gamma = 0 also away from the resonances, where the
        matrix is singular).

    Returns
    -------
    numpy.ndarray
        2x2 complex array, from the closed form of the module docstring.
    """
    _params_tuple(params)
    T = _check_period(params, "T", T)
    a11, a12, a21, a22, da12, da22 = call_kernel(_coefficients, T, params.gamma, params.omega)
    return np.array([[a11, a12], [a21, a22]], dtype=complex)


def a_derivatives(params: Parameters, T: float) -> tuple[complex, complex, complex, complex]:
    """(a12, a22, da12/dT, da22/dT) at T > 0 (for continuation of the fixed points)."""
    _params_tuple(params)
    T = _check_period(params, "T", T)
    a11, a12, a21, a22, da12, da22 = call_kernel(_coefficients, T, params.gamma, params.omega)
    return complex(a12), complex(a22), complex(da12), complex(da22)


def _q(params: Parameters) -> complex:
    return impact_q.py_func(params.d, params.mu)  # the compiled formula run as Python: no dispatch cost


def f1(params: Parameters, T):
    """F1(T) = 1 + Re(q a22(T)) (MODEL.md §5), for a float or an array of T > 0."""
    _params_tuple(params)
    arr = _check_times(params, "T", T)
    val, _ = call_kernel(_f1_many, np.atleast_1d(arr).ravel(), params.gamma, params.omega, _q(params))
    return float(val[0]) if arr.ndim == 0 else val.reshape(arr.shape)


def f1_derivative(params: Parameters, T):
    """dF1/dT, for a float or an array of T > 0."""
    _params_tuple(params)
    arr = _check_times(params, "T", T)
    _, der = call_kernel(_f1_many, np.atleast_1d(arr).ravel(), params.gamma, params.omega, _q(params))
    return float(der[0]) if arr.ndim == 0 else der.reshape(arr.shape)


@dataclass(frozen=True)
class F1Zero:
    """A zero of F1: the period of a pair of one-impact orbits.

    Attributes
    ----------
    T : float
        The zero.
    n : int
        Index of its pair.
    kind : str
        ``"a"`` (F1 turns negative: T0,n,a) or ``"b"`` (F1 turns positive: T0,n,b).
    slope : float
        dF1/dT at the zero (0 for a double zero).
    double : bool
        True when F1 touches 0 within rounding (the pair has merged: a smooth fold).
    """

    T: float
    n: int
    kind: str
    slope: float
    double: bool = False


#: Largest growth exponent, growth rate times period, of a flight over which F1 is evaluated.
MAX_GROWTH = 300.0


def flight_growth(params: Parameters) -> float:
    """The fastest rate at which a free flight grows or decays: |gamma| / 2 + sqrt(max(gamma^2 / 4 - omega^2, 0)).

    The eigenvalues of the flight are -gamma/2 - i +- h with h^2 = gamma^2/4 - omega^2 (MODEL.md §3), so its
    terms and those of e^{-AT} behave like e^{growth T} at most; F1 and the flight are evaluated for periods
    T up to ``MAX_GROWTH / growth`` (`period_limit`). The rate increases with |gamma| and decreases with omega.
    """
    check_params(params)
    return growth_rate(params.gamma, half_discriminant.py_func(params.gamma, params.omega))


def growth_rate(gamma: float, h2: float, direction: int = 0) -> float:
    """The fastest growth of a flight from the damping and the half discriminant h2 = gamma^2/4 - omega^2
    (`half_discriminant`): -gamma/2 + sqrt(max(h2, 0)) forwards in time (``direction`` > 0), gamma/2 + ...
    backwards (< 0), and |gamma|/2 + ... either way (0: `flight_growth`)."""
    h = math.sqrt(h2) if h2 > 0 else 0.0
    if direction == 0:
        return abs(gamma) / 2.0 + h
    return h + (-0.5 * gamma if direction > 0 else 0.5 * gamma)


def period_limit(params: Parameters) -> float:
    """The largest ``t_max`` that `f1_zeros` accepts at ``params`` (inf where the flight neither grows nor decays)."""
    growth = flight_growth(params)
    return math.inf if growth == 0.0 else MAX_GROWTH / growth


def check_growth(name: str, value: float, growth: float, where: str) -> float:
    """Return the period ``value`` unless it exceeds ``MAX_GROWTH / growth``, beyond which a flight growing or
    decaying like e^{growth T} leaves the range where it is evaluated accurately; ``where`` names the
    parameters in the `ParameterError`."""
    if growth > 0.0 and value > MAX_GROWTH / growth:
        raise ParameterError(f"{name} = {value!r} is too large at {where} (the free flight grows or decays like "
                             f"e^{{±{growth:.3g} T}}); allowed: {name} <= {MAX_GROWTH / growth:.6g}")
    return value


def _check_period_limit(params: Parameters, name: str, value: float) -> float:
    return check_growth(name, value, flight_growth(params), f"gamma = {params.gamma:g}, omega = {params.omega:g}")


def _check_period(params: Parameters, name: str, value) -> float:
    """``value`` as a period in (0, period_limit(params)]: beyond it the flight and e^{-AT} leave the range
    where they are evaluated accurately."""
    return _check_period_limit(params, name, check_range(name, value, low=0.0, low_open=True))


#: Longest search for zeros of F1 and one-impact orbits: the orbits up to t_max grow like t_max^2 near the
#: undamped resonance (about 10^4 of them in minutes at 1e4), and the impact model's periods are of order 10.
MAX_T_MAX = 1e4


def searchable_t_max(params: Parameters, t_max: float) -> float:
    """The longest search for one-impact orbits up to ``t_max`` that `f1_zeros` accepts at ``params``:
    ``min(t_max, period_limit(params), MAX_T_MAX)``. For naming the orbits a study reached, where a strong
    damping (a short `period_limit`) must not refuse a search the user did not ask for; orbits of longer
    period are left unnamed."""
    check_params(params)
    t_max = check_range("t_max", t_max, low=0.0, low_open=True)
    return min(t_max, period_limit(params), MAX_T_MAX)


def admissible_orbits(params: Parameters, t_max: float) -> list[ImpactOrbit]:
    """The admissible one-impact orbits at ``params`` with periods up to ``t_max``, or as far as they can be
    searched there (`searchable_t_max`): those a study's simulations may reach and name."""
    return [o for o in one_impact_orbits(params, t_max=searchable_t_max(params, t_max)) if o.admissible]


def _check_t_max(params: Parameters, t_max) -> float:
    """``t_max`` in (0, min(`MAX_T_MAX`, `period_limit`)]."""
    t_max = _check_period(params, "t_max", t_max)
    if t_max > MAX_T_MAX:
        raise ParameterError(f"t_max = {t_max!r} is too large; allowed: t_max <= {MAX_T_MAX:g} (the orbits up to "
                             "t_max grow like t_max^2)")
    return t_max


def f1_zeros(params: Parameters, t_max: float = 12.0) -> tuple[F1Zero, ...]:
    """Every zero of F1 on (0, t_max], in increasing order, labelled in pairs.

    The zeros are isolated with a guarantee (module docstring): none is missed,
    including the two zeros of a pair about to merge. A minimum of F1 within
    rounding of 0 is reported as a double zero (two entries at one T).

    Parameters
    ----------
    params : Parameters
        Model parameters (any gamma; at gamma = 0 the poles of F1 are skipped).
    t_max : float
        End of the search interval.

    Returns
    -------
    tuple of F1Zero
    """
    _params_tuple(params)
    t_max = _check_t_max(params, t_max)
    if params.gamma == 0.0 and params.mu == 0.0 and params.d == 1.0:
        # no damping, no friction, elastic impacts: 1 + 2 Re(a22) vanishes for every T
        raise ParameterError(
            "gamma = 0, mu = 0 and d = 1 make F1 vanish identically (every period is a zero); "
            "allowed: gamma != 0, mu != 0 or d < 1"
        )
    zt, zd, zf, s0, status = call_kernel(_f1_zeros_kernel, params.gamma, params.omega, params.d, params.mu, t_max)
    if status != ISO_OK:
        # the steps of the isolation grow with the zeros on (0, t_max], which are unbounded at gamma = 0
        raise IsolationLimit(
            f"t_max = {t_max!r} is too large at gamma = {params.gamma:g}, omega = {params.omega:g}, d = {params.d:g}, "
            f"mu = {params.mu:g}: the isolation of the zeros of F1 on (0, t_max] needs more than {MAX_STEPS} steps; "
            "allowed: a smaller t_max"
        )
    h2 = half_discriminant.py_func(params.gamma, params.omega)
    q = _q(params)
    inside = [(float(t), direction, flag) for t, direction, flag in zip(zt, zd, zf) if 0.0 < t <= t_max]
    zeros = []
    for (t, direction, flag), (n, kind) in zip(inside, label_f1_zeros([z[1] for z in inside], s0 > 0)):
        if params.gamma == 0.0:
            d0, d1, d2, p0, p1, p2, sd, sp = call_kernel(_dp_tilde, t, params.gamma, h2)
            if abs(d0) <= 1e-8 * abs(d0 + q * p0):
                # a pole of F1 (a resonance at gamma = 0), the limit of a zero as gamma -> 0:
                # it keeps its place in the labelling but has no orbit
                continue
        slope = 0.0 if flag else float(f1_derivative(params, t))
        zeros.append(F1Zero(T=t, n=n, kind=kind, slope=slope, double=bool(flag)))
    return tuple(zeros)


def label_f1_zeros(directions: Sequence[int], starts_positive: bool) -> list[tuple[int, str]]:
    """Pair index n and kind of each zero of F1, in increasing T (MODEL.md §5).

    A zero where F1 turns negative (direction < 0) opens pair n (kind ``"a"``,
    T0,n,a); the next one, where F1 turns positive, closes it (kind ``"b"``).
    Where F1 starts negative (``starts_positive`` False) the first zero closes
    pair 1.

    Parameters
    ----------
    directions : sequence of int
        Sign of the change of F1 across each zero, in increasing T.
    starts_positive : bool
        F1 > 0 just after T = 0.

    Returns
    -------
    list of (int, str)
        (n, kind) of each zero, n >= 1.

    Raises
    ------
    ParameterError
        Unless ``directions`` is a sequence of signs (+1, -1, 0) and ``starts_positive`` a bool.
    """
    signs = real_array(directions)
    if signs is None or signs.ndim != 1 or not np.all(np.isin(np.sign(signs), (-1.0, 0.0, 1.0))) \
            or not np.all(np.isfinite(signs)):
        raise ParameterError(f"directions = {directions!r} is invalid; allowed: a sequence of the signs of F1's "
                             "changes (+1, -1)")
    starts_positive = check_bool("starts_positive", starts_positive)
    n = 0 if starts_positive else 1
    labels = []
    for direction in directions:
        if direction < 0:
            n += 1
            kind = "a"
        else:
            kind = "b"
        labels.append((max(n, 1), kind))
    return labels


#: The branch letters of one-impact orbits (MODEL.md §5): a, b at the smaller root rdot, c, d at the larger.
BRANCH_LETTERS = ("a", "b", "c", "d")


def root_branches(kind: str) -> tuple[str, str]:
    """Branch letters of the smaller and the larger root rdot at a zero of ``kind`` (MODEL.md §5).

    ``"a"`` gives (a, c), ``"b"`` gives (b, d).
    """
    check_choice("kind", kind, ("a", "b"))
    return (kind, "c" if kind == "a" else "d")


def stable_quadratic_roots(a: float, b: float, c: float) -> tuple[float, tuple[float, ...]]:
    """Real roots of a x^2 + 2 b x + c = 0, computed without cancellation.

    The root of larger magnitude is -(b + sgn(b) sqrt(b^2 - a c)) / a, the
    other follows from the product of the roots, c / a.

    Returns
    -------
    discriminant : float
        b^2 - a c.
    roots : tuple of float
        The two real roots, smaller first; empty where the discriminant is
        negative or a = 0.

    Raises
    ------
    ParameterError
        Unless a, b and c are finite real numbers.
    """
    a, b, c = (check_finite(name, value) for name, value in (("a", a), ("b", b), ("c", c)))
    # The equation divided by s has the same roots. Far from 1, s is the power of two nearest the largest
    # coefficient, so that b^2 - a c cannot overflow or underflow; a power of two scales exactly, so the
    # roots are those the unscaled formula gives wherever it does not overflow.
    largest = max(abs(a), abs(b), abs(c))
    if largest == 0.0:
        return 0.0, ()
    s = 1.0 if 2.0**-500 < largest < 2.0**500 else math.ldexp(1.0, math.frexp(largest)[1])
    a, b, c = a / s, b / s, c / s
    scaled = b * b - a * c
    disc = scaled * s * s  # may overflow to +-inf for huge coefficients, with the right sign
    if disc == 0.0 and scaled != 0.0:
        disc = math.copysign(math.ulp(0.0), scaled)  # underflowed: the smallest float of its sign
    if scaled < 0.0 or a == 0.0:
        return float(disc), ()
    sq = math.sqrt(scaled)
    qq = -(b + math.copysign(sq, b))
    roots = sorted([qq / a, c / qq if qq != 0.0 else qq / a])
    return float(disc), (float(roots[0]), float(roots[1]))


def rdot_roots(params: Parameters, T: float) -> tuple[float, tuple[float, ...]]:
    """Roots of |q a12|^2 rdot^2 + 2 Re(q a12) rdot + 1 - |k|^2 = 0 at period T.

    Returns
    -------
    discriminant : float
        Re(q a12)^2 - |q a12|^2 (1 - |k|^2); no real root where negative.
    roots : tuple of float
        The real roots, smaller first (empty where the discriminant is negative).
    """
    _params_tuple(params)
    T = _check_period(params, "T", T)
    a11, a12, a21, a22, da12, da22 = call_kernel(_coefficients, T, params.gamma, params.omega)
    qa = _q(params) * a12
    return stable_quadratic_roots(abs(qa) ** 2, qa.real, 1.0 - abs(params.k) ** 2)


def fixed_point_residual(params: Parameters, T: float, rdot: float) -> tuple[np.ndarray, np.ndarray]:
    """Residual of the one-impact fixed-point equations in the unknowns (T, rdot), and its Jacobian.

    R1 = F1(T) = 1 + Re(q a22(T)), R2 = |1 + q a12(T) rdot|^2 - |k|^2; a
    fixed point with rdot != 0 is a zero of (R1, R2). theta and thetadot follow
    from `theta = Arg(k / (1 + q a12 rdot))`, `thetadot = -Im(q a22) rdot`.

    Returns
    -------
    residual : numpy.ndarray, shape (2,)
    jacobian : numpy.ndarray, shape (2, 2)
        d(R1, R2) / d(T, rdot).
    """
    _params_tuple(params)
    T = _check_period(params, "T", T)
    rdot = check_range("rdot", rdot, low=-MAX_VELOCITY, high=MAX_VELOCITY)
    q = _q(params)
    a11, a12, a21, a22, da12, da22 = call_kernel(_coefficients, T, params.gamma, params.omega)
    z = 1.0 + q * a12 * rdot
    res = np.array([1.0 + (q * a22).real, abs(z) ** 2 - abs(params.k) ** 2])
    jac = np.array(
        [
            [(q * da22).real, 0.0],
            [2.0 * (z.conjugate() * q * da12 * rdot).real, 2.0 * (z.conjugate() * q * a12).real],
        ]
    )
    return res, jac


# ---------------------------------------------------------------------------
# Interior extrema of r along a flight
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class FlightExtrema:
    """Interior local extrema of r = |U| along one flight between impacts.

    Attributes
    ----------
    times : numpy.ndarray
        Times of the extrema after the impact, in (0, T).
    radii : numpy.ndarray
        r at those times.
    maxima : numpy.ndarray
        True for a local maximum, False for a local minimum.
    """

    times: np.ndarray
    radii: np.ndarray
    maxima: np.ndarray

    @property
    def count(self) -> int:
        """Number of interior extrema."""
        return int(self.times.shape[0])

    @property
    def r_max(self) -> float | None:
        """Largest interior local maximum of r, or None where r has none."""
        if not np.any(self.maxima):
            return None
        return float(np.max(self.radii[self.maxima]))


def _extrema_from_post(params: Parameters, u0: complex, du0: complex, T: float) -> FlightExtrema:
    k = params.k
    zt, zd, zf, radii, status = call_kernel(_flight_extrema_kernel, params.gamma, params.omega, k, u0 - k, du0, T)
    if status != ISO_OK:
        raise RuntimeError("isolation of the extrema of r did not finish (iteration limit)")
    edge = 1e-12 * (1.0 + T)
    keep = (zf == 0) & (zt > edge) & (zt < T - edge)
    return FlightExtrema(times=zt[keep], radii=radii[keep], maxima=zd[keep] < 0)


def flight_extrema(params: Parameters, state, T: float, *, law: str = IDEAL) -> FlightExtrema:
    """Interior local extrema of r on the flight from the impact at ``state`` to time T.

    The zeros of r rdot = Re(conj(U) U') on (0, T) are isolated with a
    guarantee (safe stepping with a rigorous bound on its second derivative
    along the exact flow), so no extremum is missed; each is polished to
    rounding, so r is exact there. Tangencies within rounding (degenerate
    extrema) are not counted.
    """
    _params_tuple(params)
    T = _check_period(params, "T", T)
    u0, du0 = post_impact_state(params, state, law=law)
    return _extrema_from_post(params, u0, du0, T)


# ---------------------------------------------------------------------------
# One-impact periodic orbits
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class ImpactOrbit:
    """A periodic orbit with one impact per period, B_n,m of MODEL.md §5.

    Attributes
    ----------
    label : str
        ``"B1,a"`` etc.
    n : int
        Index of the pair of zeros of F1.
    branch : str
        ``"a"``, ``"b"``, ``"c"`` or ``"d"``.
    T : float
        Period (time between impacts).
    theta : float
        Impact angle in (-pi, pi].
    rdot : float
        Radial velocity just before the impact.
    thetadot : float
        Angular velocity just before the impact.
    admissible : bool
        rdot > 0 (the rotor arrives from inside); otherwise the orbit is virtual.
    plausible : bool
        Admissible, slipping, and r < 1 strictly between the impacts.
    slipping : bool
        The impact slips with v_rel > 0 (v_rel > mu (1 + d) rdot), so the
        simulator's slip-bounded law acts as the law of MODEL.md §5.
    r_max_interior : float or None
        Largest interior local maximum of r, or None where there is none.
    interior_extrema : int
        Number of interior local extrema of r.
    multipliers : tuple of complex or None
        Eigenvalues of the Jacobian of P_I (law of MODEL.md §5), largest
        modulus first; None when virtual.
    stable : bool or None
        All multipliers inside the unit circle; None when virtual or when
        `friction_reverses` (see `orbit_stability`).
    params : Parameters
        The parameters of the orbit.

    See Also
    --------
    friction_reverses : whether the fixed point is an orbit of the simulator at all.
    """

    label: str
    n: int
    branch: str
    T: float
    theta: float
    rdot: float
    thetadot: float
    admissible: bool
    plausible: bool
    slipping: bool
    r_max_interior: float | None
    interior_extrema: int
    multipliers: tuple[complex, ...] | None
    stable: bool | None
    params: Parameters = field(repr=False)

    @property
    def friction_reverses(self) -> bool:
        """True when the friction of the law of MODEL.md §5 does not stop at v_rel = 0 at this impact.

        That law applies the friction impulse mu (1 + d) rdot- against +theta
        whatever the relative surface velocity v_rel- = r_ratio + 1 + thetadot-
        is. Where it is at least v_rel- (small ``r_ratio``: v_rel- near zero or
        negative), the impulse would reverse v_rel within the impact. The
        simulator's friction never reverses v_rel (MODEL.md §2), so such a
        fixed point is not an orbit of the simulator: it is neither plausible
        nor called stable (``stable`` is None). False for virtual orbits, which
        have no impact.
        """
        return bool(self.admissible and not self.slipping)

    @property
    def state(self) -> np.ndarray:
        """(theta, rdot-, thetadot-), the fixed point of P_I."""
        return np.array([self.theta, self.rdot, self.thetadot])

    def initial_condition(self) -> tuple[complex, complex]:
        """(U, U') just after the impact: starts `simulate` on the orbit."""
        return post_impact_state(self.params, self.state, law=IDEAL)

    def jacobian(self) -> np.ndarray:
        """The analytic 3x3 Jacobian of P_I at the fixed point (law of MODEL.md §5)."""
        return impact_map_jacobian(self.params, self.state, self.T, law=IDEAL)[1]

    def to_dict(self) -> dict[str, Any]:
        """Plain data (the ``orbits --json`` contract)."""
        return {
            "label": self.label,
            "n": self.n,
            "branch": self.branch,
            "T": self.T,
            "theta": self.theta,
            "rdot": self.rdot,
            "thetadot": self.thetadot,
            "admissible": self.admissible,
            "plausible": self.plausible,
            "friction_reverses": self.friction_reverses,
            "r_max_interior": self.r_max_interior,
            "interior_extrema": self.interior_extrema,
            "multipliers": None if self.multipliers is None else [[m.real, m.imag] for m in self.multipliers],
            "stable": self.stable,
        }


def orbit_stability(multipliers, slipping: bool) -> bool | None:
    """Stability of an admissible one-impact orbit from the multipliers of its impact map.

    Parameters
    ----------
    multipliers : sequence of complex
        Eigenvalues of the Jacobian of P_I at the fixed point.
    slipping : bool
        The impact slips with v_rel- > mu (1 + d) rdot- (`ImpactOrbit.slipping`).

    Returns
    -------
    bool or None
        True when every multiplier lies inside the unit circle; None when the
        impact does not slip, since the friction of the law of MODEL.md §5
        then reverses v_rel (`ImpactOrbit.friction_reverses`) and the fixed
        point is not an orbit of the simulator, whose stability could be claimed.

    Raises
    ------
    ParameterError
        Unless ``multipliers`` is a non-empty sequence of finite (complex) numbers and ``slipping`` a bool.
    """
    z = complex_array(multipliers)
    if z is None or z.ndim != 1 or z.size == 0 or not np.all(np.isfinite(z)):
        raise ParameterError(f"multipliers = {multipliers!r} is invalid; allowed: a non-empty sequence of finite "
                             "(complex) numbers")
    if not check_bool("slipping", slipping):
        return None
    return bool(np.all(np.abs(z) < 1.0))


def _orbit(params: Parameters, zero: F1Zero, branch: str, rdot: float) -> ImpactOrbit:
    g, w, k, d, mu, rr = _params_tuple(params)
    q = _q(params)
    T = zero.T
    a11, a12, a21, a22, da12, da22 = call_kernel(_coefficients, T, g, w)
    theta = call_kernel(wrap_angle, cmath.phase(k / (1.0 + q * a12 * rdot)))
    thetadot = -(q * a22).imag * rdot
    admissible = rdot > 0.0
    slipping = call_kernel(slides_forward, thetadot, rdot, d, mu, rr)
    state = (theta, rdot, thetadot)
    speed = abs(complex(rdot, thetadot))
    if not speed <= MAX_VELOCITY:
        raise ParameterError(
            f"rho = {params.rho:g} (gamma = {params.gamma:g}, omega = {params.omega:g}, mu = {params.mu:g}, "
            f"d = {params.d:g}) gives the orbit B{zero.n},{branch} an impact at |(rdot, thetadot)| = {speed:.3g} "
            f"clearances per unit time; allowed: parameters whose orbits impact at most {MAX_VELOCITY:g} (the "
            "unbalance rho sets their speed)"
        )
    u0, du0 = post_impact_state(params, state, law=IDEAL)
    ext = _extrema_from_post(params, u0, du0, T)
    r_max = ext.r_max
    multipliers = None
    stable = None
    plausible = False
    if admissible:
        x1, jac, dtau, _ = call_kernel(_jacobian_kernel, g, w, k, d, mu, rr, theta, rdot, thetadot, T, _LAWS[IDEAL])
        ev = np.linalg.eigvals(jac)
        ev = ev[np.argsort(-np.abs(ev), kind="stable")]
        multipliers = tuple(complex(x) for x in ev)
        stable = orbit_stability(multipliers, slipping)
        if slipping and (r_max is None or r_max < 1.0):
            # With the extrema of r isolated, r < 1 on (0, T) already follows: r falls after
            # the impact, rises into the next one, and every interior maximum is below 1.
            # Cross-check with the simulator's guaranteed impact location: the first impact
            # is the one at T, up to the resolution of a crossing at speed rdot.
            horizon = T * (1.0 + 1e-6) + 1e-9
            code, tau = call_kernel(next_crossing, u0 - k, du0, k, g, w, horizon, True)
            slack = max(1e-8 * (1.0 + T), 64.0 * EPS * ((abs(k) + 1.0) ** 2 + 1.0) / rdot)
            plausible = code == CROSSING and T - slack <= tau <= T + slack
    return ImpactOrbit(
        label=f"B{zero.n},{branch}",
        n=zero.n,
        branch=branch,
        T=T,
        theta=theta,
        rdot=rdot,
        thetadot=thetadot,
        admissible=admissible,
        plausible=plausible,
        slipping=slipping,
        r_max_interior=r_max,
        interior_extrema=ext.count,
        multipliers=multipliers,
        stable=stable,
        params=params,
    )


#: The form of a one-impact orbit's label, B<n>,<a|b|c|d> (MODEL.md §5).
ORBIT_LABEL = re.compile(r"B[1-9][0-9]*,[abcd]")


def check_orbit_label(name: str, value: Any) -> str:
    """Return ``value`` if it has the form of a one-impact orbit's label (`ORBIT_LABEL`), else a `ParameterError`
    naming ``name``."""
    if not isinstance(value, str) or not ORBIT_LABEL.fullmatch(value):
        raise ParameterError(f"{name} = {value!r} is not a one-impact orbit label; allowed: 'B<n>,<a|b|c|d>', such "
                             "as 'B1,d'")
    return value


def one_impact_orbits(params: Parameters, t_max: float = 12.0) -> tuple[ImpactOrbit, ...]:
    """All periodic orbits with one impact per period and period T in (0, t_max].

    Every zero of F1 is found (see `f1_zeros`); each gives up to two orbits,
    the real roots rdot of the quadratic of MODEL.md §5 (none where the roots
    are complex). Admissible orbits get their multipliers (eigenvalues of the
    analytic Jacobian of P_I) and stability; plausibility is checked with the
    simulator's guaranteed impact location.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    t_max : float
        Largest period searched.

    Returns
    -------
    tuple of ImpactOrbit
        Sorted by pair n, then branch a, b, c, d.
    """
    orbits = []
    for zero in f1_zeros(params, t_max):
        disc, roots = rdot_roots(params, zero.T)
        if not roots:
            continue
        for rdot, branch in zip(roots, root_branches(zero.kind)):
            orbits.append(_orbit(params, zero, branch, rdot))
    orbits.sort(key=lambda o: (o.n, o.branch, o.T))
    return tuple(orbits)
