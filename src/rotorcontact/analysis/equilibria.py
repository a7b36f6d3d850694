"""Equilibria of the rotor model and their boundary equilibrium bifurcations (MODEL.md §4).

Three kinds of equilibria of the co-rotating system:

* the **regular equilibrium** x_R, the contact-free synchronous whirl U = k;
* the **pseudo-equilibria** x_P1 and x_P2, synchronous forward whirl rub: the
  rotor rests on the stator (r = 1, rdot = 0, thetadot = 0) in continuous
  contact, held there by the normal force N and slipping against friction;
* the **boundary equilibrium** x_B, the regular equilibrium touching the stator
  (|k| = 1), at gamma* = sqrt(rho^2 - (1 - omega^2)^2).

The state of the free-flight field is x = (r, theta, rdot, thetadot) (MODEL.md
§2); ``polar_field`` is F, ``polar_jacobian`` is F_x. The boundary is H = 1 - r
(H > 0 inside the clearance) and W = (0, 0, 1 + d, mu (1 + d) sgn(v_rel)) is the
direction of the velocity jump of an impact (x+ = x- - rdot- W) and of the
contact force in continuous contact (x' = F(x) - eta W with N = (1 + d) eta).

Boundary equilibrium bifurcation (see docs/equilibria.md). Near gamma*, with
eps = gamma - gamma*, the regular equilibrium has H(x_R) = tau eps + O(eps^2)
and the pseudo-equilibrium that meets it has eta = H(x_R) / c + O(eps^2), where

    tau = H_gamma - H_x F_x^{-1} F_gamma      (transversality, != 0)
    c   = -H_x F_x^{-1} W                     (!= 0)

are evaluated numerically at x_B. x_R is admissible where H(x_R) > 0 and the
pseudo-equilibrium where eta > 0. So c > 0 gives a **non-smooth fold** (both
admissible on one side of gamma*, both virtual on the other) and c < 0 gives
**persistence** (x_R turns into the pseudo-equilibrium). The row vector H_x is the one in
front of F_x^{-1} W (MODEL.md §4; docs/equilibria.md on the form with H_gamma sometimes written).

Analytically (`beb_omega_ranges`), c = (1 + d) (1 - omega^2 - mu gamma*) / rho^2,
so the bifurcation is a non-smooth fold for
1 - rho < omega^2 < 1 - mu rho / sqrt(1 + mu^2) and persistence for
1 - mu rho / sqrt(1 + mu^2) < omega^2 < 1 + rho. The partner of x_R is x_P1 in
the non-smooth fold and x_P2 in persistence.

Angles are in (-pi, pi]. Where an object does not exist (no real gamma*, no
real arccos for the pseudo-equilibria, the undamped resonance) the results say
so (``exists`` / ``None`` fields and a ``reason``) rather than holding NaN.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Literal, Sequence

import numpy as np
from scipy.optimize import brentq

from ..model.angles import angle_difference, point_angle, wrap_angle
from ..errors import ParameterError
from ..model import contact_law
from ..model.flow import flight_coefficients, has_regular_equilibrium
from ..model.impact_law import impact_q, relative_velocity
from ..model.params import BRANCH_PARAMETERS, MAX_MAGNITUDE, Parameters, check_finite
from ..model.validation import (MAX_EQUILIBRIUM_POINTS, check_choice, check_float, check_int, check_params, quoted,
                                real_array)

__all__ = [
    "STATE_NAMES",
    "BRANCH_PARAMETERS",
    "PSEUDO_NAMES",
    "friction_sign",
    "polar_field",
    "polar_jacobian",
    "polar_field_gamma",
    "boundary_function_gradient",
    "impact_direction",
    "normal_force",
    "contact_field",
    "contact_jacobian",
    "system_matrix",
    "RegularEquilibrium",
    "PseudoEquilibrium",
    "BoundaryEquilibrium",
    "Equilibria",
    "BEBOmegaRanges",
    "EquilibriumEvent",
    "BranchEvent",
    "PseudoBranch",
    "EquilibriumBranches",
    "regular_equilibrium",
    "pseudo_equilibria",
    "boundary_gamma",
    "boundary_equilibrium",
    "beb_omega_ranges",
    "classify_beb_analytic",
    "equilibria",
    "equilibrium_branches",
]

#: Names of the components of the polar state x.
STATE_NAMES = ("r", "theta", "rdot", "thetadot")

#: Names of the pseudo-equilibria, in the order MODEL.md §4 gives them.
PSEUDO_NAMES = ("P1", "P2")

BEBKind = Literal["nonsmooth-fold", "persistence"]

# Relative tolerance below which a non-degeneracy quantity counts as zero.
_DEGENERACY_RTOL = 1e-10


def _at_border(omega_sq: float, border: float) -> bool:
    """Whether omega^2 is within the degeneracy tolerance of a border of the boundary equilibrium's omega-ranges
    (`BEBOmegaRanges`): the numerical classification and the analytic one count a border alike."""
    return abs(omega_sq - border) <= _DEGENERACY_RTOL * (1.0 + omega_sq)

#: Largest magnitude of r, rdot and thetadot in a state given to the fields, and 1 / the smallest r: a million
#: times the fastest motion of the model (|U'| <= `rotorcontact.model.params.MAX_VELOCITY`, the rolling rate
#: 1 + r_ratio <= 1 + `rotorcontact.model.params.MAX_MAGNITUDE`). Within it the fields and their Jacobians are
#: far from overflow; closer to r = 0 the polar coordinates are singular (the field grows like 1 / r^2).
MAX_STATE = 1e12


# ---------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------


def _check_rate(name: str, value: Any) -> float:
    """``value`` as a float if it is a finite real number with |value| <= `MAX_STATE` (an angular velocity)."""
    return check_float(name, value, -MAX_STATE, MAX_STATE)


def _contact_args(theta: Any, thetadot: Any, params: Any) -> tuple[float, float, Parameters]:
    """The arguments (theta, thetadot, params) of the contact fields, checked: a finite angle, an angular
    velocity (`_check_rate`) and `Parameters`."""
    return check_float("theta", theta), _check_rate("thetadot", thetadot), check_params(params)


def _friction_sign(thetadot: float, params: Parameters) -> float:
    return float(np.sign(relative_velocity(params.r_ratio, thetadot)))


def friction_sign(thetadot: float, params: Parameters) -> float:
    """sgn(v_rel) with v_rel = r_ratio + 1 + thetadot (MODEL.md §2); 0 when v_rel = 0.

    Raises
    ------
    ParameterError
        Unless ``thetadot`` is a finite real number with |thetadot| <= `MAX_STATE` and ``params`` are `Parameters`.
    """
    return _friction_sign(_check_rate("thetadot", thetadot), check_params(params))


def _as_state(x: Sequence[float], params: Any) -> tuple[float, float, float, float]:
    """The polar state ``x`` as four floats, and ``params`` checked to be `Parameters`."""
    check_params(params)
    arr = real_array(x)
    allowed = (f"allowed: a polar state (r, theta, rdot, thetadot) of 4 finite real numbers with "
               f"{1.0 / MAX_STATE:g} <= r <= {MAX_STATE:g} and |rdot|, |thetadot| <= {MAX_STATE:g}")
    if arr is None or arr.shape != (4,) or not np.all(np.isfinite(arr)):
        raise ParameterError(f"x = {quoted(x)} is invalid; {allowed}")
    r, th, rd, thd = (float(v) for v in arr)
    if not 1.0 / MAX_STATE <= r <= MAX_STATE:
        why = ": the polar field is singular at r = 0" if r < 1.0 / MAX_STATE else ""
        raise ParameterError(f"x = {quoted(x)} is invalid (r = {r!r}{why}); {allowed}")
    if not (abs(rd) <= MAX_STATE and abs(thd) <= MAX_STATE):
        raise ParameterError(f"x = {quoted(x)} is invalid (rdot = {rd!r}, thetadot = {thd!r}); {allowed}")
    return r, th, rd, thd


# ---------------------------------------------------------------------------
# Vector fields and their Jacobians
# ---------------------------------------------------------------------------


def polar_field(x: Sequence[float], params: Parameters) -> np.ndarray:
    """The polar free-flight field F(x), x = (r, theta, rdot, thetadot) (MODEL.md §2).

    Parameters
    ----------
    x : sequence of 4 floats
        Polar state with r > 0.
    params : Parameters
        Model parameters.

    Returns
    -------
    numpy.ndarray
        (rdot, thetadot, rddot, thetaddot).

    Raises
    ------
    ParameterError
        Unless ``x`` is 4 finite real numbers with 1 / `MAX_STATE` <= r <= `MAX_STATE` and |rdot|, |thetadot|
        <= `MAX_STATE`, and ``params`` are `Parameters`.
    """
    r, th, rd, thd = _as_state(x, params)
    p = params
    psi = p.phi - th
    rdd = r * ((1.0 + thd) ** 2 - p.omega**2) - p.gamma * rd + p.rho * math.cos(psi)
    thdd = (-(1.0 + thd) * (p.gamma * r + 2.0 * rd) + p.rho * math.sin(psi)) / r
    return np.array([rd, thd, rdd, thdd])


def polar_jacobian(x: Sequence[float], params: Parameters) -> np.ndarray:
    """The 4x4 Jacobian F_x of `polar_field` at ``x`` (exact partial derivatives).

    Raises
    ------
    ParameterError
        As `polar_field`.
    """
    r, th, rd, thd = _as_state(x, params)
    p = params
    psi = p.phi - th
    s, c = math.sin(psi), math.cos(psi)
    w = 1.0 + thd
    jac = np.zeros((4, 4))
    jac[0, 2] = 1.0
    jac[1, 3] = 1.0
    jac[2] = [w * w - p.omega**2, p.rho * s, -p.gamma, 2.0 * r * w]
    jac[3] = [
        (2.0 * w * rd - p.rho * s) / (r * r),
        -p.rho * c / r,
        -2.0 * w / r,
        -p.gamma - 2.0 * rd / r,
    ]
    return jac


def polar_field_gamma(x: Sequence[float], params: Parameters) -> np.ndarray:
    """dF/dgamma, the derivative of `polar_field` with respect to gamma.

    Raises
    ------
    ParameterError
        As `polar_field`.
    """
    r, th, rd, thd = _as_state(x, params)
    return np.array([0.0, 0.0, -rd, -(1.0 + thd)])


def boundary_function_gradient() -> tuple[np.ndarray, float]:
    """(H_x, H_gamma) of the boundary function H = 1 - r (H > 0 inside the clearance)."""
    return np.array([-1.0, 0.0, 0.0, 0.0]), 0.0


def impact_direction(params: Parameters, thetadot: float = 0.0) -> np.ndarray:
    """W = (0, 0, 1 + d, mu (1 + d) sgn(v_rel)): the reset is x+ = x- - rdot- W (MODEL.md §2, §4).

    Raises
    ------
    ParameterError
        As `friction_sign`.
    """
    thetadot = _check_rate("thetadot", thetadot)
    check_params(params)
    q = impact_q(params.d, params.mu)
    return np.array([0.0, 0.0, q.real, q.imag * _friction_sign(thetadot, params)])


def normal_force(theta: float, thetadot: float, params: Parameters) -> float:
    """Normal force per unit mass in continuous contact, N = (1 + thetadot)^2 - omega^2 + rho cos(phi - theta).

    Raises
    ------
    ParameterError
        Unless ``theta`` is a finite real number, ``thetadot`` one with |thetadot| <= `MAX_STATE` and ``params``
        are `Parameters`.
    """
    return _normal_force(*_contact_args(theta, thetadot, params))


def _normal_force(theta: float, thetadot: float, p: Parameters) -> float:
    return float(contact_law.normal_force(theta, thetadot, p.omega, p.rho, p.phi))


def contact_field(theta: float, thetadot: float, params: Parameters) -> np.ndarray:
    """Continuous-contact dynamics on r = 1 (MODEL.md §4): (thetadot, thetaddot).

    thetaddot = -(1 + thetadot) gamma + rho sin(phi - theta) - mu N sgn(v_rel).

    Raises
    ------
    ParameterError
        As `normal_force`.
    """
    theta, thetadot, p = _contact_args(theta, thetadot, params)
    sgn = _friction_sign(thetadot, p)
    thdd = contact_law.sliding_accel(theta, thetadot, sgn, p.gamma, p.omega, p.rho, p.mu, p.phi)
    return np.array([thetadot, thdd])


def contact_jacobian(theta: float, thetadot: float, params: Parameters) -> np.ndarray:
    """2x2 Jacobian of `contact_field` in (theta, thetadot), sgn(v_rel) held at its value there.

    Raises
    ------
    ParameterError
        As `normal_force`.
    """
    return _contact_jacobian(*_contact_args(theta, thetadot, params))


def _contact_jacobian(theta: float, thetadot: float, p: Parameters) -> np.ndarray:
    sgn = _friction_sign(thetadot, p)
    return contact_law.sliding_field_jacobian(theta, thetadot, sgn, p.gamma, p.rho, p.mu, p.phi)


def system_matrix(params: Parameters) -> np.ndarray:
    """The complex 2x2 matrix A of the free flight w' = A w + b (MODEL.md §3).

    Raises
    ------
    ParameterError
        Unless ``params`` are `Parameters`.
    """
    check_params(params)
    a, b = flight_coefficients(params.gamma, params.omega)
    return np.array([[0.0, 1.0], [b, -2.0 * a]], dtype=complex)


def _by_name(items: Sequence[Any], name: Any) -> Any:
    """The item of ``items`` (pseudo-equilibria or their branches) named ``name``, one of `PSEUDO_NAMES`."""
    check_choice("name", name, PSEUDO_NAMES)
    return next(item for item in items if item.name == name)


def _sorted_eigenvalues(values: Iterable[complex]) -> tuple[complex, ...]:
    return tuple(sorted((complex(v) for v in values), key=lambda z: (round(z.real, 12), z.imag)))


def _linear_eigenvalues(params: Parameters) -> tuple[complex, ...]:
    """Eigenvalues of free flight as a real 4-dimensional system: those of A and their conjugates."""
    a = system_matrix(params)
    real_form = np.block([[a.real, -a.imag], [a.imag, a.real]])
    return _sorted_eigenvalues(np.linalg.eigvals(real_form))


# ---------------------------------------------------------------------------
# Result types
# ---------------------------------------------------------------------------


def _complex_list(values: Iterable[complex]) -> list[list[float]]:
    return [[float(z.real) + 0.0, float(z.imag) + 0.0] for z in values]  # + 0.0: no -0.0


@dataclass(frozen=True)
class RegularEquilibrium:
    """The regular equilibrium x_R: U = k, r = |k| (MODEL.md §4).

    Attributes
    ----------
    exists : bool
        False only at the undamped resonance (omega = 1, gamma = 0), where
        omega^2 - 1 + i gamma = 0 and no equilibrium exists.
    r : float or None
        |k|.
    theta : float or None
        arg k in (-pi, pi]; None where r = 0 (rho = 0), where the angle is undefined.
    u : complex or None
        k.
    admissible : bool
        r < 1 (inside the clearance). False where x_R does not exist.
    stable : bool
        All eigenvalues have negative real part (gamma > 0).
    eigenvalues : tuple of complex
        The four eigenvalues of the free flight linearised at x_R (those of A and
        their conjugates; equal to those of the polar Jacobian F_x at x_R).
    reason : str or None
        Why something is undefined, else None.
    """

    exists: bool
    r: float | None
    theta: float | None
    u: complex | None
    admissible: bool
    stable: bool
    eigenvalues: tuple[complex, ...]
    reason: str | None = None

    @property
    def state(self) -> np.ndarray | None:
        """The polar state (r, theta, 0, 0), or None where it is undefined."""
        if self.r is None or self.theta is None:
            return None
        return np.array([self.r, self.theta, 0.0, 0.0])

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data (the ``equilibria --json`` ``"regular"`` entry)."""
        return {
            "r": self.r,
            "theta": self.theta,
            "admissible": bool(self.admissible),
            "stable": bool(self.stable),
            "eigenvalues": _complex_list(self.eigenvalues),
            "exists": bool(self.exists),
            "reason": self.reason,
        }


