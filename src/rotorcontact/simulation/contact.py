"""Continuous contact on r = 1: sliding with Coulomb friction, rolling, slip and lift-off (MODEL.md §4).

The contact law (`rotorcontact.model.contact_law`): on the stator (r = 1,
rdot = 0) the normal force per unit mass that keeps rdot'' = 0 is

    N = (1 + thetadot)^2 - omega^2 + rho cos(phi - theta),

and contact persists while N > 0. The tangential motion is

    thetadot' = F(theta, thetadot) - mu N sgn(v_rel),
    F = -(1 + thetadot) gamma + rho sin(phi - theta),

with v_rel = r_ratio + 1 + thetadot. Sliding phases are integrated with an
adaptive Dormand-Prince 5(4) scheme (rtol = atol = `CONTACT_TOL`), and every
switch is located on the integrator's own steps to `EVENT_TOL` in time.

Rolling (v_rel = 0 held) is exact: thetadot = -(1 + r_ratio) and theta is
linear in time. The tangential force that holds it is -F, and rolling lasts
while |F| <= mu N; with psi = phi - theta moving at the constant rate
1 + r_ratio, both limits are of the form a + b cos(psi) + c sin(psi), so the
first slip or lift-off is found in closed form.

Its functions are compiled kernels for the event loops and take their arguments unchecked (NaN gives NaN;
text is a numba typing error): `rotorcontact.simulate`, `drop` and `run_general` are the checked entry
points.
"""

from __future__ import annotations

import math

from numba import njit

from ..model.contact_law import free_tangential, normal_force, sliding_accel
from ..model.impact_law import relative_velocity
from .tables import grow_rows

CONTACT_TOL = 1e-11
EVENT_TOL = 1e-12
MAX_CONTACT_STEPS = 2_000_000
STEADY_TOL = 10.0 * CONTACT_TOL  # |thetadot|, |thetadot'| below this: on a pseudo-equilibrium
SLIDE_FIRST_STEP = 1e-3  # the first step size tried in a sliding phase

SLIDE_FORWARD = 0
ROLLING = 1
SLIDE_BACKWARD = 2
ACCUMULATION = 3  # from the last resolved impact of a chatter sequence to its accumulation point
KIND_NAMES = ("sliding-forward", "rolling", "sliding-backward", "accumulation")

# exit codes of a contact phase
END = 0
LIFTOFF = 1
TO_ROLLING = 2
TO_SLIDE_FORWARD = 3
TO_SLIDE_BACKWARD = 4
STEP_LIMIT = 5


_accel = sliding_accel


# Dormand-Prince 5(4) tableau
_C2, _C3, _C4, _C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0
_A21 = 1.0 / 5.0
_A31, _A32 = 3.0 / 40.0, 9.0 / 40.0
_A41, _A42, _A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
_A51, _A52, _A53, _A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
_A61, _A62, _A63, _A64, _A65 = 9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0
_B1, _B3, _B4, _B5, _B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
_E1, _E3, _E4, _E5, _E6, _E7 = (
    71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0,
)


