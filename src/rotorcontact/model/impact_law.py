"""The impact law: Newton restitution and Coulomb friction with a slip bound (MODEL.md §2).

At |U| = 1 with radial velocity rdot- > 0 the normal impulse per unit mass is
P_n = (1 + d) rdot-, so rdot+ = -d rdot-. The friction impulse opposes the
relative surface velocity v_rel = r_ratio + 1 + thetadot and has magnitude
mu P_n, except that it stops at v_rel = 0 rather than reversing it:

    thetadot+ = thetadot- - sgn(v_rel) min(mu P_n, |v_rel|).

For v_rel > 0 and no sticking this is U'+ = U'- - q rdot- U, q = (1 + d)(1 + i mu).
"""

from __future__ import annotations

import math

from numba import njit

__all__ = ["apply_reset", "polar_velocity"]


@njit(cache=True)
def polar_velocity(u: complex, du: complex) -> tuple[float, float]:
    """(rdot, thetadot) of the motion U, U' at a point with |U| > 0."""
    r = abs(u)
    e = u / r
    w = e.conjugate() * du
    return w.real, w.imag / r


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
    e = u / abs(u)
    rdot, thetadot = polar_velocity(e, du)
    v_rel = r_ratio + 1.0 + thetadot
    p_n = (1.0 + d) * rdot
    rdot_plus = -d * rdot
    slip = mu * p_n
    if abs(v_rel) <= slip:
        p_t = -v_rel
    else:
        p_t = -math.copysign(slip, v_rel)
    thetadot_plus = thetadot + p_t
    du_plus = e * complex(rdot_plus, thetadot_plus)
    return du_plus, rdot, thetadot, rdot_plus, thetadot_plus, v_rel, p_n, p_t