@dataclass(frozen=True)
class PseudoEquilibrium:
    """A pseudo-equilibrium x_P1 or x_P2: r = 1, rdot = 0, thetadot = 0, in continuous contact.

    Attributes
    ----------
    name : str
        ``"P1"`` or ``"P2"`` (MODEL.md §4: P1 takes the minus sign before the arccos).
    exists : bool
        False where the arccos of MODEL.md §4 has no real value.
    theta : float or None
        Contact angle in (-pi, pi].
    normal_force : float or None
        N = 1 - omega^2 + rho cos(phi - theta).
    admissible : bool
        N > 0 (the stator pushes the rotor in). False where it does not exist.
    stable : bool or None
        Both eigenvalues of the 2x2 contact linearisation in (theta, thetadot)
        have negative real part. None where it does not exist.
    eigenvalues : tuple of complex
        Eigenvalues of `contact_jacobian` at the pseudo-equilibrium (empty where
        it does not exist).
    reason : str or None
        Why it does not exist, else None.
    """

    name: str
    exists: bool
    theta: float | None
    normal_force: float | None
    admissible: bool
    stable: bool | None
    eigenvalues: tuple[complex, ...] = ()
    reason: str | None = None

    #: Pseudo-equilibria lie on the stator.
    r: float = 1.0

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data (one entry of the ``equilibria --json`` ``"pseudo"`` list)."""
        return {
            "name": self.name,
            "theta": self.theta,
            "normal_force": self.normal_force,
            "admissible": bool(self.admissible),
            "stable": self.stable,
            "r": self.r if self.exists else None,
            "thetadot": 0.0 if self.exists else None,
            "eigenvalues": _complex_list(self.eigenvalues),
            "exists": bool(self.exists),
            "reason": self.reason,
        }


@dataclass(frozen=True)
class BoundaryEquilibrium:
    """The boundary equilibrium x_B and the classification of its bifurcation in gamma.

    Attributes
    ----------
    gamma_star : float or None
        gamma* = sqrt(rho^2 - (1 - omega^2)^2) >= 0, where |k| = 1; None when not real.
    theta : float or None
        Angle of x_B (arg k at gamma*), in (-pi, pi].
    kind : {"nonsmooth-fold", "persistence"} or None
        From the sign of `coefficient`; None where gamma* is not real or a
        non-degeneracy condition fails (see `reason`).
    partner : {"P1", "P2"} or None
        The pseudo-equilibrium that coincides with x_R at gamma* (found by
        matching angles, not assumed).
    coefficient : float or None
        c = -H_x F_x^{-1} W at x_B: > 0 non-smooth fold, < 0 persistence.
    transversality : float or None
        H_gamma - H_x F_x^{-1} F_gamma at x_B, i.e. d H(x_R) / d gamma at gamma*.
    det_jacobian : float or None
        det F_x at x_B.
    params : Parameters or None
        The parameters with gamma = gamma*.
    reason : str or None
        Why gamma* or the classification is missing, else None.
    """

    gamma_star: float | None
    theta: float | None
    kind: BEBKind | None
    partner: str | None
    coefficient: float | None = None
    transversality: float | None = None
    det_jacobian: float | None = None
    params: Parameters | None = None
    reason: str | None = None

    @property
    def exists(self) -> bool:
        """True where gamma* is real."""
        return self.gamma_star is not None

    @property
    def state(self) -> np.ndarray | None:
        """x_B = (1, theta, 0, 0), or None."""
        return None if self.theta is None else np.array([1.0, self.theta, 0.0, 0.0])

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data (the ``equilibria --json`` ``"boundary"`` entry)."""
        return {
            "gamma_star": self.gamma_star,
            "theta": self.theta,
            "kind": self.kind,
            "partner": self.partner,
            "coefficient": self.coefficient,
            "transversality": self.transversality,
            "det_jacobian": self.det_jacobian,
            "reason": self.reason,
        }


