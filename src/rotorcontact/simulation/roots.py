"""Guaranteed location of the next impact: the first t > 0 with |U(t)| = 1, |U| increasing.

Method: safe stepping on f(s) = |U(s)|^2 - 1, with s the time since the start
of the flight. At a point with f < 0, Taylor's theorem gives

    f(s + h) <= f + f' h + f'' h^2 / 2 + M3 h^3 / 6      (M3 >= |f'''| ahead)
    f(s + h) <= f + f' h + M2 h^2 / 2                     (M2 >= |f''| ahead)

so no crossing lies before the first positive root of either right-hand side,
and the step to it is safe (`_step_from_moments` also uses the exact f''' and
f'''' with bounds up to M5). The bounds are rigorous. In the flight's own
inertial frame Z(s) = U(s) e^{is} (|Z| = |U|),

    Z(s) = k e^{i s} + W(s),   W'' + gamma W' + omega^2 W = 0.

When the flow is underdamped with gamma >= 0 (a decaying whirl), W = A e^{mu_+ s}
+ B e^{mu_- s}, so f is a constant plus decaying exponentials of known rates and
|f^{(n)}| ahead is at most the sum of their moduli times their rates to the n
(`_whirl_moments`). Otherwise every derivative obeys W^{(n)}(s + h) =
e^{-gamma h/2}[C(h) p_n + S(h) q_n] (p_n = W^{(n)}(s), q_n = gamma p_n / 2 +
p_{n+1}, C and S as in `flow`), which gives |W^{(n)}| <= Cmax |p_n| + Smax |q_n|
on a finite window, and |Z^{(n)}| <= |k| + |W^{(n)}| bounds the derivatives of
f = |Z|^2 - 1 (`_step_from_bounds`).

Stepping never crosses the surface. Near a transversal crossing the steps
converge to it from below at least quadratically (like Newton); near a tangency
that stays below 1 they walk past it; a crossing whose excursion above 1 is
tiny is still found because no step can jump over it.

Its functions are compiled kernels for the event loops and take their arguments unchecked (NaN gives NaN;
text is a numba typing error): `rotorcontact.simulate`, `drop` and `run_general` are the checked entry
points.
"""

from __future__ import annotations

import cmath
import math

from numba import njit

from ..interpreted import complex_quotient, int_power
from ..model.flow import half_discriminant, scaled_cs

NO_CROSSING = 0
CROSSING = 1
STUCK = 2
ITERATION_LIMIT = 3

MAX_STEPS = 200_000
EPS = 2.220446049250313e-16
#: Trial steps of `_step_from_moments`: a decaying whirl's bounds, to the seventh derivative, allow long steps
#: that take more trials to find; bounds from |Z^(n)| (`_step_from_bounds`) do not.
WHIRL_TRIALS = 4
BOUND_TRIALS = 2
#: f' above this (|U|^2 per unit time) is a transversal crossing, whose sign rounding cannot change
TRANSVERSAL_SLOPE = 1e-8


@njit(cache=True)
def inertial_flow(w0: complex, dw0: complex, s: float, gamma: float, omega: float) -> tuple[complex, complex]:
    """(W, W') at time s of W'' + gamma W' + omega^2 W = 0 from (w0, dw0) at 0."""
    h2 = half_discriminant(gamma, omega)
    c, sn = scaled_cs(s, gamma, h2)
    g2 = 0.5 * gamma
    w = c * w0 + sn * (g2 * w0 + dw0)
    dw = c * dw0 + sn * (-omega * omega * w0 - g2 * dw0)
    return w, dw


@njit(cache=True)
def window_bounds(gamma: float, h2: float, width: float) -> tuple[float, float]:
    """Cmax >= e^{-gamma s/2}|C(s)| and Smax >= e^{-gamma s/2}|S(s)| for s in [0, width]."""
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
def _bound(p: complex, q: complex, cmax: float, smax: float, sqrt_form: bool, nu: float) -> float:
    """Bound on |e^{-gamma h/2}(C(h) p + S(h) q)| ahead of the current point."""
    pp = p.real * p.real + p.imag * p.imag
    qq = q.real * q.real + q.imag * q.imag
    if sqrt_form:
        return math.sqrt(pp + qq / (nu * nu))
    return cmax * math.sqrt(pp) + smax * math.sqrt(qq)


