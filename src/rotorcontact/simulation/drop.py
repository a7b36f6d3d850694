"""The event-driven kernel of the general machine (MODEL.md §7): flights, impacts with spin, failure.

Data flows one way: machine -> per-axis exact flight (`general_flight.make_flight`) -> guaranteed
impact location (`general_flight.next_impact`) -> impact law with spin and effective mass
(`rotorcontact.model.machine_model.impact_with_spin`) -> table of impacts. The magnetic bearing fails at
t_fail: the flight in progress is cut there and the next one has K = C = F_s = 0 and, with a polar
inertia, a free speed. The rigid impact law sits behind one call, `_impact`; with a contact stiffness the
compliant law of MODEL.md §8 replaces it: each impact starts a contact episode (`_episode`,
`compliant.compliant_episode`) integrated until the surfaces part.

Its functions are compiled kernels for the event loops and take their arguments unchecked (NaN gives NaN;
text is a numba typing error): `rotorcontact.simulate`, `drop` and `run_general` are the checked entry
points.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..interpreted import complex_quotient
from ..model.angles import point_angle
from ..model.machine_model import (
    effective_mass_factor, impact_dissipation, impact_duration, impact_with_spin, kinetic_energy, race_spin,
    rolling_whirl_rate, surface_velocity,
)
from .compliant import E_REST, E_SEPARATED, NQ, NY, compliant_episode
from .general_contact import C_END, C_LIFTOFF, C_RACE, C_REST, C_STEP_LIMIT, NP, contact_phase, contact_rates
from .general_flight import flight_state, make_flight, make_stator_flight, next_impact
from .rolling import fast_rolling_applies, rolling_fixed_phase
from .roots import CROSSING, ITERATION_LIMIT, NO_CROSSING, STUCK
from .tables import push_row

__all__ = ["drop_kernel", "IMPACT_FIELDS", "COMPLIANT_FIELDS", "CONTACT_FIELDS", "CONTACT_KINDS", "STATUS_NAMES"]

COMPLETED = 0
CHATTER = 1
MAX_EVENTS = 2
FAILED = 3
AT_REST = 4
STATUS_NAMES = {COMPLETED: "completed", CHATTER: "chatter", MAX_EVENTS: "max-events", FAILED: "failed",
                AT_REST: "at-rest"}

#: Columns of the kernel's impact table (SI).
IMPACT_FIELDS = ("t_s", "angle_rad", "normal_velocity_m_per_s", "normal_impulse_Ns", "tangential_impulse_Ns",
                 "spin_before", "spin_after", "race_after", "x_m", "y_m", "vx_plus", "vy_plus",
                 "energy_lost_J", "v_rel_before", "duration_s", "max_force_N", "max_penetration_m", "rebound_ratio", "kind")
#: The columns only a compliant contact episode fills (nan for a rigid impact); kind as in `CONTACT_KINDS`.
COMPLIANT_FIELDS = ("duration_s", "max_force_N", "max_penetration_m", "rebound_ratio", "kind")
NCOL = len(IMPACT_FIELDS)
BOUNDARY_TOL = 1e-12
#: Columns of the kernel's contact table (SI): kind 0 sliding forward, 1 rolling, 2 sliding backward.
CONTACT_FIELDS = ("t_start_s", "t_end_s", "kind", "max_normal_force_N", "whirl_rate_rad_per_s")
CONTACT_KINDS = ("sliding-forward", "rolling", "sliding-backward")
MAX_STALLS = 50
#: Contact phases in a row that use the integrator's whole step budget (`contact.MAX_CONTACT_STEPS`) to
#: advance less than CRAWL_TIME (1 + t) s end the run as failed: the integrator cannot go on there.
MAX_CRAWLS = 2
CRAWL_TIME = 1e-6
VREL_TOL = 1e-12  # |v_rel| below this times the surface speeds: the surfaces roll
#: A compliant episode lasting longer than this many times the elastic impact at its start speed
#: (`machine_model.impact_duration`) is lasting contact (a rub, rolling, a rotor settled on the
#: bearing): it is also a row of the contact table.
LASTING_CONTACT = 10.0


@njit(cache=True)
def _contact_params(mass, clearance, ecc, radius, mu, kx, ky, cx, cy, b_y, inv_p, inv_race, race_torque, race_coef):
    p = np.empty(NP)
    p[0] = mass
    p[1] = clearance
    p[2] = ecc
    p[3] = radius
    p[4] = radius + clearance
    p[5] = mu
    p[6] = kx
    p[7] = ky
    p[8] = cx
    p[9] = cy
    p[10] = b_y
    p[11] = inv_p
    p[12] = inv_race
    p[13] = race_torque
    p[14] = race_coef
    return p


@njit(cache=True)
def _slip_rate(y, p, sgn):
    """sgn * v_rel' while sliding along sgn: positive where that slip is consistent (it grows)."""
    r, _n, _q, _v = contact_rates(y, p, False, sgn)
    return sgn * (p[1] * r[1] + p[3] * r[3] - p[4] * r[4])