@dataclass(frozen=True)
class Equilibria:
    """All equilibria at one parameter point.

    Attributes
    ----------
    params : Parameters
    regular : RegularEquilibrium
    pseudo : tuple of PseudoEquilibrium
        (P1, P2).
    boundary : BoundaryEquilibrium
        The boundary equilibrium in gamma (it depends on all parameters but gamma).
    """

    params: Parameters
    regular: RegularEquilibrium
    pseudo: tuple[PseudoEquilibrium, PseudoEquilibrium]
    boundary: BoundaryEquilibrium

    def pseudo_by_name(self, name: str) -> PseudoEquilibrium:
        """The pseudo-equilibrium named ``name`` (``"P1"`` or ``"P2"``).

        Raises
        ------
        ParameterError
            Unless ``name`` is one of `PSEUDO_NAMES`.
        """
        return _by_name(self.pseudo, name)

    def to_dict(self) -> dict[str, Any]:
        """The ``equilibria --json`` contract: ``regular``, ``pseudo``, ``boundary`` (plus ``parameters``)."""
        boundary = self.boundary.to_dict()
        boundary["kind_analytic"] = classify_beb_analytic(self.params)
        return {
            "parameters": self.params.as_dict(),
            "regular": self.regular.to_dict(),
            "pseudo": [pe.to_dict() for pe in self.pseudo],
            "boundary": boundary,
        }