@njit(cache=True)
def _dp_step(x, v, h, sgn, gamma, omega, rho, mu, phi):
    """One Dormand-Prince step of (theta, thetadot); returns the new state and the error norm."""
    k1x, k1v = v, _accel(x, v, sgn, gamma, omega, rho, mu, phi)
    x2, v2 = x + h * _A21 * k1x, v + h * _A21 * k1v
    k2x, k2v = v2, _accel(x2, v2, sgn, gamma, omega, rho, mu, phi)
    x3, v3 = x + h * (_A31 * k1x + _A32 * k2x), v + h * (_A31 * k1v + _A32 * k2v)
    k3x, k3v = v3, _accel(x3, v3, sgn, gamma, omega, rho, mu, phi)
    x4 = x + h * (_A41 * k1x + _A42 * k2x + _A43 * k3x)
    v4 = v + h * (_A41 * k1v + _A42 * k2v + _A43 * k3v)
    k4x, k4v = v4, _accel(x4, v4, sgn, gamma, omega, rho, mu, phi)
    x5 = x + h * (_A51 * k1x + _A52 * k2x + _A53 * k3x + _A54 * k4x)
    v5 = v + h * (_A51 * k1v + _A52 * k2v + _A53 * k3v + _A54 * k4v)
    k5x, k5v = v5, _accel(x5, v5, sgn, gamma, omega, rho, mu, phi)
    x6 = x + h * (_A61 * k1x + _A62 * k2x + _A63 * k3x + _A64 * k4x + _A65 * k5x)
    v6 = v + h * (_A61 * k1v + _A62 * k2v + _A63 * k3v + _A64 * k4v + _A65 * k5v)
    k6x, k6v = v6, _accel(x6, v6, sgn, gamma, omega, rho, mu, phi)
    xn = x + h * (_B1 * k1x + _B3 * k3x + _B4 * k4x + _B5 * k5x + _B6 * k6x)
    vn = v + h * (_B1 * k1v + _B3 * k3v + _B4 * k4v + _B5 * k5v + _B6 * k6v)
    k7x, k7v = vn, _accel(xn, vn, sgn, gamma, omega, rho, mu, phi)
    ex = h * (_E1 * k1x + _E3 * k3x + _E4 * k4x + _E5 * k5x + _E6 * k6x + _E7 * k7x)
    ev = h * (_E1 * k1v + _E3 * k3v + _E4 * k4v + _E5 * k5v + _E6 * k6v + _E7 * k7v)
    sx = CONTACT_TOL * (1.0 + max(abs(x), abs(xn)))
    sv = CONTACT_TOL * (1.0 + max(abs(v), abs(vn)))
    rx, rv = ex / sx, ev / sv
    err = math.sqrt(0.5 * (rx * rx + rv * rv))
    return xn, vn, err


@njit(cache=True)
def _events(x, v, r_ratio, omega, rho, phi, sgn):
    """Switching functions of a sliding phase: N (lift-off) and sgn * v_rel (end of slip)."""
    return normal_force(x, v, omega, rho, phi), sgn * relative_velocity(r_ratio, v)


@njit(cache=True)
def _attracting(x, v, sgn, gamma, omega, rho, mu, phi):
    """The linearised sliding dynamics at (x, v) are asymptotically stable (trace < 0 < det)."""
    hx = 1e-6 * (1.0 + abs(x))
    hv = 1e-6
    a_x = (_accel(x + hx, v, sgn, gamma, omega, rho, mu, phi) - _accel(x - hx, v, sgn, gamma, omega, rho, mu, phi)) / (2 * hx)
    a_v = (_accel(x, v + hv, sgn, gamma, omega, rho, mu, phi) - _accel(x, v - hv, sgn, gamma, omega, rho, mu, phi)) / (2 * hv)
    # Jacobian [[0, 1], [a_x, a_v]]: trace a_v, determinant -a_x
    return a_v < 0.0 and -a_x > 0.0


@njit(cache=True)
def _append(path, n, t, x, v, sgn, gamma, omega, rho, mu, phi):
    path = grow_rows(path, n)
    path[n, 0] = t
    path[n, 1] = x
    path[n, 2] = v
    path[n, 3] = _accel(x, v, sgn, gamma, omega, rho, mu, phi)
    return path, n + 1


# outcomes of one step attempt of a sliding phase (`slide_attempt`)
REJECTED = 0  # the step was rejected; the step size is reduced
STEPPED = 1  # an accepted step inside the phase
AT_REST = 2  # an accepted step onto a stable pseudo-equilibrium, which holds until t_end
SWITCHED = 3  # the phase ends at a located switch inside the step
AT_END = 4  # t_end was reached before the attempt