@njit(cache=True)
def _first_positive_root(c0: float, c1: float, c2: float) -> float:
    """Smallest s > 0 with c0 + c1 s + c2 s^2 / 2 = 0 for c0 <= 0 (inf if none).

    With c0 = 0 the answer is the second root when the polynomial dips below
    zero, and 0 when it does not (no safe step).
    """
    if c0 == 0.0:
        if c1 < 0.0:
            return -2.0 * c1 / c2 if c2 > 0.0 else math.inf
        if c1 == 0.0 and c2 < 0.0:
            return math.inf
        return 0.0
    if c2 == 0.0:
        return -c0 / c1 if c1 > 0.0 else math.inf
    disc = c1 * c1 - 2.0 * c2 * c0
    if disc < 0.0:
        return math.inf
    sq = math.sqrt(disc)
    if c2 > 0.0:
        if c1 >= 0.0:
            return -2.0 * c0 / (c1 + sq)
        return (sq - c1) / c2
    if c1 <= 0.0:
        return math.inf
    return -2.0 * c0 / (c1 + sq)


@njit(cache=True)
def _dot(a: complex, b: complex) -> float:
    """Re(conj(a) b)."""
    return a.real * b.real + a.imag * b.imag


@njit(cache=True)
def _step_from_moments(f, fp, fpp, f3, f4, f5, f6, m2, m3, m4, m5, m7, trials):
    """Largest crossing-free step given the derivatives f to f6 and bounds m_n >= |f^(n)| ahead.

    With those bounds, for h in [0, S]

        f(h) <= f + f1 h + c2(S) h^2 / 2,
        c2(S) = min(f2 + M3 S / 3,
                    f2 + f3+ S / 3 + M4 S^2 / 12,
                    f2 + f3+ S / 3 + f4+ S^2 / 12 + M5 S^3 / 60,
                    f2 + f3+ S / 3 + f4+ S^2 / 12 + f5+ S^3 / 60 + f6+ S^4 / 360 + M7 S^5 / 2520),

    (fn+ = max(fn, 0); h^n / n! <= S^(n-2) h^2 / n! on [0, S]), so min(S, first
    root of that quadratic) is safe for any trial S, and ``trials`` trials pick a
    good one (S doubled while it is safe, else moved half way to the root). The
    second-order bound M2 gives a safe step to start from. Without f5, f6 and M7
    (a flight whose bounds stop at M5), pass 0, 0 and inf.
    """
    best = _first_positive_root(f, fp, m2)
    f3p = max(f3, 0.0)
    f4p = max(f4, 0.0)
    f5p = max(f5, 0.0)
    f6p = max(f6, 0.0)
    trial = 2.0 * best
    if fpp < 0.0:
        trial = max(trial, -1.5 * fpp / m3)
    for _ in range(trials):
        t2 = trial * trial
        low = fpp + f3p * trial / 3.0 + f4p * t2 / 12.0
        c2 = min(
            fpp + m3 * trial / 3.0,
            fpp + f3p * trial / 3.0 + m4 * t2 / 12.0,
            low + m5 * t2 * trial / 60.0,
            low + t2 * trial * (f5p / 60.0 + trial * (f6p / 360.0 + trial * m7 / 2520.0)),
        )
        g = _first_positive_root(f, fp, c2)
        if g >= trial:
            best = max(best, trial)
            trial *= 2.0
        else:
            best = max(best, g)
            trial = 0.5 * (g + trial)
    return best


