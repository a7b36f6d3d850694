"""The hybrid simulator: exact free flight, guaranteed impact location, reset.

Data flows one way: parameters -> exact flow (`flow`) -> impact location
(`roots`) -> reset (`reset`) -> `Trajectory`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .errors import ParameterError
from .flow import equilibrium_point, propagate
from .params import Machine, Parameters, check_finite, check_range
from .reset import apply_reset, polar_velocity
from .contact import (
    LIFTOFF,
    ROLLING,
    SLIDE_BACKWARD,
    SLIDE_FORWARD,
    STEP_LIMIT,
    TO_ROLLING,
    TO_SLIDE_BACKWARD,
    TO_SLIDE_FORWARD,
    END,
    normal_force,
    roll,
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

NCOL = len(COLUMNS)
BOUNDARY_TOL = 1e-12


@njit(cache=True)
def _wrap(theta: float) -> float:
    """Angle in (-pi, pi]."""
    theta = math.atan2(math.sin(theta), math.cos(theta))
    if theta <= -math.pi:
        return theta + 2.0 * math.pi
    return theta


@njit(cache=True)
def _push(table, n, row):
    """Append ``row`` to ``table`` (grown by doubling); return the table and the new count."""
    if n == table.shape[0]:
        bigger = np.empty((2 * table.shape[0], table.shape[1]))
        bigger[:n] = table[:n]
        table = bigger
    table[n, :] = row
    return table, n + 1


@njit(cache=True)
def simulate_kernel(gamma, omega, rho, mu, d, phi, r_ratio, u0, du0, t_end, max_events, chatter_rdot,
                    chatter_dt, stop_on_chatter):
    """Run the rotor from (u0, du0) at t = 0 to t_end through flights, impacts and contact.

    Returns
    -------
    impacts : (n, NCOL) array, one row per impact (`trajectory.COLUMNS`).
    flights : (m, 5) array: start time and (U, U') at the start of each free flight.
    contacts : (c, 5) array: t_start, t_end, kind, first and last row in ``path``.
    path : (q, 4) array: t, theta, thetadot, thetadot' along contact phases.
    status : int
    t_stop : float
    """
    k = equilibrium_point(gamma, omega, rho, phi)
    impacts = np.empty((64, NCOL))
    flights = np.empty((64, 5))
    contacts = np.empty((16, 5))
    path = np.empty((256, 4))
    n_imp = 0
    n_fl = 0
    n_ct = 0
    n_path = 0
    row = np.empty(NCOL)
    row5 = np.empty(5)
    roll_dot = -(1.0 + r_ratio)
    status = COMPLETED
    t = 0.0
    u = u0
    du = du0
    on_boundary = abs(abs(u0) - 1.0) <= BOUNDARY_TOL
    if on_boundary:
        u = u0 / abs(u0)
    in_contact = False
    liftoff = False
    theta_c = 0.0
    thetadot_c = 0.0
    events = 0
    stalls = 0
    while True:
        events += 1
        if events > max_events:
            status = MAX_EVENTS
            break
        if not in_contact:
            row5[0] = t
            row5[1] = u.real
            row5[2] = u.imag
            row5[3] = du.real
            row5[4] = du.imag
            flights, n_fl = _push(flights, n_fl, row5)
            if on_boundary and n_imp == 0 and not liftoff and polar_velocity(u, du)[0] > 0.0:
                code, tau = CROSSING, 0.0
            else:
                code, tau = next_crossing(u - k, du, k, gamma, omega, t_end - t, on_boundary, liftoff)
            liftoff = False
            if code == NO_CROSSING:
                break
            if code == ITERATION_LIMIT:
                status = FAILED
                t = t + tau
                break
            if code == STUCK:
                # on the boundary with no inward velocity and pressed outwards: contact
                if stop_on_chatter:
                    status = CHATTER
                    break
                theta_c = math.atan2(u.imag, u.real)
                thetadot_c = polar_velocity(u, du)[1]
                in_contact = True
                continue
            v, dv = propagate(u - k, du, tau, gamma, omega)
            ui = k + v
            ui = ui / abs(ui)
            du_plus, rd, td, rdp, tdp, vrel, pn, pt = apply_reset(ui, dv, d, mu, r_ratio)
            t = t + tau
            theta = _wrap(math.atan2(ui.imag, ui.real))
            n_force = normal_force(theta, tdp, omega, rho, phi)
            row[0] = t
            row[1] = theta
            row[2] = rd
            row[3] = td
            row[4] = rdp
            row[5] = tdp
            row[6] = vrel
            row[7] = pn
            row[8] = pt
            row[9] = ui.real
            row[10] = ui.imag
            row[11] = du_plus.real
            row[12] = du_plus.imag
            row[13] = n_force
            impacts, n_imp = _push(impacts, n_imp, row)
            u = ui
            du = du_plus
            on_boundary = True
            if n_force > 0.0 and (rd < chatter_rdot or 2.0 * d * rd < chatter_dt * n_force):
                # impacts accumulate: sum the geometric tails of the intervals and of the
                # friction impulses, and continue in contact from the accumulation point
                t_acc = t
                q = d
                if n_imp >= 3:
                    d1 = impacts[n_imp - 1, 0] - impacts[n_imp - 2, 0]
                    d0 = impacts[n_imp - 2, 0] - impacts[n_imp - 3, 0]
                    if d0 > 0.0 and 0.0 < d1 < d0:
                        q = d1 / d0
                        t_acc = t + d1 * q / (1.0 - q)
                tail = mu * (1.0 + d) * rd * d / (1.0 - d) if d < 1.0 else 0.0
                vrel_p = r_ratio + 1.0 + tdp
                tdp = tdp - math.copysign(min(tail, abs(vrel_p)), vrel_p)
                theta_c = theta + tdp * (t_acc - t)
                thetadot_c = tdp
                if t_acc >= t_end:
                    break
                t = t_acc
                if stop_on_chatter:
                    status = CHATTER
                    break
                in_contact = True
            continue
        # continuous contact from (theta_c, thetadot_c) at t
        n_force = normal_force(theta_c, thetadot_c, omega, rho, phi)
        vrel = r_ratio + 1.0 + thetadot_c
        if n_force <= 0.0:
            mode = LIFTOFF
        elif abs(vrel) <= 1e-12 * (1.0 + r_ratio):
            thetadot_c = roll_dot
            mode = stick_or_slip(theta_c, thetadot_c, gamma, omega, rho, mu, phi)
        else:
            mode = TO_SLIDE_FORWARD if vrel > 0.0 else TO_SLIDE_BACKWARD
        t_start = t
        p_start = n_path
        if mode == TO_ROLLING:
            kind = ROLLING
            path, n_path = _push(path, n_path, np.array([t, theta_c, roll_dot, 0.0]))
            code, t, theta_c = roll(theta_c, t, t_end, gamma, omega, rho, mu, phi, r_ratio)
            thetadot_c = roll_dot
            path, n_path = _push(path, n_path, np.array([t, theta_c, roll_dot, 0.0]))
        elif mode == LIFTOFF:
            kind = -1
            code = LIFTOFF
        else:
            sgn = 1.0 if mode == TO_SLIDE_FORWARD else -1.0
            kind = SLIDE_FORWARD if sgn > 0.0 else SLIDE_BACKWARD
            code, t, theta_c, thetadot_c, path, n_path = slide(
                theta_c, thetadot_c, t, t_end, sgn, gamma, omega, rho, mu, phi, r_ratio, path, n_path
            )
        if kind >= 0:
            contacts, n_ct = _push(contacts, n_ct, np.array([t_start, t, kind, p_start, n_path - 1]))
        stalls = stalls + 1 if t == t_start else 0
        if stalls > 50:
            status = FAILED
            break
        if code == END:
            break
        if code == STEP_LIMIT:
            status = FAILED
            break
        if code == LIFTOFF:
            e = complex(math.cos(theta_c), math.sin(theta_c))
            u = e
            du = e * complex(0.0, thetadot_c)
            in_contact = False
            on_boundary = True
            liftoff = True
        elif code == TO_ROLLING:
            thetadot_c = roll_dot
    t_stop = min(t, t_end) if status != COMPLETED else t_end
    return (impacts[:n_imp].copy(), flights[:n_fl].copy(), contacts[:n_ct].copy(), path[:n_path].copy(),
            status, t_stop)


def _as_complex(name: str, value) -> complex:
    if isinstance(value, (tuple, list, np.ndarray)) and len(value) == 2:
        re, im = value
    else:
        try:
            z = complex(value)
        except (TypeError, ValueError):
            raise ParameterError(f"{name} = {value!r} is not a complex number; give RE,IM") from None
        re, im = z.real, z.imag
    return complex(check_finite(f"{name} (real part)", re), check_finite(f"{name} (imaginary part)", im))


def simulate(
    params: Parameters,
    u0: complex = 0j,
    du0: complex = 0j,
    t_end: float = 500.0,
    *,
    on_chatter: str = "contact",
    max_events: int = 10_000_000,
    chatter_rdot: float = 1e-5,
    chatter_dt: float = 1e-3,
    machine: Machine | None = None,
) -> Trajectory:
    """Simulate the rotor from (U, U') = (u0, du0) at t = 0 up to t_end.

    Free flight is evaluated in closed form and every impact is located with a
    guarantee (`rotorcontact.roots`). When impacts accumulate (chatter) the
    rotor continues in continuous contact (`rotorcontact.contact`): sliding,
    rolling, slip and lift-off, after which free flight continues exactly.

    Parameters
    ----------
    params : Parameters
        Dimensionless parameters.
    u0, du0 : complex or (float, float)
        Initial position (|u0| <= 1) and velocity in the co-rotating frame.
    t_end : float
        Final dimensionless time, > 0.
    on_chatter : {"contact", "stop"}
        At an accumulation of impacts, continue in continuous contact (default)
        or stop there with status ``"chatter"``.
    max_events : int
        Stop with status ``"max-events"`` after this many flights and contact
        phases; it bounds the run time whatever the dynamics.
    chatter_rdot, chatter_dt : float
        With the rotor pressed outwards (N > 0), impacts are taken to
        accumulate when the impact velocity falls below ``chatter_rdot`` or the
        next bounce, of duration 2 d rdot / N, is shorter than ``chatter_dt``.
        The switch to contact is made at the accumulation point, the sum of
        the geometric series of the intervals. The rotor then stays within
        about rdot^2 / (2 N) of the stator, which bounds the error of the switch.
    machine : Machine, optional
        The machine the parameters come from, for results in SI units.

    Returns
    -------
    Trajectory
        ``status`` is ``"completed"``, ``"chatter"`` (only with
        ``on_chatter="stop"``), ``"max-events"`` or ``"failed"``.
    """
    if not isinstance(params, Parameters):
        raise ParameterError(f"params = {params!r} is not a Parameters object")
    u0 = _as_complex("u0", u0)
    du0 = _as_complex("du0", du0)
    if abs(u0) > 1.0 + BOUNDARY_TOL:
        raise ParameterError(
            f"u0 = {u0.real:g},{u0.imag:g} lies outside the clearance (|u0| = {abs(u0):.6g}); allowed: |u0| <= 1"
        )
    t_end = check_range("t_end", t_end, low=0.0, low_open=True)
    if on_chatter not in ("contact", "stop"):
        raise ParameterError(f"on_chatter = {on_chatter!r} is invalid; allowed: 'contact', 'stop'")
    if isinstance(max_events, bool) or not isinstance(max_events, (int, np.integer)) or max_events < 1:
        raise ParameterError(f"max_events = {max_events!r} is invalid; allowed: an integer >= 1")
    chatter_rdot = check_range("chatter_rdot", chatter_rdot, low=0.0, low_open=True)
    chatter_dt = check_range("chatter_dt", chatter_dt, low=0.0)
    p = params
    impacts, flights, contacts, path, status, t_stop = simulate_kernel(
        p.gamma, p.omega, p.rho, p.mu, p.d, p.phi, p.r_ratio, u0, du0, t_end, int(max_events), chatter_rdot,
        chatter_dt, on_chatter == "stop",
    )
    return Trajectory(
        params=params,
        u0=u0,
        du0=du0,
        t_end=t_end,
        t_stop=float(t_stop),
        status=STATUS_NAMES[int(status)],
        records=impacts,
        flights=flights,
        contacts=contacts,
        path=path,
        machine=machine,
    )
