"""The fixed-point equations of one-impact orbits in a form fit for continuation.

MODEL.md §5 reduces a one-impact periodic orbit to two real equations in the
period T and the impact velocity rdot (`rotorcontact.maps.impact_map.fixed_point_residual`):

    F1(T) = 1 + Re(q a22(T)) = 0,     Q(T, rdot) = |1 + q a12(T) rdot|^2 - |k|^2 = 0.

With a12 = S/D and a22 = P/D (the closed form in `rotorcontact.maps.impact_map`),

    D = 2 (cosh(mT) - C),   P = C + mS - e^{mT},   C = cosh(hT),  S = sinh(hT)/h,
    m = -(gamma/2 + i),     h^2 = gamma^2/4 - omega^2,

F1 and Q have poles where D = 0. For gamma != 0, D has no real zero but
T = 0, and nothing changes; at gamma = 0, D vanishes at the undamped
resonances, and each zero T0,n,b of F1 passes through one of them as gamma
changes sign (it is the limit of the zero; `rotorcontact.maps.impact_map.f1_zeros`).
A branch B_n,b or B_n,d therefore runs into a pole of the equations at
gamma = 0.

Here both equations are multiplied by |D|^2 / W with W = |D|^2 + T^4 > 0:

    R1 = Re((D + q P) conj(D)) / W = F1 |D|^2 / W,
    R2 = (|D + q S rdot|^2 - |k|^2 |D|^2) / W = Q |D|^2 / W.

For D != 0 the zero set is exactly that of (F1, Q), with the same signs of
the partial derivatives there (dR1/dT = F1' |D|^2 / W on R1 = 0, and
dR2/drdot = Q_rdot |D|^2 / W), so the labels a/b (F1 decreasing/increasing
through 0) and small/large root (Q_rdot < 0 / > 0) read off the same. The
numerators are entire functions of T and of the parameters, so R has no pole:
the branches pass gamma = 0 smoothly. There the two orbits of a b-zero have
rdot -> 0 and both pass through the resonance point (T_res, rdot = 0); the
smaller root continues as the larger root on the other side (B_n,b <-> B_n,d).
Dividing by W, which behaves like |D|^2 away from the resonances, keeps R
close to (F1, Q) in size (R -> (F1, Q) where |D|^2 >> T^4).

The unknowns are y = (T, rdot, lambda), lambda one of the parameters gamma,
omega, rho, mu, d. Partial derivatives in T and rdot are analytic, the one
in lambda is a central difference.

At a solution, the orbit follows as in MODEL.md §5: theta = Arg(k D / (D + q S rdot)),
thetadot = -Im(q P / D) rdot.
"""

from __future__ import annotations

import cmath
import math
import sys
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..model.angles import wrap_angle
from ..model.flow import half_discriminant, period_closed_form
from ..model.impact_law import impact_q, slides_forward
from ..model.validation import check_bool, check_choice, check_float, check_int, check_params, quoted
from ..errors import ParameterError
from .impact_map import (
    BRANCH_LETTERS,
    IDEAL,
    FlightExtrema,
    ImpactOrbit,
    f1_zeros,
    flight_extrema,
    growth_rate,
    impact_map,
    impact_map_jacobian,
    orbit_stability,
)
from ..model.params import BRANCH_PARAMETERS, MAX_VELOCITY, Parameters

__all__ = [
    "BRANCH_PARAMETERS",
    "closed_form",
    "regularised_residual",
    "OneImpactSystem",
    "with_parameters",
    "orbit_at",
    "orbit_with_extrema",
    "orbit_angles",
    "label_of",
]

EPS = 2.220446049250313e-16


@dataclass(frozen=True)
class ClosedForm:
    """D, P, S, C and their first two T-derivatives at one period (see the module docstring)."""

    D: complex
    P: complex
    S: float
    C: float
    D_T: complex
    P_T: complex
    D_TT: complex
    P_TT: complex
    h2: float


#: ln of the largest float: e^x overflows beyond it.
LN_MAX_FLOAT = math.log(sys.float_info.max)