@njit(cache=True)
def _step_from_bounds(f, fp, fpp, f3, f4, z0, z1, z2, z3, z4, z5):
    """Largest crossing-free step given bounds z_n >= |Z^(n)| ahead: `_step_from_moments` with the bounds
    M_n = sum_j C(n, j) z_j z_(n-j) on the derivatives of f = |Z|^2 - 1."""
    return _step_from_moments(
        f, fp, fpp, f3, f4, 0.0, 0.0,
        2.0 * z1 * z1 + 2.0 * z0 * z2,
        6.0 * z1 * z2 + 2.0 * z0 * z3,
        6.0 * z2 * z2 + 8.0 * z1 * z3 + 2.0 * z0 * z4,
        2.0 * z0 * z5 + 10.0 * z1 * z4 + 20.0 * z2 * z3,
        math.inf, BOUND_TRIALS,
    )


#: Public name of the crossing-free step from derivative bounds, for other flights (`general_flight`).
crossing_free_step = _step_from_bounds


@njit(cache=True)
def _derivatives(w: complex, dw: complex, gamma: float, omega: float):
    """W'' to W^(6) from W and W' by the flow's own law W'' = -gamma W' - omega^2 W."""
    om2 = omega * omega
    w2 = -gamma * dw - om2 * w
    w3 = -gamma * w2 - om2 * dw
    w4 = -gamma * w3 - om2 * w2
    w5 = -gamma * w4 - om2 * w3
    w6 = -gamma * w5 - om2 * w4
    return w2, w3, w4, w5, w6


@njit(cache=True)
def _whirl_moments(k: complex, w: complex, dw: complex, gamma: float, h2: float):
    """Bounds on |W| and on the derivatives of f ahead of any point of an underdamped flight with gamma >= 0.

    There W = A e^{mu_+ s} + B e^{mu_- s}, mu_+- = -gamma/2 +- i nu, so with
    Z = k e^{is} + W

        f = |k|^2 - 1 + (|A|^2 + |B|^2) e^{-gamma s} + 2 Re[k conj(A) e^{l1 s}]
            + 2 Re[k conj(B) e^{l2 s}] + 2 Re[A conj(B) e^{l3 s}],

    l1 = -gamma/2 + i(1 - nu), l2 = -gamma/2 + i(1 + nu), l3 = -gamma + 2i nu. No
    term grows, so at time s and for every time after it

        |W| <= (|A| + |B|) e^{-gamma s/2},
        |f^(n)| <= slow_n e^{-gamma s/2} + fast_n e^{-gamma s},
        slow_n = 2|k|(|A||l1|^n + |B||l2|^n),  fast_n = (|A|^2 + |B|^2) gamma^n + 2|A||B||l3|^n.

    Returns (|A| + |B|, slow_2, fast_2, ..., slow_7, fast_7) for the flight from (w, dw) at s = 0.
    """
    g2 = 0.5 * gamma
    nu = math.sqrt(-h2)
    a = complex_quotient(g2 * w + dw + 1j * nu * w, 2j * nu)  # (dw - mu_- w) / (mu_+ - mu_-)
    a_abs = abs(a)
    b_abs = abs(w - a)
    k_abs = abs(k)
    l1 = abs(complex(-g2, 1.0 - nu))
    l2 = abs(complex(-g2, 1.0 + nu))
    l3 = abs(complex(-gamma, 2.0 * nu))
    ka = 2.0 * k_abs * a_abs
    kb = 2.0 * k_abs * b_abs
    p = a_abs * a_abs + b_abs * b_abs
    ab = 2.0 * a_abs * b_abs
    return (a_abs + b_abs,
            _rates(ka, l1, kb, l2, 2), _rates(p, gamma, ab, l3, 2),
            _rates(ka, l1, kb, l2, 3), _rates(p, gamma, ab, l3, 3),
            _rates(ka, l1, kb, l2, 4), _rates(p, gamma, ab, l3, 4),
            _rates(ka, l1, kb, l2, 5), _rates(p, gamma, ab, l3, 5),
            _rates(ka, l1, kb, l2, 6), _rates(p, gamma, ab, l3, 6),
            _rates(ka, l1, kb, l2, 7), _rates(p, gamma, ab, l3, 7))


