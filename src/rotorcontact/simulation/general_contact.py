"""Continuous contact of the general machine on |z| = c_r: sliding and rolling with spin (MODEL.md §7).

State (theta, theta', psi, Omega, Omega_b, E_d), E_d the energy the touchdown bearing has dissipated
(friction power -F_t v_rel and the race's drag power, MODEL.md §7); the accelerations are `machine_model.contact_accelerations`
(the rigid contact law; a compliant law would give its own). Phases are integrated with the
Dormand-Prince 5(4) scheme of `contact` (tolerance `contact.CONTACT_TOL` relative), and each switch is
located by bisection on single steps to `contact.EVENT_TOL` in time:

* sliding ends where v_rel = c_r theta' + R Omega - R_b Omega_b reaches 0 (then rolling if the friction it
  needs, |q| <= mu n, is available, else sliding the other way) or at lift-off (n = 0);
* rolling ends where |q| reaches mu n (slip) or at lift-off;
* a race whose bearing has a constant drag torque T_b stops where Omega_b reaches 0, and is then held
  while the contact's torque m R_b |q| stays within T_b (static friction: the phase is that of a fixed
  stator), or turns back; a held race turns again where m R_b |q| reaches T_b.

Its functions are compiled kernels for the event loops and take their arguments unchecked (NaN gives NaN;
text is a numba typing error): `rotorcontact.simulate`, `drop` and `run_general` are the checked entry
points.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..model.machine_model import contact_accelerations
from .contact import (
    _A21, _A31, _A32, _A41, _A42, _A43, _A51, _A52, _A53, _A54, _A61, _A62, _A63, _A64, _A65,
    _B1, _B3, _B4, _B5, _B6, _E1, _E3, _E4, _E5, _E6, _E7, CONTACT_TOL, EVENT_TOL, MAX_CONTACT_STEPS,
)
from .peaks import BEST, PEAK_SLOTS, PEAK_STEPS, may_exceed, peak_next, peak_record, peak_search, peak_search_end

__all__ = ["contact_phase", "contact_rates", "rotor_energy_above_rest", "SLIDING", "ROLLING_MODE", "C_LIFTOFF",
           "C_END", "C_SWITCH", "C_STEP_LIMIT", "C_REST", "C_RACE"]

SLIDING = 0
ROLLING_MODE = 1
C_END = 0
C_LIFTOFF = 1
C_SWITCH = 2
C_STEP_LIMIT = 3
C_REST = 4
C_RACE = 5
# mass, cr, ecc, R, Rb, mu, kx, ky, cx, cy, b_y, inv_polar, inv_race, race_torque, race_coef. A race with a
# constant drag torque T_b: race_torque = +-T_b while it turns, signed as its turn (the drag's sign at
# Omega_b = 0, where a phase may start it), and inv_race = 0, race_torque = T_b while its bearing holds it.
NP = 15


@njit(cache=True)
def contact_rates(y, p, rolling, sgn):
    """(y', n, q, v_rel) of the contact state y = (theta, theta', psi, Omega, Omega_b, E_d); ``p`` as `NP`."""
    mass, cr, ecc, r, rb, mu = p[0], p[1], p[2], p[3], p[4], p[5]
    th, thd, psi, om, omb = y[0], y[1], y[2], y[3], y[4]
    e = complex(math.cos(th), math.sin(th))
    z = cr * e
    v = 1j * cr * thd * e
    f = complex(-(p[6] * z.real + p[8] * v.real) / mass, -(p[7] * z.imag + p[9] * v.imag) / mass + p[10])
    f += ecc * om * om * complex(math.cos(psi), math.sin(psi))
    w = e.conjugate() * f
    drag = 0.0
    if p[12] > 0.0:
        way = (1.0 if omb > 0.0 else -1.0) if omb != 0.0 else (1.0 if p[13] > 0.0 else -1.0)
        drag = way * abs(p[13]) + p[14] * omb
    delta = psi - th
    thdd, omd, ombd, n, q = contact_accelerations(w.real, w.imag, math.sin(delta), math.cos(delta), ecc, cr, thd, mu,
                                                  sgn, rolling, mass, r,
                                                  p[11], rb, p[12], drag)
    v_rel = cr * thd + r * om - rb * omb
    out = np.empty(6)
    out[0] = thd
    out[1] = thdd
    out[2] = om
    out[3] = omd
    out[4] = ombd
    # the friction force m q opposes v_rel (0 when rolling); the race's drag torque opposes Omega_b
    out[5] = -mass * q * v_rel + drag * omb
    return out, n, q, v_rel


@njit(cache=True)
def _step(y, h, p, rolling, sgn):
    k1 = contact_rates(y, p, rolling, sgn)[0]
    k2 = contact_rates(y + h * _A21 * k1, p, rolling, sgn)[0]
    k3 = contact_rates(y + h * (_A31 * k1 + _A32 * k2), p, rolling, sgn)[0]
    k4 = contact_rates(y + h * (_A41 * k1 + _A42 * k2 + _A43 * k3), p, rolling, sgn)[0]
    k5 = contact_rates(y + h * (_A51 * k1 + _A52 * k2 + _A53 * k3 + _A54 * k4), p, rolling, sgn)[0]
    k6 = contact_rates(y + h * (_A61 * k1 + _A62 * k2 + _A63 * k3 + _A64 * k4 + _A65 * k5), p, rolling, sgn)[0]
    yn = y + h * (_B1 * k1 + _B3 * k3 + _B4 * k4 + _B5 * k5 + _B6 * k6)
    k7 = contact_rates(yn, p, rolling, sgn)[0]
    err_v = h * (_E1 * k1 + _E3 * k3 + _E4 * k4 + _E5 * k5 + _E6 * k6 + _E7 * k7)
    # the rates are measured against the fastest surface speed of the state (c_r theta', R Omega, R_b
    # Omega_b): a rate passing through 0 (a race stopping) keeps the tolerance of the motion it is part of
    speed = max(abs(p[1] * y[1]), abs(p[3] * y[3]), abs(p[4] * y[4]))
    # a rotor without radius (R = 0) has a spin no contact changes: no floor binds it
    floor = (1e-3, speed / p[1], 1e-3, speed / p[3] if p[3] > 0.0 else math.inf, speed / p[4])
    err = 0.0
    for i in range(5):  # E_d, a quadrature of the others, is left out of the error control
        scale = CONTACT_TOL * max(1e-3 + max(abs(y[i]), abs(yn[i])), floor[i])
        err = max(err, abs(err_v[i]) / scale)
    return yn, err


@njit(cache=True)
def rotor_energy_above_rest(y, p):
    """m (c_r theta')^2 / 2 + I_p Omega^2 / 2 plus the potential of the constant force m f_y above its
    lowest point on the wall, m c_r (|f_y| - f_y sin(theta)), J (the spin's part 0 with the speed held).

    Zero only for a rotor at rest at the bottom: a rotor rolling to and fro passes through zero kinetic
    energy at each turning point, but not through zero of this.
    """
    speed = p[1] * y[1]
    energy = 0.5 * p[0] * (speed * speed) + p[0] * p[1] * (abs(p[10]) - p[10] * math.sin(y[0]))
    if p[11] > 0.0:
        energy += 0.5 * y[3] * y[3] / p[11]
    return energy


@njit(cache=True)
def _events(y, p, rolling, sgn, rest_energy):
    """Switching functions, positive inside the phase: n; sgn v_rel (sliding) or mu n - |q| (rolling); the
    rotor's energy above rest (`rotor_energy_above_rest`) above ``rest_energy`` (1 where that is 0: no
    rest event); and, for a race with a constant drag torque T_b, its turn (it stops at Omega_b = 0) or,
    held by its bearing, T_b - m R_b |q| (it slips beyond)."""
    _r, n, q, v_rel = contact_rates(y, p, rolling, sgn)
    g3 = rotor_energy_above_rest(y, p) - rest_energy if rest_energy > 0.0 else 1.0
    g4 = 1.0
    if p[13] != 0.0:
        if p[12] > 0.0:
            g4 = y[4] if p[13] > 0.0 else -y[4]
        else:
            g4 = p[13] - p[0] * p[4] * abs(q)
    if rolling:
        return n, p[5] * n - abs(q), g3, g4
    return n, sgn * v_rel, g3, g4


@njit(cache=True)
def _searched(ya, ha, y, p, rolling, sgn, search):
    """Run the started ``search`` over times x from y (x < 0: from ya, ``ha`` before it); its largest force."""
    for _ in range(PEAK_STEPS):
        x = peak_next(search)
        if x != x:  # done
            break
        ys = _step(ya, ha + x, p, rolling, sgn)[0] if x < 0.0 else _step(y, x, p, rolling, sgn)[0]
        peak_record(search, x, contact_rates(ys, p, rolling, sgn)[1])
    return search[BEST]


@njit(cache=True)
def _largest_force(ya, ha, y, h, na, nc, nb, p, rolling, sgn, search):
    """The largest normal force within the step ``ha`` before the state y (from ya) and the step ``h`` after
    it, where the samples na < nc >= nb bracket a maximum (`peaks`; ``search``: its slots)."""
    peak_search(search, -ha, na, 0.0, nc, h, nb)
    return _searched(ya, ha, y, p, rolling, sgn, search)


@njit(cache=True)
def _largest_force_at_end(y, h, n0, n1, p, rolling, sgn, search):
    """The largest normal force within the step ``h`` from the state y, the first or last of a phase, whose end
    sample (n0 at y, or n1) is the larger (`peaks.peak_search_end`)."""
    peak_search_end(search, 0.0, n0, h, n1)
    return _searched(y, 0.0, y, p, rolling, sgn, search)


@njit(cache=True)
def contact_phase(y0, t0, t_end, p, rolling, sgn, rest_energy=0.0):
    """Integrate one contact phase from y0 at t0 until lift-off, a switch, rest, or t_end.

    ``rest_energy`` > 0: the phase also ends where the rotor's energy above rest (`rotor_energy_above_rest`)
    falls to it (`C_REST`).

    Returns
    -------
    code : int
        `C_LIFTOFF`, `C_SWITCH` (end of slip or start of slip), `C_REST`, `C_RACE` (the race stops, or its
        bearing lets it slip), `C_END` or `C_STEP_LIMIT`.
    t : float
    y : (6,) array
        The state at the end.
    n_max : float
        Largest normal force per unit mass over the phase: at its ends, at the integrator's steps, and at each
        maximum between them that may exceed the largest so far (located by `_largest_force`).
    """
    t = t0
    y = y0.copy()
    nc = _events(y, p, rolling, sgn, rest_energy)[0]
    n_max = max(nc, 0.0)
    # the accepted point before y (none yet: ha = 0), for the maxima between steps
    ya = y
    ha = 0.0
    na = nc
    search = np.empty(PEAK_SLOTS)
    h = 1e-3 / (1.0 + abs(y[1]) + abs(y[3]))
    for _ in range(MAX_CONTACT_STEPS):
        if t >= t_end:
            if ha > 0.0 and nc >= na:
                n_max = max(n_max, _largest_force_at_end(ya, ha, na, nc, p, rolling, sgn, search))
            return C_END, t_end, y, n_max
        h = min(h, t_end - t)
        yn, err = _step(y, h, p, rolling, sgn)
        if err > 1.0:
            h *= max(0.2, 0.9 * err ** -0.2)
            continue
        g1, g2, g3, g4 = _events(yn, p, rolling, sgn, rest_energy)
        if g1 <= 0.0 or g2 <= 0.0 or g3 <= 0.0 or g4 <= 0.0:
            lo, hi = 0.0, h
            for _b in range(200):
                if hi - lo <= EVENT_TOL * (abs(t) + 1e-3):
                    break
                mid = 0.5 * (lo + hi)
                ym, _e = _step(y, mid, p, rolling, sgn)
                a1, a2, a3, a4 = _events(ym, p, rolling, sgn, rest_energy)
                if a1 <= 0.0 or a2 <= 0.0 or a3 <= 0.0 or a4 <= 0.0:
                    hi = mid
                else:
                    lo = mid
                    n_max = max(n_max, a1)
            ye, _e = _step(y, hi, p, rolling, sgn)
            e1, e2, e3, _e4 = _events(ye, p, rolling, sgn, rest_energy)
            n_max = max(n_max, e1)
            if ha > 0.0 and na < nc and nc >= e1 and may_exceed(-ha, na, 0.0, nc, hi, e1, n_max):
                n_max = max(n_max, _largest_force(ya, ha, y, hi, na, nc, e1, p, rolling, sgn, search))
            if e1 >= nc or ha == 0.0:  # the phase's last (or only) step: a maximum inside it, by an end
                n_max = max(n_max, _largest_force_at_end(y, hi, nc, e1, p, rolling, sgn, search))
            code = C_LIFTOFF if e1 <= 0.0 else (C_SWITCH if e2 <= 0.0 else (C_REST if e3 <= 0.0 else C_RACE))
            return code, t + hi, ye, n_max
        if ha > 0.0 and na < nc and nc >= g1 and may_exceed(-ha, na, 0.0, nc, h, g1, n_max):
            n_max = max(n_max, _largest_force(ya, ha, y, h, na, nc, g1, p, rolling, sgn, search))
        elif ha == 0.0 and nc >= g1:  # the phase's first step, from its larger end
            n_max = max(n_max, _largest_force_at_end(y, h, nc, g1, p, rolling, sgn, search))
        t += h
        ya, ha, na = y, h, nc
        y = yn
        nc = g1
        n_max = max(n_max, g1)
        h *= min(5.0, 0.9 * max(err, 1e-10) ** -0.2)
    if ha > 0.0 and nc >= na:
        n_max = max(n_max, _largest_force_at_end(ya, ha, na, nc, p, rolling, sgn, search))
    return C_STEP_LIMIT, t, y, n_max