@njit(cache=True)
def _contact_mode(y, p, at_switch):
    """(mode, sgn) at a contact state: -1 lift-off (n <= 0), 0 sliding along sgn, 1 rolling.

    ``at_switch``: the state ends a phase at v_rel = 0 (located to the event tolerance in time), so v_rel
    is taken as 0 there.

    Away from v_rel = 0 the slip goes on along sgn(v_rel). At v_rel = 0 the surfaces roll when the
    friction rolling needs is available (|q| <= mu n); else they slip the way whose slip grows.
    """
    _r, n, q, v_rel = contact_rates(y, p, True, 1.0)
    scale = abs(p[1] * y[1]) + abs(p[3] * y[3]) + abs(p[4] * y[4]) + 1e-300
    sgn = 1.0 if v_rel > 0.0 else -1.0
    away = abs(v_rel) > VREL_TOL * scale and not at_switch
    if away or _slip_rate(y, p, sgn) > 0.0:
        # the slip goes on (away from v_rel = 0, or from it while it grows); otherwise v_rel is 0 to the
        # event tolerance and neither slip grows: the surfaces roll if friction allows
        if away or _slip_rate(y, p, -sgn) <= 0.0:
            if contact_rates(y, p, False, sgn)[1] <= 0.0:
                return -1, sgn
            return 0, sgn
    if n <= 0.0:
        return -1, 1.0
    if abs(q) <= p[5] * n:
        return 1, 1.0
    sgn = -1.0 if q > 0.0 else 1.0
    return 0, sgn


@njit(cache=True)
def _impact(z, v, spin, race, mass, d, mu, radius, inv_polar, race_radius, inv_race):
    """The contact law at an impact (rigid: restitution and slip-bounded Coulomb friction, MODEL.md §7)."""
    return impact_with_spin(z, v, spin, race, mass, d, mu, radius, inv_polar, race_radius, inv_race)


@njit(cache=True)
def _episode_params(mass, cr, ecc, radius, mu, kx, ky, cx, cy, b_y, inv_p, inv_race, race_torque, race_coef,
                    stiffness, exponent, damp, tol, v_scale, stator):
    q = np.empty(NQ)
    q[:NP] = _contact_params(mass, cr, ecc, radius, mu, kx, ky, cx, cy, b_y, inv_p, inv_race, race_torque,
                             race_coef)
    q[NP:NP + 5] = np.array([stiffness, exponent, damp, tol, v_scale])  # the slots of `compliant.NQ`
    q[NP + 5:] = stator
    return q


