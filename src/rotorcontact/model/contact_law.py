"""Continuous contact on r = 1: the normal force and the sliding dynamics (MODEL.md §4).

On the stator (r = 1, rdot = 0) the normal force per unit mass that keeps r'' = 0 is

    N = (1 + thetadot)^2 - omega^2 + rho cos(phi - theta),

and contact persists while N > 0. The tangential motion is

    thetadot' = F - mu N sgn(v_rel),     F = -(1 + thetadot) gamma + rho sin(phi - theta),

with v_rel = r_ratio + 1 + thetadot (`rotorcontact.model.impact_law.relative_velocity`).
Every function is compiled and takes scalars, or arrays where noted, so that the
contact integrator of `rotorcontact.simulation.contact` and the analyses call the same code. They take
their arguments unchecked (NaN gives NaN; text is a numba typing error): the checked entry points are
`Trajectory.contact_forces` and `rotorcontact.analysis.equilibria`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "normal_force",
    "normal_force_gradient",
    "free_tangential",
    "forces_along",
    "free_tangential_gradient",
    "sliding_accel",
    "sliding_jacobian",
    "sliding_field_jacobian",
    "accumulation_tail",
]


@njit(cache=True)
def normal_force(theta, thetadot, omega: float, rho: float, phi: float):
    """N = (1 + thetadot)^2 - omega^2 + rho cos(phi - theta) on r = 1 with rdot = 0."""
    spin = 1.0 + thetadot
    return spin * spin - omega * omega + rho * math.cos(phi - theta)


@njit(cache=True)
def normal_force_gradient(theta: float, thetadot: float, rho: float, phi: float) -> tuple[float, float]:
    """(dN/dtheta, dN/dthetadot) = (rho sin(phi - theta), 2 (1 + thetadot))."""
    return rho * math.sin(phi - theta), 2.0 * (1.0 + thetadot)


@njit(cache=True)
def free_tangential(theta, thetadot, gamma: float, rho: float, phi: float):
    """F = -(1 + thetadot) gamma + rho sin(phi - theta), the tangential acceleration without friction."""
    return -(1.0 + thetadot) * gamma + rho * math.sin(phi - theta)


@njit(cache=True)
def forces_along(theta: np.ndarray, thetadot: np.ndarray, gamma: float, omega: float, rho: float,
                 phi: float) -> tuple[np.ndarray, np.ndarray]:
    """`normal_force` and `free_tangential` at each point (theta[i], thetadot[i])."""
    n = np.empty(theta.shape[0])
    f = np.empty(theta.shape[0])
    for i in range(theta.shape[0]):
        n[i] = normal_force(theta[i], thetadot[i], omega, rho, phi)
        f[i] = free_tangential(theta[i], thetadot[i], gamma, rho, phi)
    return n, f


@njit(cache=True)
def free_tangential_gradient(theta: float, gamma: float, rho: float, phi: float) -> tuple[float, float]:
    """(dF/dtheta, dF/dthetadot) = (-rho cos(phi - theta), -gamma)."""
    return -rho * math.cos(phi - theta), -gamma


@njit(cache=True)
def sliding_accel(theta, thetadot, sgn, gamma: float, omega: float, rho: float, mu: float, phi: float):
    """thetadot' = F - mu N sgn of a sliding phase, sgn = sgn(v_rel) held fixed."""
    n = normal_force(theta, thetadot, omega, rho, phi)
    return free_tangential(theta, thetadot, gamma, rho, phi) - mu * n * sgn


@njit(cache=True)
def sliding_jacobian(theta: float, thetadot: float, sgn: float, gamma: float, rho: float, mu: float,
                     phi: float) -> tuple[float, float]:
    """(d thetadot'/d theta, d thetadot'/d thetadot) of `sliding_accel`, sgn held fixed.

    The Jacobian of the field (thetadot, thetadot') in (theta, thetadot) is
    [[0, 1], [a_theta, a_thetadot]] with the returned (a_theta, a_thetadot).
    """
    psi = phi - theta
    a_theta = -rho * math.cos(psi) - mu * sgn * rho * math.sin(psi)
    a_thetadot = -gamma - 2.0 * mu * sgn * (1.0 + thetadot)
    return a_theta, a_thetadot


@njit(cache=True)
def accumulation_tail(rdot: float, n_force: float, d: float, mu: float) -> tuple[float, float]:
    """Duration and friction impulse of the impacts that accumulate after one of velocity ``rdot``.

    Bounces of a rotor pressed outwards with force N last 2 d^j rdot / N, so
    they end after t_tail = 2 d rdot / (N (1 - d)); their friction impulses add
    up to p_tail = mu (1 + d) rdot d / (1 - d) (docs/contact.md). Both are 0
    for d >= 1, where the bounces do not accumulate.
    """
    if d < 1.0:
        return 2.0 * d * rdot / (n_force * (1.0 - d)), mu * (1.0 + d) * rdot * d / (1.0 - d)
    return 0.0, 0.0


@njit(cache=True)
def sliding_field_jacobian(theta: float, thetadot: float, sgn: float, gamma: float, rho: float, mu: float,
                           phi: float) -> np.ndarray:
    """2x2 Jacobian of the sliding field (thetadot, thetadot') in (theta, thetadot), sgn held fixed."""
    a_theta, a_thetadot = sliding_jacobian(theta, thetadot, sgn, gamma, rho, mu, phi)
    out = np.empty((2, 2))
    out[0, 0] = 0.0
    out[0, 1] = 1.0
    out[1, 0] = a_theta
    out[1, 1] = a_thetadot
    return out