def closed_form(T: float, gamma: float, omega: float) -> ClosedForm:
    """D(T), P(T), S(T), C(T) and derivatives for the given damping and stiffness.

    Raises
    ------
    ParameterError
        Unless T > 0, gamma and omega are finite, and the closed form is finite at T. A flight growing or
        decaying like e^{growth T} (`rotorcontact.maps.impact_map.flight_growth`) may overflow from
        T = ln(largest float) / growth, about 709.8 / growth, on; the analyses stop well before, at
        `rotorcontact.maps.impact_map.period_limit`.
    """
    T = check_float("T", T, 0.0, low_open=True)
    gamma = check_float("gamma", gamma)
    omega = check_float("omega", omega)
    h2 = half_discriminant.py_func(gamma, omega)
    c, s, em, ch, d0, d1, d2, p0, p1, p2 = period_closed_form(T, gamma, h2)
    if not all(cmath.isfinite(v) for v in (c, s, d0, d1, d2, p0, p1, p2)):
        raise ParameterError(f"T = {T!r} is too large at gamma = {gamma:g}, omega = {omega:g}: the flight's closed "
                             f"form, growing like e^{{{growth_rate(gamma, h2):.3g} T}} at most, overflows; allowed: "
                             "a smaller T")
    return ClosedForm(D=complex(d0), P=complex(p0), S=float(s), C=float(c), D_T=complex(d1), P_T=complex(p1),
                      D_TT=complex(d2), P_TT=complex(p2), h2=h2)


def with_parameters(base: Parameters, changes: dict[str, float], *, extend: bool = False) -> Parameters:
    """``base`` with some parameters changed.

    With ``extend``, values outside the range that `Parameters` validates (but
    finite) are accepted without validation, for the evaluation of analytic
    equations just beyond a physical bound during a continuation.

    Raises
    ------
    ParameterError
        Unless ``base`` is a `Parameters` and ``changes`` a dict of parameter names to values that
        `Parameters` accepts (with ``extend``, finite real numbers).
    """
    check_params(base, "base")
    if not isinstance(changes, Mapping):
        raise ParameterError(f"changes = {quoted(changes)} is invalid; allowed: a dict of parameter names to values, "
                             "e.g. {'gamma': 0.1}")
    try:
        return base.replace(**changes)
    except ParameterError as refused:
        if not extend or set(changes) - set(base.as_dict()):
            raise
        try:
            values = {name: check_float(name, value) for name, value in changes.items()}
        except ParameterError:
            raise refused from None
        return base.unchecked_replace(**values)


def _q(p: Parameters) -> complex:
    return impact_q.py_func(p.d, p.mu)  # the compiled formula run as Python: no dispatch cost


def regularised_residual(params: Parameters, T: float, rdot: float) -> tuple[np.ndarray, np.ndarray]:
    """R = (R1, R2) of the module docstring and its Jacobian d(R1, R2)/d(T, rdot).

    Parameters
    ----------
    params : Parameters
        Model parameters.
    T : float
        Period, > 0.
    rdot : float
        Impact velocity.

    Returns
    -------
    residual : numpy.ndarray, shape (2,)
    jacobian : numpy.ndarray, shape (2, 2)
    """
    check_params(params)
    T = check_float("T", T, 0.0, low_open=True)
    rdot = check_float("rdot", rdot)
    cf = closed_form(T, params.gamma, params.omega)
    q = _q(params)
    k2 = abs(params.k) ** 2
    D, P, S, C = cf.D, cf.P, cf.S, cf.C
    T3 = T * T * T
    W = (D * D.conjugate()).real + T3 * T
    W_T = 2.0 * (D.conjugate() * cf.D_T).real + 4.0 * T3
    E = D + q * P
    n1 = (E * D.conjugate()).real
    n1_T = ((cf.D_T + q * cf.P_T) * D.conjugate() + E * cf.D_T.conjugate()).real
    Z = D + q * S * rdot
    Z_T = cf.D_T + q * C * rdot
    n2 = (Z * Z.conjugate()).real - k2 * (D * D.conjugate()).real
    n2_T = 2.0 * (Z.conjugate() * Z_T).real - 2.0 * k2 * (D.conjugate() * cf.D_T).real
    n2_r = 2.0 * (Z.conjugate() * q * S).real
    r1 = n1 / W
    r2 = n2 / W
    res = np.array([r1, r2])
    jac = np.array([[(n1_T - r1 * W_T) / W, 0.0], [(n2_T - r2 * W_T) / W, n2_r / W]])
    return res, jac