@njit(cache=True)
def _episode(t, zs, vs, psi, spin, race, v_n, mass, cr, ecc, radius, mu, kx, ky, cx, cy, fs, g, inv_polar, inv_race,
             race_torque, race_coef, t_fail, t_end, stiffness, exponent, chi, v_floor, tol,
             rest_energy, max_steps, stator, zb, vb):
    """A compliant contact episode from the impact point zs (m) with velocity vs (m/s) at t (MODEL.md §8),
    through the bearing's failure, until the surfaces part, the rotor rests or t_end.

    ``stator``: (1/m_s, k_sx, k_sy, c_sx, c_sy) of a stator on springs at zb (m) with velocity vb (m/s), zeros
    for a fixed stator.

    The damping D = chi / max(v_n, v_floor) is fixed at the start. Returns (code, t, y, f_max, d_max, kind,
    calls) with y the `compliant.NY` state at the end, ``kind`` the friction mode (`CONTACT_KINDS`) the
    episode spent most of its time in and ``calls`` the integrator calls (at most ``max_steps``).
    """
    y = np.zeros(NY)  # E_d, P_n, P_t start at 0
    y[:7] = np.array([zs.real, zs.imag, vs.real, vs.imag, psi, spin, race])
    y[10] = math.atan2(zs.imag - zb.imag, zs.real - zb.real)
    y[11:] = np.array([zb.real, zb.imag, vb.real, vb.imag])
    damp = chi / max(v_n, v_floor)
    v_scale = abs(vs) + 1e3 * v_floor  # the error control's velocity scale: the impact's and the machine's
    f_max = 0.0
    d_max = 0.0
    modes = np.zeros(3)
    code = E_SEPARATED
    calls = 0
    while t < t_end and calls < max_steps:
        calls += 1
        if t < t_fail:
            q = _episode_params(mass, cr, ecc, radius, mu, kx, ky, cx, cy, fs / mass - g, 0.0, inv_race,
                                race_torque, race_coef, stiffness, exponent, damp, tol, v_scale, stator)
            stop = min(t_fail, t_end)
            rest = 0.0
        else:
            q = _episode_params(mass, cr, ecc, radius, mu, 0.0, 0.0, 0.0, 0.0, -g, inv_polar, inv_race, race_torque,
                                race_coef, stiffness, exponent, damp, tol, v_scale, stator)
            stop = t_end
            rest = rest_energy if inv_polar > 0.0 else 0.0
        code, t, y, f_max, d_max = compliant_episode(y, t, stop, q, f_max, d_max, modes, rest)
        if code == E_SEPARATED or code == E_REST:
            break
    return code, t, y, f_max, d_max, float(np.argmax(modes)), calls


@njit(cache=True)
def _stator_energy(zb, vb, cr, mass, kx, ky):
    """Kinetic and spring energy of the stator on springs at zb, vb (clearances, clearances/s), J."""
    return kinetic_energy(mass, vb * cr, 0.0, 0.0, 0.0, 0.0) + 0.5 * cr * cr * (kx * zb.real * zb.real
                                                                               + ky * zb.imag * zb.imag)


