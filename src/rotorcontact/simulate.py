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
from .params import Parameters, check_finite, check_range
from .reset import apply_reset, polar_velocity
from .roots import CROSSING, ITERATION_LIMIT, NO_CROSSING, STUCK, next_crossing
from .trajectory import COLUMNS, Trajectory

__all__ = ["simulate", "STATUS_NAMES"]

COMPLETED = 0
CHATTER = 1
MAX_IMPACTS = 2
FAILED = 3
STATUS_NAMES = {COMPLETED: "completed", CHATTER: "chatter", MAX_IMPACTS: "max-impacts", FAILED: "failed"}

NCOL = len(COLUMNS)
BOUNDARY_TOL = 1e-12


@njit(cache=True)
def normal_force(theta: float, thetadot: float, omega: float, rho: float, phi: float) -> float:
    """Normal contact force per unit mass on r = 1 with rdot = 0 (MODEL.md §4)."""
    return (1.0 + thetadot) ** 2 - omega * omega + rho * math.cos(phi - theta)


@njit(cache=True)
def _wrap(theta: float) -> float:
    """Angle in (-pi, pi]."""
    if theta <= -math.pi:
        return theta + 2.0 * math.pi
    return theta


@njit(cache=True)
def simulate_kernel(gamma, omega, rho, mu, d, phi, r_ratio, u0, du0, t_end, max_impacts, chatter_rdot):
    """Run the impacting rotor from (u0, du0) at t = 0 to t_end.

    Returns
    -------
    records : (n, NCOL) float array, one row per impact (see `trajectory.COLUMNS`).
    status : int
    t_stop : float
        Time the simulation reached (t_end, or the accumulation time on chatter).
    """
    k = equilibrium_point(gamma, omega, rho, phi)
    records = np.empty((min(max_impacts, 256) + 1, NCOL))
    n = 0
    t_seg = 0.0
    u = u0
    du = du0
    on_boundary = abs(abs(u0) - 1.0) <= BOUNDARY_TOL
    if on_boundary:
        u = u0 / abs(u0)
    status = COMPLETED
    t_stop = t_end
    while True:
        if on_boundary and n == 0 and polar_velocity(u, du)[0] > 0.0:
            code, tau = CROSSING, 0.0
        else:
            code, tau = next_crossing(u - k, du, k, gamma, omega, t_end - t_seg, on_boundary)
        if code == NO_CROSSING:
            break
        if code == STUCK:
            status = CHATTER
            t_stop = t_seg
            break
        if code == ITERATION_LIMIT:
            status = FAILED
            t_stop = t_seg + tau
            break
        v, dv = propagate(u - k, du, tau, gamma, omega)
        ui = k + v
        ui = ui / abs(ui)
        du_plus, rd, td, rdp, tdp, vrel, pn, pt = apply_reset(ui, dv, d, mu, r_ratio)
        t_imp = t_seg + tau
        theta = _wrap(math.atan2(ui.imag, ui.real))
        if n == records.shape[0]:
            grown = np.empty((min(2 * n, max_impacts + 1), NCOL))
            grown[:n] = records[:n]
            records = grown
        row = records[n]
        row[0] = t_imp
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
        row[13] = normal_force(theta, tdp, omega, rho, phi)
        n += 1
        t_seg = t_imp
        u = ui
        du = du_plus
        on_boundary = True
        if rd < chatter_rdot and row[13] > 0.0:
            # impacts accumulate: add the geometric tail of the intervals (MODEL.md §3)
            status = CHATTER
            t_stop = t_imp
            if n >= 3:
                d1 = records[n - 1, 0] - records[n - 2, 0]
                d0 = records[n - 2, 0] - records[n - 3, 0]
                if d0 > 0.0 and 0.0 < d1 < d0:
                    q = d1 / d0
                    t_stop = t_imp + d1 * q / (1.0 - q)
            break
        if n >= max_impacts:
            status = MAX_IMPACTS
            t_stop = t_imp
            break
    return records[:n].copy(), status, min(t_stop, t_end)


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
    max_impacts: int = 10_000_000,
    chatter_rdot: float = 1e-5,
    machine=None,
) -> Trajectory:
    """Simulate the rotor from (U, U') = (u0, du0) at t = 0 up to t_end.

    Free flight is evaluated in closed form and every impact is located with a
    guarantee (see `rotorcontact.roots`); nothing is integrated numerically.

    Parameters
    ----------
    params : Parameters
        Dimensionless parameters.
    u0, du0 : complex or (float, float)
        Initial position (|u0| <= 1) and velocity in the co-rotating frame.
    t_end : float
        Final dimensionless time, > 0.
    max_impacts : int
        Stop with status ``"max-impacts"`` after this many impacts.
    chatter_rdot : float
        Impact velocity below which, with the rotor pressed outwards (N > 0),
        impacts are taken to accumulate; the run stops with status ``"chatter"``.
    machine : Machine, optional
        The machine the parameters come from, for results in SI units.

    Returns
    -------
    Trajectory
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
    if isinstance(max_impacts, bool) or not isinstance(max_impacts, (int, np.integer)) or max_impacts < 1:
        raise ParameterError(f"max_impacts = {max_impacts!r} is invalid; allowed: an integer >= 1")
    chatter_rdot = check_range("chatter_rdot", chatter_rdot, low=0.0, low_open=True)
    p = params
    records, status, t_stop = simulate_kernel(
        p.gamma, p.omega, p.rho, p.mu, p.d, p.phi, p.r_ratio, u0, du0, t_end, int(max_impacts), chatter_rdot
    )
    return Trajectory(
        params=params,
        u0=u0,
        du0=du0,
        t_end=t_end,
        t_stop=float(t_stop),
        status=STATUS_NAMES[int(status)],
        records=records,
        machine=machine,
    )