def orbit_angles(params: Parameters, T: float, rdot: float) -> tuple[float, float]:
    """(theta, thetadot) of the orbit with period T and impact velocity rdot (MODEL.md §5).

    Raises
    ------
    ParameterError
        Unless ``params`` are `Parameters`, T > 0 and rdot finite.
    """
    check_params(params)
    rdot = check_float("rdot", rdot)
    cf = closed_form(T, params.gamma, params.omega)
    q = _q(params)
    Z = cf.D + q * cf.S * rdot
    theta = wrap_angle(cmath.phase(params.k * cf.D / Z))
    thetadot = -(q * cf.P / cf.D).imag * rdot
    return theta, thetadot


def label_of(params: Parameters, T: float, rdot: float, t_max: float | None = None) -> tuple[int, str]:
    """(n, branch) of the one-impact orbit with period T and impact velocity rdot.

    The branch letter follows MODEL.md §5 from local signs: a zero where F1
    decreases is T0,n,a, one where it increases is T0,n,b; the smaller root of
    the quadratic (dQ/drdot < 0) is a or b, the larger c or d. The index n of
    the pair is that of the nearest zero found by `f1_zeros`.
    """
    res, jac = regularised_residual(params, T, rdot)
    kind_a = jac[0, 0] < 0.0
    small = jac[1, 1] < 0.0
    branch = ("a" if small else "c") if kind_a else ("b" if small else "d")
    top = T * (1.0 + 1e-6) + 1e-6 if t_max is None else max(t_max, T * (1.0 + 1e-6) + 1e-6)
    n = 0
    try:
        zeros = f1_zeros(params, top)
    except (ParameterError, RuntimeError):
        zeros = ()
    same = [z for z in zeros if z.kind == ("a" if kind_a else "b")] or list(zeros)
    if same:
        n = min(same, key=lambda z: abs(z.T - T)).n
    return max(n, 1), branch


def orbit_at(params: Parameters, T: float, rdot: float, *, n: int | None = None,
             branch: str | None = None) -> ImpactOrbit:
    """The one-impact orbit with period T and impact velocity rdot (see `orbit_with_extrema`)."""
    return orbit_with_extrema(params, T, rdot, n=n, branch=branch)[0]


def orbit_with_extrema(params: Parameters, T: float, rdot: float, *, n: int | None = None,
                       branch: str | None = None) -> tuple[ImpactOrbit, FlightExtrema]:
    """The one-impact orbit with period T and impact velocity rdot (a solution of R = 0).

    All reported properties are computed as in
    `rotorcontact.maps.impact_map.one_impact_orbits`: admissibility (rdot > 0),
    slipping, the interior extrema of r (guaranteed isolation), plausibility
    (admissible, slipping, r < 1 between the impacts, and the simulator's
    impact location finds the next impact at T), and for admissible orbits
    the multipliers of the analytic Jacobian of P_I and stability
    (`rotorcontact.maps.impact_map.orbit_stability`).

    Parameters
    ----------
    params : Parameters
    T, rdot : float
        A solution of the fixed-point equations.
    n, branch : optional
        The label; computed by `label_of` when omitted.

    Returns
    -------
    orbit : ImpactOrbit
    extrema : FlightExtrema
        The interior extrema of r along the flight.

    Raises
    ------
    ParameterError
        Unless ``params`` are `Parameters`, T > 0, |rdot| <= `rotorcontact.model.params.MAX_VELOCITY`, ``n``
        a whole number >= 0 (0 where no zero of F1 is found below T) and ``branch`` one of a, b, c, d.
    """
    check_params(params)
    T = check_float("T", T, 0.0, low_open=True)
    rdot = check_float("rdot", rdot, -MAX_VELOCITY, MAX_VELOCITY)
    if n is not None:
        n = check_int("n", n, 0)
    if branch is not None:
        branch = check_choice("branch", branch, BRANCH_LETTERS)
    if n is None or branch is None:
        n0, b0 = label_of(params, T, rdot)
        n = n0 if n is None else n
        branch = b0 if branch is None else branch
    theta, thetadot = orbit_angles(params, T, rdot)
    state = (theta, rdot, thetadot)
    admissible = rdot > 0.0
    slipping = slides_forward(thetadot, rdot, params.d, params.mu, params.r_ratio)
    ext = flight_extrema(params, state, T, law=IDEAL)
    r_max = ext.r_max
    multipliers = None
    stable = None
    plausible = False
    if admissible:
        _, jac, _ = impact_map_jacobian(params, state, T, law=IDEAL)
        ev = np.linalg.eigvals(jac)
        ev = ev[np.argsort(-np.abs(ev), kind="stable")]
        multipliers = tuple(complex(x) for x in ev)
        stable = orbit_stability(multipliers, slipping)
        if slipping and (r_max is None or r_max < 1.0):
            k = params.k
            hit = impact_map(params, state, horizon=T * (1.0 + 1e-6) + 1e-9, law=IDEAL)
            slack = max(1e-8 * (1.0 + T), 64.0 * EPS * ((abs(k) + 1.0) ** 2 + 1.0) / rdot)
            plausible = hit.status == "impact" and hit.time is not None and abs(hit.time - T) <= slack
    orbit = ImpactOrbit(
        label=f"B{n},{branch}",
        n=int(n),
        branch=branch,
        T=float(T),
        theta=theta,
        rdot=float(rdot),
        thetadot=thetadot,
        admissible=admissible,
        plausible=bool(plausible),
        slipping=bool(slipping),
        r_max_interior=r_max,
        interior_extrema=ext.count,
        multipliers=multipliers,
        stable=stable,
        params=params,
    )
    return orbit, ext


