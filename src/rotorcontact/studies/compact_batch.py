"""The batch kernel's items without allocating: what the batch kernel's threads and a GPU thread run.

The simulator's kernel (`rotorcontact.simulation.simulator.simulate_into`) grows its tables as it goes. A
GPU thread cannot allocate, and the batch reads little of those tables, so these functions run the same
item with fixed buffers:

* the impacts of a run are kept in a *ring* of ``2 R`` rows (`RING`), each written at ``i % R`` and at
  ``i % R + R``, so that the last ``min(n, R)`` impacts are always contiguous; R is larger than the
  3 `MAX_PERIOD_IMPACTS` + 1 impacts that period detection reads;
* the recorded section is written in the item's own section rows as a ring and put in order at the end;
* of the contact phases only what the batch kernel reads is kept: the last phase's end state, and for
  the window the number of phases, their time, and the latest end of any and of those not sliding
  forwards; sliding phases take the simulator's own steps (`rotorcontact.simulation.contact.slide_attempt`)
  without recording them.

They take every step of the simulator (`rotorcontact.simulation.simulator.simulate_into`): its flights,
impacts, test for impacts that accumulate, contact phases, switches and lift-offs, and the batch kernel's
transient, window, final state and classification, in the same order on the same numbers, so an item
they finish has the batch kernel's results bit for bit on the same processor. One case is left to the
batch kernel: a window whose contact phases end out of order or after its stop time (a phase that
overshoots its end time by rounding), where what is kept cannot give the kernel's summary exactly. Such
an item is *deferred*, and is computed again through the simulator's kernel
(`rotorcontact.studies.batch._run_steps`, `rotorcontact.studies.cuda_batch`).

Its functions are compiled kernels and take their arguments unchecked; `simulate_batch` and the
studies check theirs.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..interpreted import complex_quotient
from ..model.contact_law import normal_force
from ..simulation.contact import (
    ACCUMULATION,
    LIFTOFF,
    ROLLING,
    SLIDE_BACKWARD,
    SLIDE_FORWARD,
    TO_ROLLING,
    TO_SLIDE_FORWARD,
    roll,
    rolled_angle,
    slide_unrecorded,
)
from ..model.flow import equilibrium_point
from ..model.impact_law import polar_velocity
from ..simulation.motion import FAILED_REGIME, MAX_PERIOD_IMPACTS, MIN_IRREGULAR, NO_CONTACT, REPEAT_TOL, WINDOW
from ..simulation.roots import ITERATION_LIMIT, NO_CROSSING, STUCK
from ..simulation.simulator import (
    BOUNDARY_TOL,
    COMPLETED,
    FAILED,
    MAX_EVENTS,
    NO_MODE,
    RDOT_MIN,
    accumulation_point,
    after_phase,
    chain_step,
    contact_mode,
    contact_start,
    flight_event,
    liftoff_state,
)
from .window import (
    NSUM,
    contact_end_state,
    detect_period_rows,
    ends_in_contact,
    fill_summary,
    flight_final_state,
    never_touches,
    regime_of,
)

__all__ = ["RING", "compact_lane", "compact_lanes", "ring_buffer"]

#: Impacts held by the ring of a run: more than the 3 MAX_PERIOD_IMPACTS + 1 that period detection reads.
RING = 4 * MAX_PERIOD_IMPACTS


@njit(cache=True)
def ring_buffer() -> np.ndarray:
    """A ring for one thread on the CPU (the GPU kernel makes its own in local memory)."""
    return np.empty((2 * RING, 4))


@njit(cache=True)
def _ring_view(ring, n):
    """The last min(n, RING) impacts of the ring, in order, and how many they are."""
    rows = min(n, RING)
    start = (n - rows) % RING
    return ring[start : start + rows], rows


@njit(cache=True)
def _keep(ring, sec, n, t, theta, rd, td):
    """Store impact number ``n`` (from 0) in the ring and, if there is one, the section ring."""
    i = n % RING
    _put(ring, i, t, theta, rd, td)
    _put(ring, i + RING, t, theta, rd, td)
    m = sec.shape[0]
    if m > 0:
        _put(sec, n % m, t, theta, rd, td)


@njit(cache=True)
def _put(rows, i, t, theta, rd, td):
    rows[i, 0] = t
    rows[i, 1] = theta
    rows[i, 2] = rd
    rows[i, 3] = td


@njit(cache=True)
def _reverse_rows(a, lo, hi):
    while lo < hi:
        for c in range(a.shape[1]):
            x = a[lo, c]
            a[lo, c] = a[hi, c]
            a[hi, c] = x
        lo += 1
        hi -= 1


@njit(cache=True)
def _unroll(sec, n):
    """Put the section ring in order (oldest kept impact first) after ``n`` impacts."""
    m = sec.shape[0]
    if n <= m:
        return
    first = n % m
    if first == 0:
        return
    # rotate left by ``first``: three reversals
    _reverse_rows(sec, 0, first - 1)
    _reverse_rows(sec, first, m - 1)
    _reverse_rows(sec, 0, m - 1)


@njit(cache=True)
def _contact_phase_seen(kind, t0, t1, n_ct, contact_time, end_max, end_not_forward):
    """Add a contact phase (not an accumulation of impacts) to what a window reads of them.

    Returns (n_ct, contact_time, end_max, end_not_forward): their number, their time (`batch._run_item`'s
    sum, where no phase ends after the run), the latest end of any, and of any not sliding forwards.
    """
    if kind != SLIDE_FORWARD:
        end_not_forward = max(end_not_forward, t1)
    return n_ct + 1, contact_time + (t1 - t0), max(end_max, t1), end_not_forward


@njit(cache=True)
def compact_run(gamma, omega, rho, mu, d, phi, r_ratio, u0, du0, t_end, max_events, chatter_tol, chatter_rdot,
                chatter_height, chatter_dt, ring, sec):
    """`rotorcontact.simulation.simulator.simulate_into` (continuing at chatter) without its tables.

    The same events in the same order: flights, impacts, touches, accumulations of impacts and the
    contact phases that follow them (sliding, rolling, lift-off). Impacts go to ``ring`` and ``sec``
    (`_keep`); of the contact phases it keeps what the batch kernel reads: the last phase, for the state
    where the run stopped, and for the window their number, time, the latest end of any, and the kind
    and end of the last one that is not an accumulation of impacts.

    Returns (status, t_stop, n_imp, n_rows, u, du, kind, t_last, contacts): how the run ended, its
    impacts, its rows of flights and contact phases, the state where it stopped and what it was doing
    there (`rotorcontact.studies.batch._final_state`), the time of its last impact (-inf if none), and
    ``contacts`` = (n_ct, contact_time, end_max, end_last, kind_last, end_not_forward) of the phases
    that are not accumulations (`_contact_phase_seen`; ends -inf and kind -1 where there are none).
    """
    k = equilibrium_point(gamma, omega, rho, phi)
    roll_dot = -(1.0 + r_ratio)
    status = COMPLETED
    t = 0.0
    u = u0
    du = du0
    on_boundary = abs(abs(u0) - 1.0) <= BOUNDARY_TOL
    if on_boundary:
        u = complex_quotient(u0, abs(u0))
    t_fl, u_fl, du_fl = t, u, du
    n_fl = 1
    n_imp = 0
    t_last = -math.inf
    liftoff = np.bool_(False)  # as in the simulator: one specialisation of next_crossing
    in_contact = False
    theta_c = 0.0
    thetadot_c = 0.0
    events = 0
    stalls = 0
    short_before = False
    chain = False
    prev_rd = 0.0
    prev_t = prev_th = prev_td = 0.0
    next_mode = NO_MODE
    # the last contact row of the simulator's table (any kind) and its last path row
    n_rows_ct = 0
    c_start = c_end = c_theta = c_thetadot = 0.0
    c_kind = -1
    # the phases that are not accumulations of impacts
    n_ct = 0
    contact_time = 0.0
    end_max = end_last = end_not_forward = -math.inf
    kind_last = -1
    while True:
        events += 1
        if events > max_events:
            status = MAX_EVENTS
            break
        if not in_contact:
            leaves = on_boundary and n_imp == 0 and events == 1 and polar_velocity(u, du)[0] > RDOT_MIN
            code, tau, touch, ui, dv, du_plus, rd, td, rdp, tdp, vrel, pn, pt, theta = flight_event(
                u, du, k, gamma, omega, d, mu, r_ratio, t_end - t, on_boundary, liftoff, leaves
            )
            liftoff = False
            if code == NO_CROSSING:
                break
            if code == ITERATION_LIMIT:
                status = FAILED
                t = t + tau
                break
            if code == STUCK:
                theta_c, thetadot_c = contact_start(u, du)
                in_contact = True
                continue
            t = t + tau
            if touch:
                chain = False
                u = ui
                du = dv
                on_boundary = True
                t_fl, u_fl, du_fl = t, u, du
                n_fl += 1
                continue
            n_force = normal_force(theta, tdp, omega, rho, phi)
            _keep(ring, sec, n_imp, t, theta, rd, td)
            n_imp += 1
            t_last = t
            u = ui
            du = du_plus
            on_boundary = True
            t_fl, u_fl, du_fl = t, u, du
            n_fl += 1
            if n_force <= 0.0:
                chain = False
                short_before = False
                continue
            accumulates, converged, short_before, t_a, th_a, td_a, e_t, e_th, e_td = chain_step(
                t, theta, rd, rdp, tdp, n_force, chain, prev_rd, prev_t, prev_th, prev_td, short_before, gamma, rho,
                mu, d, phi, r_ratio, chatter_tol, chatter_rdot, chatter_height, chatter_dt
            )
            if accumulates:
                t_acc, theta_acc, td_acc = accumulation_point(converged, t, theta, rd, tdp, n_force, t_a, th_a,
                                                              td_a, e_t, e_th, e_td, t_end, gamma, rho, mu, d, phi,
                                                              r_ratio)
                if t_acc > t:
                    n_rows_ct += 1
                    c_start, c_end, c_kind, c_theta, c_thetadot = t, t_acc, ACCUMULATION, theta_acc, td_acc
                theta_c = theta_acc
                thetadot_c = td_acc
                t = t_acc
                chain = False
                if t >= t_end:
                    break
                in_contact = True
                next_mode = NO_MODE
                continue
            chain = True
            prev_rd = rd
            prev_t = t_a
            prev_th = th_a
            prev_td = td_a
            continue
        # continuous contact from (theta_c, thetadot_c) at t, as in the simulator
        mode, thetadot_c = contact_mode(theta_c, thetadot_c, next_mode, gamma, omega, rho, mu, phi, r_ratio)
        t_start = t
        if mode == LIFTOFF:
            code = LIFTOFF
        else:
            if mode == TO_ROLLING:
                kind = ROLLING
                code, t, theta_end = roll(theta_c, t, t_end, gamma, omega, rho, mu, phi, r_ratio)
                c_theta = rolled_angle(theta_c, roll_dot, t_start, t)
                theta_c = theta_end
                thetadot_c = roll_dot
            else:
                sgn = 1.0 if mode == TO_SLIDE_FORWARD else -1.0
                kind = SLIDE_FORWARD if sgn > 0.0 else SLIDE_BACKWARD
                code, t, theta_c, thetadot_c = slide_unrecorded(theta_c, thetadot_c, t, t_end, sgn, gamma, omega,
                                                                rho, mu, phi, r_ratio)
                c_theta = theta_c
            n_rows_ct += 1
            c_start, c_end, c_kind, c_thetadot = t_start, t, kind, thetadot_c
            n_ct, contact_time, end_max, end_not_forward = _contact_phase_seen(kind, t_start, t, n_ct, contact_time,
                                                                               end_max, end_not_forward)
            end_last, kind_last = t, kind
        stop, status, reason, stalls, next_mode = after_phase(code, t, t_start, stalls)
        if stop:
            break
        if code == LIFTOFF:
            u, du = liftoff_state(theta_c, thetadot_c)
            in_contact = False
            on_boundary = True
            liftoff = True
            short_before = False
            chain = False
            t_fl, u_fl, du_fl = t, u, du
            n_fl += 1
    t_stop = t_end if status == COMPLETED else min(t, t_end)
    if n_rows_ct > 0 and ends_in_contact(n_fl, t_fl, c_start, c_end):
        u, du = contact_end_state(c_theta, c_thetadot)
        kind = c_kind
    else:
        u, du = flight_final_state(t_fl, u_fl, du_fl, t_stop, gamma, omega, rho, phi)
        kind = -1
    contacts = (n_ct, contact_time, end_max, end_last, kind_last, end_not_forward)
    return status, t_stop, n_imp, n_fl + n_rows_ct, u, du, kind, t_last, contacts


@njit(cache=True)
def _compact_transient(p, u, du, n_transient, t_transient, settle, c_tol, c_rdot, c_height, c_dt, ring, no_sec):
    """`rotorcontact.studies.batch._transient` without tables: (u, du, status, duration, impacts)."""
    gamma, omega, rho, mu, d, phi, rr = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    if n_transient <= 0:
        return u, du, COMPLETED, 0.0, 0
    if settle <= 0:
        status, t_stop, n_imp, n_rows, u, du, kind, t_last, contacts = compact_run(
            gamma, omega, rho, mu, d, phi, rr, u, du, t_transient, n_transient, c_tol, c_rdot, c_height, c_dt,
            ring, no_sec
        )
        return u, du, status, t_stop, n_imp
    events_left = n_transient
    time_left = t_transient
    t_total = 0.0
    n_total = 0
    status = COMPLETED
    while events_left > 0 and time_left > 0.0:
        if never_touches(u, du, gamma, omega, rho, phi):
            break
        status, t_stop, n_imp, n_rows, u, du, kind, t_last, contacts = compact_run(
            gamma, omega, rho, mu, d, phi, rr, u, du, time_left, min(settle, events_left), c_tol, c_rdot,
            c_height, c_dt, ring, no_sec
        )
        events_left -= max(1, n_rows)
        time_left -= t_stop
        t_total += t_stop
        n_total += n_imp
        if status != MAX_EVENTS:
            break
        last, rows = _ring_view(ring, n_imp)
        per_p, period = detect_period_rows(last, rows, MAX_PERIOD_IMPACTS, REPEAT_TOL)
        if per_p > 0:
            break
    return u, du, status, t_total, n_total


@njit(cache=True)
def compact_item(p, u0, du0, n_transient, n_record, t_transient, t_record, settle, c_tol, c_rdot, c_height, c_dt,
                 ring, sec, summ):
    """`rotorcontact.studies.batch._run_item` without tables: (deferred, u, du), filling ``sec`` and ``summ``.

    ``deferred`` (``sec`` and ``summ`` then unfinished) where what this form keeps of the window's contact
    phases cannot give the batch kernel's summary exactly: a phase that ends after the window's stop time,
    or an earlier phase that ends later than the last one (both only where a phase overshoots its end
    time by rounding).
    """
    gamma, omega, rho, mu, d, phi, rr = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    no_sec = sec[0:0]
    u, du, tr_status, t_tr, tr_impacts = _compact_transient(
        p, u0, du0, n_transient, t_transient, settle, c_tol, c_rdot, c_height, c_dt, ring, no_sec
    )
    for i in range(sec.shape[0]):
        for c in range(4):
            sec[i, c] = math.nan
    if tr_status == FAILED:
        fill_summary(summ, FAILED, tr_status, FAILED_REGIME, 0, math.nan, 0, 0, 0.0, -1, u, du, t_tr, 0.0, tr_impacts)
        return False, u, du
    if settle > 0 and never_touches(u, du, gamma, omega, rho, phi):
        u, du = flight_final_state(0.0, u, du, t_record, gamma, omega, rho, phi)
        fill_summary(summ, COMPLETED, tr_status, NO_CONTACT, 0, math.nan, 0, 0, 0.0, -1, u, du, t_tr, t_record,
                     tr_impacts)
        return False, u, du
    status, t_stop, n_imp, n_rows, u, du, kind, t_last, contacts = compact_run(
        gamma, omega, rho, mu, d, phi, rr, u, du, t_record, n_record, c_tol, c_rdot, c_height, c_dt, ring, sec
    )
    n_ct, contact_time, end_max, end_last, kind_last, end_not_forward = contacts
    t_win = t_stop * (1.0 - WINDOW)
    # `batch._classify_window` reads the phases that end after t_win: whether there are any, the kind of the
    # last, and whether all slide forwards; `batch._run_item` sums min(end, t_stop) - start over all
    late_contacts = end_max > t_win
    if end_max > t_stop or (late_contacts and not end_last > t_win):
        return True, u0, du0
    _unroll(sec, n_imp)
    last, rows = _ring_view(ring, n_imp)
    late = n_imp > 0 and t_last >= t_win
    regime, per_p, period = regime_of(status, late, 1 if late_contacts else 0, kind_last if late_contacts else -1,
                                      not end_not_forward > t_win, last, rows, n_imp, MAX_PERIOD_IMPACTS, REPEAT_TOL,
                                      MIN_IRREGULAR)
    fill_summary(summ, status, tr_status, regime, per_p, period, n_imp, n_ct, contact_time, kind, u, du, t_tr, t_stop,
                 tr_impacts)
    return False, u, du


@njit(cache=True)
def compact_lane(lane, params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle, c_tol, c_rdot,
                 c_height, c_dt, sections, summary, ring):
    """The steps of one lane; returns (step, u, du): the first deferred step and its start state.

    ``step`` is -1 when every step was finished here.
    """
    u = u0[lane, 0]
    du = du0[lane, 0]
    for s in range(params.shape[1]):
        if not carry:
            u = u0[lane, s]
            du = du0[lane, s]
        deferred, u_end, du_end = compact_item(params[lane, s], u, du, n_transient, n_record, t_transient, t_record,
                                               settle, c_tol, c_rdot, c_height, c_dt, ring, sections[lane, s],
                                               summary[lane, s])
        if deferred:
            return s, u, du
        u = u_end
        du = du_end
    return -1, u, du


@njit(cache=True)
def compact_lanes(params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle, c_tol, c_rdot,
                  c_height, c_dt, sections, summary, deferred, start_u, start_du):
    """`compact_lane` for every lane on the CPU, one after the other (a reference for the GPU kernel)."""
    ring = ring_buffer()
    for lane in range(params.shape[0]):
        s, u, du = compact_lane(lane, params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle,
                                c_tol, c_rdot, c_height, c_dt, sections, summary, ring)
        deferred[lane] = s
        start_u[lane] = u
        start_du[lane] = du


assert RING >= 3 * MAX_PERIOD_IMPACTS + 1 and NSUM == 16