@njit(cache=True)
def slide_attempt(t, x, v, h, t_end, sgn, gamma, omega, rho, mu, phi, r_ratio):
    """One step attempt of a sliding phase from (t, x, v) with step size h.

    Returns (outcome, t, x, v, h, code): the outcome (`STEPPED`, `REJECTED`, ...), the state after it
    (unchanged if rejected or at the end), the next step size, and for `SWITCHED` the phase that follows
    (`LIFTOFF`, or `stick_or_slip`'s code with v_rel = 0 exactly). `slide` runs these attempts and
    records their states; `slide_unrecorded` runs them without recording, for the batch kernel and the GPU
    (`rotorcontact.studies.compact_batch`).
    """
    if t >= t_end:
        return AT_END, t, x, v, h, END
    h = min(h, t_end - t)
    xn, vn, err = _dp_step(x, v, h, sgn, gamma, omega, rho, mu, phi)
    if err > 1.0:
        h *= max(0.2, 0.9 * err ** -0.2)
        return REJECTED, t, x, v, h, END
    g_n, g_v = _events(xn, vn, r_ratio, omega, rho, phi, sgn)
    if g_n <= 0.0 or g_v <= 0.0:
        # locate the first switch inside the step by bisection on single steps from t
        lo, hi = 0.0, h
        for _b in range(200):
            if hi - lo <= EVENT_TOL * (1.0 + t):
                break
            mid = 0.5 * (lo + hi)
            xm, vm, _e = _dp_step(x, v, mid, sgn, gamma, omega, rho, mu, phi)
            a_n, a_v = _events(xm, vm, r_ratio, omega, rho, phi, sgn)
            if a_n <= 0.0 or a_v <= 0.0:
                hi = mid
            else:
                lo = mid
        xe, ve, _e = _dp_step(x, v, hi, sgn, gamma, omega, rho, mu, phi)
        g_n, g_v = _events(xe, ve, r_ratio, omega, rho, phi, sgn)
        t = t + hi
        if g_n <= 0.0:
            return SWITCHED, t, xe, ve, h, LIFTOFF
        # slip ends: v_rel = 0 exactly
        ve = -(1.0 + r_ratio)
        return SWITCHED, t, xe, ve, h, stick_or_slip(xe, ve, gamma, omega, rho, mu, phi)
    t += h
    if abs(vn) < STEADY_TOL and abs(_accel(xn, vn, sgn, gamma, omega, rho, mu, phi)) < STEADY_TOL and \
            _attracting(xn, vn, sgn, gamma, omega, rho, mu, phi):
        # at rest on a stable pseudo-equilibrium to the integrator's tolerance: it holds until t_end
        return AT_REST, t, xn, vn, h, END
    h *= min(5.0, 0.9 * max(err, 1e-10) ** -0.2)
    return STEPPED, t, xn, vn, h, END


@njit(cache=True)
def slide(theta, thetadot, t0, t_end, sgn, gamma, omega, rho, mu, phi, r_ratio, path, n_path):
    """Integrate a sliding phase until lift-off, the end of slip, or t_end.

    Appends (t, theta, thetadot, thetadot') rows to ``path`` at every
    accepted step. Returns (code, t, theta, thetadot, path, n_path).
    """
    t = t0
    x = theta
    v = thetadot
    h = SLIDE_FIRST_STEP
    path, n_path = _append(path, n_path, t, x, v, sgn, gamma, omega, rho, mu, phi)
    for _ in range(MAX_CONTACT_STEPS):
        outcome, t, x, v, h, code = slide_attempt(t, x, v, h, t_end, sgn, gamma, omega, rho, mu, phi, r_ratio)
        if outcome == REJECTED:
            continue
        if outcome == AT_END:
            return END, t, x, v, path, n_path
        path, n_path = _append(path, n_path, t, x, v, sgn, gamma, omega, rho, mu, phi)
        if outcome == AT_REST:
            path, n_path = _append(path, n_path, t_end, x, v, sgn, gamma, omega, rho, mu, phi)
            return END, t_end, x, v, path, n_path
        if outcome == SWITCHED:
            return code, t, x, v, path, n_path
    return STEP_LIMIT, t, x, v, path, n_path


