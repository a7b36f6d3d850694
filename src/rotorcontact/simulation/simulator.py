"""The hybrid simulator: exact free flight, guaranteed impact location, reset, chatter and contact.

Data flows one way: parameters -> exact flow (`flow`) -> impact location
(`roots`) -> reset (`reset`) -> continuous contact when impacts accumulate
(`contact`) -> `Trajectory`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit

from ..errors import ParameterError
from ..interpreted import call_kernel, complex_quotient
from ..model.flow import equilibrium_point, has_regular_equilibrium, propagate
from ..model.validation import MAX_COUNT, check_int, check_machine, check_machine_params, check_params, complex_value
from ..model.params import MAX_T_END, Machine, Parameters, check_range, check_velocity
from ..model.impact_law import apply_reset, polar_velocity, relative_velocity
from ..model.angles import point_angle, wrap_angle
from .tables import grow_rows, push_row
from ..model.contact_law import accumulation_tail, free_tangential, normal_force
from .contact import (
    ACCUMULATION,
    LIFTOFF,
    ROLLING,
    SLIDE_BACKWARD,
    SLIDE_FORWARD,
    STEP_LIMIT,
    TO_ROLLING,
    TO_SLIDE_BACKWARD,
    TO_SLIDE_FORWARD,
    END,
    roll,
    rolled_angle,
    slide,
    stick_or_slip,
)
from .roots import CROSSING, ITERATION_LIMIT, NO_CROSSING, STUCK, next_crossing
from .trajectory import COLUMNS, Trajectory

__all__ = ["simulate", "STATUS_NAMES"]

COMPLETED = 0
CHATTER = 1
MAX_EVENTS = 2
FAILED = 3
STATUS_NAMES = {COMPLETED: "completed", CHATTER: "chatter", MAX_EVENTS: "max-events", FAILED: "failed"}
#: The criteria for an accumulation of impacts (chatter) and their defaults in `simulate`, in the order of
#: `simulate_kernel`'s arguments.
CHATTER_DEFAULTS = {"chatter_tol": 1e-11, "chatter_rdot": 1e-5, "chatter_height": 0.0, "chatter_dt": 1e-3}

NCOL = len(COLUMNS)
BOUNDARY_TOL = 1e-12
RDOT_MIN = 1e-13  # normal velocities below this (relative) are touches, not impacts
MAX_STALLS = 50
NO_MODE = -1
K_MAX = 1e3  # largest |k| (in clearances) for which the closed form keeps its accuracy
# the error estimate of the tail is used where successive impact velocities shrink by d to within
# RATIO_TOL (1 - d): the sequence is in its asymptotic regime
RATIO_TOL = 0.1
MAX_RESOLVED = 1e4  # micro-bouncing that needs more impacts than this to accumulate is switched by chatter_dt

NO_FAILURE = 0
ROOT_LIMIT = 1
CONTACT_STALL = 2
CONTACT_STEP_LIMIT = 3
FAILURE_MESSAGES = {
    ROOT_LIMIT: "the impact search exceeded its step limit",
    CONTACT_STALL: "contact phases switched repeatedly without progress in time",
    CONTACT_STEP_LIMIT: "a contact phase exceeded the integrator's step limit",
}


@njit(cache=True)
def _push_state(table, n, t, u, du):
    """Append the row (t, Re u, Im u, Re du, Im du) without a temporary array."""
    table = grow_rows(table, n)
    table[n, 0] = t
    table[n, 1] = u.real
    table[n, 2] = u.imag
    table[n, 3] = du.real
    table[n, 4] = du.imag
    return table, n + 1


@njit(cache=True)
def _push_linear_phase(contacts, n_ct, path, n_path, kind, t0, t1, theta0, thetadot):
    """Record a phase on r = 1 where theta moves linearly (rolling)."""
    p_start = n_path
    path, n_path = push_row(path, n_path, np.array([t0, theta0, thetadot, 0.0]))
    path, n_path = push_row(path, n_path, np.array([t1, rolled_angle(theta0, thetadot, t0, t1), thetadot, 0.0]))
    contacts, n_ct = push_row(contacts, n_ct, np.array([t0, t1, float(kind), float(p_start), float(n_path - 1)]))
    return contacts, n_ct, path, n_path


@njit(cache=True)
def _first_order_tail(t, theta, rd, tdp, n_force, t_cap, gamma, rho, mu, d, phi, r_ratio):
    """The accumulation point predicted from one impact to first order in its velocity rd.

    Bounces of a rotor pressed outwards with force N last 2 d^j rd / N, so they
    end after tau = 2 d rd / (N (1 - d)); over it the tangential motion takes
    the smooth force F tau and the friction impulses mu (1 + d) rd d / (1 - d),
    bounded so that v_rel does not reverse (docs/contact.md). The tail is cut
    at t_cap. Returns (t_acc, theta_acc, thetadot_acc), each off by O(rd^2).
    """
    t_tail, p_tail = accumulation_tail(rd, n_force, d, mu)
    tau = min(t_tail, max(t_cap - t, 0.0))
    vrel_p = relative_velocity(r_ratio, tdp)
    f_t = free_tangential(theta, tdp, gamma, rho, phi)
    td_acc = tdp + f_t * tau - math.copysign(min(p_tail, abs(vrel_p)), vrel_p)
    return t + tau, theta + 0.5 * (tdp + td_acc) * tau, td_acc


@njit(cache=True)
def accumulation_point(converged, t, theta, rd, tdp, n_force, t_a, th_a, td_a, e_t, e_th, e_td, t_end, gamma, rho,
                       mu, d, phi, r_ratio):
    """Where a sequence of impacts that accumulates (`chain_step`) ends: (t_acc, theta_acc, thetadot_acc).

    The corrected tail where the sequence has converged onto it, else the first order (as in the
    linearisation of `rotorcontact.analysis.lyapunov.accumulation_saltation`).
    """
    if converged and t <= t_a + e_t <= t_end:
        return t_a + e_t, th_a + e_th, td_a + e_td
    return _first_order_tail(t, theta, rd, tdp, n_force, t_end, gamma, rho, mu, d, phi, r_ratio)


@njit(cache=True)
def contact_start(u, du):
    """(theta, thetadot) of a state on the stator that enters continuous contact."""
    return math.atan2(u.imag, u.real), polar_velocity(u, du)[1]


@njit(cache=True)
def liftoff_state(theta, thetadot):
    """(U, U') where the rotor leaves the stator at angle theta moving at thetadot."""
    e = complex(math.cos(theta), math.sin(theta))
    return e, e * complex(0.0, thetadot)


@njit(cache=True)
def contact_mode(theta, thetadot, next_mode, gamma, omega, rho, mu, phi, r_ratio):
    """The phase that continuous contact from (theta, thetadot) goes on with, and thetadot for it.

    ``next_mode`` is the phase decided by the switch that ended the previous phase (`NO_MODE` if none);
    otherwise the normal force and relative velocity decide, and a start at v_rel = 0 (to rounding)
    takes rolling's thetadot exactly.
    """
    if next_mode != NO_MODE:
        return next_mode, thetadot
    n_force = normal_force(theta, thetadot, omega, rho, phi)
    vrel = relative_velocity(r_ratio, thetadot)
    if n_force <= 0.0:
        return LIFTOFF, thetadot
    if abs(vrel) <= 1e-12 * (1.0 + r_ratio):
        roll_dot = -(1.0 + r_ratio)
        return stick_or_slip(theta, roll_dot, gamma, omega, rho, mu, phi), roll_dot
    return (TO_SLIDE_FORWARD if vrel > 0.0 else TO_SLIDE_BACKWARD), thetadot


@njit(cache=True)
def after_phase(code, t, t_start, stalls):
    """What follows a contact phase from t_start to t that ended with ``code``.

    Returns (stop, status, reason, stalls, next_mode): whether the run stops there, with what status and
    failure reason (`COMPLETED` and `NO_FAILURE` at its end time); the count of phases in a row that
    made no progress in time; and the phase the switch decided (`NO_MODE` where the next start decides).
    """
    stalls = stalls + 1 if t == t_start else 0
    if stalls > MAX_STALLS:
        return True, FAILED, CONTACT_STALL, stalls, NO_MODE
    if code == END:
        return True, COMPLETED, NO_FAILURE, stalls, NO_MODE
    if code == STEP_LIMIT:
        return True, FAILED, CONTACT_STEP_LIMIT, stalls, NO_MODE
    if code == TO_ROLLING or code == TO_SLIDE_FORWARD or code == TO_SLIDE_BACKWARD:
        return False, COMPLETED, NO_FAILURE, stalls, code
    return False, COMPLETED, NO_FAILURE, stalls, NO_MODE


@njit(cache=True)
def flight_event(u, du, k, gamma, omega, d, mu, r_ratio, horizon, on_boundary, liftoff, leaves_at_once):
    """The flight from (u, du) to its next event: an impact, a touch, contact, no crossing, or a failure.

    ``leaves_at_once`` starts the flight with a crossing at s = 0 (a start on the
    boundary moving outwards). Returns (code, tau, touch, ui, dv, du_plus, rd, td,
    rdp, tdp, vrel, pn, pt, theta): `rotorcontact.simulation.roots.next_crossing`'s code and
    time; for a crossing, the point ui on |U| = 1 and the velocity dv there, and
    ``touch`` when its normal velocity is at rounding level (no impulse), else the
    reset (`rotorcontact.model.impact_law.apply_reset`) and the impact angle.
    """
    if leaves_at_once:
        code, tau = CROSSING, 0.0
    else:
        code, tau = next_crossing(u - k, du, k, gamma, omega, horizon, on_boundary, liftoff)
    if code != CROSSING:
        return code, tau, False, u, du, du, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    v, dv = propagate(u - k, du, tau, gamma, omega)
    ui = k + v
    ui = complex_quotient(ui, abs(ui))
    du_plus, rd, td, rdp, tdp, vrel, pn, pt = apply_reset(ui, dv, d, mu, r_ratio)
    if rd <= RDOT_MIN * (1.0 + abs(dv)):
        return code, tau, True, ui, dv, dv, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return code, tau, False, ui, dv, du_plus, rd, td, rdp, tdp, vrel, pn, pt, point_angle(ui)


@njit(cache=True)
def chain_step(t, theta, rd, rdp, tdp, n_force, chain, prev_rd, prev_t, prev_th, prev_td, short_before, gamma, rho,
               mu, d, phi, r_ratio, chatter_tol, chatter_rdot, chatter_height, chatter_dt):
    """Whether an impact with the rotor pressed outwards (N > 0) ends a sequence of impacts that accumulates.

    Impacts accumulate (docs/contact.md): the first-order tail from this impact, A_n, is off by
    c rd^2 + O(rd^3); with the ratio q of successive impact velocities, E = (A_n - A_{n-1}) q^2 / (1 - q^2)
    estimates that error and A_n + E is off by O(rd^3). ``chain`` says the previous impact was one of the
    sequence, with velocity ``prev_rd`` and tail ``(prev_t, prev_th, prev_td)``.

    Returns (accumulates, converged, short_before, t_a, th_a, td_a, e_t, e_th, e_td): the first-order tail
    A_n and the estimate E (0 where it does not apply).
    """
    t_a, th_a, td_a = _first_order_tail(t, theta, rd, tdp, n_force, math.inf, gamma, rho, mu, d, phi, r_ratio)
    ratio = rd / prev_rd if chain else math.inf
    estimate = math.inf
    e_t = e_th = e_td = 0.0
    if d < 1.0 and 0.0 < ratio < 1.0 and abs(ratio - d) <= RATIO_TOL * (1.0 - d):
        w = ratio * ratio / (1.0 - ratio * ratio)
        e_t = (t_a - prev_t) * w
        e_th = wrap_angle(th_a - prev_th) * w
        e_td = (td_a - prev_td) * w
        estimate = max(abs(e_t), abs(e_th), abs(e_td)) * rd
    bounce = 2.0 * d * rd / n_force
    short = bounce < chatter_dt and short_before
    short_before = bounce < chatter_dt
    # micro-bouncing that does not contract towards chatter_rdot within MAX_RESOLVED impacts
    # (elastic impacts, d = 1, never accumulate by themselves)
    slow = chain and (ratio >= 1.0 or math.log(chatter_rdot / rd) < MAX_RESOLVED * math.log(ratio))
    converged = estimate <= chatter_tol
    accumulates = converged or rd < chatter_rdot or rdp * rdp < 2.0 * chatter_height * n_force or (short and slow)
    return accumulates, converged, short_before, t_a, th_a, td_a, e_t, e_th, e_td


@njit(cache=True)
def new_tables():
    """Empty tables for `simulate_into`: impacts, flights, contacts, path (grown as they fill)."""
    return np.empty((64, NCOL)), np.empty((64, 5)), np.empty((16, 5)), np.empty((256, 4))


@njit(cache=True)
def simulate_kernel(gamma, omega, rho, mu, d, phi, r_ratio, u0, du0, t_end, max_events, chatter_tol,
                    chatter_rdot, chatter_height, chatter_dt, stop_on_chatter):
    """Run the rotor from (u0, du0) at t = 0 to t_end through flights, impacts and contact.

    Returns
    -------
    impacts : (n, NCOL) array, one row per impact (`trajectory.COLUMNS`).
    flights : (m, 5) array: start time and (U, U') at the start of each free flight.
    contacts : (c, 5) array: t_start, t_end, kind, first and last row in ``path``
        (kind `ACCUMULATION` marks the interval from the last impact of a chatter
        sequence to its accumulation point, where the rotor stays on r = 1).
    path : (q, 4) array: t, theta, thetadot, thetadot' along contact phases.
    status, reason : int
    t_stop : float

    The tables are the filled rows of the grown ones (`tables.grow_rows`), not copies.
    """
    impacts, flights, contacts, path = new_tables()
    impacts, flights, contacts, path, n_imp, n_fl, n_ct, n_path, status, reason, t_stop = simulate_into(
        gamma, omega, rho, mu, d, phi, r_ratio, u0, du0, t_end, max_events, chatter_tol, chatter_rdot,
        chatter_height, chatter_dt, stop_on_chatter, impacts, flights, contacts, path
    )
    return (impacts[:n_imp], flights[:n_fl], contacts[:n_ct], path[:n_path],
            status, reason, t_stop)


@njit(cache=True)
def simulate_into(gamma, omega, rho, mu, d, phi, r_ratio, u0, du0, t_end, max_events, chatter_tol,
                  chatter_rdot, chatter_height, chatter_dt, stop_on_chatter, impacts, flights, contacts, path):
    """`simulate_kernel` writing into the tables it is given (`new_tables`), from their first row.

    A caller that runs many simulations (the batch kernel) hands the same tables to each, so that they
    are allocated and grown once rather than once per simulation. Returns the tables (grown where they
    filled), the numbers of rows used in each, then status, reason and t_stop as `simulate_kernel`.
    """
    k = equilibrium_point(gamma, omega, rho, phi)
    n_imp = np.int64(0)  # not a literal: one specialisation of the helpers it is passed to
    n_fl = np.int64(0)  # not a literal: one specialisation of the helpers it is passed to
    n_ct = np.int64(0)  # not a literal: one specialisation of the helpers it is passed to
    n_path = np.int64(0)  # not a literal: one specialisation of the helpers it is passed to
    roll_dot = -(1.0 + r_ratio)
    status = COMPLETED
    reason = NO_FAILURE
    t = 0.0
    u = u0
    du = du0
    on_boundary = abs(abs(u0) - 1.0) <= BOUNDARY_TOL
    if on_boundary:
        u = complex_quotient(u0, abs(u0))
    flights, n_fl = _push_state(flights, n_fl, t, u, du)
    in_contact = False
    liftoff = np.bool_(False)  # not a literal: one specialisation of next_crossing
    theta_c = 0.0
    thetadot_c = 0.0
    events = 0
    stalls = 0
    short_before = False
    chain = False  # the previous event was an impact of an accumulating sequence (N > 0)
    prev_rd = 0.0
    prev_t = prev_th = prev_td = 0.0
    next_mode = NO_MODE
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
                reason = ROOT_LIMIT
                t = t + tau
                break
            if code == STUCK:
                # on the boundary, no inward velocity, pressed outwards: contact
                if stop_on_chatter:
                    status = CHATTER
                    break
                theta_c, thetadot_c = contact_start(u, du)
                in_contact = True
                continue
            t = t + tau
            if touch:
                # a touch at rounding level with no normal velocity: no impulse, flight goes on
                chain = False
                u = ui
                du = dv
                on_boundary = True
                flights, n_fl = _push_state(flights, n_fl, t, u, du)
                continue
            n_force = normal_force(theta, tdp, omega, rho, phi)
            impacts = grow_rows(impacts, n_imp)
            impacts[n_imp, 0] = t
            impacts[n_imp, 1] = theta
            impacts[n_imp, 2] = rd
            impacts[n_imp, 3] = td
            impacts[n_imp, 4] = rdp
            impacts[n_imp, 5] = tdp
            impacts[n_imp, 6] = vrel
            impacts[n_imp, 7] = pn
            impacts[n_imp, 8] = pt
            impacts[n_imp, 9] = ui.real
            impacts[n_imp, 10] = ui.imag
            impacts[n_imp, 11] = du_plus.real
            impacts[n_imp, 12] = du_plus.imag
            impacts[n_imp, 13] = n_force
            n_imp += 1
            u = ui
            du = du_plus
            on_boundary = True
            flights, n_fl = _push_state(flights, n_fl, t, u, du)
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
                    # the phase holds the states at its two ends (dense output interpolates between them)
                    p_start = n_path
                    path, n_path = push_row(path, n_path, np.array([t, theta, tdp, 0.0]))
                    path, n_path = push_row(path, n_path, np.array([t_acc, theta_acc, td_acc, 0.0]))
                    contacts, n_ct = push_row(
                        contacts, n_ct, np.array([t, t_acc, float(ACCUMULATION), float(p_start), float(n_path - 1)])
                    )
                theta_c = theta_acc
                thetadot_c = td_acc
                t = t_acc
                chain = False
                if stop_on_chatter:
                    status = CHATTER
                    break
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
        # continuous contact from (theta_c, thetadot_c) at t
        mode, thetadot_c = contact_mode(theta_c, thetadot_c, next_mode, gamma, omega, rho, mu, phi, r_ratio)
        t_start = t
        if mode == TO_ROLLING:
            code, t, theta_end = roll(theta_c, t, t_end, gamma, omega, rho, mu, phi, r_ratio)
            contacts, n_ct, path, n_path = _push_linear_phase(
                contacts, n_ct, path, n_path, ROLLING, t_start, t, theta_c, roll_dot
            )
            theta_c = theta_end
            thetadot_c = roll_dot
        elif mode == LIFTOFF:
            code = LIFTOFF
        else:
            sgn = 1.0 if mode == TO_SLIDE_FORWARD else -1.0
            p_start = n_path
            code, t, theta_c, thetadot_c, path, n_path = slide(
                theta_c, thetadot_c, t, t_end, sgn, gamma, omega, rho, mu, phi, r_ratio, path, n_path
            )
            kind = SLIDE_FORWARD if sgn > 0.0 else SLIDE_BACKWARD
            contacts, n_ct = push_row(contacts, n_ct,
                                      np.array([t_start, t, float(kind), float(p_start), float(n_path - 1)]))
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
            flights, n_fl = _push_state(flights, n_fl, t, u, du)
    t_stop = t_end if status == COMPLETED else min(t, t_end)
    return impacts, flights, contacts, path, n_imp, n_fl, n_ct, n_path, status, reason, t_stop


def check_start(u0: Any, du0: Any) -> tuple[complex, complex]:
    """The initial state (u0, du0) as complex numbers, checked as `simulate` requires.

    Raises
    ------
    ParameterError
        Unless both are finite complex numbers (or RE,IM pairs), |u0| <= 1 and
        |du0| <= `rotorcontact.model.params.MAX_VELOCITY`.
    """
    u0 = complex_value("u0", u0)
    du0 = check_velocity("du0", complex_value("du0", du0))
    if abs(u0) > 1.0 + BOUNDARY_TOL:
        raise ParameterError(
            f"u0 = {u0.real!r},{u0.imag!r} lies outside the clearance (|u0| = {abs(u0)!r}); allowed: |u0| <= 1"
        )
    return u0, du0


def check_forced_response(params: Parameters) -> None:
    """Raise `ParameterError` where the forced response |k| = rho / |omega^2 - 1 + i gamma| (MODEL.md §3)
    exceeds `K_MAX` clearances, beyond which the closed form loses its accuracy; the message names rho, omega
    and gamma and the bound on rho."""
    check_forced_response_of(params.gamma, params.omega, params.rho, params.phi)


def check_forced_response_of(gamma: float, omega: float, rho: float, phi: float) -> None:
    """`check_forced_response` of the parameters given by value (no `Parameters` made: for many rows)."""
    regular = call_kernel(has_regular_equilibrium, gamma, omega)
    k_abs = abs(call_kernel(equilibrium_point, gamma, omega, rho, phi)) if regular else math.inf
    if k_abs > K_MAX:
        distance = abs(complex(omega**2 - 1.0, gamma))
        raise ParameterError(
            f"rho = {rho!r}, omega = {omega!r}, gamma = {gamma!r}: the forced response "
            f"|k| = rho / |omega^2 - 1 + i gamma| = {k_abs:.3g} clearances is beyond the simulator's accurate range "
            f"(|k| <= {K_MAX:g}); allowed: rho <= {K_MAX:g} |omega^2 - 1 + i gamma| = {K_MAX * distance:.3g}, or "
            "omega and gamma farther from the undamped resonance (omega = 1, gamma = 0)"
        )


def simulate(
    params: Parameters,
    u0: complex = 0j,
    du0: complex = 0j,
    t_end: float = 500.0,
    *,
    on_chatter: str = "contact",
    max_events: int = 10_000_000,
    chatter_tol: float = CHATTER_DEFAULTS["chatter_tol"],
    chatter_rdot: float = CHATTER_DEFAULTS["chatter_rdot"],
    chatter_height: float = CHATTER_DEFAULTS["chatter_height"],
    chatter_dt: float = CHATTER_DEFAULTS["chatter_dt"],
    machine: Machine | None = None,
) -> Trajectory:
    """Simulate the rotor from (U, U') = (u0, du0) at t = 0 up to t_end.

    Free flight is evaluated in closed form and every impact is located with a
    guarantee (`rotorcontact.simulation.roots`). When impacts accumulate (chatter) the
    rotor continues in continuous contact (`rotorcontact.simulation.contact`): sliding,
    rolling, slip and lift-off, after which free flight continues exactly.

    Parameters
    ----------
    params : Parameters
        Dimensionless parameters.
    u0, du0 : complex or (float, float)
        Initial position (|u0| <= 1) and velocity (|du0| <= `rotorcontact.model.params.MAX_VELOCITY`) in the
        co-rotating frame.
    t_end : float
        Final dimensionless time, > 0.
    on_chatter : {"contact", "stop"}
        At an accumulation of impacts, continue in continuous contact (default)
        or stop there with status ``"chatter"``.
    max_events : int
        Stop with status ``"max-events"`` after this many flights and contact
        phases; it bounds the run time whatever the dynamics.
    chatter_tol, chatter_rdot, chatter_height, chatter_dt : float
        With the rotor pressed outwards (N > 0) and d < 1, impacts accumulate
        geometrically. The simulator follows them one by one and switches to
        contact at the accumulation point, predicted from the last impact by a
        tail that is corrected to second order in the impact velocity from the
        last two impacts (docs/contact.md). It switches when the estimated
        error of that tail is below ``chatter_tol`` (default 1e-11), when the
        impact velocity falls below ``chatter_rdot`` (1e-5; below about 1e-7
        the crossing times of double precision are too coarse to resolve the
        bounces), or when the next bounce, of height (d rdot)^2 / (2 N), is
        lower than ``chatter_height`` (0: off). Sustained micro-bouncing that
        does not contract (d = 1, or needing more than 10^4 impacts to reach
        ``chatter_rdot``) is switched when two bounces in a row last less than
        ``chatter_dt`` (2 d rdot / N); the switch then neglects the bounce
        energy (d rdot)^2 / 2. ``chatter_dt = 0`` resolves every such bounce.
    machine : Machine, optional
        The machine the parameters come from (``machine.parameters()``, to 1e-12), for results in SI
        units.

    Returns
    -------
    Trajectory
        ``status`` is ``"completed"``, ``"chatter"`` (only with
        ``on_chatter="stop"``), ``"max-events"`` or ``"failed"``.
    """
    check_params(params)
    check_machine(machine)
    check_machine_params(params, machine)
    u0, du0 = check_start(u0, du0)
    t_end = check_range("t_end", t_end, low=0.0, high=MAX_T_END, low_open=True,
                        why="beyond it double precision cannot resolve the impact times")
    if on_chatter not in ("contact", "stop"):
        raise ParameterError(f"on_chatter = {on_chatter!r} is invalid; allowed: 'contact', 'stop'")
    max_events = check_int("max_events", max_events, 1, MAX_COUNT)
    chatter_tol = check_range("chatter_tol", chatter_tol, low=0.0)
    chatter_rdot = check_range("chatter_rdot", chatter_rdot, low=0.0, low_open=True)
    chatter_height = check_range("chatter_height", chatter_height, low=0.0)
    chatter_dt = check_range("chatter_dt", chatter_dt, low=0.0)
    check_forced_response(params)
    p = params
    impacts, flights, contacts, path, status, reason, t_stop = call_kernel(
        simulate_kernel, p.gamma, p.omega, p.rho, p.mu, p.d, p.phi, p.r_ratio, u0, du0, t_end, int(max_events),
        chatter_tol, chatter_rdot, chatter_height, chatter_dt, on_chatter == "stop",
    )
    return Trajectory(
        params=params,
        u0=u0,
        du0=du0,
        t_end=t_end,
        t_stop=float(t_stop),
        status=STATUS_NAMES[int(status)],
        failure=FAILURE_MESSAGES.get(int(reason)),
        records=impacts,
        flights=flights,
        contacts=contacts,
        path=path,
        machine=machine,
    )