@njit(cache=True)
def _rates(x: float, a: float, y: float, b: float, n: int) -> float:
    """x a^n + y b^n: the bound on the n-th derivative of two terms of moduli x, y and rates a, b."""
    return x * int_power(a, n) + y * int_power(b, n)


#: `_whirl_moments` of a flight that has none (not underdamped, or gamma < 0): its first entry is negative.
NO_WHIRL = (-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
#: The bounds M2 to M7 of a flight without `_whirl_moments`: none.
NO_MOMENTS = (-1.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True)
def _higher_derivatives(z, dz, w, dw, gamma, omega):
    """The third to sixth derivatives of f = |Z|^2 - 1 at the current point (Leibniz, with
    Z^(n) = i^n k e^{is} + W^(n))."""
    w2, w3, w4, w5, w6 = _derivatives(w, dw, gamma, omega)
    kr = z - w  # k e^{is}
    z2 = -kr + w2
    z3 = -1j * kr + w3
    z4 = kr + w4
    z5 = 1j * kr + w5
    z6 = -kr + w6
    f3 = 6.0 * _dot(dz, z2) + 2.0 * _dot(z, z3)
    f4 = 6.0 * _dot(z2, z2) + 8.0 * _dot(dz, z3) + 2.0 * _dot(z, z4)
    f5 = 2.0 * _dot(z, z5) + 10.0 * _dot(dz, z4) + 20.0 * _dot(z2, z3)
    f6 = 2.0 * _dot(z, z6) + 12.0 * _dot(dz, z5) + 30.0 * _dot(z2, z4) + 20.0 * _dot(z3, z3)
    return f3, f4, f5, f6


@njit(cache=True)
def _safe_step(z, dz, w, dw, k_abs, f, fp, fpp, f3, f4, f5, f6, gamma, omega, h2, horizon, window, moments):
    """Largest step from the current point guaranteed free of crossings.

    ``f3`` to ``f6`` are the third to sixth derivatives of f there (`_higher_derivatives`);
    ``moments`` holds the bounds M2 to M7 on the magnitudes of its second to seventh derivatives ahead of a
    decaying whirl (from `_whirl_moments`), its first entry negative where the flight has none (`NO_MOMENTS`).
    """
    g2 = 0.5 * gamma
    best = 0.0
    nu = math.sqrt(-h2) if h2 < 0.0 else 0.0
    if moments[0] >= 0.0:
        best = _step_from_moments(f, fp, fpp, f3, f4, f5, f6, moments[0], moments[1], moments[2], moments[3],
                                  moments[5], WHIRL_TRIALS)
    width = min(window, horizon)
    # the finite window helps only where the all-time bound is poor: growth, or nu small against omega (near
    # critical damping) or against the rotation (a soft bearing: the whirl's terms, of size |W'| / nu, cancel)
    if best < width and (gamma < 0.0 or nu < 0.5 * omega or nu < 0.5):
        w2, w3, w4, w5, w6 = _derivatives(w, dw, gamma, omega)
        cmax, smax = window_bounds(gamma, h2, width)
        h = min(
            _step_from_bounds(
                f, fp, fpp, f3, f4,
                k_abs + _bound(w, g2 * w + dw, cmax, smax, False, 1.0),
                k_abs + _bound(dw, g2 * dw + w2, cmax, smax, False, 1.0),
                k_abs + _bound(w2, g2 * w2 + w3, cmax, smax, False, 1.0),
                k_abs + _bound(w3, g2 * w3 + w4, cmax, smax, False, 1.0),
                k_abs + _bound(w4, g2 * w4 + w5, cmax, smax, False, 1.0),
                k_abs + _bound(w5, g2 * w5 + w6, cmax, smax, False, 1.0),
            ),
            width,
        )
        best = max(best, h)
    return best


@njit(cache=True)
def _liftoff_step(z, dz, w, dw, k_abs, gamma, omega, h2, horizon, window):
    """A step away from a lift-off point, where f = f' = f'' = 0 to the event tolerance.

    With f3 = f''' < 0 and M4 >= |f''''| ahead, f(h) <= f3 h^3/6 + M4 h^4/24 < 0
    on (0, -4 f3/M4); half of that is returned (0 when f3 >= 0).
    """
    g2 = 0.5 * gamma
    w2, w3, w4, w5, _w6 = _derivatives(w, dw, gamma, omega)
    f3 = _higher_derivatives(z, dz, w, dw, gamma, omega)[0]
    if f3 >= 0.0:
        return 0.0
    width = min(window, horizon)
    if gamma >= 0.0 and h2 < 0.0:
        cmax, smax, sq, nu = 1.0, 1.0, True, math.sqrt(-h2)
    else:
        cmax, smax = window_bounds(gamma, h2, width)
        sq, nu = False, 1.0
    z0 = k_abs + _bound(w, g2 * w + dw, cmax, smax, sq, nu)
    z1 = k_abs + _bound(dw, g2 * dw + w2, cmax, smax, sq, nu)
    z2 = k_abs + _bound(w2, g2 * w2 + w3, cmax, smax, sq, nu)
    z3 = k_abs + _bound(w3, g2 * w3 + w4, cmax, smax, sq, nu)
    z4 = k_abs + _bound(w4, g2 * w4 + w5, cmax, smax, sq, nu)
    m4 = 6.0 * z2 * z2 + 8.0 * z1 * z3 + 2.0 * z0 * z4
    h = -2.0 * f3 / m4
    if not sq:
        h = min(h, width)
    return h


@njit(cache=True)
def _no_return_bound(w, dw, gamma, h2, whirl, decay):
    """Bound on |W| at every time ahead of the current point, for the decaying flow (gamma > 0).

    Underdamped: `_whirl_moments`' (|A| + |B|) e^{-gamma s/2} (``decay`` is e^{-gamma s/2}), exact for a
    circular whirl. Otherwise, with q = gamma W / 2 + W', e^{-gamma s/2} C(s) <= 1 always and
    e^{-gamma s/2} S(s) <= 1/(2 kappa) (overdamped, kappa < gamma/2) or <= 2/(e gamma) (critical).
    """
    if whirl[0] >= 0.0:
        return whirl[0] * decay
    q = 0.5 * gamma * w + dw
    if h2 > 0.0:
        return abs(w) + abs(q) / (2.0 * math.sqrt(h2))
    return abs(w) + abs(q) * 2.0 / (math.e * gamma)


@njit(cache=True)
def _surface(k, w0, dw0, s, gamma, omega):
    """Z, Z', W, W' and f, f', f'' at time s of the flight."""
    w, dw = inertial_flow(w0, dw0, s, gamma, omega)
    rot = cmath.exp(1j * s)
    kr = k * rot
    z = kr + w
    dz = 1j * kr + dw
    ddz = -kr - gamma * dw - omega * omega * w
    f = (z.real * z.real + z.imag * z.imag) - 1.0
    fp = 2.0 * (z.real * dz.real + z.imag * dz.imag)
    fpp = 2.0 * (dz.real * dz.real + dz.imag * dz.imag) + 2.0 * (z.real * ddz.real + z.imag * ddz.imag)
    return z, dz, w, dw, f, fp, fpp


@njit(cache=True)
def _nearest_root(f: float, fp: float, fpp: float) -> float:
    """The root of f + fp h + fpp h^2 / 2 nearest to h = 0, for fp > 0 (nan if it has none)."""
    disc = fp * fp - 2.0 * fpp * f
    if disc < 0.0:
        return math.nan
    return -2.0 * f / (fp + math.sqrt(disc))


#: Public name of the quadratic model's nearest root, the polishing step of a crossing.
nearest_root_step = _nearest_root


@njit(cache=True)
def _model_root(f, fp, fpp, f3, f4, f5, f6, m3, m7):
    """A crossing ahead located by the Taylor polynomial of f: (h, e) with the first crossing in [h - e, h + e].

    For f < 0 < f' with M3 and M7 bounds on the magnitudes of the third and seventh derivatives of f
    ahead, let P be the Taylor polynomial of degree 6 of f, h a root of P (Newton from the quadratic
    model's root) and H = 5h/4. On [0, H] the slope of f is at least min(f', f' + f'' H - M3 H^2/2)
    (a concave bound, least at an end), so where that is positive f rises through at most one
    crossing there; and |f(h) - P(h)| <= M7 h^7/5040, so f(h) lies within |P(h)| + M7 h^7/5040 of 0 and
    the crossing within e = that over the slope of h. When e <= h/4 that crossing lies in [0, H] and is
    the first. Returns (nan, inf) where the model does not certify one (far from the wall, a slope too
    small, or no root of the model). The bracket is that of exact derivatives: their rounding adds the
    conditioning of the crossing itself, O(eps |Z|^2 / f'), as in `_polish`.
    """
    h = _nearest_root(f, fp, fpp)
    if not h > 0.0:
        return math.nan, math.inf
    c2, c3, c4, c5, c6 = 0.5 * fpp, f3 / 6.0, f4 / 24.0, f5 / 120.0, f6 / 720.0
    for _ in range(2):
        value = f + h * (fp + h * (c2 + h * (c3 + h * (c4 + h * (c5 + h * c6)))))
        rate = fp + h * (2.0 * c2 + h * (3.0 * c3 + h * (4.0 * c4 + h * (5.0 * c5 + h * 6.0 * c6))))
        h -= value / rate
    big = 1.25 * h
    slope = min(fp, fp + big * (fpp - 0.5 * m3 * big))
    if not (h > 0.0 and slope > 0.0):
        return math.nan, math.inf
    residual = f + h * (fp + h * (c2 + h * (c3 + h * (c4 + h * (c5 + h * c6)))))
    h7 = h * h * h * h * h * h * h
    e = (abs(residual) + m7 * h7 / 5040.0) / slope
    if not e <= 0.25 * h:
        return math.nan, math.inf
    return h, e


@njit(cache=True)
def _polish(k, w0, dw0, s, f, fp, fpp, gamma, omega):
    """The crossing near s, where f is within rounding of 0 and f' > 0, to the rounding limit of f.

    Iterates on the quadratic Taylor model of f (its nearest root), which
    converges cubically at a transversal crossing and stays accurate at a
    graze, where f' is small and Newton's linear model is not. Returns -1 when
    the model has no root: the maximum of f stays below 0 by more than its
    rounding error (a tangency, not an impact). The safe steps have shown
    that no crossing lies before s, so a model root behind s (rounding) is
    taken as s itself.
    """
    s_safe = s
    for _ in range(8):
        h = _nearest_root(f, fp, fpp)
        if h != h:
            return -1.0
        s_new = max(s + h, s_safe)
        if s_new == s:
            break
        if abs(h) <= 4.0 * EPS * (1.0 + s_new) and fp > 2.0 * abs(fpp * h) + TRANSVERSAL_SLOPE:
            # a move at rounding level across a transversal crossing, where f' keeps its sign
            return s_new
        s = s_new
        _z, _dz, _w, _dw, f, fp, fpp = _surface(k, w0, dw0, s, gamma, omega)
        if fp <= 0.0:
            return -1.0
        if abs(h) <= 4.0 * EPS * (1.0 + s):
            break
    return s


@njit(cache=True)
def next_crossing(v0: complex, dv0: complex, k: complex, gamma: float, omega: float,
                  horizon: float, on_boundary: bool, liftoff: bool = False) -> tuple[int, float]:
    """First time s in (0, horizon] where |k + V(s)| reaches 1 while increasing.

    Parameters
    ----------
    v0, dv0 : complex
        V = U - k and V' (co-rotating frame) at s = 0.
    k : complex
        Regular equilibrium.
    gamma, omega : float
        Parameters of the flow.
    horizon : float
        Search up to this time.
    on_boundary : bool
        True when the start lies on |U| = 1 (just after an impact).
    liftoff : bool
        True when the start is a lift-off from continuous contact: on the
        boundary with rdot = 0 and N = 0 to the event tolerance; the flight
        leaves when the third derivative of |U|^2 is negative (`_liftoff_step`).

    Returns
    -------
    code, s : int, float
        ``CROSSING`` and the time; ``NO_CROSSING`` and ``horizon``; ``STUCK``
        when starting on the boundary with no inward velocity and outward
        acceleration (impacts accumulate); ``ITERATION_LIMIT``.
    """
    # the flight's inertial frame: Z(s) = U(s) e^{is}, W = V e^{is}
    w0 = v0
    dw0 = dv0 + 1j * v0
    h2 = half_discriminant(gamma, omega)
    k_abs = abs(k)
    window = 1.0
    s = 0.0
    if gamma >= 0.0 and h2 < 0.0:
        whirl = _whirl_moments(k, w0, dw0, gamma, h2)
    else:
        whirl = NO_WHIRL
    decay = 1.0
    for _ in range(MAX_STEPS):
        z, dz, w, dw, f, fp, fpp = _surface(k, w0, dw0, s, gamma, omega)
        reach = k_abs + abs(w)
        scale = reach * reach + 1.0
        ftol = 16.0 * EPS * scale
        if whirl[0] >= 0.0:
            decay = math.exp(-0.5 * gamma * s)
        inside = True  # f < 0 beyond rounding
        if on_boundary and s == 0.0:
            f = 0.0
            if fp > -ftol * (1.0 + abs(dz)):
                # no inward velocity: the sign of f2 decides, and at a lift-off (f2 = 0 to
                # the event tolerance) the sign of the third derivative
                if fpp >= -ftol:
                    if not liftoff:
                        return STUCK, 0.0
                    h = _liftoff_step(z, dz, w, dw, k_abs, gamma, omega, h2, horizon, window)
                    if h <= 0.0:
                        return STUCK, 0.0
                    if h >= horizon:
                        return NO_CROSSING, horizon
                    s = h
                    continue
                fp = min(fp, 0.0)
        elif gamma > 0.0 and k_abs + _no_return_bound(w, dw, gamma, h2, whirl, decay) < 1.0 - ftol:
            # |Z| <= |k| + |W| stays below 1 for ever: no impact in any horizon
            return NO_CROSSING, horizon
        elif f >= -ftol:
            if fp > 0.0:
                root = _polish(k, w0, dw0, s, f, fp, fpp, gamma, omega)
                if root >= 0.0:
                    return CROSSING, root
            # a tangency within rounding of the wall that does not reach it: walk past
            f = -ftol
            inside = False
        f3, f4, f5, f6 = _higher_derivatives(z, dz, w, dw, gamma, omega)
        moments = NO_MOMENTS
        h = -1.0
        if whirl[0] >= 0.0:
            d2 = decay * decay
            moments = (whirl[1] * decay + whirl[2] * d2, whirl[3] * decay + whirl[4] * d2,
                       whirl[5] * decay + whirl[6] * d2, whirl[7] * decay + whirl[8] * d2,
                       whirl[9] * decay + whirl[10] * d2, whirl[11] * decay + whirl[12] * d2)
            if inside and fp > 0.0:
                # near a transversal crossing: the Taylor model locates it, or steps to just short of it
                hm, e = _model_root(f, fp, fpp, f3, f4, f5, f6, moments[1], moments[5])
                if s + hm + e < horizon:
                    if e <= 4.0 * EPS * (1.0 + s):
                        return CROSSING, s + hm
                    h = hm - e
        if h < 0.0:
            h = _safe_step(z, dz, w, dw, k_abs, f, fp, fpp, f3, f4, f5, f6, gamma, omega, h2, horizon - s, window,
                           moments)
        if s + h == s:
            # the step is below the resolution of s: a crossing here, or a tangency to walk past
            if fp > 0.0:
                root = _polish(k, w0, dw0, s, f, fp, fpp, gamma, omega)
                if root >= 0.0:
                    return CROSSING, root
            h = 4.0 * EPS * abs(s)
        if s + h >= horizon:
            return NO_CROSSING, horizon
        s += h
    return ITERATION_LIMIT, s
