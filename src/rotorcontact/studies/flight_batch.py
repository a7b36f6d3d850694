"""The batch kernel's items in flight and impacts, without allocating: the code a GPU thread runs.

`rotorcontact.studies.batch` runs every item through the simulator's kernel, which grows its tables as
it goes. A GPU thread cannot allocate, so these functions run the same item with fixed buffers:

* the impacts of a run are kept in a *ring* of ``2 R`` rows (`RING`), each written at ``i % R`` and at
  ``i % R + R``, so that the last ``min(n, R)`` impacts are always contiguous; R is larger than the
  3 `MAX_PERIOD_IMPACTS` + 1 impacts that period detection reads;
* the recorded section is written in the item's own section rows as a ring and put in order at the end.

They take every step of the simulator's flights (`rotorcontact.simulation.simulator.flight_event`), its
test for impacts that accumulate (`rotorcontact.simulation.simulator.chain_step`), and the batch kernel's
transient, window, final state and classification, in the same order on the same numbers, so an item
they finish has the batch kernel's results bit for bit on the same processor. Where the simulator would
enter continuous contact (impacts that accumulate, or a start pressed onto the stator), they stop and
say so: such an item is *deferred*, and is computed again by the batch kernel itself
(`rotorcontact.studies.cuda_batch`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..interpreted import complex_quotient
from ..model.contact_law import normal_force
from ..model.flow import equilibrium_point
from ..model.impact_law import polar_velocity
from ..simulation.motion import FAILED_REGIME, MAX_PERIOD_IMPACTS, MIN_IRREGULAR, NO_CONTACT, REPEAT_TOL, WINDOW
from ..simulation.roots import ITERATION_LIMIT, NO_CROSSING, STUCK
from ..simulation.simulator import (
    BOUNDARY_TOL,
    COMPLETED,
    FAILED,
    MAX_EVENTS,
    RDOT_MIN,
    chain_step,
    flight_event,
)
from .window import NSUM, detect_period_rows, fill_summary, flight_final_state, never_touches, regime_of

__all__ = ["RING", "flight_lane", "flight_lanes", "ring_buffer"]

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
def flight_run(gamma, omega, rho, mu, d, phi, r_ratio, u0, du0, t_end, max_events, chatter_tol, chatter_rdot,
               chatter_height, chatter_dt, ring, sec):
    """`rotorcontact.simulation.simulator.simulate_kernel` (continuing at chatter) for a run in flight.

    Returns (deferred, status, t_stop, n_imp, n_flights, u, du, t_last): ``deferred`` when the
    simulator would enter continuous contact (the run is abandoned there); otherwise how the run ended,
    its impacts and flights, the state where it stopped (`rotorcontact.studies.batch._final_state`) and the
    time of its last impact (-inf if none).
    """
    k = equilibrium_point(gamma, omega, rho, phi)
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
    events = 0
    short_before = False
    chain = False
    prev_rd = 0.0
    prev_t = prev_th = prev_td = 0.0
    while True:
        events += 1
        if events > max_events:
            status = MAX_EVENTS
            break
        leaves = on_boundary and n_imp == 0 and events == 1 and polar_velocity(u, du)[0] > RDOT_MIN
        code, tau, touch, ui, dv, du_plus, rd, td, rdp, tdp, vrel, pn, pt, theta = flight_event(
            u, du, k, gamma, omega, d, mu, r_ratio, t_end - t, on_boundary, liftoff, leaves
        )
        if code == NO_CROSSING:
            break
        if code == ITERATION_LIMIT:
            status = FAILED
            t = t + tau
            break
        if code == STUCK:
            return True, status, t, n_imp, n_fl, u, du, t_last
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
            return True, status, t, n_imp, n_fl, u, du, t_last
        chain = True
        prev_rd = rd
        prev_t = t_a
        prev_th = th_a
        prev_td = td_a
    t_stop = t_end if status == COMPLETED else min(t, t_end)
    u, du = flight_final_state(t_fl, u_fl, du_fl, t_stop, gamma, omega, rho, phi)
    return False, status, t_stop, n_imp, n_fl, u, du, t_last


@njit(cache=True)
def _flight_transient(p, u, du, n_transient, t_transient, settle, c_tol, c_rdot, c_height, c_dt, ring, no_sec):
    """`rotorcontact.studies.batch._transient` in flight: (deferred, u, du, status, duration, impacts)."""
    gamma, omega, rho, mu, d, phi, rr = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    if n_transient <= 0:
        return False, u, du, COMPLETED, 0.0, 0
    if settle <= 0:
        deferred, status, t_stop, n_imp, n_fl, u, du, t_last = flight_run(
            gamma, omega, rho, mu, d, phi, rr, u, du, t_transient, n_transient, c_tol, c_rdot, c_height, c_dt,
            ring, no_sec
        )
        return deferred, u, du, status, t_stop, n_imp
    events_left = n_transient
    time_left = t_transient
    t_total = 0.0
    n_total = 0
    status = COMPLETED
    while events_left > 0 and time_left > 0.0:
        if never_touches(u, du, gamma, omega, rho, phi):
            break
        deferred, status, t_stop, n_imp, n_fl, u, du, t_last = flight_run(
            gamma, omega, rho, mu, d, phi, rr, u, du, time_left, min(settle, events_left), c_tol, c_rdot,
            c_height, c_dt, ring, no_sec
        )
        if deferred:
            return True, u, du, status, t_total, n_total
        events_left -= max(1, n_fl)
        time_left -= t_stop
        t_total += t_stop
        n_total += n_imp
        if status != MAX_EVENTS:
            break
        last, rows = _ring_view(ring, n_imp)
        per_p, period = detect_period_rows(last, rows, MAX_PERIOD_IMPACTS, REPEAT_TOL)
        if per_p > 0:
            break
    return False, u, du, status, t_total, n_total


@njit(cache=True)
def flight_item(p, u0, du0, n_transient, n_record, t_transient, t_record, settle, c_tol, c_rdot, c_height, c_dt,
                ring, sec, summ):
    """`rotorcontact.studies.batch._run_item` in flight: (deferred, u, du), filling ``sec`` and ``summ``."""
    gamma, omega, rho, mu, d, phi, rr = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    no_sec = sec[0:0]
    deferred, u, du, tr_status, t_tr, tr_impacts = _flight_transient(
        p, u0, du0, n_transient, t_transient, settle, c_tol, c_rdot, c_height, c_dt, ring, no_sec
    )
    if deferred:
        return True, u, du
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
    deferred, status, t_stop, n_imp, n_fl, u, du, t_last = flight_run(
        gamma, omega, rho, mu, d, phi, rr, u, du, t_record, n_record, c_tol, c_rdot, c_height, c_dt, ring, sec
    )
    if deferred:
        return True, u, du
    _unroll(sec, n_imp)
    last, rows = _ring_view(ring, n_imp)
    late = n_imp > 0 and t_last >= t_stop * (1.0 - WINDOW)
    regime, per_p, period = regime_of(status, late, 0, -1, True, last, rows, n_imp, MAX_PERIOD_IMPACTS, REPEAT_TOL,
                                      MIN_IRREGULAR)
    fill_summary(summ, status, tr_status, regime, per_p, period, n_imp, 0, 0.0, -1, u, du, t_tr, t_stop, tr_impacts)
    return False, u, du


@njit(cache=True)
def flight_lane(lane, params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle, c_tol, c_rdot,
                c_height, c_dt, sections, summary, ring):
    """The steps of one lane in flight; returns (step, u, du): the first deferred step and its start state.

    ``step`` is -1 when every step was finished here.
    """
    u = u0[lane, 0]
    du = du0[lane, 0]
    for s in range(params.shape[1]):
        if not carry:
            u = u0[lane, s]
            du = du0[lane, s]
        deferred, u_end, du_end = flight_item(params[lane, s], u, du, n_transient, n_record, t_transient, t_record,
                                              settle, c_tol, c_rdot, c_height, c_dt, ring, sections[lane, s],
                                              summary[lane, s])
        if deferred:
            return s, u, du
        u = u_end
        du = du_end
    return -1, u, du


@njit(cache=True)
def flight_lanes(params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle, c_tol, c_rdot,
                 c_height, c_dt, sections, summary, deferred, start_u, start_du):
    """`flight_lane` for every lane on the CPU, one after the other (a reference for the GPU kernel)."""
    ring = ring_buffer()
    for lane in range(params.shape[0]):
        s, u, du = flight_lane(lane, params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle,
                               c_tol, c_rdot, c_height, c_dt, sections, summary, ring)
        deferred[lane] = s
        start_u[lane] = u
        start_du[lane] = du


assert RING >= 3 * MAX_PERIOD_IMPACTS + 1 and NSUM == 16
