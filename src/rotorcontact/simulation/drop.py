"""The event-driven kernel of the general machine (MODEL.md §7): flights, impacts with spin, failure.

Data flows one way: machine -> per-axis exact flight (`general_flight.make_flight`) -> guaranteed
impact location (`general_flight.next_impact`) -> impact law with spin and effective mass
(`rotorcontact.model.machine_model.impact_with_spin`) -> table of impacts. The magnetic bearing fails at
t_fail: the flight in progress is cut there and the next one has K = C = F_s = 0 and, with a polar
inertia, a free speed. The rigid impact law sits behind one call, `_impact`, where another contact law
can plug in.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..model.angles import wrap_angle
from ..model.machine_model import impact_with_spin, kinetic_energy, race_spin
from .general_flight import flight_state, make_flight, next_impact
from .roots import CROSSING, ITERATION_LIMIT, NO_CROSSING, STUCK
from .tables import push_row

__all__ = ["drop_kernel", "IMPACT_FIELDS", "STATUS_NAMES"]

COMPLETED = 0
CHATTER = 1
MAX_EVENTS = 2
FAILED = 3
STATUS_NAMES = {COMPLETED: "completed", CHATTER: "chatter", MAX_EVENTS: "max-events", FAILED: "failed"}

#: Columns of the kernel's impact table (SI).
IMPACT_FIELDS = ("t_s", "angle_rad", "normal_velocity_m_per_s", "normal_impulse_Ns", "tangential_impulse_Ns",
                 "spin_before", "spin_after", "race_after", "x_m", "y_m", "vx_plus", "vy_plus",
                 "energy_lost_J", "v_rel_before")
NCOL = len(IMPACT_FIELDS)
BOUNDARY_TOL = 1e-12


@njit(cache=True)
def _impact(z, v, spin, race, mass, d, mu, radius, inv_polar, race_radius, inv_race):
    """The contact law at an impact (rigid: restitution and slip-bounded Coulomb friction, MODEL.md §7)."""
    return impact_with_spin(z, v, spin, race, mass, d, mu, radius, inv_polar, race_radius, inv_race)


@njit(cache=True)
def drop_kernel(mass, clearance, ecc, radius, mu, d, kx, ky, cx, cy, fs, g, polar, race_inertia, race_torque,
                race_coef, z0, v0, psi0, spin0, race0, t_fail, t_end, max_events, chatter_v):
    """Run the general machine from (z0, v0) (m, m/s) at t = 0 to t_end.

    ``polar`` and ``race_inertia`` are 0 for a held speed and a fixed stator. The speed is held until
    t_fail; from t_fail on K, C, F_s vanish and the speed is free when ``polar`` > 0. A run stops with
    status chatter where impacts accumulate: a normal velocity below ``chatter_v`` (m/s) or a start on the
    wall pressed outwards (continuous contact follows there).

    Returns
    -------
    impacts : (n, NCOL) array (`IMPACT_FIELDS`)
    status : int
    t_stop : float
    state : (7,) array: t, x, y, vx, vy, spin, race at the stop (SI)
    """
    cr = clearance
    inv_polar = 1.0 / polar if polar > 0.0 else 0.0
    inv_race = 1.0 / race_inertia if race_inertia > 0.0 else 0.0
    race_radius = radius + clearance
    impacts = np.empty((64, NCOL))
    row = np.empty(NCOL)
    n_imp = 0
    t = 0.0
    z = z0 / cr
    v = v0 / cr
    psi = psi0
    spin = spin0
    race = race0
    on_boundary = abs(abs(z) - 1.0) <= BOUNDARY_TOL
    status = COMPLETED
    events = 0
    while t < t_end:
        events += 1
        if events > max_events:
            status = MAX_EVENTS
            break
        levitated = t < t_fail
        if levitated:
            gx, w2x, gy, w2y, by = cx / mass, kx / mass, cy / mass, ky / mass, (fs / mass - g) / cr
            horizon = min(t_fail, t_end) - t
            inv_p = 0.0
        else:
            gx, w2x, gy, w2y, by = 0.0, 0.0, 0.0, 0.0, -g / cr
            horizon = t_end - t
            inv_p = inv_polar
        flight = make_flight(z, v, spin, psi, gx, w2x, gy, w2y, by, ecc / cr)
        code, s = next_impact(flight, spin, horizon, on_boundary)
        if code == ITERATION_LIMIT:
            status = FAILED
            break
        if code == STUCK:
            status = CHATTER
            break
        z, v = flight_state(flight, spin, s)
        if code == CROSSING:
            t = t + s
        else:  # the flight reached its horizon: the failure (exactly at t_fail) or the end
            t = t_fail if levitated and t_fail < t_end else t_end
        psi = psi + spin * s
        if race_inertia > 0.0:
            race = race_spin(race, s, race_inertia, race_torque, race_coef)
        if code == NO_CROSSING:
            on_boundary = abs(abs(z) - 1.0) <= BOUNDARY_TOL
            continue
        z = z / abs(z)
        zs = z * cr
        vs = v * cr
        e_before = kinetic_energy(mass, vs, polar if inv_p > 0.0 else 0.0, spin, race_inertia, race)
        v_plus, spin_plus, race_plus, v_n, v_rel, p_n, p_t = _impact(
            zs, vs, spin, race, mass, d, mu, radius, inv_p, race_radius, inv_race)
        e_after = kinetic_energy(mass, v_plus, polar if inv_p > 0.0 else 0.0, spin_plus, race_inertia, race_plus)
        row[0] = t
        row[1] = wrap_angle(math.atan2(z.imag, z.real))
        row[2] = v_n
        row[3] = p_n
        row[4] = p_t
        row[5] = spin
        row[6] = spin_plus
        row[7] = race_plus
        row[8] = zs.real
        row[9] = zs.imag
        row[10] = v_plus.real
        row[11] = v_plus.imag
        row[12] = e_before - e_after
        row[13] = v_rel
        impacts, n_imp = push_row(impacts, n_imp, row)
        v = v_plus / cr
        spin = spin_plus
        race = race_plus
        on_boundary = True
        if v_n < chatter_v:
            status = CHATTER
            break
    state = np.array([min(t, t_end), z.real * cr, z.imag * cr, v.real * cr, v.imag * cr, spin, race])
    return impacts[:n_imp].copy(), status, min(t, t_end), state
