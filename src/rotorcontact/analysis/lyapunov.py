"""Lyapunov exponents of the impacting rotor, with saltation corrections (MODEL.md §2-§4).

State and tangent space
-----------------------
In free flight the state is the real 4-vector of the co-rotating Cartesian
coordinates

    x = (Re U, Im U, Re U', Im U'),

and the spectrum is that of this 4-dimensional state, largest first. In
continuous contact (r = 1, rdot = 0) the state is y = (theta, thetadot) and
the tangent space is 2-dimensional (1-dimensional while rolling).

Tangent vectors are propagated exactly along a trajectory of
`rotorcontact.simulation.simulator` (the analysis does not integrate the motion itself):

* **Free flight** is affine, w' = A w + b with w = (U, U'), so its tangent map
  is e^{A s}, complex-linear; in real form it is the 4x4 matrix of
  `flight_tangent`, built from `rotorcontact.model.flow.propagate`.
* **Impacts**: the tangent vector jumps by the saltation matrix

      S = D_x R + (f+ - D_x R f-) (grad h)^T / (grad h . f-),   h = |U|^2 - 1,

  with R the reset of `rotorcontact.model.impact_law.apply_reset` (U+ = U,
  U'+ = e (-d rdot + i thetadot+)), f- and f+ the free-flight field before
  and after (`impact_saltation`). S does not depend on how R is extended off
  the surface: S maps f- to f+ and acts as D_x R on the tangent space of
  the surface. When the friction impulse is capped (the contact point
  sticks, thetadot+ = -(1 + r_ratio) whatever thetadot-), D_x R annihilates
  the variation of thetadot- and S has rank 3.
* **Into contact**. Impacts accumulate in finite time (chatter) and the
  simulator switches, at the sum of the geometric series of the bounces, to
  continuous contact (`rotorcontact.simulation.simulator.simulate_kernel`). The tangent
  map across this switch is the linearisation of that same construction: the
  last resolved impact moves in time by dt = -(grad h . dx) / (grad h . f-),
  its state on Sigma determines the contact state y_c and the length of the
  accumulation tail, and the contact state at the nominal switching time is
  y_c + dy_c - g(y_c) (dt + dt_tail), with g the contact field
  (`accumulation_saltation`, a 2x4 matrix of rank 2). It linearises the
  first-order tail 2 d rdot / (N (1 - d)); where the simulator summed the
  tail with its second-order correction (the default, docs/contact.md), the
  two tails differ by O(rdot^2) in time and their derivatives by O(rdot),
  rdot the last resolved normal speed (about 1e-4 at the default switch): a
  relative error of that size in the tangent map at each accumulation,
  which moves an exponent by at most about that much over the window per
  accumulation in it. A flight that starts
  on the stator with no normal velocity while pressed outwards enters
  contact directly; there the polar variations (dtheta, dthetadot) are kept
  and (dr, drdot) dropped (`contact_projection`). In both cases two
  directions of the 4-dimensional state are annihilated: their exponents are
  reported as -inf (``null`` in JSON), and they stay -inf for the rest of the
  trajectory, since a collapsed volume never grows again.
* **In contact** the variational equations of the sliding dynamics

      theta'' = -(1 + thetadot) gamma + rho sin(phi - theta) - mu N sgn(v_rel)

  are integrated (DOP853, rtol 1e-11) together with the state from the start
  of each sliding phase of the simulator's path. Rolling holds v_rel = 0, so
  thetadot is fixed and only dtheta survives: entering rolling from sliding,
  the saltation across v_rel = 0 is diag(1, 0) (f+ = (thetadot, 0)) and one
  more exponent becomes -inf; during rolling dtheta is constant. Leaving
  rolling into sliding the field is continuous (|F| = mu N there), so the
  saltation is the identity. A reversal of sliding without rolling has the
  saltation diag(1, theta''+ / theta''-).
* **Lift-off** at N = 0: the contact state is embedded in the 4-dimensional
  state (dU = i e dtheta, dU' = e (i dthetadot - thetadot dtheta)) and
  corrected by the saltation of the switching surface N = 0,
  (f_free - E g) (grad N)^T / (grad N . g) (`liftoff_saltation`). From
  sliding the correction vanishes, since the contact force is proportional
  to N; from rolling it does not.
* A grazing touch of the stator without impulse is passed with the identity
  (the saltation matrix is unbounded at grazing; such touches are isolated
  events of zero measure).

Benettin's method
-----------------
The tangent basis is re-orthonormalised by QR (Benettin et al. 1980) at every
impact and every switch, and at least every ``qr_interval`` time units; the
logarithms of the diagonal of R are summed over the averaging window. The
initial transient ``t_transient`` is discarded: the basis is propagated
through it (and so is already aligned with the Lyapunov vectors when the
window starts), and completed to a full orthonormal basis of the current
phase at the start of the window. When impacts fill the window (at least
two, and the pieces before the first and after the last are shorter than
the longest interval between impacts) it runs from the first impact after
``t_transient`` to the last one (both taken just before the impact). For a periodic impacting motion this
makes the averages exact products over whole periods, so the exponent along
the flow converges to 0 like 1/t without the bounded oscillation of the
speed along the orbit.

Error estimates and changes of regime
-------------------------------------
The running sums are recorded after every map, so that the exponents can
be taken over any part of the window: the error estimate of each exponent
is the standard error of the mean of its values over
`rotorcontact.analysis.regime_change.SUBWINDOWS` sub-windows (cut at impacts when
the window runs from impact to impact). The regime the run ends in, and the
time it began, are found by `rotorcontact.analysis.regime_change.final_regime`;
when it began inside the window, the result says so (``regime_change``) and
gives the spectrum over the final regime alone (``final_exponents``): from
just after the switch into a final contact phase or flight, or from impact
to impact for a final periodic motion.

For a trajectory on a periodic orbit with one impact per period T the
spectrum is 0 (the direction of the flow) and log|lambda_i| / T for the three
multipliers lambda_i of the impact map (`rotorcontact.maps.impact_map`). In pure
free flight it is the real parts of the eigenvalues of the real form of A:
Re(lambda+-), each twice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
from scipy.integrate import solve_ivp

from ..simulation.contact import ACCUMULATION, ROLLING, SLIDE_FORWARD
from ..errors import ParameterError
from ..model import contact_law
from ..maps.impact_map import MAX_GROWTH, growth_rate
from ..model.flow import flight_accel, half_discriminant, propagate
from ..model.impact_law import ideal_reset, impact_q, relative_velocity, reset_jacobian, slip_bound
from ..model.params import Parameters, check_range
from ..model.validation import check_bool, check_float, check_params, check_type, complex_array, quoted, real_array
from ..simulation.simulator import simulate
from ..simulation.trajectory import Trajectory
from .equilibria import MAX_STATE, _contact_args
from .regime_change import SUBWINDOWS, _spread, _subwindow_rates, final_regime

__all__ = [
    "COORDINATES",
    "LyapunovResult",
    "lyapunov_spectrum",
    "trajectory_lyapunov",
    "trajectory_tangent",
    "flight_tangent",
    "impact_saltation",
    "accumulation_saltation",
    "contact_projection",
    "liftoff_saltation",
    "contact_variational_matrix",
]

#: The coordinates of the 4-dimensional state whose spectrum is computed.
COORDINATES = ("Re U", "Im U", "Re U'", "Im U'")

DIM = 4
CONTACT_RTOL = 1e-11
CONTACT_ATOL = 1e-13
#: Largest distance | |U| - 1 | of a point given as a point of the stator (an impact, a lift-off).
ON_STATOR_TOL = 1e-6


# ---------------------------------------------------------------------------
# Checks of the arguments of the public maps
# ---------------------------------------------------------------------------


def _complex_number(name: str, value: Any, allowed: str, ok: Callable[[complex], bool]) -> complex:
    """``value`` as a complex number if it is one number (int, float, complex, numpy's or a 0-d array), finite
    and ``ok``; else a `ParameterError` naming ``name``, the value and ``allowed``."""
    z = complex_array(value)
    if z is not None and z.ndim == 0 and np.isfinite(z):
        z = complex(z)
        if ok(z):
            return z
    raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: {allowed}")


def _stator_point(name: str, value: Any) -> complex:
    """A point U of the stator: a finite complex number with | |U| - 1 | <= `ON_STATOR_TOL`."""
    return _complex_number(name, value, f"a complex number on the stator, | |{name}| - 1 | <= {ON_STATOR_TOL:g}",
                           lambda z: abs(abs(z) - 1.0) <= ON_STATOR_TOL)


def _velocity(name: str, value: Any) -> complex:
    """A velocity U': a finite complex number with |U'| <= `rotorcontact.analysis.equilibria.MAX_STATE`."""
    return _complex_number(name, value, f"a finite complex number with |{name}| <= {MAX_STATE:g}",
                           lambda z: abs(z) <= MAX_STATE)


def _impact_args(params: Any, u: Any, du_minus: Any) -> tuple[complex, complex]:
    """(u, du_minus) of an impact, checked: `Parameters`, a point of the stator and a velocity approaching it."""
    check_params(params)
    u = _stator_point("u", u)
    du_minus = _velocity("du_minus", du_minus)
    _check_approach(u, du_minus)
    return u, du_minus


def _check_approach(u: complex, du_minus: complex) -> float:
    """Re(conj(u) du_minus), or a `ParameterError` where it is not > 0 (the velocity does not approach)."""
    hdot = (u.conjugate() * du_minus).real
    if not hdot > 0.0:
        raise ParameterError(
            f"du_minus = {du_minus!r} does not approach the stator at u = {u!r} "
            f"(Re(conj(u) du) = {hdot!r}); allowed: an approaching velocity"
        )
    return hdot


def _contact_vector(value: Any) -> np.ndarray:
    """The argument ``contact_field``: (thetadot, theta'') as an array of 2 finite real numbers."""
    g = real_array(value)
    if g is None or g.shape != (2,) or not np.all(np.isfinite(g)):
        raise ParameterError(f"contact_field = {quoted(value)} is invalid; allowed: (thetadot, theta''), "
                             "2 finite real numbers")
    return g


def _finite_map(m: np.ndarray | None, name: str, value: Any, why: str) -> np.ndarray:
    """``m`` if it is finite, else a `ParameterError` naming the argument ``name`` = ``value`` and ``why``."""
    if m is None or not np.all(np.isfinite(m)):
        raise ParameterError(f"{name} = {quoted(value)} is invalid: {why}, so the tangent map is not finite; "
                             "allowed: a transversal crossing")
    return m


# ---------------------------------------------------------------------------
# Real forms and vector fields
# ---------------------------------------------------------------------------


def _real_matrix(m: np.ndarray) -> np.ndarray:
    """Real 4x4 form of a complex-linear map of (dU, dU') (a 2x2 complex matrix)."""
    out = np.empty((4, 4))
    for i in range(2):
        for j in range(2):
            z = complex(m[i, j])
            out[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] = [[z.real, -z.imag], [z.imag, z.real]]
    return out


def _vec(du: complex, ddu: complex) -> np.ndarray:
    return np.array([du.real, du.imag, ddu.real, ddu.imag])


def _basis() -> list[tuple[complex, complex]]:
    """The real basis of (dU, dU') as complex pairs, in the order of `COORDINATES`."""
    return [(1.0 + 0j, 0j), (1j, 0j), (0j, 1.0 + 0j), (0j, 1j)]


def _accel(params: Parameters, u: complex, du: complex) -> complex:
    """U'' of free flight: -(gamma + 2i) U' + (1 - omega^2 - i gamma) (U - k)."""
    return flight_accel(complex(u), complex(du), params.k, params.gamma, params.omega)


def _contact_accel(params: Parameters, theta: float, thetadot: float, sgn: float) -> float:
    p = params
    return contact_law.sliding_accel(float(theta), float(thetadot), float(sgn), p.gamma, p.omega, p.rho, p.mu, p.phi)


def _normal_gradient(params: Parameters, theta: float, thetadot: float) -> np.ndarray:
    """(dN/dtheta, dN/dthetadot) of the normal force N (`rotorcontact.model.contact_law.normal_force`)."""
    return np.array(contact_law.normal_force_gradient(float(theta), float(thetadot), params.rho, params.phi))


def _contact_jacobian(params: Parameters, theta: float, thetadot: float, sgn: float) -> np.ndarray:
    p = params
    return contact_law.sliding_field_jacobian(float(theta), float(thetadot), float(sgn), p.gamma, p.rho, p.mu, p.phi)


def contact_variational_matrix(params: Parameters, theta: float, thetadot: float, sgn: float) -> np.ndarray:
    """2x2 Jacobian of the sliding contact field (thetadot, theta'') in (theta, thetadot).

    ``sgn`` is the sign of v_rel of the sliding phase (held fixed).

    Raises
    ------
    ParameterError
        Unless ``params`` are `Parameters`, ``theta`` is a finite real number, ``thetadot`` one with
        |thetadot| <= `rotorcontact.analysis.equilibria.MAX_STATE` and ``sgn`` is -1, 0 or 1.
    """
    theta, thetadot, params = _contact_args(theta, thetadot, params)
    if check_float("sgn", sgn) not in (-1.0, 0.0, 1.0):
        raise ParameterError(f"sgn = {sgn!r} is invalid; allowed: -1, 0 or 1 (the sign of v_rel)")
    return _contact_jacobian(params, theta, thetadot, sgn)


# ---------------------------------------------------------------------------
# Tangent maps
# ---------------------------------------------------------------------------


def flight_tangent(params: Parameters, s: float) -> np.ndarray:
    """Real 4x4 tangent map e^{A s} of a free flight of length s, in `COORDINATES`.

    The homogeneous flow is linear, so the columns are the flows of the basis
    vectors of (dU, dU') (`rotorcontact.model.flow.propagate`).

    Raises
    ------
    ParameterError
        Unless ``params`` are `Parameters` and ``s`` is a finite real number over which the map grows at most
        like e^MAX_GROWTH (`rotorcontact.maps.impact_map.MAX_GROWTH`; backwards too, s < 0).
    """
    check_params(params)
    s = check_float("s", s)
    g, w = params.gamma, params.omega
    rate = growth_rate(g, half_discriminant.py_func(g, w), -1 if s < 0.0 else 1)  # the fastest mode over the flight
    if rate * abs(s) > MAX_GROWTH:
        raise ParameterError(
            f"s = {s!r} is invalid: the flight grows like e^({rate:.3g} |s|) at gamma = {g:g}, omega = {w:g}; "
            f"allowed: |s| <= {MAX_GROWTH / rate:.6g}"
        )
    return _flight_tangent(params, s)


def _flight_tangent(params: Parameters, s: float) -> np.ndarray:
    g, w = params.gamma, params.omega
    phi11, phi21 = propagate(1.0 + 0j, 0j, float(s), g, w)
    phi12, phi22 = propagate(0j, 1.0 + 0j, float(s), g, w)
    return _real_matrix(np.array([[phi11, phi12], [phi21, phi22]]))


def _reset_linearisation(params: Parameters, u: complex, du: complex):
    """Post-impact velocity, the real 4x4 D_x R at (U, U'-) on |U| = 1, and whether the contact sticks.

    The reset is that of `rotorcontact.model.impact_law.apply_reset`, extended off the
    surface with e = U / |U|.
    """
    p = params
    e = u / abs(u)
    w = e.conjugate() * du
    rdot, thetadot = w.real, w.imag
    v_rel = relative_velocity(p.r_ratio, thetadot)
    slip = slip_bound(p.d, p.mu, rdot)
    r11, r12, r21, r22, sticking = reset_jacobian(v_rel, slip, p.d, p.mu, False)
    if sticking:
        w_plus = complex(-p.d * rdot, -(p.r_ratio + 1.0))
        du_plus = e * w_plus
    else:
        # the law U'+ = U'- - q rdot U with the friction along -sgn(v_rel)
        sgn = 1.0 if v_rel >= 0.0 else -1.0
        du_plus = ideal_reset(e, du, rdot, impact_q(p.d, sgn * p.mu))
        w_plus = e.conjugate() * du_plus
    cols = []
    for d_u, d_du in _basis():
        # U'+ = e (rdot+ + i thetadot+): its variation is de w+ + e J dw with J the polar reset Jacobian
        de = d_u - e * (e.conjugate() * d_u).real
        dw = de.conjugate() * du + e.conjugate() * d_du
        d_du_plus = de * w_plus + e * complex(r11 * dw.real + r12 * dw.imag, r21 * dw.real + r22 * dw.imag)
        cols.append(_vec(d_u, d_du_plus))
    return du_plus, np.array(cols).T, bool(sticking)


def impact_saltation(params: Parameters, u: complex, du_minus: complex) -> tuple[np.ndarray, complex, bool]:
    """Saltation matrix of an impact at U (|U| = 1) with velocity U'- just before it.

    S = D_x R + (f+ - D_x R f-) (grad h)^T / (grad h . f-), h = |U|^2 - 1, in
    `COORDINATES`; the reset includes the sticking branch of the friction law.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    u : complex
        Impact point (|u| = 1).
    du_minus : complex
        Velocity just before the impact (approaching: Re(conj(u) du_minus) > 0).

    Returns
    -------
    S : numpy.ndarray
        4x4 real saltation matrix.
    du_plus : complex
        Velocity just after the impact.
    sticking : bool
        True when the friction impulse is capped at v_rel = 0 (S has rank 3).

    Raises
    ------
    ParameterError
        Unless ``params`` are `Parameters`, ``u`` a point of the stator (| |u| - 1 | <= `ON_STATOR_TOL`) and
        ``du_minus`` a finite velocity (|du_minus| <= `rotorcontact.analysis.equilibria.MAX_STATE`) that
        approaches it, not so nearly grazing that S is not finite.
    """
    u, du_minus = _impact_args(params, u, du_minus)
    with np.errstate(all="ignore"):
        out = _impact_saltation(params, u, du_minus)
    _finite_map(out[0], "du_minus", du_minus, f"it grazes the stator at u = {u!r}")
    return out


def _impact_saltation(params: Parameters, u: complex, du_minus: complex) -> tuple[np.ndarray, complex, bool]:
    u = complex(u)
    du_minus = complex(du_minus)
    hdot = _check_approach(u, du_minus)
    du_plus, dr, sticking = _reset_linearisation(params, u, du_minus)
    f_minus = _vec(du_minus, _accel(params, u, du_minus))
    f_plus = _vec(du_plus, _accel(params, u, du_plus))
    grad = np.array([u.real, u.imag, 0.0, 0.0])  # grad h / 2
    s = dr + np.outer(f_plus - dr @ f_minus, grad) / hdot
    return s, du_plus, sticking


def _sigma_projection(params: Parameters, u: complex, du_minus: complex) -> tuple[np.ndarray, np.ndarray]:
    """Variations on Sigma of a perturbed impact: d(theta, rdot-, thetadot-) and the impact-time shift.

    Returns the 3x4 matrix of d(theta, rdot, thetadot) at the perturbed impact
    and the 1x4 row of dt = -(grad h . dx) / (grad h . f-).
    """
    e = u / abs(u)
    hdot = (e.conjugate() * du_minus).real
    ddu = _accel(params, u, du_minus)
    proj = np.empty((3, 4))
    dt_row = np.empty(4)
    for j, (d_u, d_du) in enumerate(_basis()):
        dt = -(e.conjugate() * d_u).real / hdot
        d_us = d_u + du_minus * dt
        d_dus = d_du + ddu * dt
        dw = d_us.conjugate() * du_minus + e.conjugate() * d_dus
        proj[:, j] = [(e.conjugate() * d_us).imag, dw.real, dw.imag]
        dt_row[j] = dt
    return proj, dt_row


def _accumulation_map(params: Parameters, theta: float, rdot: float, thetadot: float):
    """The simulator's accumulation of impacts from the last resolved impact, and its derivatives.

    From the pre-impact state (theta, rdot, thetadot) on Sigma: the contact
    state (theta_c, thetadot_c) at the accumulation point, the length of the
    tail, and their gradients with respect to (theta, rdot, thetadot).
    """
    p = params
    d, mu, rr = p.d, p.mu, p.r_ratio
    v_rel = relative_velocity(rr, thetadot)
    slip = slip_bound(d, mu, rdot)
    r11, r12, r21, r22, sticking = reset_jacobian(v_rel, slip, d, mu, False)
    if sticking:
        tdp = -(rr + 1.0)
    else:
        sgn = 1.0 if v_rel >= 0.0 else -1.0
        tdp = thetadot - sgn * slip
    dtdp = np.array([0.0, r21, r22])  # d thetadot+ / d(theta, rdot, thetadot)
    n = contact_law.normal_force(theta, tdp, p.omega, p.rho, p.phi)
    dn_theta, dn_thetadot = contact_law.normal_force_gradient(theta, tdp, p.rho, p.phi)
    dn = dn_thetadot * dtdp + np.array([dn_theta, 0.0, 0.0])
    e_rd = np.array([0.0, 1.0, 0.0])
    t_tail, p_tail = contact_law.accumulation_tail(rdot, n, d, mu)
    if d < 1.0:
        dt_tail = 2.0 * d / (1.0 - d) * (e_rd / n - rdot * dn / (n * n))
        dp_tail = mu * (1.0 + d) * d / (1.0 - d) * e_rd
    else:
        dt_tail, dp_tail = np.zeros(3), np.zeros(3)
    # over the tail the smooth tangential force F acts for t_tail (as in the simulator)
    f_t = contact_law.free_tangential(theta, tdp, p.gamma, p.rho, p.phi)
    df_theta, df_thetadot = contact_law.free_tangential_gradient(theta, p.gamma, p.rho, p.phi)
    df_t = df_thetadot * dtdp + np.array([df_theta, 0.0, 0.0])
    vrel_p = relative_velocity(rr, tdp)
    s_p = math.copysign(1.0, vrel_p)
    if p_tail < abs(vrel_p):
        td_acc = tdp + f_t * t_tail - s_p * p_tail
        dtd_acc = dtdp + df_t * t_tail + f_t * dt_tail - s_p * dp_tail
    else:
        td_acc = f_t * t_tail - (rr + 1.0)
        dtd_acc = df_t * t_tail + f_t * dt_tail
    theta_c = theta + 0.5 * (tdp + td_acc) * t_tail
    dtheta_c = np.array([1.0, 0.0, 0.0]) + 0.5 * (dtdp + dtd_acc) * t_tail + 0.5 * (tdp + td_acc) * dt_tail
    return (theta_c, td_acc, t_tail), np.vstack([dtheta_c, dtd_acc]), dt_tail


def accumulation_saltation(
    params: Parameters, u: complex, du_minus: complex, contact_field: np.ndarray
) -> np.ndarray:
    """2x4 tangent map from the flight into continuous contact across an accumulation of impacts.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    u, du_minus : complex
        The last resolved impact: its point and the velocity just before it.
    contact_field : array_like
        (thetadot, theta'') of the contact phase that follows, at the
        accumulation point.

    Returns
    -------
    numpy.ndarray
        d(theta, thetadot) at the (nominal) accumulation time as a function of
        the 4-dimensional variation just before the impact; rank 2.

    Raises
    ------
    ParameterError
        As `impact_saltation` for ``params``, ``u`` and ``du_minus``; unless ``contact_field`` is 2 finite real
        numbers; where the map is not finite (a grazing impact, no normal force after it).
    """
    u, du_minus = _impact_args(params, u, du_minus)
    g = _contact_vector(contact_field)
    try:
        with np.errstate(all="ignore"):
            out = _accumulation_saltation(params, u, du_minus, g)
    except ZeroDivisionError:
        out = None
    return _finite_map(out, "du_minus", du_minus, f"the accumulation it starts at u = {u!r} is singular "
                       "(a grazing impact, or no normal force after it)")


def _accumulation_saltation(
    params: Parameters, u: complex, du_minus: complex, contact_field: np.ndarray
) -> np.ndarray:
    e = u / abs(u)
    w = e.conjugate() * du_minus
    theta = math.atan2(e.imag, e.real)
    proj, dt_row = _sigma_projection(params, u, du_minus)
    _y, dy, dt_tail = _accumulation_map(params, theta, w.real, w.imag)
    g = np.asarray(contact_field, dtype=float)
    return dy @ proj - np.outer(g, dt_row + dt_tail @ proj)


def contact_projection(u: complex, du: complex) -> np.ndarray:
    """2x4 map from (dU, dU') to (dtheta, dthetadot) at a point of the stator (|U| = 1).

    dtheta = Im(conj(e) dU) and dthetadot = Im(dw) - 2 thetadot dr with
    w = conj(U) U' = r rdot + i r^2 thetadot; the normal variations are dropped.

    Raises
    ------
    ParameterError
        Unless ``u`` is a point of the stator (| |u| - 1 | <= `ON_STATOR_TOL`) and ``du`` a finite velocity
        (|du| <= `rotorcontact.analysis.equilibria.MAX_STATE`).
    """
    return _contact_projection(_stator_point("u", u), _velocity("du", du))


def _contact_projection(u: complex, du: complex) -> np.ndarray:
    e = u / abs(u)
    thetadot = (e.conjugate() * du).imag
    out = np.empty((2, 4))
    for j, (d_u, d_du) in enumerate(_basis()):
        dw = d_u.conjugate() * du + e.conjugate() * d_du
        out[:, j] = [(e.conjugate() * d_u).imag, dw.imag - 2.0 * thetadot * (e.conjugate() * d_u).real]
    return out


def liftoff_saltation(params: Parameters, theta: float, thetadot: float, contact_field: np.ndarray) -> np.ndarray:
    """4x2 tangent map from continuous contact into free flight at lift-off (N = 0).

    S = E + (f_free - E g) (grad N)^T / (grad N . g), with E the embedding of
    (dtheta, dthetadot) in `COORDINATES`, g the contact field before lift-off
    and f_free the free-flight field at the lift-off point. Where N is not
    decreasing along g (a lift-off at the start of a contact attempt), the
    plain embedding is returned.

    Raises
    ------
    ParameterError
        Unless ``params`` are `Parameters`, ``theta`` is a finite real number, ``thetadot`` one with
        |thetadot| <= `rotorcontact.analysis.equilibria.MAX_STATE` and ``contact_field`` 2 finite real numbers;
        where the lift-off is so nearly tangent (grad N . g -> 0-) that S is not finite.
    """
    theta, thetadot, params = _contact_args(theta, thetadot, params)
    g = _contact_vector(contact_field)
    with np.errstate(all="ignore"):
        out = _liftoff_saltation(params, theta, thetadot, g)
    return _finite_map(out, "contact_field", contact_field, "N = 0 is reached tangentially along it")


def _liftoff_saltation(params: Parameters, theta: float, thetadot: float, contact_field: np.ndarray) -> np.ndarray:
    e = complex(math.cos(theta), math.sin(theta))
    emb = np.column_stack([_vec(1j * e, -thetadot * e), _vec(0j, 1j * e)])
    g = np.asarray(contact_field, dtype=float)
    grad_n = _normal_gradient(params, theta, thetadot)
    rate = float(grad_n @ g)
    if not rate < 0.0:
        return emb
    du = 1j * thetadot * e
    f_free = _vec(du, _accel(params, e, du))
    return emb + np.outer(f_free - emb @ g, grad_n) / rate


# ---------------------------------------------------------------------------
# Benettin bookkeeping
# ---------------------------------------------------------------------------


class _Tangent:
    """Orthonormal tangent basis with the running sums of log |R_ii|."""

    def __init__(self, dim: int, active: bool):
        self.q = np.eye(dim)
        self.sums = np.zeros(DIM)
        self.active = active
        self.n_qr = 0

    @property
    def alive(self) -> int:
        return self.q.shape[1]

    def apply(self, m: np.ndarray, rank: int | None = None) -> None:
        """Apply the linear map ``m`` to the basis and re-orthonormalise; keep at most ``rank`` columns."""
        y = m @ self.q
        if y.shape[1] == 0:
            self.q = y
            return
        q, r = np.linalg.qr(y)
        keep = min(y.shape[0], y.shape[1])
        if rank is not None:
            keep = min(keep, rank)
        diag = np.abs(np.diag(r))[:keep]
        with np.errstate(divide="ignore"):
            logs = np.log(diag)
        if self.active:
            self.sums[:keep] += logs
        self.q = q[:, :keep]
        self.n_qr += 1

    def complete(self) -> None:
        """Complete the basis to a full orthonormal basis of its space and start the sums."""
        dim, m = self.q.shape
        if m < dim:
            q, _ = np.linalg.qr(np.hstack([self.q, np.eye(dim)]))
            self.q = q[:, :dim]
        self.sums = np.zeros(DIM)
        self.active = True


class _Product(_Tangent):
    """The product of the tangent maps themselves (no re-orthonormalisation)."""

    def apply(self, m: np.ndarray, rank: int | None = None) -> None:
        self.q = m @ self.q

    def complete(self) -> None:
        self.active = True


# ---------------------------------------------------------------------------
# Result
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class LyapunovResult:
    """The Lyapunov spectrum of a trajectory.

    Attributes
    ----------
    exponents : tuple of float
        The four exponents of the state `COORDINATES`, largest first, in
        units of 1 / (dimensionless time). ``-inf`` for directions that the
        dynamics annihilates (the normal directions on entering continuous
        contact, the slip direction of a sticking impact or of rolling).
    time : float
        Length of the averaging window.
    t_start, t_stop : float
        The averaging window.
    n_impacts : int
        Number of impacts in the window.
    collapsed : int
        Number of annihilated directions (exponents equal to -inf).
    aligned : bool
        True when the window runs from impact to impact.
    trajectory : Trajectory
        The trajectory the spectrum was computed along.
    errors : tuple of float
        Error estimate of each exponent (same order): the standard error of
        the mean of the exponents over `rotorcontact.analysis.regime_change.SUBWINDOWS`
        sub-windows of the window (cut at impacts when the window runs from
        impact to impact); 0 for -inf exponents, inf when the window cannot
        be cut.
    regime_change : bool
        True when the motion settled on its final regime inside the window
        (a chaotic transient that ends in rolling, a transient that settles on
        a periodic orbit): ``exponents`` then average over two regimes, and
        ``final_exponents`` are those of the final one.
    final_regime : str or None
        The regime the run ends in (`rotorcontact.analysis.regime_change.final_regime`:
        ``"contact"``, ``"no-contact"``, ``"periodic"``), None when unsettled.
    regime_start : float or None
        Time at which the final regime began.
    final_exponents, final_errors : tuple of float or None
        The spectrum over the final regime alone (from ``max(regime_start,
        t_start)`` to the end of the window) and its error estimate.
    """

    exponents: tuple[float, ...]
    time: float
    t_start: float
    t_stop: float
    n_impacts: int
    collapsed: int
    aligned: bool
    trajectory: Trajectory = field(repr=False)
    errors: tuple[float, ...] = ()
    regime_change: bool = False
    final_regime: str | None = None
    regime_start: float | None = None
    final_exponents: tuple[float, ...] | None = None
    final_errors: tuple[float, ...] | None = None

    @property
    def coordinates(self) -> tuple[str, ...]:
        """Coordinates of the state whose spectrum this is."""
        return COORDINATES

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data; -inf exponents become None."""
        return {
            "exponents": [x if math.isfinite(x) else None for x in self.exponents],
            "time": self.time,
            "t_start": self.t_start,
            "t_stop": self.t_stop,
            "n_impacts": self.n_impacts,
            "collapsed": self.collapsed,
            "aligned": self.aligned,
            "coordinates": list(COORDINATES),
            "status": self.trajectory.status,
            "errors": _json_list(self.errors),
            "regime_change": self.regime_change,
            "final_regime": self.final_regime,
            "regime_start": self.regime_start,
            "final_exponents": None if self.final_exponents is None else _json_list(self.final_exponents),
            "final_errors": None if self.final_errors is None else _json_list(self.final_errors),
        }


def _json_list(values) -> list[float | None]:
    """Finite values as they are, infinite ones as None."""
    return [float(x) if math.isfinite(x) else None for x in values]


# ---------------------------------------------------------------------------
# Walking a trajectory
# ---------------------------------------------------------------------------


class _Walker:
    """Replays a trajectory's flights, impacts and contact phases in time order."""

    def __init__(self, traj: Trajectory, t_transient: float, qr_interval: float, align: bool):
        self.traj = traj
        self.p = traj.params
        self.fl = traj.flights
        self.ct = traj.contacts
        self.im = traj.records
        self.path = traj.path
        self.t_transient = t_transient
        self.qr = qr_interval
        self.align = align
        self.tan = _Tangent(DIM, active=False)
        self.t_start: float | None = None
        self.snapshots: list[tuple[float, np.ndarray, int]] = []
        #: (time, running sums) after every map once the window has opened, in time order
        self.marks: list[tuple[float, np.ndarray]] = []
        self.n_impacts = 0

    # -- the window ---------------------------------------------------------

    def _maybe_start(self, t: float) -> None:
        if self.t_start is None and t >= self.t_transient:
            self.tan.complete()
            self.t_start = t
            self._mark(t)

    def _mark(self, t: float) -> None:
        if self.t_start is not None:
            self.marks.append((float(t), self.tan.sums.copy()))

    def _advance_time(self, t0: float, t1: float, step) -> None:
        """Advance over [t0, t1] by maps step(a, b), with QR at least every qr_interval and at t_transient."""
        t = t0
        while t < t1:
            t_next = min(t1, t + self.qr)
            if self.t_start is None and t < self.t_transient < t_next:
                t_next = self.t_transient
            step(t, t_next)
            t = t_next
            self._mark(t)
            self._maybe_start(t)

    # -- phases -------------------------------------------------------------

    def _flight(self, t0: float, t1: float) -> None:
        self._maybe_start(t0)
        self._advance_time(t0, t1, lambda a, b: self.tan.apply(_flight_tangent(self.p, b - a)))

    def _impact(self, row: np.ndarray) -> tuple[complex, complex]:
        t = float(row[0])
        self._maybe_start(t)
        u = complex(row[9], row[10])
        du_minus = u * complex(row[2], row[3])
        if self.tan.active:
            self.snapshots.append((t, self.tan.sums.copy(), self.tan.alive))
            self.n_impacts += 1
        self._mark(t)
        return u, du_minus

    def _slide(self, c: np.ndarray) -> None:
        t0, t1 = float(c[0]), float(c[1])
        sgn = 1.0 if int(c[2]) == SLIDE_FORWARD else -1.0
        first = self.path[int(c[3])]
        state = np.array([first[1], first[2]])
        p = self.p

        def rhs(_t, z):
            th, thd = z[0], z[1]
            jac = _contact_jacobian(p, th, thd, sgn)
            phi = z[2:].reshape(2, 2)
            return np.concatenate([[thd, _contact_accel(p, th, thd, sgn)], (jac @ phi).ravel()])

        def step(a, b):
            nonlocal state
            if b <= a:
                return
            z0 = np.concatenate([state, np.eye(2).ravel()])
            sol = solve_ivp(rhs, (a, b), z0, method="DOP853", rtol=CONTACT_RTOL, atol=CONTACT_ATOL)
            state = sol.y[:2, -1]
            self.tan.apply(sol.y[2:, -1].reshape(2, 2))

        self._maybe_start(t0)
        self._advance_time(t0, t1, step)

    def _contact_field(self, kind: int, row: np.ndarray) -> np.ndarray:
        """(thetadot, theta'') of a contact phase at a path row."""
        if kind == ROLLING:
            return np.array([row[2], 0.0])
        return np.array([row[2], row[3]])

    # -- main loop ----------------------------------------------------------

    def run(self) -> None:
        fl, ct, im, p = self.fl, self.ct, self.im, self.p
        n_f, n_c, n_i = fl.shape[0], ct.shape[0], im.shape[0]
        t_stop = self.traj.t_stop
        jf, ic, ii = 0, 0, 0
        while jf < n_f:
            t0 = float(fl[jf, 0])
            nxt = jf + 1
            if (
                ii < n_i
                and nxt < n_f
                and im[ii, 0] == fl[nxt, 0]
                and im[ii, 0] >= t0
                and np.array_equal(im[ii, 9:13], fl[nxt, 1:5])
            ):
                t_i = float(im[ii, 0])
                self._flight(t0, t_i)
                u, du_minus = self._impact(im[ii])
                ii += 1
                if ic < n_c and ct[ic, 0] == t_i:
                    # impacts accumulate: into continuous contact
                    t_c = t_i
                    if int(ct[ic, 2]) == ACCUMULATION:
                        t_c = float(ct[ic, 1])
                        ic += 1
                    g = self._first_contact_field(ic, t_c, u, du_minus)
                    self.tan.apply(_accumulation_saltation(p, u, du_minus, g))
                    self._mark(t_c)
                    jf, ic = self._contact(nxt + 1, ic, t_c)
                    continue
                s, _du_plus, sticking = _impact_saltation(p, u, du_minus)
                self.tan.apply(s, rank=3 if sticking else None)
                self._mark(t_i)
                jf = nxt
                continue
            if ic < n_c and ct[ic, 0] == t0 and int(ct[ic, 2]) != ACCUMULATION:
                # a flight starting on the stator with no normal velocity, pressed outwards
                u = complex(fl[jf, 1], fl[jf, 2])
                du = complex(fl[jf, 3], fl[jf, 4])
                self._maybe_start(t0)
                self.tan.apply(_contact_projection(u, du))
                self._mark(t0)
                jf, ic = self._contact(nxt, ic, t0)
                continue
            if nxt < n_f:
                # a touch without impulse (or an immediate lift-off): the state is continuous
                self._flight(t0, float(fl[nxt, 0]))
                jf = nxt
                continue
            self._flight(t0, t_stop)
            break

    def _first_contact_field(self, ic: int, t_c: float, u: complex, du_minus: complex) -> np.ndarray:
        """Field of the contact phase that starts at t_c (sliding in the sign of v_rel if none is recorded)."""
        ct = self.ct
        if ic < ct.shape[0] and ct[ic, 0] == t_c:
            kind = int(ct[ic, 2])
            return self._contact_field(kind, self.path[int(ct[ic, 3])])
        p = self.p
        e = u / abs(u)
        w = e.conjugate() * du_minus
        theta = math.atan2(e.imag, e.real)
        (theta_c, thetadot_c, _t), _dy, _dt = _accumulation_map(p, theta, w.real, w.imag)
        sgn = 1.0 if p.r_ratio + 1.0 + thetadot_c >= 0.0 else -1.0
        return np.array([thetadot_c, _contact_accel(p, theta_c, thetadot_c, sgn)])

    def _contact(self, next_flight: int, ic: int, t: float) -> tuple[int, int]:
        """Walk the contact phases from time t; return the flight after lift-off (or past the end) and ic."""
        fl, ct, p = self.fl, self.ct, self.p
        n_f, n_c = fl.shape[0], ct.shape[0]
        prev_kind: int | None = None
        prev_row: np.ndarray | None = None
        while True:
            starts_phase = ic < n_c and ct[ic, 0] == t and int(ct[ic, 2]) != ACCUMULATION
            lifts = next_flight < n_f and fl[next_flight, 0] == t
            if lifts and starts_phase:
                # lift-off and immediate return onto the stator: no flight in between
                next_flight += 1
                continue
            if starts_phase:
                c = ct[ic]
                kind = int(c[2])
                first = self.path[int(c[3])]
                if prev_kind is not None and kind != prev_kind and kind != ROLLING and prev_kind != ROLLING:
                    # reversal of sliding across v_rel = 0 without rolling
                    a_minus, a_plus = float(prev_row[3]), float(first[3])
                    if a_minus != 0.0:
                        self.tan.apply(np.diag([1.0, a_plus / a_minus]))
                        self._mark(float(c[0]))
                self._maybe_start(float(c[0]))
                if kind == ROLLING:
                    self.tan.apply(np.diag([1.0, 0.0]), rank=1)
                    # dtheta is constant while rolling: the window may open inside the phase,
                    # and a basis completed there lies in the rolling tangent space again
                    waiting = self.t_start is None
                    self._maybe_start(min(float(c[1]), max(float(c[0]), self.t_transient)))
                    if waiting and self.t_start is not None:
                        self.tan.apply(np.diag([1.0, 0.0]), rank=1)
                    self._mark(max(float(c[0]), self.t_start if self.t_start is not None else -math.inf))
                else:
                    self._slide(c)
                prev_kind = kind
                prev_row = self.path[int(c[4])]
                t = float(c[1])
                ic += 1
                continue
            if lifts:
                u = complex(fl[next_flight, 1], fl[next_flight, 2])
                du = complex(fl[next_flight, 3], fl[next_flight, 4])
                theta = math.atan2(u.imag, u.real)
                thetadot = (u.conjugate() * du).imag
                if prev_kind is None:
                    sgn = 1.0 if p.r_ratio + 1.0 + thetadot >= 0.0 else -1.0
                    g = np.array([thetadot, _contact_accel(p, theta, thetadot, sgn)])
                else:
                    g = self._contact_field(prev_kind, prev_row)
                self._maybe_start(t)
                self.tan.apply(_liftoff_saltation(p, theta, thetadot, g))
                self._mark(t)
                return next_flight, ic
            # the run ends in contact
            return n_f, ic

    # -- result -------------------------------------------------------------

    def result(self) -> LyapunovResult:
        traj = self.traj
        tan = self.tan
        t_stop = traj.t_stop
        if self.t_start is None:
            raise ParameterError(
                f"t_transient = {self.t_transient!r} leaves no averaging window (the run reached "
                f"t = {t_stop!r}); allowed: t_transient < t_end"
            )
        snaps = self.snapshots
        aligned = False
        if self.align and len(snaps) >= 2 and snaps[-1][0] > snaps[0][0]:
            # impact to impact only where the impacts fill the window: the ends left out are
            # shorter than the longest interval between impacts (not, say, a run ending in contact)
            gap = max(b[0] - a[0] for a, b in zip(snaps, snaps[1:]))
            aligned = snaps[0][0] - self.t_start <= gap and t_stop - snaps[-1][0] <= gap
        if aligned:
            t_a, sums_a, _alive_a = snaps[0]
            t_b, sums_b, alive = snaps[-1]
            sums = sums_b - sums_a
            n_imp = len(snaps) - 1
        else:
            t_a, t_b = self.t_start, t_stop
            sums, alive = tan.sums, tan.alive
            n_imp = self.n_impacts
        time = t_b - t_a
        if not time > 0.0:
            raise ParameterError(
                f"the averaging window [{t_a!r}, {t_b!r}] is empty; allowed: t_transient < t_end"
            )
        exps, errors = self._spectrum(sums[:alive] / time, self._rates(t_a, t_b, aligned, after=False), alive)
        change = self._final(t_a, t_b, aligned, alive)
        return LyapunovResult(
            exponents=exps,
            time=float(time),
            t_start=float(t_a),
            t_stop=float(t_b),
            n_impacts=int(n_imp),
            collapsed=DIM - alive,
            aligned=bool(aligned),
            trajectory=traj,
            errors=errors,
            **change,
        )

    @staticmethod
    def _spectrum(means: np.ndarray, rates: np.ndarray | None, alive: int):
        """Exponents largest first (-inf for annihilated directions) and their errors in the same order."""
        order = np.argsort(-means, kind="stable")
        err = _spread(rates[:, :alive]) if rates is not None else np.full(alive, math.inf)
        exps = tuple([float(means[i]) for i in order] + [-math.inf] * (DIM - alive))
        errors = tuple([float(err[i]) for i in order] + [0.0] * (DIM - alive))
        return exps, errors

    def _sums_at(self, t: float, after: bool) -> np.ndarray:
        """Running sums at time t: before (the first mark at t) or after (the last mark at t) the maps at t."""
        times = np.array([m[0] for m in self.marks])
        i = int(np.searchsorted(times, t, side="right" if after else "left"))
        if after and i > 0 and times[i - 1] == t:
            return self.marks[i - 1][1]
        if not after and i < len(times) and times[i] == t:
            return self.marks[i][1]
        i = min(max(i, 1), len(times) - 1)
        (t0, s0), (t1, s1) = self.marks[i - 1], self.marks[i]
        return s0 + (s1 - s0) * ((t - t0) / (t1 - t0)) if t1 > t0 else s1

    def _rates(self, t_a: float, t_b: float, at_impacts: bool, after: bool) -> np.ndarray | None:
        """Exponents over the sub-windows of [t_a, t_b] (cut at impacts when ``at_impacts``); None if it cannot be cut."""
        if at_impacts:
            t_imp = np.array([s[0] for s in self.snapshots if t_a <= s[0] <= t_b])
            if t_imp.size < 3:
                return None
            edges = np.unique(t_imp[np.round(np.linspace(0, t_imp.size - 1, SUBWINDOWS + 1)).astype(int)])
        else:
            edges = np.linspace(t_a, t_b, SUBWINDOWS + 1)
        if edges.size < 3 or len(self.marks) < 2:
            return None
        times = np.array([m[0] for m in self.marks])
        sums = np.array([m[1] for m in self.marks])
        rates = _subwindow_rates(times, sums, edges)
        if after:
            # the first sub-window starts after the maps at t_a (entering a contact phase)
            first = (self._sums_at(edges[1], False) - self._sums_at(t_a, True)) / (edges[1] - t_a)
            rates[0] = first
        return rates

    def _final(self, t_a: float, t_b: float, aligned: bool, alive: int) -> dict[str, Any]:
        """The final regime of the run, whether it began inside the window, and its own spectrum."""
        regime = final_regime(self.traj)
        if regime is None:
            return {}
        out: dict[str, Any] = {"final_regime": regime.kind, "regime_start": float(regime.t_begin),
                               "regime_change": bool(regime.t_begin > t_a)}
        periodic = regime.kind == "periodic"
        t0 = max(regime.t_begin, t_a)
        t1 = t_b
        if periodic and self.snapshots:
            t1 = self.snapshots[-1][0]
        if not t1 > t0:
            return out
        start = self._sums_at(t0, after=not periodic)
        end = self._sums_at(t1, after=False) if periodic else self.tan.sums
        means = (end - start)[:alive] / (t1 - t0)
        exps, errors = self._spectrum(means, self._rates(t0, t1, periodic, after=not periodic), alive)
        out.update(final_exponents=exps, final_errors=errors)
        return out


# ---------------------------------------------------------------------------
# Public API
# ---------------------------------------------------------------------------


MAX_T_END = 1e6  # tangent propagation in contact is integrated; longer runs would not end in bounded time
MAX_QR_STEPS = 1e6


def _check_options(t_transient, qr_interval, t_end: float | None = None) -> tuple[float, float]:
    t_transient = check_range("t_transient", t_transient, low=0.0)
    qr_interval = check_range("qr_interval", qr_interval, low=0.0, low_open=True)
    if t_end is not None:
        check_range("t_end", t_end, low=0.0, high=MAX_T_END, low_open=True)
        if t_end / qr_interval > MAX_QR_STEPS:
            raise ParameterError(
                f"qr_interval = {qr_interval!r} is too small for t_end = {t_end!r}; allowed: "
                f"qr_interval >= t_end / {MAX_QR_STEPS:g} = {t_end / MAX_QR_STEPS:g}"
            )
    return t_transient, qr_interval


def trajectory_lyapunov(
    traj: Trajectory, *, t_transient: float = 0.0, qr_interval: float = 1.0, align: bool = True
) -> LyapunovResult:
    """Lyapunov spectrum along an existing trajectory of `rotorcontact.simulation.simulator`.

    Parameters
    ----------
    traj : Trajectory
        A simulated trajectory (run with ``on_chatter="contact"``).
    t_transient : float
        Initial time discarded from the averages.
    qr_interval : float
        Longest time between re-orthonormalisations (QR is also done at every
        impact and switch).
    align : bool
        Average from impact to impact when impacts fill the window (module docstring).

    Returns
    -------
    LyapunovResult
    """
    check_type("traj", traj, Trajectory, "a Trajectory (rotorcontact.simulate)")
    align = check_bool("align", align)
    t_transient, qr_interval = _check_options(t_transient, qr_interval, traj.t_stop)
    if traj.status == "chatter":
        raise ParameterError(
            "the trajectory stopped at an accumulation of impacts (on_chatter='stop'); "
            "allowed: a trajectory simulated with on_chatter='contact'"
        )
    if t_transient >= traj.t_stop:
        early = "" if traj.status == "completed" else f", where it stopped early ({traj.status}: {traj.message})"
        raise ParameterError(
            f"t_transient = {t_transient!r} is not below the end of the run t = {traj.t_stop!r}{early}; "
            "allowed: t_transient below the end of the run"
        )
    walker = _Walker(traj, t_transient, qr_interval, align)
    walker.run()
    return walker.result()


def trajectory_tangent(traj: Trajectory) -> np.ndarray:
    """The tangent map of a whole trajectory: d(final state) / d(initial state).

    The product of the same maps that `trajectory_lyapunov` re-orthonormalises:
    flights, impact saltations, the accumulation into contact, the contact
    variational equations and lift-off. The initial state is
    (Re U, Im U, Re U', Im U') at t = 0; the final state is the same
    4-vector at ``traj.t_stop`` when the run ends in flight, and
    (theta, thetadot) when it ends in continuous contact. Meant for checks
    against perturbed simulations over short runs.

    Returns
    -------
    numpy.ndarray
        4x4 (ends in flight), 2x4 (ends in contact).
    """
    if not isinstance(traj, Trajectory):
        raise ParameterError(f"traj = {traj!r} is not a Trajectory")
    if traj.status == "chatter":
        raise ParameterError(
            "the trajectory stopped at an accumulation of impacts (on_chatter='stop'); "
            "allowed: a trajectory simulated with on_chatter='contact'"
        )
    walker = _Walker(traj, 0.0, math.inf, False)
    walker.tan = _Product(DIM, active=True)
    walker.t_start = 0.0
    walker.run()
    return walker.tan.q


def lyapunov_spectrum(
    params: Parameters,
    u0: complex = 0j,
    du0: complex = 0j,
    t_end: float = 2000.0,
    *,
    t_transient: float | None = None,
    qr_interval: float = 1.0,
    align: bool = True,
    max_events: int = 10_000_000,
) -> LyapunovResult:
    """The full Lyapunov spectrum of the 4-dimensional state along a simulated trajectory.

    Simulates from (U, U') = (u0, du0) up to ``t_end`` with
    `rotorcontact.simulation.simulator` and propagates tangent vectors exactly along it,
    with the saltation corrections at impacts and at the transitions into and
    out of continuous contact (module docstring).

    Parameters
    ----------
    params : Parameters
        Model parameters.
    u0, du0 : complex or (float, float)
        Initial state in the co-rotating frame.
    t_end : float
        Length of the run, > 0.
    t_transient : float, optional
        Time discarded from the averages; default a quarter of ``t_end``.
    qr_interval : float
        Longest time between re-orthonormalisations.
    align : bool
        Average from impact to impact when impacts fill the window (module docstring).
    max_events : int
        Passed to `rotorcontact.simulation.simulator`.

    Returns
    -------
    LyapunovResult
        Exponents of `COORDINATES`, largest first (-inf for annihilated directions).
    """
    check_params(params)
    align = check_bool("align", align)
    t_end = check_range("t_end", t_end, low=0.0, low_open=True)
    if t_transient is None:
        t_transient = 0.25 * t_end
    t_transient, qr_interval = _check_options(t_transient, qr_interval, t_end)
    if t_transient >= t_end:
        raise ParameterError(f"t_transient = {t_transient!r} is not below t_end = {t_end!r}; allowed: [0, t_end)")
    traj = simulate(params, u0, du0, t_end, on_chatter="contact", max_events=max_events)
    if traj.status == "failed":
        raise RuntimeError(f"the simulation failed: {traj.message}")
    return trajectory_lyapunov(traj, t_transient=t_transient, qr_interval=qr_interval, align=align)
