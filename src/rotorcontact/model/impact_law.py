"""The impact law: Newton restitution and Coulomb friction with a slip bound (MODEL.md §2).

At |U| = 1 with radial velocity rdot- > 0 the normal impulse per unit mass is
P_n = (1 + d) rdot-, so rdot+ = -d rdot-. The friction impulse opposes the
relative surface velocity v_rel = r_ratio + 1 + thetadot and has magnitude
mu P_n, except that it stops at v_rel = 0 rather than reversing it:

    thetadot+ = thetadot- - sgn(v_rel) min(mu P_n, |v_rel|).

For v_rel > 0 and no sticking this is U'+ = U'- - q rdot- U, q = (1 + d)(1 + i mu).

Every formula of the law lives here: `apply_reset` (the slip-bounded law),
`ideal_reset` (the law of MODEL.md §5), `impact_q`, `relative_velocity`,
`slip_bound`, `sticks`, `slides_forward` and the polar reset Jacobian
`reset_jacobian`. All are compiled and callable from Python and from kernels, and take their arguments
unchecked (NaN gives NaN; text is a numba typing error): the checked entry points are `simulate` and
`rotorcontact.maps.impact_map.impact_map`.
"""

from __future__ import annotations

import math

from numba import njit

from ..interpreted import complex_quotient
__all__ = [
    "apply_reset",
    "ideal_reset",
    "polar_velocity",
    "impact_q",
    "relative_velocity",
    "slip_bound",
    "sticks",
    "slides_forward",
    "reset_jacobian",
]


@njit(cache=True)
def polar_velocity(u: complex, du: complex) -> tuple[float, float]:
    """(rdot, thetadot) of the motion U, U' at a point with |U| > 0."""
    r = abs(u)
    e = complex_quotient(u, r)
    w = e.conjugate() * du
    return w.real, w.imag / r


@njit(cache=True)
def impact_q(d: float, mu: float) -> complex:
    """q = (1 + d)(1 + i mu), the factor of the reset U'+ = U'- - q rdot- U (MODEL.md §2).

    A friction impulse along -sgn(v_rel) is ``impact_q(d, sgn * mu)``.
    """
    return complex(1.0 + d, (1.0 + d) * mu)


@njit(cache=True)
def relative_velocity(r_ratio: float, thetadot: float) -> float:
    """v_rel = r_ratio + 1 + thetadot, the slip velocity of the contact point (MODEL.md §2); scalars or arrays."""
    return r_ratio + 1.0 + thetadot


@njit(cache=True)
def slip_bound(d: float, mu: float, rdot: float) -> float:
    """mu P_n = mu (1 + d) rdot-, the largest friction impulse of an impact (MODEL.md §2)."""
    return mu * ((1.0 + d) * rdot)


@njit(cache=True)
def sticks(v_rel: float, slip: float) -> bool:
    """The friction impulse is capped at v_rel = 0: 0 < ``slip`` and |v_rel| <= ``slip`` (`slip_bound`)."""
    return slip > 0.0 and abs(v_rel) <= slip


@njit(cache=True)
def slides_forward(thetadot: float, rdot: float, d: float, mu: float, r_ratio: float) -> bool:
    """The impact slips with v_rel > 0 throughout: v_rel- > mu (1 + d) rdot-.

    Only then does the slip-bounded law act as the law of MODEL.md §5.
    """
    return relative_velocity(r_ratio, thetadot) > slip_bound(d, mu, rdot)


@njit(cache=True)
def apply_reset(u: complex, du: complex, d: float, mu: float, r_ratio: float):
    """Velocity just after an impact at the point u (|u| = 1).

    Returns
    -------
    du_plus : complex
        Velocity after the impact.
    rdot, thetadot, rdot_plus, thetadot_plus, v_rel : float
        Polar velocities before and after, and v_rel before.
    normal_impulse, tangential_impulse : float
        Impulses per unit mass; the tangential one is signed along +theta.
    """
    e = complex_quotient(u, abs(u))
    rdot, thetadot = polar_velocity(e, du)
    v_rel = relative_velocity(r_ratio, thetadot)
    p_n = (1.0 + d) * rdot
    rdot_plus = -d * rdot
    slip = mu * p_n
    if sticks(v_rel, slip):
        p_t = -v_rel
    else:
        p_t = -math.copysign(slip, v_rel)
    thetadot_plus = thetadot + p_t
    du_plus = e * complex(rdot_plus, thetadot_plus)
    return du_plus, rdot, thetadot, rdot_plus, thetadot_plus, v_rel, p_n, p_t


@njit(cache=True)
def ideal_reset(e: complex, du: complex, rdot: float, q: complex) -> complex:
    """U'+ = U'- - q rdot- e at the impact point e (|e| = 1), the law of MODEL.md §5 with q = `impact_q`."""
    return du - q * rdot * e


@njit(cache=True)
def reset_jacobian(v_rel: float, slip: float, d: float, mu: float, ideal: bool):
    """Jacobian of the reset in polar velocities, d(rdot+, thetadot+) / d(rdot-, thetadot-).

    Parameters
    ----------
    v_rel, slip : float
        v_rel- (`relative_velocity`) and the slip bound mu (1 + d) rdot- (`slip_bound`).
    d, mu : float
        Restitution and friction coefficient.
    ideal : bool
        The law of MODEL.md §5 (friction always along -theta) instead of the slip-bounded law.

    Returns
    -------
    r11, r12, r21, r22 : float
        The 2x2 Jacobian: rdot+ = -d rdot-; thetadot+ = thetadot- - sgn(v_rel) mu (1 + d) rdot-
        while slipping, and thetadot+ = -(1 + r_ratio) (a constant) while sticking.
    sticking : bool
        The slip-bounded law caps the friction impulse (`sticks`).
    """
    if not ideal and sticks(v_rel, slip):
        return -d, 0.0, 0.0, 0.0, True
    sgn = 1.0 if (ideal or v_rel >= 0.0) else -1.0
    return -d, 0.0, -sgn * mu * (1.0 + d), 1.0, False