@njit(cache=True)
def drop_kernel(mass, clearance, ecc, radius, mu, d, kx, ky, cx, cy, fs, g, polar, race_inertia, race_torque,
                race_coef, z0, v0, psi0, spin0, race0, t_fail, t_end, max_events, chatter_v, follow_contact=True,
                rest_energy=0.0, chatter_rel=0.0, contact_stiffness=0.0, contact_exponent=1.5, contact_chi=0.0,
                contact_v_floor=0.0, contact_tol=1e-10, contact_duration_factor=0.0, stator_mass=0.0, stator_kx=0.0,
                stator_ky=0.0, stator_cx=0.0, stator_cy=0.0, stator_z0=0j, stator_v0=0j):
    """Run the general machine from (z0, v0) (m, m/s) at t = 0 to t_end.

    ``polar`` and ``race_inertia`` are 0 for a held speed and a fixed stator. The speed is held until
    t_fail; from t_fail on K, C, F_s vanish and the speed is free when ``polar`` > 0. A run stops with
    status chatter where impacts accumulate: a normal velocity below ``chatter_v`` (m/s) or below
    ``chatter_rel`` times the centre's speed, or a start on the wall pressed outwards. With
    ``follow_contact`` continuous contact follows there (`general_contact`: sliding, rolling, lift-off;
    `rolling`: rolling on a fixed stator with a free speed), else the run stops with status chatter. After the
    failure, with a free speed, a contact phase in which the rotor's energy above rest (kinetic, and
    potential above the bottom: `general_contact.rotor_energy_above_rest`) falls to ``rest_energy``
    (J, > 0) ends the run with status at-rest.

    ``contact_stiffness`` > 0 selects the compliant law of MODEL.md §8 (K_c in N/m^n, n =
    ``contact_exponent``, D = ``contact_chi`` / max(v_n, ``contact_v_floor``), relative tolerance
    ``contact_tol``): each impact becomes a contact episode, a
    row of the impact table with its `COMPLIANT_FIELDS`, and impacts never accumulate into rigid contact.
    An episode that lasts (`LASTING_CONTACT` elastic impacts, of `machine_model.impact_duration` with
    ``contact_duration_factor`` from `machine_model.impact_duration_factor`) is a row of the contact table
    too, with its mean whirl rate. ``stator_mass`` > 0 (with the compliant law only) puts the stator on
    springs (N/m) and dampers (N s/m) per axis: it starts at ``stator_z0`` (m) with velocity ``stator_v0``
    (m/s), flies freely on its support between episodes, and the gap is measured from it (MODEL.md §8).

    Returns
    -------
    impacts : (n, NCOL) array (`IMPACT_FIELDS`)
    contacts : (c, 5) array (`CONTACT_FIELDS`)
    status : int
    t_stop : float
    state : (12,) array: t, x, y, vx, vy, spin, race at the stop, the energy the touchdown bearing
        dissipated (impacts, friction in contact, the race's drag, the stator's support damping), J, and the
        stator's x, y, vx, vy
    """
    cr = clearance
    inv_polar = 1.0 / polar if polar > 0.0 else 0.0
    inv_race = 1.0 / race_inertia if race_inertia > 0.0 else 0.0
    race_radius = radius + clearance
    impacts = np.empty((64, NCOL))
    contacts = np.empty((16, 5))
    crow = np.empty(5)
    n_ct = 0
    row = np.empty(NCOL)
    row[14:] = math.nan
    compliant = contact_stiffness > 0.0
    moving_stator = compliant and stator_mass > 0.0
    inv_ms = 1.0 / stator_mass if moving_stator else 0.0
    stator_p = np.array([inv_ms, stator_kx, stator_ky, stator_cx, stator_cy])  # inert with inv_ms = 0: z_s stays 0
    stator = np.zeros((0, 10))
    zb = complex_quotient(stator_z0, cr) if moving_stator else 0j  # the stator's centre and velocity, clearances and clearances/s
    vb = complex_quotient(stator_v0, cr) if moving_stator else 0j
    n_imp = 0
    in_contact = False
    liftoff = False
    switched = False
    stalls = 0
    crawls = 0
    t = 0.0
    z = complex_quotient(z0, cr)
    v = complex_quotient(v0, cr)
    psi = psi0
    spin = spin0
    race = race0
    on_boundary = abs(abs(z - zb) - 1.0) <= BOUNDARY_TOL
    status = COMPLETED
    events = 0
    dissipated = 0.0
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
        if in_contact:
            on = 1.0 if levitated else 0.0
            y = np.array([math.atan2(z.imag, z.real), (z.conjugate() * v).imag, psi, spin, race, 0.0])
            # a race at rest is held by its bearing's static friction while the contact's torque m R_b |q|
            # stays within T_b (then the stator is fixed); otherwise it turns the way of that torque
            inv_race_c = inv_race
            torque_c = race_torque
            held = False
            if inv_race > 0.0 and race_torque > 0.0:
                if race != 0.0:
                    torque_c = math.copysign(race_torque, race)
                else:
                    p = _contact_params(mass, cr, ecc, radius, mu, on * kx, on * ky, on * cx, on * cy, by * cr,
                                        inv_p, 0.0, race_torque, race_coef)
                    mode, sgn = _contact_mode(y, p, switched)
                    q_held = contact_rates(y, p, mode == 1, sgn)[2]
                    if mass * race_radius * abs(q_held) <= race_torque:
                        inv_race_c = 0.0
                        held = True  # p, mode and sgn are those of the held race
                    else:
                        torque_c = -math.copysign(race_torque, q_held)
            if not held:
                p = _contact_params(mass, cr, ecc, radius, mu, on * kx, on * ky, on * cx, on * cy, by * cr, inv_p,
                                    inv_race_c, torque_c, race_coef)
                mode, sgn = _contact_mode(y, p, switched)
            switched = False
            t0 = t
            if mode >= 0:
                rolling = mode == 1
                if rolling:
                    y[1] = rolling_whirl_rate(radius, cr, spin, race_radius, race)
                rest = rest_energy if inv_p > 0.0 else 0.0
                if rolling and fast_rolling_applies(p):
                    code_c, t1, y1, n_max = rolling_fixed_phase(y, t, t + horizon, p, rest)
                else:
                    code_c, t1, y1, n_max = contact_phase(y, t, t + horizon, p, rolling, sgn, rest)
                kind = 1.0 if rolling else (0.0 if sgn > 0.0 else 2.0)
                if n_ct > 0 and contacts[n_ct - 1, 1] == t0 and contacts[n_ct - 1, 2] == kind and t1 > t0:
                    # the same phase goes on (after the integrator's step budget, or the failure): one interval
                    t_a = contacts[n_ct - 1, 0]
                    contacts[n_ct - 1, 4] = (contacts[n_ct - 1, 4] * (t0 - t_a) + (y1[0] - y[0])) / (t1 - t_a)
                    contacts[n_ct - 1, 1] = t1
                    contacts[n_ct - 1, 3] = max(contacts[n_ct - 1, 3], n_max * mass)
                elif t1 > t0:
                    crow[0] = t0
                    crow[1] = t1
                    crow[2] = kind
                    crow[3] = n_max * mass
                    crow[4] = (y1[0] - y[0]) / (t1 - t0)
                    contacts, n_ct = push_row(contacts, n_ct, crow)
                stalls = stalls + 1 if t1 == t0 else 0
                # a phase that spends the integrator's whole step budget on next to no time is crawling
                crawls = crawls + 1 if code_c == C_STEP_LIMIT and t1 - t0 < CRAWL_TIME * (1.0 + t0) else 0
                if stalls > MAX_STALLS or crawls > MAX_CRAWLS:
                    status = FAILED
                    break
                t = t1
                e1 = complex(math.cos(y1[0]), math.sin(y1[0]))
                z = e1
                v = 1j * y1[1] * e1
                psi, spin, race = y1[2], y1[3], y1[4]
                dissipated += y1[5]
                if code_c == C_REST:
                    status = AT_REST
                    break
                if code_c == C_RACE:
                    # the race stops (then its bearing holds it, or it turns back), or its bearing slips
                    if inv_race_c > 0.0:
                        race = 0.0
                    switched = rolling
                    continue
                if code_c == C_END or code_c == C_STEP_LIMIT:
                    if t >= t_end:
                        break
                    # the bearing failed (the contact goes on with the new forces), or the phase goes on
                    # after the integrator's step budget
                    continue
                if code_c != C_LIFTOFF:
                    switched = True
                    continue  # a switch between sliding and rolling
            in_contact = False
            liftoff = True
            on_boundary = True
            continue
        flight = make_flight(z, v, spin, psi, gx, w2x, gy, w2y, by, ecc / cr)
        if moving_stator:
            stator = make_stator_flight(zb, vb, stator_cx * inv_ms, stator_kx * inv_ms, stator_cy * inv_ms,
                                        stator_ky * inv_ms)
        # a compliant run may start in contact (a penetration): its episode starts at once
        penetrated = compliant and abs(z - zb) > 1.0 + BOUNDARY_TOL
        if penetrated:
            code, s = CROSSING, 0.0
        else:
            code, s = next_impact(flight, spin, horizon, on_boundary, liftoff, stator)
        liftoff = False
        resumed = False
        if code == ITERATION_LIMIT:
            if not s > 0.0:
                status = FAILED
                break
            # the search's step budget ran out on a long flight (a levitated whirl of many periods): [0, s]
            # is certified free of crossings, so the flight goes on from z(s) as a new one
            code = NO_CROSSING
            resumed = True
        if code == STUCK and compliant:
            # pressed outwards on the wall: an episode starts at once
            code = CROSSING
            s = 0.0
        if code == STUCK:
            if not follow_contact:
                status = CHATTER
                break
            stalls += 1
            if stalls > MAX_STALLS:
                status = FAILED
                break
            w = complex_quotient(z.conjugate() * v, abs(z))
            v = complex_quotient(z, abs(z)) * complex(0.0, w.imag)
            in_contact = True
            continue
        z, v = flight_state(flight, spin, s)
        if moving_stator:
            e_stator = _stator_energy(zb, vb, cr, stator_mass, stator_kx, stator_ky)
            zb, vb = flight_state(stator, 0.0, s)
            if stator_cx > 0.0 or stator_cy > 0.0:  # its support's damping (>= 0 but for rounding)
                dissipated += max(0.0, e_stator - _stator_energy(zb, vb, cr, stator_mass, stator_kx, stator_ky))
        if code == CROSSING or resumed:
            t = t + s
        else:  # the flight reached its horizon: the failure (exactly at t_fail) or the end
            t = t_fail if levitated and t_fail < t_end else t_end
        psi = psi + spin * s
        if race_inertia > 0.0:
            race_after = race_spin(race, s, race_inertia, race_torque, race_coef)
            dissipated += 0.5 * race_inertia * (race * race - race_after * race_after)  # the race's drag
            race = race_after
        if code == NO_CROSSING:
            on_boundary = abs(abs(z - zb) - 1.0) <= BOUNDARY_TOL
            continue
        normal = complex_quotient(z - zb, abs(z - zb))
        if not penetrated:
            z = zb + normal
        zs = z * cr
        vs = v * cr
        if compliant:
            w = normal.conjugate() * (vs - vb * cr)  # the velocity relative to the stator
            t0 = t
            code_e, t, y_e, f_max, d_max, kind, calls = _episode(
                t, zs, vs, psi, spin, race, max(w.real, 0.0), mass, cr, ecc, radius, mu, kx, ky, cx, cy, fs, g,
                inv_polar, inv_race, race_torque, race_coef, t_fail, t_end, contact_stiffness, contact_exponent,
                contact_chi, contact_v_floor, contact_tol, rest_energy, max(max_events - events, 1), stator_p,
                zb * cr, vb * cr)
            events += calls - 1
            z_end = complex(y_e[0], y_e[1])
            v_end = complex(y_e[2], y_e[3])
            zb_end = complex(y_e[11], y_e[12])
            vb_end = complex(y_e[13], y_e[14])
            n_end = complex_quotient(z_end - zb_end, abs(z_end - zb_end))
            row[0] = t0
            row[1] = point_angle(normal)
            row[2] = w.real
            row[3] = y_e[8]
            row[4] = y_e[9]
            row[5] = spin
            row[6] = y_e[5]
            row[7] = y_e[6]
            row[8] = zs.real
            row[9] = zs.imag
            row[10] = v_end.real
            row[11] = v_end.imag
            row[12] = y_e[7]
            row[13] = surface_velocity(w.imag, radius, spin, race_radius, race)
            row[14] = t - t0
            row[15] = f_max
            row[16] = d_max
            # normal velocity out over in; nan while the episode goes on at the stop
            row[17] = -(n_end.conjugate() * (v_end - vb_end)).real / w.real \
                if code_e == E_SEPARATED and w.real > 0.0 else math.nan
            row[18] = kind
            impacts, n_imp = push_row(impacts, n_imp, row)
            if t - t0 > LASTING_CONTACT * impact_duration(mass, max(w.real, contact_v_floor), contact_stiffness,
                                                          contact_exponent, contact_duration_factor):
                crow[0] = t0
                crow[1] = t
                crow[2] = kind
                crow[3] = f_max
                crow[4] = (y_e[10] - math.atan2(normal.imag, normal.real)) / (t - t0)
                contacts, n_ct = push_row(contacts, n_ct, crow)
            dissipated += y_e[7]
            zb = complex_quotient(zb_end, cr)
            vb = complex_quotient(vb_end, cr)
            z = zb + n_end if code_e == E_SEPARATED else complex_quotient(z_end, cr)
            v = complex_quotient(v_end, cr)
            psi, spin, race = y_e[4], y_e[5], y_e[6]
            on_boundary = True
            if code_e == E_REST:
                status = AT_REST
                break
            if code_e != E_SEPARATED and t < t_end:
                status = MAX_EVENTS
                break
            continue
        v_plus, spin_plus, race_plus, v_n, v_rel, p_n, p_t = _impact(
            zs, vs, spin, race, mass, d, mu, radius, inv_p, race_radius, inv_race)
        # the loss of kinetic energy (with the motor's work where the speed is held) from the impulses, not as
        # a difference of energies that a large spin energy would swamp (MODEL.md §7)
        lost = impact_dissipation(mass, d, v_n, v_rel, p_t,
                                  effective_mass_factor(mass, radius, inv_p, race_radius, inv_race))
        dissipated += lost
        row[0] = t
        row[1] = point_angle(z)
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
        row[12] = lost
        row[13] = v_rel
        impacts, n_imp = push_row(impacts, n_imp, row)
        v = complex_quotient(v_plus, cr)
        spin = spin_plus
        race = race_plus
        on_boundary = True
        if v_n < chatter_v or v_n < chatter_rel * abs(vs):
            if not follow_contact:
                status = CHATTER
                break
            # the impacts accumulate: continuous contact from here with the normal velocity dropped
            w = z.conjugate() * v
            v = z * complex(0.0, w.imag)
            in_contact = True
    state = np.array([min(t, t_end), z.real * cr, z.imag * cr, v.real * cr, v.imag * cr, spin, race, dissipated,
                      zb.real * cr, zb.imag * cr, vb.real * cr, vb.imag * cr])
    return impacts[:n_imp].copy(), contacts[:n_ct].copy(), status, min(t, t_end), state