@njit(cache=True)
def slide_unrecorded(theta, thetadot, t0, t_end, sgn, gamma, omega, rho, mu, phi, r_ratio):
    """`slide` without its path: the same steps, returning (code, t, theta, thetadot) where it ends.

    The state returned is the last row `slide` records.
    """
    t = t0
    x = theta
    v = thetadot
    h = SLIDE_FIRST_STEP
    for _ in range(MAX_CONTACT_STEPS):
        outcome, t, x, v, h, code = slide_attempt(t, x, v, h, t_end, sgn, gamma, omega, rho, mu, phi, r_ratio)
        if outcome == AT_REST:
            return END, t_end, x, v
        if outcome == AT_END or outcome == SWITCHED:
            return code, t, x, v
    return STEP_LIMIT, t, x, v


@njit(cache=True)
def stick_or_slip(theta, thetadot, gamma, omega, rho, mu, phi):
    """Phase that follows from a point with v_rel = 0: rolling, or slip in the direction of the force."""
    n = normal_force(theta, thetadot, omega, rho, phi)
    if n <= 0.0:
        return LIFTOFF
    f = free_tangential(theta, thetadot, gamma, rho, phi)
    if abs(f) <= mu * n:
        return TO_ROLLING
    return TO_SLIDE_FORWARD if f > 0.0 else TO_SLIDE_BACKWARD


@njit(cache=True)
def _first_zero(a, b, c, psi0):
    """Smallest x >= 0 where g(x) = a + b cos(psi0 + x) + c sin(psi0 + x) turns negative (inf if never).

    g is already negative at x = 0 when g(0) < -tol; at g(0) within tol of 0
    (the start lies on the limit, to rounding) it turns negative at once only
    if it is decreasing there; otherwise the next down-crossing is returned.
    """
    amp = abs(complex(b, c))
    if a > amp:
        return math.inf
    tol = 64.0 * 2.220446049250313e-16 * (abs(a) + amp)
    g0 = a + b * math.cos(psi0) + c * math.sin(psi0)
    slope0 = -b * math.sin(psi0) + c * math.cos(psi0)
    if g0 < -tol or (g0 <= tol and slope0 < 0.0):
        return 0.0
    delta = math.atan2(c, b)
    half = math.acos(max(-1.0, min(1.0, -a / amp)))
    # g = a + amp cos(psi - delta) crosses zero downwards at psi = delta + half (mod 2 pi)
    two_pi = 2.0 * math.pi
    x = (delta + half - psi0) % two_pi
    if x <= 1e-12 and g0 <= tol:
        # the start is that crossing itself, on its rising side: take the next turn
        x += two_pi
    return x


@njit(cache=True)
def rolled_angle(theta0, thetadot, t0, t1):
    """theta at t1 of rolling from theta0 at t0 (theta linear in time), as a rolling phase's path records it."""
    return theta0 + thetadot * (t1 - t0)


@njit(cache=True)
def roll(theta, t0, t_end, gamma, omega, rho, mu, phi, r_ratio):
    """Exact rolling from (theta, thetadot = -(1 + r_ratio)) at t0.

    Returns (code, t, theta) at the first slip or lift-off, or at t_end.
    """
    rate = 1.0 + r_ratio  # psi = phi - theta grows at this rate
    psi0 = phi - theta
    base_n = r_ratio * r_ratio - omega * omega
    # mu N - F >= 0 and mu N + F >= 0 with F = r_ratio gamma + rho sin(psi), N = base_n + rho cos(psi)
    x_fwd = _first_zero(mu * base_n - r_ratio * gamma, mu * rho, -rho, psi0)
    x_bwd = _first_zero(mu * base_n + r_ratio * gamma, mu * rho, rho, psi0)
    x_lift = _first_zero(base_n, rho, 0.0, psi0)
    x = min(x_fwd, x_bwd, x_lift)
    t_switch = t0 + x / rate
    if t_switch >= t_end:
        return END, t_end, theta - rate * (t_end - t0)
    th = theta - x
    if x == x_lift:
        return LIFTOFF, t_switch, th
    if x == x_fwd:
        return TO_SLIDE_FORWARD, t_switch, th
    return TO_SLIDE_BACKWARD, t_switch, th