class OneImpactSystem:
    """R(T, rdot; lambda) = 0 as a continuation problem in y = (T, rdot, lambda).

    Parameters
    ----------
    base : Parameters
        The parameters other than ``param``.
    param : str
        The continuation parameter, one of `BRANCH_PARAMETERS`.
    fd_step : float
        Relative step of the central difference in lambda.
    extend : bool
        Evaluate the equations also at values of ``param`` outside the range
        that `Parameters` accepts (d > 1, mu < 0, ...): they are analytic
        there, so a continuation can step across a bound of the physical range
        and locate the bound exactly. Such parameters are never returned in a
        result.
    """

    def __init__(self, base: Parameters, param: str, fd_step: float = 1e-6, extend: bool = True):
        check_params(base)
        if param not in BRANCH_PARAMETERS:
            raise ParameterError(
                f"param = {param!r} is not a branch parameter; allowed: {', '.join(BRANCH_PARAMETERS)}"
            )
        self.base = base
        self.param = param
        self.fd_step = check_float("fd_step", fd_step, 0.0, 1e-2, low_open=True)
        self.extend = check_bool("extend", extend)
        #: The range of ``param`` in which results are reported (set by the caller).
        self.bounds: tuple[float, float] = (-math.inf, math.inf)
        self._cache: dict[float, Parameters] = {}

    def params_at(self, value: float) -> Parameters:
        """The parameters with ``param`` = value (validated; cached)."""
        value = check_float("value", value)
        p = self._cache.get(value)
        if p is None:
            p = with_parameters(self.base, {self.param: value}, extend=self.extend)
            if len(self._cache) > 4096:
                self._cache.clear()
            self._cache[value] = p
        return p

    def residual(self, y: np.ndarray) -> np.ndarray:
        """R at y = (T, rdot, lambda)."""
        T, rdot, lam = _point(y)
        return regularised_residual(self.params_at(lam), T, rdot)[0]

    def jacobian(self, y: np.ndarray) -> np.ndarray:
        """dR/d(T, rdot, lambda): analytic in T and rdot, a central difference in lambda."""
        T, rdot, lam = _point(y)
        res, jac = regularised_residual(self.params_at(lam), T, rdot)
        h = self.fd_step * max(1.0, abs(lam))
        lo, hi = lam - h, lam + h
        try:
            rp = regularised_residual(self.params_at(hi), T, rdot)[0]
        except ParameterError:
            rp, hi = res, lam
        try:
            rm = regularised_residual(self.params_at(lo), T, rdot)[0]
        except ParameterError:
            rm, lo = res, lam
        out = np.empty((2, 3))
        out[:, :2] = jac
        out[:, 2] = (rp - rm) / (hi - lo)
        return out

    def orbit(self, y: np.ndarray, **label) -> ImpactOrbit:
        """The orbit at a solution y (see `orbit_at`)."""
        T, rdot, lam = _point(y)
        return orbit_at(self.params_at(lam), T, rdot, **label)


def _point(y) -> tuple[float, float, float]:
    """A point y = (T, rdot, lambda) of a branch as three floats; a `ParameterError` naming ``y`` otherwise."""
    try:
        T, rdot, lam = y
    except (TypeError, ValueError):
        raise ParameterError(f"y = {quoted(y)} is invalid; allowed: (T, rdot, lambda), three numbers") from None
    return check_float("T", T), check_float("rdot", rdot), check_float("lambda", lam)