# ---------------------------------------------------------------------------
# The equilibria
# ---------------------------------------------------------------------------


def regular_equilibrium(params: Parameters) -> RegularEquilibrium:
    """The regular equilibrium x_R (MODEL.md §4).

    Parameters
    ----------
    params : Parameters

    Returns
    -------
    RegularEquilibrium
    """
    p = check_params(params)
    eig = _linear_eigenvalues(p)
    stable = max(z.real for z in eig) < 0.0
    if not has_regular_equilibrium(p.gamma, p.omega):
        return RegularEquilibrium(
            exists=False,
            r=None,
            theta=None,
            u=None,
            admissible=False,
            stable=stable,
            eigenvalues=eig,
            reason="omega = 1 and gamma = 0: undamped resonance, omega^2 - 1 + i gamma = 0, no regular equilibrium",
        )
    k = p.k
    r = abs(k)
    if r == 0.0:
        return RegularEquilibrium(
            exists=True,
            r=0.0,
            theta=None,
            u=k,
            admissible=True,
            stable=stable,
            eigenvalues=eig,
            reason="rho = 0: x_R is the origin, its angle is undefined",
        )
    return RegularEquilibrium(
        exists=True,
        r=r,
        theta=point_angle(k),
        u=k,
        admissible=r < 1.0,
        stable=stable,
        eigenvalues=eig,
    )


def _pseudo_absent(reason: str) -> tuple[PseudoEquilibrium, PseudoEquilibrium]:
    return tuple(  # type: ignore[return-value]
        PseudoEquilibrium(
            name=n, exists=False, theta=None, normal_force=None, admissible=False, stable=None, reason=reason
        )
        for n in PSEUDO_NAMES
    )


def _pseudo_existence_margin(params: Parameters) -> float:
    """rho sqrt(1 + mu^2) - |gamma + mu (1 - omega^2)|: >= 0 where the pseudo-equilibria exist."""
    p = params
    return p.rho * math.hypot(1.0, p.mu) - abs(p.gamma + p.mu * (1.0 - p.omega**2))


