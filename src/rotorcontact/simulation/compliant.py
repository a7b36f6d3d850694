"""Contact episodes of the general machine with the compliant (Hunt-Crossley) law (MODEL.md §8).

An episode starts where the rigid kernel would impact (|z| = c_r, outward normal velocity v_0) and follows
the penetrating motion with the forces of the flight (bearing, static force, gravity, unbalance) and the
contact forces F_n = max(0, K_c delta^n (1 + D delta')), D = chi / v_0, and Coulomb friction: sliding,
F_t = -mu F_n sgn(v_rel), or rolling, v_rel = 0 held by the F_t it needs while |F_t| <= mu F_n. A stator on
springs moves under the reaction of these forces and its support; the gap and the surface velocities are
relative to it. The state is (x, y, x', y', psi, Omega, Omega_b, E_d, P_n, P_t, Theta, x_s, y_s, x_s', y_s')
in SI: E_d the energy dissipated, P_n and P_t the integrals of F_n and F_t, Theta the angle of z - z_s
followed continuously (the whirl), z_s the stator's centre (0 for a fixed stator). It is integrated with the
Dormand-Prince 5(4) scheme of `contact` (relative tolerance ``tol``); its end (delta back to 0), the switches between sliding and rolling (v_rel = 0,
|F_t| = mu F_n), the rotor at rest and the maxima of delta and F_n are located by bisection on single
steps to `contact.EVENT_TOL` in time.

Its functions are compiled kernels for the event loops and take their arguments unchecked (NaN gives NaN;
text is a numba typing error): `rotorcontact.simulate`, `drop` and `run_general` are the checked entry
points.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..model.machine_model import compliant_normal_force, kinetic_energy, surface_velocity
from .contact import (
    _A21, _A31, _A32, _A41, _A42, _A43, _A51, _A52, _A53, _A54, _A61, _A62, _A63, _A64, _A65,
    _B1, _B3, _B4, _B5, _B6, _E1, _E3, _E4, _E5, _E6, _E7, EVENT_TOL, MAX_CONTACT_STEPS,
)

__all__ = ["compliant_episode", "energy_above_rest", "episode_rates", "NQ", "NY", "E_HORIZON", "E_SEPARATED",
           "E_STEP_LIMIT", "E_REST"]

E_HORIZON = 0
E_SEPARATED = 1
E_STEP_LIMIT = 3
E_REST = 4
#: mass, cr, ecc, R, Rb, mu, kx, ky, cx, cy, b_y (m/s^2), inv_polar, inv_race, race_torque, race_coef,
#: K_c, n, D, tol, v_scale (the velocity scale of the error control, m/s),
#: 1/m_s (0: a fixed stator), k_sx, k_sy, c_sx, c_sy (the stator's support)
NQ = 25
NY = 15
MAX_BISECTIONS = 200


@njit(cache=True)
def episode_rates(y, p, rolling, sgn, rdir):
    """(y', F_n, F_n', delta, delta', v_rel, F_t) of the episode state y (SI, `NY` entries); ``p`` as `NQ`.

    Sliding along ``sgn`` (F_t = -mu F_n sgn) or ``rolling`` (F_t holds v_rel' = 0); the race turning along
    ``rdir`` = +-1 or held at rest by its static drag torque (``rdir`` = 0). F_n' is the rate of the normal
    force along the motion (0 where F_n = 0).
    """
    mass, cr, ecc, r, rb, mu = p[0], p[1], p[2], p[3], p[4], p[5]
    x, yy, vx, vy, psi, om, omb = y[0], y[1], y[2], y[3], y[4], y[5], y[6]
    inv_ms = p[20]
    xs, ys, vxs, vys = y[11], y[12], y[13], y[14]
    # the rotor relative to the stator's centre (MODEL.md §8)
    dist = abs(complex(x - xs, yy - ys))
    nx = (x - xs) / dist
    ny = (yy - ys) / dist
    delta = dist - cr
    vn = (vx - vxs) * nx + (vy - vys) * ny
    vt = (vy - vys) * nx - (vx - vxs) * ny
    kc, expo, damp = p[15], p[16], p[17]
    fn, fel = compliant_normal_force(delta, vn, kc, expo, damp)
    v_rel = surface_velocity(vt, r, om, rb, omb)
    inv_race = p[12] if rdir != 0.0 else 0.0  # a race held at rest moves as the stator
    drag = p[13] * rdir + p[14] * omb if inv_race > 0.0 else 0.0
    cp = math.cos(psi)
    sp = math.sin(psi)
    om2 = om * om
    # the external force per unit mass without the contact and the unbalance's Omega' term
    fx = -(p[6] * x + p[8] * vx) / mass + ecc * om2 * cp
    fy = -(p[7] * yy + p[9] * vy) / mass + p[10] + ecc * om2 * sp
    # the stator's support force per unit of its mass
    fxs = -(p[21] * xs + p[23] * vxs) * inv_ms
    fys = -(p[22] * ys + p[24] * vys) * inv_ms
    if rolling:
        # v_rel' = f_t - f_st - e Omega' cos(psi - theta) - v_t v_n / r + F_t (1/m + 1/m_s) + R Omega'
        # - R_b Omega_b' = 0 with Omega' = R F_t / I_p, Omega_b' = -(R_b F_t + drag) / I_b (MODEL.md §8)
        f_t = (fy - fys) * nx - (fx - fxs) * ny
        cd = cp * nx + sp * ny
        den = 1.0 / mass + inv_ms + (r * r - ecc * r * cd) * p[11] + rb * rb * inv_race
        ft = -(f_t - vt * vn / dist + rb * drag * inv_race) / den
    else:
        ft = -mu * fn * sgn
    omd = r * ft * p[11]
    ombd = -(rb * ft + drag) * inv_race
    # m z'' = -K z - C z' + i m b_y + m e (Omega^2 - i Omega') e^{i psi} - F_n n + F_t i n (MODEL.md §7, §8)
    ax = fx + ecc * omd * sp + (-fn * nx - ft * ny) / mass
    ay = fy - ecc * omd * cp + (-fn * ny + ft * nx) / mass
    # m_s z_s'' = -K_s z_s - C_s z_s' + F_n n - F_t i n: the reaction of the contact
    axs = fxs + (fn * nx + ft * ny) * inv_ms
    ays = fys + (fn * ny - ft * nx) * inv_ms
    out = np.empty(NY)
    out[0] = vx
    out[1] = vy
    out[2] = ax
    out[3] = ay
    out[4] = om
    out[5] = omd
    out[6] = ombd
    # dissipation: the damping part F_n - F_el of the normal force against delta', friction, the race's drag,
    # the stator's support damping
    out[7] = (fn - fel) * vn - ft * v_rel + drag * omb + p[23] * vxs * vxs + p[24] * vys * vys
    out[8] = fn
    out[9] = ft
    out[10] = vt / dist
    out[11] = vxs
    out[12] = vys
    out[13] = axs
    out[14] = ays
    dfn = 0.0
    if fn > 0.0:
        an = (ax - axs) * nx + (ay - ays) * ny + vt * vt / dist  # delta''
        dfn = expo * kc * delta ** (expo - 1.0) * vn * (1.0 + damp * vn) + fel * damp * an
    return out, fn, dfn, delta, vn, v_rel, ft


@njit(cache=True)
def _rates(y, p, rolling, sgn, rdir):
    return episode_rates(y, p, rolling, sgn, rdir)[0]


@njit(cache=True)
def _step(y, h, p, rolling, sgn, rdir):
    k1 = _rates(y, p, rolling, sgn, rdir)
    k2 = _rates(y + h * _A21 * k1, p, rolling, sgn, rdir)
    k3 = _rates(y + h * (_A31 * k1 + _A32 * k2), p, rolling, sgn, rdir)
    k4 = _rates(y + h * (_A41 * k1 + _A42 * k2 + _A43 * k3), p, rolling, sgn, rdir)
    k5 = _rates(y + h * (_A51 * k1 + _A52 * k2 + _A53 * k3 + _A54 * k4), p, rolling, sgn, rdir)
    k6 = _rates(y + h * (_A61 * k1 + _A62 * k2 + _A63 * k3 + _A64 * k4 + _A65 * k5), p, rolling, sgn, rdir)
    yn = y + h * (_B1 * k1 + _B3 * k3 + _B4 * k4 + _B5 * k5 + _B6 * k6)
    k7 = _rates(yn, p, rolling, sgn, rdir)
    err_v = h * (_E1 * k1 + _E3 * k3 + _E4 * k4 + _E5 * k5 + _E6 * k6 + _E7 * k7)
    err = 0.0
    for i in range(NY):
        if 7 <= i <= 10:
            continue  # E_d, P_n, P_t, Theta: quadratures of the others, left out of the error control
        if i < 2 or 11 <= i <= 12:
            floor = p[1]
        elif i < 4 or i >= 13:
            floor = p[19]
        else:
            floor = 1.0
        scale = p[18] * (floor + max(abs(y[i]), abs(yn[i])))
        err = max(err, abs(err_v[i]) / scale)
    return yn, err


@njit(cache=True)
def _kinetic(y, p):
    """Kinetic energy of the rotor (whirl, and spin where it is free) and of a stator on springs, J."""
    ke = kinetic_energy(p[0], complex(y[2], y[3]), 1.0 / p[11] if p[11] > 0.0 else 0.0, y[5], 0.0, 0.0)
    if p[20] > 0.0:
        ke += kinetic_energy(1.0 / p[20], complex(y[13], y[14]), 0.0, 0.0, 0.0, 0.0)
    return ke


@njit(cache=True)
def energy_above_rest(y, p):
    """The energy of the episode state y above the rotor's rest on the stator, J (0 only at that rest).

    The kinetic energy (`_kinetic`) and the potential energy of the constant force m b_y, of the contact's
    elasticity K_c delta^(n+1)/(n+1) and of a stator's springs, less its least value: the rotor resting on the
    wall where m b_y points, pressed in by delta_s (K_c delta_s^n = m |b_y|), the stator's springs carrying
    that force. The compliant form of `general_contact.rotor_energy_above_rest` (MODEL.md §7-8).
    """
    mass, cr, b_y, kc, expo = p[0], p[1], p[10], p[15], p[16]
    xs, ys = y[11], y[12]
    delta = abs(complex(y[0] - xs, y[1] - ys)) - cr
    energy = _kinetic(y, p) + (kc * delta ** (expo + 1.0) / (expo + 1.0) if delta > 0.0 else 0.0)
    if p[20] > 0.0:
        energy += 0.5 * (p[21] * xs * xs + p[22] * ys * ys)
    if b_y != 0.0:
        force = mass * abs(b_y)
        side = 1.0 if b_y > 0.0 else -1.0
        # -m b_y y less its value at rest, and the least elastic energies: F (c_r - side y) + F delta_s n/(n+1)
        # (+ F^2 / (2 k_sy) with the stator's springs)
        energy += force * (cr - side * y[1]) + force * (force / kc) ** (1.0 / expo) * expo / (expo + 1.0)
        if p[20] > 0.0 and p[22] > 0.0:
            energy += 0.5 * force * force / p[22]
    return energy


@njit(cache=True)
def _inside(y, p, rolling, sgn, rdir, which, rest_energy):
    """Whether y lies before the event sought by `_bisect`: delta' > 0 (which = 0), F_n' > 0 (1), or every
    switching function of `_events` positive (2)."""
    if which == 2:
        g1, g2, g3, g4 = _events(y, p, rolling, sgn, rdir, rest_energy)
        return g1 > 0.0 and g2 > 0.0 and g3 > 0.0 and g4 > 0.0
    _r, _fn, dfn, _d, vn, _v, _f = episode_rates(y, p, rolling, sgn, rdir)
    return (vn if which == 0 else dfn) > 0.0


@njit(cache=True)
def _bisect(y, h, p, rolling, sgn, rdir, which, t, rest_energy):
    """(lo, hi): the event of `_inside` within the step from y of length h, bracketed to EVENT_TOL in time."""
    lo, hi = 0.0, h
    for _ in range(MAX_BISECTIONS):
        if hi - lo <= EVENT_TOL * (abs(t) + 1e-3):
            break
        mid = 0.5 * (lo + hi)
        ym, _e = _step(y, mid, p, rolling, sgn, rdir)
        if _inside(ym, p, rolling, sgn, rdir, which, rest_energy):
            lo = mid
        else:
            hi = mid
    return lo, hi


@njit(cache=True)
def _peak(y, h, p, rolling, sgn, rdir, which, t):
    """(F_n, delta) where delta' (which = 0) or F_n' (which = 1) falls through 0 within the step from y of
    length h."""
    lo, _hi = _bisect(y, h, p, rolling, sgn, rdir, which, t, 0.0)
    ym, _e = _step(y, lo, p, rolling, sgn, rdir)
    _r, fn, _dfn, delta, _vn, _v, _f = episode_rates(ym, p, rolling, sgn, rdir)
    return fn, delta


@njit(cache=True)
def race_mode(y, p, at_switch, rolling_now):
    """The race's direction at an episode state: 1 for a fixed stator (no race); sgn(Omega_b) while it turns;
    at rest (Omega_b = 0, or ``at_switch``: it has just stopped, and Omega_b is set to 0) 0, held by its drag
    torque T_b while the friction's torque R_b |F_t| does not exceed it, else the way the friction drives it
    (``rolling_now``: the surfaces roll, so v_rel is taken as 0 in that friction)."""
    if p[12] == 0.0:
        return 1.0
    if y[6] != 0.0 and not at_switch:
        return 1.0 if y[6] > 0.0 else -1.0
    y[6] = 0.0
    rolling, sgn = friction_mode(y, p, rolling_now, 0.0)
    ft = episode_rates(y, p, rolling, sgn, 0.0)[6]
    if p[4] * abs(ft) <= p[13]:
        return 0.0
    return -1.0 if ft > 0.0 else 1.0


@njit(cache=True)
def friction_mode(y, p, at_switch, rdir):
    """(rolling, sgn) at an episode state: sliding along sgn(v_rel) away from v_rel = 0; at it (``at_switch``,
    or |v_rel| below 1e-12 of the surface speeds) rolling where the friction it needs is available
    (|F_t| <= mu F_n), else sliding the way its F_t opposes."""
    _r, fn, _dfn, _d, _vn, v_rel, ft = episode_rates(y, p, True, 1.0, rdir)
    scale = abs(p[3] * y[5]) + abs(p[4] * y[6]) + abs(complex(y[2], y[3])) + 1e-300
    if abs(v_rel) > 1e-12 * scale and not at_switch:
        return False, 1.0 if v_rel > 0.0 else -1.0
    if abs(ft) <= p[5] * fn:
        return True, 1.0
    return False, -1.0 if ft > 0.0 else 1.0


@njit(cache=True)
def _events(y, p, rolling, sgn, rdir, rest_energy):
    """Switching functions, positive inside the phase: delta; sgn v_rel (sliding) or mu F_n - |F_t| (rolling);
    the energy above rest (`energy_above_rest`) above ``rest_energy`` (1 where that is 0: no rest event);
    rdir Omega_b (the race turning) or T_b - R_b |F_t| (the race held; 1 without a race)."""
    _r, fn, _dfn, delta, _vn, v_rel, ft = episode_rates(y, p, rolling, sgn, rdir)
    g2 = p[5] * fn - abs(ft) if rolling else sgn * v_rel
    g3 = energy_above_rest(y, p) - rest_energy if rest_energy > 0.0 else 1.0
    if p[12] == 0.0:
        g4 = 1.0
    elif rdir == 0.0:
        g4 = p[13] - p[4] * abs(ft)
    else:
        g4 = rdir * y[6]
    return delta, g2, g3, g4


@njit(cache=True)
def _mode_index(rolling, sgn):
    """0 sliding forward, 1 rolling, 2 sliding backward: the kinds of `drop.CONTACT_KINDS`."""
    if rolling:
        return 1
    return 0 if sgn > 0.0 else 2


@njit(cache=True)
def compliant_episode(y0, t0, t_end, p, f_max, d_max, modes, rest_energy=0.0):
    """Integrate a compliant contact episode from y0 at t0 until the surfaces part (delta back to 0), rest,
    or t_end, sliding and rolling as friction allows.

    ``f_max``, ``d_max``: the largest normal force (N) and penetration (m) so far in the episode, updated.
    ``modes``: (3,) array of the time spent sliding forward (v_rel > 0), rolling and sliding backward, s,
    added to in place.
    ``rest_energy`` > 0: the episode also ends where its energy above rest (`energy_above_rest`) falls to it.

    Returns
    -------
    code : int
        `E_SEPARATED`, `E_REST`, `E_HORIZON` (t_end) or `E_STEP_LIMIT`.
    t : float
    y : (NY,) array
        The state at the end.
    f_max, d_max : float
    """
    t = t0
    y = y0.copy()
    rdir = race_mode(y, p, False, False)
    rolling, sgn = friction_mode(y, p, False, rdir)
    _r, fn, dfn, delta, vn, _v, _f = episode_rates(y, p, rolling, sgn, rdir)
    f_max = max(f_max, fn)
    d_max = max(d_max, delta)
    # a first step from the penetration rate, or from the scales of the motion at a graze
    h = 1e-3 * p[1] / (p[19] + abs(vn))
    for _ in range(MAX_CONTACT_STEPS):
        if t >= t_end:
            return E_HORIZON, t_end, y, f_max, d_max
        h = min(h, t_end - t)
        yn, err = _step(y, h, p, rolling, sgn, rdir)
        if err > 1.0 or not math.isfinite(err):
            h *= max(0.2, 0.9 * err ** -0.2) if math.isfinite(err) else 0.2
            continue
        _r1, fn1, dfn1, delta1, vn1, _v1, _f1 = episode_rates(yn, p, rolling, sgn, rdir)
        # a maximum of delta (of F_n) within the step is located where it can exceed the largest so far: the
        # rate falls through the step, so the maximum is at most delta + h delta' (F_n + h F_n') (twice for safety)
        if vn > 0.0 and vn1 <= 0.0 and delta + 2.0 * h * vn > d_max:
            d_max = max(d_max, _peak(y, h, p, rolling, sgn, rdir, 0, t)[1])
        if dfn > 0.0 and dfn1 <= 0.0 and fn1 > 0.0 and fn + 2.0 * h * dfn > f_max:
            f_max = max(f_max, _peak(y, h, p, rolling, sgn, rdir, 1, t)[0])
        g1, g2, g3, g4 = _events(yn, p, rolling, sgn, rdir, rest_energy)
        if g1 <= 0.0 or g2 <= 0.0 or g3 <= 0.0 or g4 <= 0.0:
            _lo, hi = _bisect(y, h, p, rolling, sgn, rdir, 2, t, rest_energy)
            ye, _e = _step(y, hi, p, rolling, sgn, rdir)
            e1, e2, e3, e4 = _events(ye, p, rolling, sgn, rdir, rest_energy)
            _re, fe, _dfe, de, _ve, _vre, _fte = episode_rates(ye, p, rolling, sgn, rdir)
            f_max = max(f_max, fe)
            d_max = max(d_max, de)
            modes[_mode_index(rolling, sgn)] += hi
            t += hi
            y = ye
            if e1 <= 0.0:
                return E_SEPARATED, t, y, f_max, d_max
            if e3 <= 0.0:
                return E_REST, t, y, f_max, d_max
            # a switch of the friction (sliding, rolling) or of the race (turning, held)
            rdir = race_mode(y, p, e4 <= 0.0, rolling)
            rolling, sgn = friction_mode(y, p, e2 <= 0.0 or rolling, rdir)
            _r, fn, dfn, delta, vn, _v, _f = episode_rates(y, p, rolling, sgn, rdir)
            continue
        modes[_mode_index(rolling, sgn)] += h
        t += h
        y = yn
        fn, dfn, delta, vn = fn1, dfn1, delta1, vn1
        f_max = max(f_max, fn)
        d_max = max(d_max, delta)
        h *= min(5.0, 0.9 * max(err, 1e-10) ** -0.2)
    return E_STEP_LIMIT, t, y, f_max, d_max