def pseudo_equilibria(params: Parameters) -> tuple[PseudoEquilibrium, PseudoEquilibrium]:
    """The pseudo-equilibria (x_P1, x_P2) in closed form (MODEL.md §4).

    With psi = phi - theta they solve rho (sin psi - mu cos psi) = gamma + mu (1 - omega^2),
    i.e. sin(psi - beta) = s with beta = arctan(mu) and
    s = (gamma + mu (1 - omega^2)) / (rho sqrt(1 + mu^2)). The MODEL.md form

        theta = phi - pi -/+ arccos(s) + arctan(1/mu)

    is evaluated with arctan(1/mu) = pi/2 - arctan(mu), equal for mu > 0 and
    its mu -> 0+ limit at mu = 0, where it gives the two roots of rho sin psi = gamma.

    Returns
    -------
    tuple of PseudoEquilibrium
        (P1, P2); each with ``exists = False`` and a reason where |s| > 1.
    """
    p = check_params(params)
    a = 1.0 - p.omega**2
    rhs = p.gamma + p.mu * a
    amp = p.rho * math.hypot(1.0, p.mu)
    if amp == 0.0:
        if rhs == 0.0:
            return _pseudo_absent(
                "rho = 0 and gamma + mu (1 - omega^2) = 0: every angle balances, no isolated pseudo-equilibrium"
            )
        return _pseudo_absent(
            f"rho = 0: the balance rho (sin psi - mu cos psi) = gamma + mu (1 - omega^2) = {rhs:.6g} has no solution"
        )
    s = rhs / amp
    if abs(s) > 1.0:
        return _pseudo_absent(
            f"(gamma + mu (1 - omega^2)) / (rho sqrt(1 + mu^2)) = {s:.6g} lies outside [-1, 1]: "
            "no real arccos, no synchronous rubbing equilibrium"
        )
    alpha = math.acos(s)
    beta = math.atan(p.mu)
    out = []
    for name, sign in zip(PSEUDO_NAMES, (1.0, -1.0)):
        psi = 0.5 * math.pi + beta + sign * alpha
        theta = wrap_angle(p.phi - psi)
        n = _normal_force(theta, 0.0, p)
        eig = _sorted_eigenvalues(np.linalg.eigvals(_contact_jacobian(theta, 0.0, p)))
        out.append(
            PseudoEquilibrium(
                name=name,
                exists=True,
                theta=theta,
                normal_force=n,
                admissible=n > 0.0,
                stable=bool(max(z.real for z in eig) < 0.0),
                eigenvalues=eig,
            )
        )
    return tuple(out)  # type: ignore[return-value]


def boundary_gamma(params: Parameters) -> float | None:
    """gamma* = sqrt(rho^2 - (1 - omega^2)^2) (MODEL.md §4), or None where it is not real.

    Only gamma* >= 0 is returned (|k| = 1 also holds at -gamma*).
    """
    p = check_params(params)
    a = abs(1.0 - p.omega**2)
    disc = (p.rho - a) * (p.rho + a)
    if disc < 0.0 or p.rho == 0.0:
        return None
    return math.sqrt(disc)


def _partner(theta_b: float, pseudo: Sequence[PseudoEquilibrium]) -> tuple[str | None, float | None]:
    """The pseudo-equilibrium closest in angle to x_B, and its angular distance."""
    best, dist = None, None
    for pe in pseudo:
        if pe.exists and pe.theta is not None:
            d = abs(angle_difference(pe.theta, theta_b))
            if dist is None or d < dist:
                best, dist = pe.name, d
    return best, dist


def boundary_equilibrium(params: Parameters) -> BoundaryEquilibrium:
    """The boundary equilibrium x_B and the type of its bifurcation in gamma.

    The non-degeneracy conditions and the sign are evaluated numerically from
    the Jacobians of the polar free-flight field at x_B = (1, theta_B, 0, 0)
    with gamma = gamma*:

    * det F_x != 0;
    * transversality: H_gamma - H_x F_x^{-1} F_gamma != 0;
    * c = -H_x F_x^{-1} W != 0, and then c > 0: non-smooth fold,
      c < 0: persistence.

    Parameters
    ----------
    params : Parameters
        Only omega, rho, mu, d, phi, r_ratio matter; gamma is replaced by gamma*.

    Returns
    -------
    BoundaryEquilibrium
    """
    p = check_params(params)
    if p.rho == 0.0:
        return BoundaryEquilibrium(
            gamma_star=None,
            theta=None,
            kind=None,
            partner=None,
            reason="rho = 0: x_R is the origin for every gamma, it never reaches the stator",
        )
    gs = boundary_gamma(p)
    if gs is None:
        a = abs(1.0 - p.omega**2)
        return BoundaryEquilibrium(
            gamma_star=None,
            theta=None,
            kind=None,
            partner=None,
            reason=(
                f"no real gamma*: rho = {p.rho:.6g} < |1 - omega^2| = {a:.6g}, "
                "so |k| < 1 for every gamma and x_R never touches the stator"
            ),
        )
    pb = p.replace(gamma=gs)
    k = pb.k
    theta_b = point_angle(k)
    xb = np.array([1.0, theta_b, 0.0, 0.0])
    fx = polar_jacobian(xb, pb)
    fg = polar_field_gamma(xb, pb)
    w = impact_direction(pb, 0.0)
    hx, hg = boundary_function_gradient()
    det = float(np.linalg.det(fx))
    common = dict(gamma_star=gs, theta=theta_b, params=pb, det_jacobian=det)
    # gamma* = sqrt(rho^2 - a^2) magnifies a rounding of rho - a near its zero: there the transversality,
    # of the size of gamma*, is tested at the border in omega^2 instead
    at_reach_border = any(_at_border(p.omega**2, b) for b in (1.0 - p.rho, 1.0 + p.rho))
    if not abs(det) > _DEGENERACY_RTOL * np.linalg.norm(fx, 2) ** 4:
        return BoundaryEquilibrium(kind=None, partner=None, reason="degenerate: det F_x = 0 at x_B", **common)
    y_g = np.linalg.solve(fx, fg)
    y_w = np.linalg.solve(fx, w)
    tau = float(hg - hx @ y_g)
    coef = float(-hx @ y_w)
    common.update(transversality=tau, coefficient=coef)
    if at_reach_border or not abs(tau) > _DEGENERACY_RTOL * np.linalg.norm(y_g):
        return BoundaryEquilibrium(
            kind=None,
            partner=None,
            reason="degenerate: transversality H_gamma - H_x F_x^-1 F_gamma = 0 (gamma* = 0)",
            **common,
        )
    if not abs(coef) > _DEGENERACY_RTOL * np.linalg.norm(y_w):
        return BoundaryEquilibrium(
            kind=None,
            partner=None,
            reason="degenerate: -H_x F_x^-1 W = 0 (x_P1 and x_P2 coincide with x_B)",
            **common,
        )
    kind: BEBKind = "nonsmooth-fold" if coef > 0.0 else "persistence"
    partner, _ = _partner(theta_b, pseudo_equilibria(pb))
    reason = None if partner is not None else "no pseudo-equilibrium resolved at gamma* (rounding at |s| = 1)"
    return BoundaryEquilibrium(kind=kind, partner=partner, reason=reason, **common)


@dataclass(frozen=True)
class BEBOmegaRanges:
    """Analytic omega-ranges of the boundary equilibrium bifurcation types (for fixed rho, mu).

    With a = 1 - omega^2, gamma* is real and positive for a^2 < rho^2, and
    -H_x F_x^{-1} W = (1 + d)(a - mu gamma*) / rho^2 (docs/equilibria.md), which
    is positive exactly when a > mu rho / sqrt(1 + mu^2). Hence, in omega^2:

    * non-smooth fold (partner P1): 1 - rho < omega^2 < 1 - mu rho / sqrt(1 + mu^2);
    * persistence (partner P2): 1 - mu rho / sqrt(1 + mu^2) < omega^2 < 1 + rho.

    d and phi play no part (d only scales the coefficient by 1 + d > 0). The
    end points are degenerate: gamma* = 0 at omega^2 = 1 -/+ rho (transversality
    fails) and the coefficient vanishes at omega_switch.

    Attributes
    ----------
    rho, mu : float
    omega_min : float or None
        sqrt(max(0, 1 - rho)); None where rho = 0 (no boundary equilibrium at all).
    omega_switch : float or None
        sqrt(1 - mu rho / sqrt(1 + mu^2)) where that is real, the border between
        the two types; None where 1 - mu rho / sqrt(1 + mu^2) <= 0 (no fold range).
    omega_max : float or None
        sqrt(1 + rho).
    """

    rho: float
    mu: float
    omega_min: float | None
    omega_switch: float | None
    omega_max: float | None

    def _limits_sq(self) -> tuple[float, float, float]:
        q = self.mu * self.rho / math.hypot(1.0, self.mu)
        return 1.0 - self.rho, 1.0 - q, 1.0 + self.rho

    @property
    def nonsmooth_fold(self) -> tuple[float, float] | None:
        """Open omega-interval of non-smooth folds, or None where empty."""
        if self.omega_min is None or self.omega_switch is None or self.omega_switch <= self.omega_min:
            return None
        return (self.omega_min, self.omega_switch)

    @property
    def persistence(self) -> tuple[float, float] | None:
        """Open omega-interval of persistence, or None where empty."""
        if self.omega_max is None:
            return None
        low = self.omega_switch if self.omega_switch is not None else 0.0
        return (max(low, self.omega_min or 0.0), self.omega_max)

    def kind(self, omega: float) -> BEBKind | None:
        """The bifurcation type at ``omega`` (None outside both open ranges or at their borders: within
        1e-10 (1 + omega^2) of one in omega^2; `boundary_equilibrium` counts the borders of existence alike and
        the switch by its own test of the coefficient, so the two can differ within about 1e-10 of it).

        Raises
        ------
        ParameterError
            Unless ``omega`` is a finite number in (0, `rotorcontact.model.params.MAX_MAGNITUDE`], the range
            of the parameter omega.
        """
        omega = _check_group("omega", omega, low_open=True)
        if self.rho <= 0.0 or omega <= 0.0:
            return None
        lo, switch, hi = self._limits_sq()
        w2 = omega * omega
        if not lo < w2 < hi or any(_at_border(w2, b) for b in (lo, switch, hi)):
            return None
        if w2 < switch:
            return "nonsmooth-fold"
        if w2 > switch:
            return "persistence"
        return None

    def partner(self, omega: float) -> str | None:
        """x_R's partner at ``omega``: P1 for the non-smooth fold, P2 for persistence.

        Raises
        ------
        ParameterError
            As `kind`.
        """
        return {"nonsmooth-fold": "P1", "persistence": "P2"}.get(self.kind(omega))  # type: ignore[arg-type]


def _check_group(name: str, value: Any, low_open: bool = False) -> float:
    """A dimensionless group rho, mu or omega: a finite number from 0 (excluded where ``low_open``) to
    `rotorcontact.model.params.MAX_MAGNITUDE`, its range in `Parameters`."""
    return check_float(name, value, 0.0, MAX_MAGNITUDE, low_open=low_open)


def beb_omega_ranges(rho: float, mu: float) -> BEBOmegaRanges:
    """The analytic omega-ranges of non-smooth fold and persistence (see `BEBOmegaRanges`).

    Raises
    ------
    ParameterError
        Unless ``rho`` and ``mu`` are finite numbers in [0, `rotorcontact.model.params.MAX_MAGNITUDE`], their
        ranges in `Parameters`.
    """
    rho = _check_group("rho", rho)
    mu = _check_group("mu", mu)
    if rho == 0.0:
        return BEBOmegaRanges(rho=rho, mu=mu, omega_min=None, omega_switch=None, omega_max=None)
    ranges = BEBOmegaRanges(rho=rho, mu=mu, omega_min=None, omega_switch=None, omega_max=None)
    lo, switch, hi = ranges._limits_sq()
    return BEBOmegaRanges(
        rho=rho,
        mu=mu,
        omega_min=math.sqrt(max(0.0, lo)),
        omega_switch=math.sqrt(switch) if switch > 0.0 else None,
        omega_max=math.sqrt(hi),
    )


def classify_beb_analytic(params: Parameters) -> BEBKind | None:
    """The bifurcation type at ``params`` from the analytic omega-ranges (`beb_omega_ranges`)."""
    p = check_params(params)
    return beb_omega_ranges(p.rho, p.mu).kind(p.omega)


def equilibria(params: Parameters) -> Equilibria:
    """x_R, (x_P1, x_P2) and x_B at ``params``."""
    p = check_params(params)
    return Equilibria(
        params=p,
        regular=regular_equilibrium(p),
        pseudo=pseudo_equilibria(p),
        boundary=boundary_equilibrium(p),
    )


# ---------------------------------------------------------------------------
# Branches against one parameter
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class EquilibriumEvent:
    """A point along a branch where an equilibrium changes character.

    Attributes
    ----------
    branch : str
        ``"x_R"``, ``"P1"`` or ``"P2"``.
    kind : str
        ``"admissibility"`` (admissible <-> virtual; for x_R this is a boundary
        equilibrium bifurcation), ``"stability"`` or ``"existence"`` (P1 and P2
        meet and disappear).
    param : str
        The parameter varied.
    value : float
        Where it happens (located by root finding).
    before, after : str
        The state just below and just above ``value``: ``"admissible"`` /
        ``"virtual"``, ``"stable"`` / ``"unstable"`` or ``"exists"`` / ``"absent"``.
    partner : str or None
        For an x_R admissibility event, the pseudo-equilibrium meeting x_R there.
    """

    branch: str
    kind: str
    param: str
    value: float
    before: str
    after: str
    partner: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data."""
        return dict(
            branch=self.branch,
            kind=self.kind,
            param=self.param,
            value=self.value,
            before=self.before,
            after=self.after,
            partner=self.partner,
        )


#: Former name of `EquilibriumEvent` (the events of continued orbit branches are
#: `rotorcontact.continuation.results.BranchEvent`).
BranchEvent = EquilibriumEvent


@dataclass(frozen=True)
class PseudoBranch:
    """One pseudo-equilibrium along a parameter range (arrays over `EquilibriumBranches.values`).

    Attributes
    ----------
    name : str
    exists : numpy.ndarray of bool
    theta, normal_force : numpy.ma.MaskedArray
        Masked where the pseudo-equilibrium does not exist.
    admissible, stable : numpy.ndarray of bool
        False where it does not exist.
    """

    name: str
    exists: np.ndarray
    theta: np.ma.MaskedArray
    normal_force: np.ma.MaskedArray
    admissible: np.ndarray
    stable: np.ndarray


@dataclass(frozen=True)
class EquilibriumBranches:
    """Equilibria along a range of one parameter, with located events.

    Attributes
    ----------
    param : str
        The parameter varied (one of `BRANCH_PARAMETERS`).
    values : numpy.ndarray
        Increasing parameter values: a uniform grid plus every event value.
    base : Parameters
        The other parameters.
    regular_r, regular_theta : numpy.ma.MaskedArray
        r = |k| and arg k of x_R (masked where undefined).
    regular_admissible, regular_stable : numpy.ndarray of bool
    pseudo : tuple of PseudoBranch
        (P1, P2).
    events : tuple of EquilibriumEvent
        Sorted by value. At an event value the boolean flags are those of
        either side (the event is the border).
    """

    param: str
    values: np.ndarray
    base: Parameters
    regular_r: np.ma.MaskedArray
    regular_theta: np.ma.MaskedArray
    regular_admissible: np.ndarray
    regular_stable: np.ndarray
    pseudo: tuple[PseudoBranch, PseudoBranch]
    events: tuple[EquilibriumEvent, ...]

    def params_at(self, value: float) -> Parameters:
        """The parameters at ``value`` of the varied parameter."""
        return self.base.replace(**{self.param: value})

    def select(self, branch: str | None = None, kind: str | None = None) -> tuple[EquilibriumEvent, ...]:
        """The events of one branch and/or one kind (None: all).

        Raises
        ------
        ParameterError
            Unless ``branch`` is ``"x_R"``, ``"P1"``, ``"P2"`` or None and ``kind`` one of ``"admissibility"``,
            ``"stability"``, ``"existence"`` or None.
        """
        _optional_choice("branch", branch, _EVENT_BRANCHES)
        _optional_choice("kind", kind, tuple(_LABELS))
        return tuple(
            e for e in self.events if (branch is None or e.branch == branch) and (kind is None or e.kind == kind)
        )

    @property
    def boundary_points(self) -> tuple[EquilibriumEvent, ...]:
        """The boundary equilibrium bifurcations: x_R crossing r = 1."""
        return self.select("x_R", "admissibility")

    @property
    def partners(self) -> tuple[str, ...]:
        """Names of the pseudo-equilibria that meet x_R at a boundary equilibrium in the range."""
        return tuple(sorted({e.partner for e in self.boundary_points if e.partner is not None}))

    def pseudo_by_name(self, name: str) -> PseudoBranch:
        """The branch of the pseudo-equilibrium named ``name``.

        Raises
        ------
        ParameterError
            Unless ``name`` is one of `PSEUDO_NAMES`.
        """
        return _by_name(self.pseudo, name)


_LABELS = {
    "admissibility": ("admissible", "virtual"),
    "stability": ("stable", "unstable"),
    "existence": ("exists", "absent"),
}

#: The branches whose events `equilibrium_branches` locates.
_EVENT_BRANCHES = ("x_R",) + PSEUDO_NAMES


def _optional_choice(name: str, value: Any, allowed: Sequence[str]) -> None:
    """Refuse ``value`` unless it is None or one of ``allowed``."""
    if value is not None and (not isinstance(value, str) or value not in allowed):
        raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: {', '.join(map(repr, allowed))} or None")


def _regular_events(p: Parameters) -> dict[str, float | None]:
    reg = regular_equilibrium(p)
    return {
        "admissibility": None if reg.r is None else 1.0 - reg.r,
        "stability": -max(z.real for z in reg.eigenvalues),
    }


def _pseudo_events(p: Parameters, index: int) -> dict[str, float | None]:
    pe = pseudo_equilibria(p)[index]
    out: dict[str, float | None] = {"existence": _pseudo_existence_margin(p)}
    if pe.exists:
        out["admissibility"] = pe.normal_force
        out["stability"] = -max(z.real for z in pe.eigenvalues)
    else:
        out["admissibility"] = None
        out["stability"] = None
    return out


def _locate(
    func: Callable[[float], float | None], grid: np.ndarray, samples: Sequence[float | None]
) -> list[tuple[float, int, int]]:
    """Sign changes of ``func`` along ``grid``; returns (value, sign before, sign after)."""
    found: list[tuple[float, int, int]] = []
    signs = [None if f is None else int(np.sign(f)) for f in samples]
    n = len(grid)
    i = 0
    while i < n:
        if signs[i] is None:
            i += 1
            continue
        j = i
        while j + 1 < n and signs[j + 1] is not None:
            j += 1
        nonzero = [m for m in range(i, j + 1) if signs[m] != 0]
        for m0, m1 in zip(nonzero, nonzero[1:]):
            if signs[m0] == signs[m1]:
                continue
            if m1 == m0 + 1:

                def g(v: float) -> float:
                    val = func(v)
                    if val is None:
                        raise ValueError("undefined")
                    return val

                try:
                    root = brentq(g, grid[m0], grid[m1], xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
                except ValueError:
                    continue
            else:
                root = float(grid[m0 + 1])  # the function is exactly zero at a grid point
            found.append((float(root), signs[m0], signs[m1]))
        i = j + 1
    return found


def equilibrium_branches(
    params: Parameters, param: str, start: float, stop: float, n: int = 401
) -> EquilibriumBranches:
    """Follow x_R, x_P1 and x_P2 as ``param`` goes from ``start`` to ``stop``.

    The events (admissible <-> virtual, stable <-> unstable, existence of the
    pseudo-equilibria) are bracketed on a uniform grid of ``n`` points and then
    located by Brent's method to machine precision. Two sign changes within
    one grid cell (a tangency) are not resolved; refine ``n`` to see them.
    Only events strictly inside the range are reported (an event at ``start``
    or ``stop`` has no side outside to compare with).

    Parameters
    ----------
    params : Parameters
        The other parameters.
    param : str
        One of ``"gamma"``, ``"omega"``, ``"rho"``, ``"mu"``, ``"d"``.
    start, stop : float
        The range, start < stop, both valid values of ``param``.
    n : int
        Number of grid points (>= 2).

    Returns
    -------
    EquilibriumBranches

    Raises
    ------
    ParameterError
        On an unknown parameter, a range with start >= stop, or invalid end values.
    """
    base = check_params(params)
    if param not in BRANCH_PARAMETERS:
        raise ParameterError(f"param = {param!r} is not a branch parameter; allowed: {', '.join(BRANCH_PARAMETERS)}")
    start = check_finite("start", start)
    stop = check_finite("stop", stop)
    if not start < stop:
        raise ParameterError(f"range {start!r} .. {stop!r} is empty; allowed: start < stop")
    n = check_int("n", n, 2, MAX_EQUILIBRIUM_POINTS)
    base.replace(**{param: start})  # validates both ends (every range of validity is an interval)
    base.replace(**{param: stop})

    def at(v: float) -> Parameters:
        return base.replace(**{param: float(v)})

    grid = np.linspace(start, stop, int(n))
    edge = 1e-12 * max(1.0, abs(start), abs(stop))
    sources: list[tuple[str, Callable[[Parameters], dict[str, float | None]]]] = [
        ("x_R", _regular_events),
        ("P1", lambda p: _pseudo_events(p, 0)),
        ("P2", lambda p: _pseudo_events(p, 1)),
    ]
    events: list[EquilibriumEvent] = []
    for branch, source in sources:
        table = [source(at(v)) for v in grid]
        for kind in table[0]:
            samples = [row[kind] for row in table]

            def func(v: float, source=source, kind=kind) -> float | None:
                return source(at(v))[kind]

            for value, s0, s1 in _locate(func, grid, samples):
                if min(value - start, stop - value) <= edge:
                    continue  # at an end of the range: no change inside it
                pos, neg = _LABELS[kind]
                partner = None
                if branch == "x_R" and kind == "admissibility":
                    reg = regular_equilibrium(at(value))
                    if reg.theta is not None:
                        partner, _ = _partner(reg.theta, pseudo_equilibria(at(value)))
                events.append(
                    EquilibriumEvent(
                        branch=branch,
                        kind=kind,
                        param=param,
                        value=value,
                        before=pos if s0 > 0 else neg,
                        after=pos if s1 > 0 else neg,
                        partner=partner,
                    )
                )
    events.sort(key=lambda e: (e.value, e.branch, e.kind))
    values = np.unique(np.concatenate((grid, [e.value for e in events])))

    regs = [regular_equilibrium(at(v)) for v in values]
    pses = [pseudo_equilibria(at(v)) for v in values]

    def masked(items: list[float | None]) -> np.ma.MaskedArray:
        mask = np.array([x is None for x in items])
        data = np.array([0.0 if x is None else x for x in items])
        return np.ma.MaskedArray(data, mask=mask)

    pseudo = tuple(
        PseudoBranch(
            name=name,
            exists=np.array([ps[i].exists for ps in pses]),
            theta=masked([ps[i].theta for ps in pses]),
            normal_force=masked([ps[i].normal_force for ps in pses]),
            admissible=np.array([ps[i].admissible for ps in pses]),
            stable=np.array([bool(ps[i].stable) for ps in pses]),
        )
        for i, name in enumerate(PSEUDO_NAMES)
    )
    return EquilibriumBranches(
        param=param,
        values=values,
        base=base,
        regular_r=masked([r.r for r in regs]),
        regular_theta=masked([r.theta for r in regs]),
        regular_admissible=np.array([r.admissible for r in regs]),
        regular_stable=np.array([r.stable for r in regs]),
        pseudo=pseudo,  # type: ignore[arg-type]
        events=tuple(events),
    )
