"""Local analysis of the non-smooth fold-Hopf (NSFH) bifurcation at a boundary equilibrium (MODEL.md §6).

The general system
------------------
A complex linear oscillator ``z'' + alpha z' + beta z = Gamma`` in ``|z| < sigma``,
i.e. ``w' = A w + b`` with ``w = (z, z')``, ``A = [[0, 1], [-beta, -alpha]]`` and
``b = (0, Gamma)``, with the impact law at ``|z| = sigma``

    z'+ - z'- = -(1 + d)(1 + i mu) Re(conj(z) z'-) z / |z|^2,

that is ``z'+ = z'- - q rdot- e^{i theta}`` with ``q = (1 + d)(1 + i mu)`` for
``z = sigma e^{i theta}``. Its equilibrium is ``z_eq = Gamma / beta``. At
``(alpha0, beta0, Gamma0)`` it lies on the boundary, ``z0 = Gamma0 / beta0 =
sigma e^{i Psi}``, and is stable (eigenvalues of ``A0`` in the open left half
plane). The parameters move along ``alpha = alpha0 + eps alpha1``, ``beta =
beta0 + eps beta1``, ``Gamma = Gamma0 + eps Gamma1``.

The rotor of MODEL.md §2 is the instance ``alpha = gamma + 2i``, ``beta = omega^2
- 1 + i gamma``, ``Gamma = rho e^{i phi}``, ``sigma = 1``, ``eps = gamma - gamma*``
(``alpha1 = 1``, ``beta1 = i``, ``Gamma1 = 0``): `LinearImpactingSystem.from_parameters`.

Fixed points and their first-order expansion (derived in docs/local.md)
-----------------------------------------------------------------------
With ``[a_ij(T)] = (e^{-AT} - I)^{-1}`` a one-impact periodic orbit of period T
satisfies

    e^{i theta} (sigma + q a12 rdot) = z_eq,   rdot F1(T) = 0,   sigma thetadot = -Im(q a22) rdot,

``F1(T) = 1 + Re(q a22(T))``. Near ``eps = 0``, with ``z1 = (Gamma1 - beta1 z0) /
beta0`` (the shift of the equilibrium), ``xi + i eta = z1 e^{-i Psi}`` and
``c_ij = q a_ij(T0)`` at a simple zero T0 of the unperturbed F1:

    rdot-     = eps xi / Re(c12)                     + O(eps^2)
    thetadot- = -eps Im(c22) xi / (sigma Re(c12))    + O(eps^2)
    theta     = Psi + eps (eta - Im(c12) xi / Re(c12)) / sigma + O(eps^2)
    T         = T0 + O(eps)

The small orbits are admissible (``rdot- > 0``) for ``eps xi / Re(c12) > 0`` and
the equilibrium for ``eps xi < 0``: for ``Re(c12) < 0`` the small orbits and the
admissible equilibrium lie on the same side of ``eps = 0`` (the rotor at its
reference parameters), for ``Re(c12) > 0`` on opposite sides.

Numerics are generic: ``e^{-AT}`` for any complex 2x2 ``A`` by Cayley-Hamilton
(`expm2`; no rotor-specific closed form), its derivative in the parameters by
`scipy.linalg.expm` of a block-triangular 4x4 matrix, zeros of F1 by sign changes on a fine grid,
refined by Brent's method, with a check of every local extremum of F1 on the
grid for a pair of zeros closer than the grid spacing.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field
from typing import Any, Iterable, Sequence

import numpy as np
import scipy.linalg
from scipy.optimize import brentq, minimize_scalar

from .equilibria import boundary_gamma
from ..model.angles import angle_difference, wrap_angle
from ..errors import ParameterError
from ..maps.impact_map import (F1Zero, check_growth, label_f1_zeros, one_impact_orbits, root_branches,
                               stable_quadratic_roots)
from ..model.impact_law import impact_q
from ..model.validation import check_choice, check_params, complex_array, complex_value, quoted, real_array
from ..model.params import MAX_MAGNITUDE, Parameters, check_finite, check_range

__all__ = [
    "LinearImpactingSystem",
    "expm2",
    "LinearFixedPoint",
    "LocalOrbit",
    "LocalAnalysis",
    "ComparisonRow",
    "LocalComparison",
    "local_analysis",
    "global_fixed_points",
    "compare_local_global",
]

#: Relative tolerance of the boundary condition |Gamma0 / beta0| = sigma.
BOUNDARY_RTOL = 1e-9
#: Relative size below which Re(q a12) counts as zero (the slopes are then undefined).
DEGENERACY_RTOL = 1e-12
#: Largest grid used to bracket the zeros of F1.
MAX_GRID = 200_000
#: Default decade of epsilon values for the comparison with the global fixed points.
DEFAULT_EPSILONS = tuple(float(x) for x in np.geomspace(1e-3, 1e-2, 5))



def _check_eps(eps: Any) -> float:
    return check_finite("eps", eps)


#: The quantities whose errors `ComparisonRow.error` gives.
QUANTITIES = ("T", "theta", "rdot", "thetadot")
#: Largest modulus of a coefficient of `LinearImpactingSystem`: ten times
#: `rotorcontact.model.params.MAX_MAGNITUDE`, room for those of every rotor (`LinearImpactingSystem.from_parameters`:
#: |alpha0| = |gamma* + 2i|, |beta0| = |Gamma0| = rho, each at most about MAX_MAGNITUDE).
MAX_COEFFICIENT = 10.0 * MAX_MAGNITUDE
_WHY = "the coefficients of a rotor are of order one; larger magnitudes are beyond the numerics of e^{-AT}"


def _check_coefficient(name: str, value: Any) -> complex:
    """A coefficient of `LinearImpactingSystem`: a finite complex number (or RE, IM) of modulus at most
    `MAX_COEFFICIENT`."""
    z = complex_value(name, value)
    if not abs(z) <= MAX_COEFFICIENT:
        raise ParameterError(f"{name} = {z!r} is invalid; allowed: a complex number with |{name}| <= "
                             f"{MAX_COEFFICIENT:g} ({_WHY})")
    return z


def _check_sigma(value: Any) -> float:
    """The radius sigma of the boundary, in (0, `rotorcontact.model.params.MAX_MAGNITUDE`]."""
    return check_range("sigma", value, low=0.0, high=MAX_MAGNITUDE, low_open=True, why=_WHY)


def _check_label(name: str, label: Any, known: Sequence[str], given: Any = None) -> str:
    """``label`` if it is one of the orbit labels ``known``, else a `ParameterError` naming ``name`` and the
    value ``given`` (``label`` itself, or the list of labels it is taken from)."""
    if isinstance(label, str) and label in known:
        return label
    shown, why = (label, "no local orbit has this label") if given is None else (given, f"no local orbit {label!r}")
    raise ParameterError(f"{name} = {quoted(shown)} is invalid ({why}); allowed: "
                         f"{', '.join(map(repr, known)) or 'none (there is no local orbit)'}")


def expm2(m: np.ndarray) -> np.ndarray:
    """e^M for complex 2x2 matrices M (shape (..., 2, 2)), exactly by Cayley-Hamilton.

    With mu = tr(M)/2 and h^2 = mu^2 - det(M), e^M = e^mu (cosh(h) I + sinh(h)/h (M - mu I)),
    sinh(h)/h from its Taylor series for small |h| (so a double eigenvalue is no special case).

    Raises
    ------
    ParameterError
        Unless ``m`` holds finite (complex) numbers in an array of shape (..., 2, 2) and e^M, as evaluated
        here, is finite (it overflows where |Re mu| or |Re h| exceeds about 700).
    """
    arr = complex_array(m)
    allowed = "allowed: finite (complex) 2x2 matrices, an array of shape (..., 2, 2)"
    if arr is None or arr.ndim < 2 or arr.shape[-2:] != (2, 2) or not np.all(np.isfinite(arr)):
        raise ParameterError(f"m = {quoted(m)} is invalid; {allowed}")
    with np.errstate(all="ignore"):
        out = _expm2(arr)
    if not np.all(np.isfinite(out)):
        raise ParameterError(f"m = {quoted(m)} is invalid: e^m overflows; {allowed} whose exponential is finite")
    return out


def _expm2(m: np.ndarray) -> np.ndarray:
    m = np.asarray(m, dtype=complex)
    tr2 = 0.5 * (m[..., 0, 0] + m[..., 1, 1])
    det = m[..., 0, 0] * m[..., 1, 1] - m[..., 0, 1] * m[..., 1, 0]
    h = np.sqrt(tr2 * tr2 - det)
    small = np.abs(h) < 1e-3
    hs = np.where(small, 1.0, h)
    h2 = h * h
    sinhc = np.where(small, 1.0 + h2 / 6.0 * (1.0 + h2 / 20.0 * (1.0 + h2 / 42.0)), np.sinh(hs) / hs)
    e = np.exp(tr2)
    c = e * np.cosh(h)
    s = e * sinhc
    out = np.empty(m.shape, dtype=complex)
    out[..., 0, 0] = c + s * (m[..., 0, 0] - tr2)
    out[..., 1, 1] = c + s * (m[..., 1, 1] - tr2)
    out[..., 0, 1] = s * m[..., 0, 1]
    out[..., 1, 0] = s * m[..., 1, 0]
    return out


#: Largest |M| (largest absolute row sum) at which `_expm2_minus_identity` sums e^M - I as a series.
SERIES_NORM = 1.0
#: Terms of that series: the first left out, 1/(SERIES_TERMS + 1)!, is below the rounding of double precision.
SERIES_TERMS = 20


def _expm2_minus_identity(m: np.ndarray) -> np.ndarray:
    """e^M - I for complex 2x2 matrices M (shape (..., 2, 2)), without cancellation where M is small.

    Where the largest absolute row sum of M is at most `SERIES_NORM`, e^M - I = M phi(M) with
    phi(M) = sum_k M^k / (k + 1)! summed by Horner's rule: an entry of e^M - I that is O(|M|^2) (the first of
    e^{-AT} - I at small T, where -A T has a zero there) is then a product, not a difference of O(1) terms.
    Elsewhere e^M - I as `_expm2` gives it.
    """
    m = np.asarray(m, dtype=complex)
    out = _expm2(m) - np.eye(2)
    small = np.abs(m).sum(axis=-1).max(axis=-1) <= SERIES_NORM
    if np.any(small):
        ms = m[small]
        phi = np.broadcast_to(np.eye(2, dtype=complex), ms.shape).copy()
        for k in range(SERIES_TERMS, 1, -1):
            phi = np.eye(2) + ms @ phi / k
        out[small] = ms @ phi
    return out


# ---------------------------------------------------------------------------
# The general system
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class LinearImpactingSystem:
    """A complex linear impacting oscillator near a stable boundary equilibrium (MODEL.md §6).

    ``z'' + alpha z' + beta z = Gamma`` in ``|z| < sigma``, with the reset
    ``z'+ - z'- = -(1 + d)(1 + i mu) Re(conj(z) z'-) z / |z|^2`` at ``|z| = sigma``,
    and the one-parameter family ``alpha = alpha0 + eps alpha1``, ``beta = beta0 +
    eps beta1``, ``Gamma = Gamma0 + eps Gamma1``.

    Attributes
    ----------
    alpha0, beta0, Gamma0 : complex
        Coefficients at the boundary equilibrium: ``|Gamma0 / beta0| = sigma``
        (relative tolerance `BOUNDARY_RTOL`) and both eigenvalues of
        ``A0 = [[0, 1], [-beta0, -alpha0]]`` with negative real part.
    mu : float
        Friction coefficient, >= 0.
    d : float
        Restitution coefficient, in [0, 1].
    sigma : float
        Radius of the boundary, > 0.
    alpha1, beta1, Gamma1 : complex
        Direction of the perturbation (derivatives with respect to eps).

    Raises
    ------
    ParameterError
        Non-finite coefficients or coefficients beyond `MAX_COEFFICIENT` in modulus, mu or sigma beyond
        `rotorcontact.model.params.MAX_MAGNITUDE`, ``beta0 = 0``, the equilibrium off the boundary, or an
        equilibrium that is not asymptotically stable.
    """

    alpha0: complex
    beta0: complex
    Gamma0: complex
    mu: float
    d: float
    sigma: float = 1.0
    alpha1: complex = 0j
    beta1: complex = 0j
    Gamma1: complex = 0j

    def __post_init__(self) -> None:
        for name in ("alpha0", "beta0", "Gamma0", "alpha1", "beta1", "Gamma1"):
            object.__setattr__(self, name, _check_coefficient(name, getattr(self, name)))
        object.__setattr__(self, "mu", check_range("mu", self.mu, low=0.0, high=MAX_MAGNITUDE, why=_WHY))
        object.__setattr__(self, "d", check_range("d", self.d, low=0.0, high=1.0))
        object.__setattr__(self, "sigma", _check_sigma(self.sigma))
        if self.beta0 == 0:
            raise ParameterError("beta0 = 0 gives no isolated equilibrium; allowed: beta0 != 0")
        r0 = abs(self.Gamma0 / self.beta0)
        if abs(r0 - self.sigma) > BOUNDARY_RTOL * self.sigma:
            raise ParameterError(
                f"Gamma0 = {self.Gamma0!r} is invalid: |Gamma0 / beta0| = {r0!r} is not sigma = {self.sigma!r}, "
                f"the equilibrium is not on the boundary; allowed: |Gamma0 / beta0| = sigma (relative tolerance "
                f"{BOUNDARY_RTOL:g}); LinearImpactingSystem.on_boundary builds Gamma0 from the equilibrium's angle"
            )
        lam = self.eigenvalues()
        if not np.all(lam.real < 0.0):
            raise ParameterError(
                f"alpha0 = {self.alpha0!r} is invalid with beta0 = {self.beta0!r}: A0 has eigenvalues "
                f"{lam[0]:.6g}, {lam[1]:.6g}, so the boundary equilibrium is not stable; allowed: alpha0 and beta0 "
                "giving both eigenvalues a negative real part"
            )

    # -- constructors ---------------------------------------------------------

    @classmethod
    def on_boundary(
        cls,
        alpha0: complex,
        beta0: complex,
        psi: float,
        *,
        mu: float,
        d: float,
        sigma: float = 1.0,
        alpha1: complex = 0j,
        beta1: complex = 0j,
        Gamma1: complex = 0j,
    ) -> "LinearImpactingSystem":
        """The system whose equilibrium at eps = 0 is ``z0 = sigma e^{i psi}`` (``Gamma0 = beta0 z0``)."""
        psi = check_finite("psi", psi)
        sigma = _check_sigma(sigma)
        beta0 = _check_coefficient("beta0", beta0)
        return cls(alpha0, beta0, beta0 * sigma * cmath.exp(1j * psi), mu=mu, d=d, sigma=sigma,
                   alpha1=alpha1, beta1=beta1, Gamma1=Gamma1)

    @classmethod
    def from_parameters(cls, params: Parameters) -> "LinearImpactingSystem":
        """The rotor of MODEL.md §2 at its boundary equilibrium, with eps = gamma - gamma*.

        ``alpha = gamma + 2i``, ``beta = omega^2 - 1 + i gamma``, ``Gamma = rho e^{i phi}``,
        ``sigma = 1``; so ``alpha1 = 1``, ``beta1 = i``, ``Gamma1 = 0``. ``params.gamma``
        is not used (it is replaced by gamma*); ``r_ratio`` does not enter (the impact
        law of MODEL.md §5, friction slipping with v_rel > 0).

        Raises
        ------
        ParameterError
            No real gamma* (rho < |1 - omega^2| or rho = 0), or gamma* = 0 (the
            equilibrium is then undamped, not asymptotically stable).
        """
        check_params(params)
        gs = boundary_gamma(params)
        if gs is None:
            raise ParameterError(
                f"no real gamma*: rho = {params.rho!r} and |1 - omega^2| = {abs(1.0 - params.omega**2)!r} "
                "give no boundary equilibrium; allowed: rho > 0 and rho >= |1 - omega^2|"
            )
        if gs <= 0.0:
            raise ParameterError(
                f"gamma* = {gs!r}: the boundary equilibrium is undamped, not asymptotically stable; "
                "allowed: rho > |1 - omega^2| (gamma* > 0)"
            )
        return cls(
            alpha0=complex(gs, 2.0),
            beta0=complex(params.omega**2 - 1.0, gs),
            Gamma0=params.rho * cmath.exp(1j * params.phi),
            mu=params.mu,
            d=params.d,
            sigma=1.0,
            alpha1=1.0,
            beta1=1j,
            Gamma1=0.0,
        )

    # -- coefficients ---------------------------------------------------------

    @property
    def q(self) -> complex:
        """q = (1 + d)(1 + i mu) (`rotorcontact.model.impact_law.impact_q`)."""
        return impact_q(self.d, self.mu)

    def coefficients(self, eps: float = 0.0) -> tuple[complex, complex, complex]:
        """(alpha, beta, Gamma) at ``eps``."""
        eps = _check_eps(eps)
        return (self.alpha0 + eps * self.alpha1, self.beta0 + eps * self.beta1, self.Gamma0 + eps * self.Gamma1)

    def matrix(self, eps: float = 0.0) -> np.ndarray:
        """A = [[0, 1], [-beta, -alpha]] at ``eps``."""
        alpha, beta, _ = self.coefficients(eps)
        return np.array([[0.0, 1.0], [-beta, -alpha]], dtype=complex)

    def eigenvalues(self, eps: float = 0.0) -> np.ndarray:
        """Eigenvalues of A at ``eps``, roots of lambda^2 + alpha lambda + beta."""
        alpha, beta, _ = self.coefficients(eps)
        s = cmath.sqrt(alpha * alpha - 4.0 * beta)
        return np.array([(-alpha + s) / 2.0, (-alpha - s) / 2.0], dtype=complex)

    def equilibrium(self, eps: float = 0.0) -> complex:
        """z_eq = Gamma / beta at ``eps`` (a `ParameterError` where beta = 0)."""
        _, beta, Gamma = self.coefficients(eps)
        if beta == 0:
            raise ParameterError(f"eps = {eps!r} gives beta = 0 (no isolated equilibrium)")
        return Gamma / beta

    @property
    def z0(self) -> complex:
        """The boundary equilibrium z0 = Gamma0 / beta0 = sigma e^{i Psi}."""
        return self.Gamma0 / self.beta0

    @property
    def psi(self) -> float:
        """Psi = Arg z0 in (-pi, pi]."""
        return wrap_angle(cmath.phase(self.z0))

    @property
    def z1(self) -> complex:
        """First-order shift of the equilibrium, d z_eq / d eps = (Gamma1 - beta1 z0) / beta0."""
        return (self.Gamma1 - self.beta1 * self.z0) / self.beta0

    # -- the matrix a and F1 --------------------------------------------------

    def _check_period(self, name: str, T: float, eps: float) -> None:
        """Refuse a period beyond which e^{-AT} leaves the accurate range (as
        `rotorcontact.maps.impact_map.period_limit`)."""
        check_growth(name, T, float(np.max(np.abs(self.eigenvalues(eps).real))), f"eps = {eps!r}")

    def a_matrix(self, T, eps: float = 0.0) -> np.ndarray:
        """[a_ij(T)] = (e^{-AT} - I)^{-1} at ``eps``; T a float (2x2) or an array (..., 2, 2).

        An empty array of T gives an empty result (no periods, no matrices).

        Raises
        ------
        ParameterError
            Unless ``T`` holds finite numbers > 0 below the limit of `rotorcontact.maps.impact_map.check_growth`
            and ``eps`` is finite.
        """
        t = real_array(T)
        if t is None or not np.all(np.isfinite(t)) or np.any(t <= 0.0):
            raise ParameterError(f"T = {T!r} is invalid; allowed: a finite number > 0, or an array of them")
        if t.size:
            self._check_period("T" if t.ndim == 0 else "max(T)", float(t.max()), eps)
        a = self.matrix(eps)
        e = _expm2_minus_identity(-t[..., None, None] * a)
        # 2x2 inverse in closed form (vectorised)
        det = e[..., 0, 0] * e[..., 1, 1] - e[..., 0, 1] * e[..., 1, 0]
        inv = np.empty(e.shape, dtype=complex)
        inv[..., 0, 0] = e[..., 1, 1] / det
        inv[..., 1, 1] = e[..., 0, 0] / det
        inv[..., 0, 1] = -e[..., 0, 1] / det
        inv[..., 1, 0] = -e[..., 1, 0] / det
        return inv

    def f1(self, T, eps: float = 0.0):
        """F1(T) = 1 + Re(q a22(T)) at ``eps``, for a float or an array of T > 0 (empty: an empty array).

        Raises
        ------
        ParameterError
            As `a_matrix`.
        """
        a = self.a_matrix(T, eps)
        val = 1.0 + (self.q * a[..., 1, 1]).real
        return float(val) if np.ndim(T) == 0 else val

    def _derivatives(self, T: float, eps: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """a, da/dT and da/deps at (T, eps)."""
        a_mat = self.matrix(eps)
        a1_mat = np.array([[0.0, 0.0], [-self.beta1, -self.alpha1]], dtype=complex)
        # Frechet derivative of expm at M = -A T in the direction -A1 T (block-triangular trick)
        m = -T * a_mat
        big = np.zeros((4, 4), dtype=complex)
        big[:2, :2] = m
        big[2:, 2:] = m
        big[:2, 2:] = -T * a1_mat
        eb = scipy.linalg.expm(big)
        e = eb[:2, :2]
        de_deps = eb[:2, 2:]
        a = self.a_matrix(T, eps)
        da_dt = a @ a_mat @ e @ a  # d/dT (e^{-AT} - I)^{-1} = a A e^{-AT} a
        da_deps = -a @ de_deps @ a
        return a, da_dt, da_deps

    def f1_derivatives(self, T: float, eps: float = 0.0) -> tuple[float, float]:
        """(dF1/dT, dF1/deps) at (T, eps)."""
        T = check_range("T", T, low=0.0, low_open=True)
        eps = _check_eps(eps)
        self._check_period("T", T, eps)
        _, da_dt, da_deps = self._derivatives(T, eps)
        return float((self.q * da_dt[1, 1]).real), float((self.q * da_deps[1, 1]).real)

    def _f1_dt(self, T: float, eps: float) -> float:
        """dF1/dT = Re(q (a A e^{-AT} a)_22) at (T, eps)."""
        a_mat = self.matrix(eps)
        e = _expm2(-T * a_mat)
        a = self.a_matrix(T, eps)
        return float((self.q * (a @ a_mat @ e @ a)[1, 1]).real)

    def _grid(self, t_max: float, eps: float) -> np.ndarray:
        """Grid for bracketing the zeros of F1: finer than 1/|lambda| and |Re lambda| (at least 2000 points)."""
        lam = self.eigenvalues(eps)
        scale = float(np.max(np.abs(lam)))
        width = float(np.min(np.abs(lam.real)))
        h = min(t_max / 2000.0, 0.05 / max(scale, 1e-300), 0.25 * width)
        n = math.ceil(t_max / h)
        if n > MAX_GRID:
            raise ParameterError(
                f"t_max = {t_max!r} needs {n} grid points to bracket the zeros of F1 (step {h:.3g}); "
                f"allowed: t_max <= {MAX_GRID * h:.6g}"
            )
        return np.linspace(t_max / n, t_max, n)

    def f1_zeros(self, t_max: float = 12.0, eps: float = 0.0) -> tuple[F1Zero, ...]:
        """The zeros of F1 on (0, t_max] at ``eps``, labelled in pairs as in MODEL.md §5.

        A zero where F1 turns negative opens pair n (kind ``"a"``, T0,n,a), the
        next one where it turns positive closes it (kind ``"b"``). The zeros are
        bracketed on a grid finer than the oscillation and decay scales of
        e^{AT} and polished by Brent's method; each local extremum of F1 on the
        grid is minimised to find a pair of zeros closer than the grid spacing.

        Parameters
        ----------
        t_max : float
            End of the search interval, > 0.
        eps : float
            Parameter.

        Returns
        -------
        tuple of `rotorcontact.maps.impact_map.F1Zero`
        """
        t_max = check_range("t_max", t_max, low=0.0, low_open=True)
        eps = _check_eps(eps)
        lam = self.eigenvalues(eps)
        if np.any(lam.real >= 0.0):
            raise ParameterError(f"eps = {eps!r}: A has eigenvalues {lam[0]:.6g}, {lam[1]:.6g} (not stable); "
                                 "allowed: eps where both have negative real part")
        self._check_period("t_max", t_max, eps)
        t = self._grid(t_max, eps)
        f = self.f1(t, eps)

        def fun(x: float) -> float:
            return self.f1(x, eps)

        found: list[tuple[float, int, bool]] = []  # (T, direction, double)
        pos = f > 0.0
        for i in np.flatnonzero((pos[:-1] != pos[1:]) & (f[:-1] != 0.0)):
            root = t[i + 1] if f[i + 1] == 0.0 else brentq(fun, t[i], t[i + 1], xtol=1e-15, rtol=1e-15, maxiter=200)
            found.append((float(root), -1 if f[i] > 0 else 1, False))
        # a pair of zeros between two grid points: a local extremum of F1 on the grid without a sign change
        sg = np.where(pos, 1.0, -1.0)
        sf = sg * f
        mid = slice(1, len(t) - 1)
        ext = (sf[mid] < sg[mid] * f[:-2]) & (sf[mid] < sg[mid] * f[2:]) & (sg[mid] * f[:-2] > 0.0) & (
            sg[mid] * f[2:] > 0.0
        )
        for i in np.flatnonzero(ext) + 1:
            si = sg[i]
            res = minimize_scalar(lambda x: si * fun(x), bounds=(t[i - 1], t[i + 1]), method="bounded",
                                  options={"xatol": 1e-14})
            tm = float(res.x)
            fm = fun(tm)
            if si * fm < 0:
                r1 = brentq(fun, t[i - 1], tm, xtol=1e-15, rtol=1e-15, maxiter=200)
                r2 = brentq(fun, tm, t[i + 1], xtol=1e-15, rtol=1e-15, maxiter=200)
                found += [(float(r1), -1 if si > 0 else 1, False), (float(r2), 1 if si > 0 else -1, False)]
            elif fm == 0.0:
                found += [(tm, -1 if si > 0 else 1, True), (tm, 1 if si > 0 else -1, True)]
        found.sort(key=lambda x: x[0])
        zeros = []
        for (root, direction, double), (n, kind) in zip(found, label_f1_zeros([x[1] for x in found], f[0] > 0)):
            slope = 0.0 if double else self._f1_dt(root, eps)
            zeros.append(F1Zero(T=root, n=n, kind=kind, slope=slope, double=double))
        return tuple(zeros)

    # -- global fixed points ---------------------------------------------------

    def fixed_points(self, eps: float = 0.0, t_max: float = 12.0) -> tuple["LinearFixedPoint", ...]:
        """All one-impact periodic orbits with period in (0, t_max] at ``eps`` (global, not expanded).

        For each zero T of F1 the quadratic
        ``|q a12|^2 rdot^2 + 2 sigma Re(q a12) rdot + sigma^2 - |z_eq|^2 = 0``
        gives rdot (smaller root: branch a / b, larger root: c / d; none where
        the roots are complex), then ``theta = Arg(z_eq / (sigma + q a12 rdot))``
        and ``thetadot = -Im(q a22) rdot / sigma`` (docs/local.md).

        Returns
        -------
        tuple of LinearFixedPoint
            Sorted by pair, then branch.
        """
        eps = _check_eps(eps)
        zeq = self.equilibrium(eps)
        q = self.q
        out = []
        for zero in self.f1_zeros(t_max, eps):
            a = self.a_matrix(zero.T, eps)
            c12 = q * a[0, 1]
            c22 = q * a[1, 1]
            disc, roots = stable_quadratic_roots(abs(c12) ** 2, self.sigma * c12.real, self.sigma**2 - abs(zeq) ** 2)
            for rdot, branch in zip(roots, root_branches(zero.kind)):
                theta = wrap_angle(cmath.phase(zeq / (self.sigma + c12 * rdot)))
                out.append(
                    LinearFixedPoint(
                        label=f"B{zero.n},{branch}",
                        n=zero.n,
                        branch=branch,
                        T=zero.T,
                        theta=theta,
                        rdot=float(rdot),
                        thetadot=float(-c22.imag * rdot / self.sigma),
                        admissible=bool(rdot > 0.0),
                        eps=eps,
                        sigma=self.sigma,
                        q=q,
                    )
                )
        out.sort(key=lambda o: (o.n, o.branch, o.T))
        return tuple(out)


@dataclass(frozen=True)
class LinearFixedPoint:
    """A one-impact periodic orbit of a `LinearImpactingSystem` (a fixed point of its impact map).

    Attributes
    ----------
    label : str
        ``"B1,a"`` etc. (MODEL.md §5 naming).
    n : int
        Index of the pair of zeros of F1.
    branch : str
        ``"a"``, ``"b"`` (smaller root of the quadratic) or ``"c"``, ``"d"`` (larger root).
    T : float
        Period.
    theta : float
        Impact angle in (-pi, pi].
    rdot, thetadot : float
        Radial and angular velocity just before the impact.
    admissible : bool
        rdot > 0.
    eps : float
        The parameter value.
    sigma : float
        Boundary radius.
    q : complex
        (1 + d)(1 + i mu).
    """

    label: str
    n: int
    branch: str
    T: float
    theta: float
    rdot: float
    thetadot: float
    admissible: bool
    eps: float
    sigma: float = field(repr=False, default=1.0)
    q: complex = field(repr=False, default=0j)

    def initial_condition(self) -> tuple[complex, complex]:
        """(z, z') just after the impact, from the reset law at ``z = sigma e^{i theta}``."""
        e = cmath.exp(1j * self.theta)
        dz_minus = e * complex(self.rdot, self.sigma * self.thetadot)
        return self.sigma * e, dz_minus - self.q * self.rdot * e


# ---------------------------------------------------------------------------
# First-order analysis
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class LocalOrbit:
    """First-order expansion in eps of a small one-impact orbit born at the boundary equilibrium.

    ``theta = theta0 + eps theta_slope``, ``rdot- = eps rdot_slope``,
    ``thetadot- = eps thetadot_slope``, each + O(eps^2); ``T = T0 + O(eps)``.

    Attributes
    ----------
    label : str
        ``"B1,a"`` etc.: the zero T0,n,a (or T0,n,b) of the unperturbed F1 and the
        root of the quadratic that tends to 0 (branch a/b where it is the smaller
        root, Re(q a12) < 0; c/d where it is the larger one).
    n : int
        Index of the pair.
    branch : str
        ``"a"``, ``"b"``, ``"c"`` or ``"d"``.
    T : float
        T0, the zero of the unperturbed F1.
    theta0 : float
        Psi, the angle of the boundary equilibrium.
    rdot_slope, thetadot_slope, theta_slope : float or None
        d(rdot-)/d eps, d(thetadot-)/d eps, d theta / d eps at eps = 0; None where
        Re(q a12(T0)) = 0 (degenerate).
    T_slope : float or None
        dT/d eps from the implicit function theorem on F1 (None at a double zero).
        It does not enter the first-order rdot, thetadot, theta.
    qa12, qa22 : complex
        q a12(T0), q a22(T0).
    side : int
        +1 if the orbit is admissible (rdot- > 0) for small eps > 0 only, -1 for
        eps < 0 only, 0 where undecided at first order.
    """

    label: str
    n: int
    branch: str
    T: float
    theta0: float
    rdot_slope: float | None
    thetadot_slope: float | None
    theta_slope: float | None
    T_slope: float | None
    qa12: complex
    qa22: complex
    side: int

    def estimate(self, eps: float) -> tuple[float, float | None, float | None, float | None]:
        """First-order estimate (T, theta, rdot-, thetadot-) at ``eps``; theta wrapped into (-pi, pi].

        T includes the first-order drift ``T_slope`` where it is defined.
        """
        eps = _check_eps(eps)
        t = self.T + (eps * self.T_slope if self.T_slope is not None else 0.0)
        if self.rdot_slope is None:
            return t, None, None, None
        return t, wrap_angle(self.theta0 + eps * self.theta_slope), eps * self.rdot_slope, eps * self.thetadot_slope

    def to_dict(self) -> dict[str, Any]:
        """The ``local --json`` contract for one orbit."""
        return {
            "label": self.label,
            "T": self.T,
            "rdot_slope": self.rdot_slope,
            "thetadot_slope": self.thetadot_slope,
            "theta_slope": self.theta_slope,
        }


@dataclass(frozen=True)
class LocalAnalysis:
    """The first-order analysis of a `LinearImpactingSystem` at its boundary equilibrium.

    Attributes
    ----------
    system : LinearImpactingSystem
    z0 : complex
        Boundary equilibrium sigma e^{i Psi}.
    psi : float
        Psi.
    z1 : complex
        d z_eq / d eps.
    radial_shift : float
        xi = Re(z1 e^{-i Psi}); |z_eq| = sigma + eps xi + O(eps^2). Nonzero for a
        transversal crossing of the boundary.
    tangential_shift : float
        eta = Im(z1 e^{-i Psi}).
    equilibrium_side : int
        Sign of eps on which the equilibrium is admissible (|z_eq| < sigma): -sgn(xi).
    orbits : tuple of LocalOrbit
        One small orbit per simple zero of the unperturbed F1 on (0, t_max].
    t_max : float
        End of the period search.
    """

    system: LinearImpactingSystem
    z0: complex
    psi: float
    z1: complex
    radial_shift: float
    tangential_shift: float
    equilibrium_side: int
    orbits: tuple[LocalOrbit, ...]
    t_max: float

    @property
    def transversal(self) -> bool:
        """The equilibrium crosses the boundary with nonzero speed (xi != 0)."""
        return self.radial_shift != 0.0

    def orbit(self, label: str) -> LocalOrbit:
        """The orbit with this label.

        Raises
        ------
        ParameterError
            Unless ``label`` is the label of one of `orbits`.
        """
        _check_label("label", label, [o.label for o in self.orbits])
        return next(o for o in self.orbits if o.label == label)

    def to_dict(self) -> dict[str, Any]:
        """Plain data: the shifts and the orbits (slopes)."""
        return {
            "z0": self.z0,
            "psi": self.psi,
            "z1": self.z1,
            "radial_shift": self.radial_shift,
            "tangential_shift": self.tangential_shift,
            "equilibrium_side": self.equilibrium_side,
            "orbits": [o.to_dict() | {"side": o.side, "T_slope": o.T_slope} for o in self.orbits],
        }


def _sign(x: float) -> int:
    return 1 if x > 0 else (-1 if x < 0 else 0)


def local_analysis(system: LinearImpactingSystem | Parameters, t_max: float = 12.0) -> LocalAnalysis:
    """First-order expansion in eps of the small one-impact orbits at the boundary equilibrium.

    For each zero T0 of the unperturbed F1 (``eps = 0``) on (0, t_max], with
    ``c_ij = q a_ij(T0)``, ``xi + i eta = z1 e^{-i Psi}``:

    * ``rdot_slope = xi / Re(c12)``,
    * ``thetadot_slope = -Im(c22) rdot_slope / sigma``,
    * ``theta_slope = (eta - Im(c12) rdot_slope) / sigma``,
    * ``T_slope = -(dF1/d eps) / (dF1/dT)``.

    Parameters
    ----------
    system : LinearImpactingSystem or Parameters
        The system; `Parameters` stand for the rotor with eps = gamma - gamma*.
    t_max : float
        End of the search for T0.

    Returns
    -------
    LocalAnalysis
    """
    if isinstance(system, Parameters):
        system = LinearImpactingSystem.from_parameters(system)
    if not isinstance(system, LinearImpactingSystem):
        raise ParameterError(f"system = {system!r} is not a LinearImpactingSystem or Parameters")
    t_max = check_range("t_max", t_max, low=0.0, low_open=True)
    z0, psi, z1 = system.z0, system.psi, system.z1
    rot = z1 * cmath.exp(-1j * psi)
    xi, eta = float(rot.real), float(rot.imag)
    sigma = system.sigma
    q = system.q
    orbits = []
    for zero in system.f1_zeros(t_max, 0.0):
        a, da_dt, da_deps = system._derivatives(zero.T, 0.0)
        c12 = complex(q * a[0, 1])
        c22 = complex(q * a[1, 1])
        t_slope = None
        if not zero.double:
            f_t = float((q * da_dt[1, 1]).real)
            f_e = float((q * da_deps[1, 1]).real)
            if f_t != 0.0:
                t_slope = -f_e / f_t
        if abs(c12.real) <= DEGENERACY_RTOL * abs(c12):
            rd = td = th = None
            side = 0
            branch = zero.kind
        else:
            rd = xi / c12.real
            td = -c22.imag * rd / sigma
            th = (eta - c12.imag * rd) / sigma
            side = _sign(rd)
            branch = root_branches(zero.kind)[0 if c12.real < 0 else 1]
        orbits.append(
            LocalOrbit(
                label=f"B{zero.n},{branch}",
                n=zero.n,
                branch=branch,
                T=zero.T,
                theta0=psi,
                rdot_slope=rd,
                thetadot_slope=td,
                theta_slope=th,
                T_slope=t_slope,
                qa12=c12,
                qa22=c22,
                side=side,
            )
        )
    return LocalAnalysis(
        system=system,
        z0=z0,
        psi=psi,
        z1=z1,
        radial_shift=xi,
        tangential_shift=eta,
        equilibrium_side=-_sign(xi),
        orbits=tuple(orbits),
        t_max=t_max,
    )


# ---------------------------------------------------------------------------
# Comparison with the global fixed points
# ---------------------------------------------------------------------------


def global_fixed_points(
    model: LinearImpactingSystem | Parameters, eps: float, t_max: float = 12.0
) -> tuple[LinearFixedPoint, ...]:
    """The global one-impact fixed points at ``eps``.

    For `Parameters` (the rotor) these are `rotorcontact.maps.impact_map.one_impact_orbits`
    at gamma = gamma* + eps (the closed-form F1 with guaranteed zero isolation);
    for a `LinearImpactingSystem`, `LinearImpactingSystem.fixed_points`.
    """
    eps = _check_eps(eps)
    if isinstance(model, Parameters):
        gs = boundary_gamma(model)
        if gs is None:
            raise ParameterError("no real gamma* for these parameters; allowed: rho > 0 and rho >= |1 - omega^2|")
        p = model.replace(gamma=gs + eps)
        q = impact_q(p.d, p.mu)
        return tuple(
            LinearFixedPoint(label=o.label, n=o.n, branch=o.branch, T=o.T, theta=o.theta, rdot=o.rdot,
                             thetadot=o.thetadot, admissible=o.admissible, eps=eps, sigma=1.0, q=q)
            for o in one_impact_orbits(p, t_max)
        )
    if isinstance(model, LinearImpactingSystem):
        return model.fixed_points(eps, t_max)
    raise ParameterError(f"model = {model!r} is not a LinearImpactingSystem or Parameters")


@dataclass(frozen=True)
class ComparisonRow:
    """Local first-order estimate against the global fixed point for one orbit at one eps.

    Attributes
    ----------
    label : str
    eps : float
    parameter : float
        The bifurcation parameter: gamma = gamma* + eps for the rotor, eps otherwise.
    T_local, theta_local, rdot_local, thetadot_local : float or None
        The estimate (`LocalOrbit.estimate`).
    T_global, theta_global, rdot_global, thetadot_global : float or None
        The global fixed point with the same label (None where there is none).
    """

    label: str
    eps: float
    parameter: float
    T_local: float
    theta_local: float | None
    rdot_local: float | None
    thetadot_local: float | None
    T_global: float | None
    theta_global: float | None
    rdot_global: float | None
    thetadot_global: float | None

    def error(self, quantity: str) -> float | None:
        """|local - global| of ``"T"``, ``"theta"`` (angle difference), ``"rdot"`` or ``"thetadot"``.

        Raises
        ------
        ParameterError
            Unless ``quantity`` is one of `QUANTITIES`.
        """
        check_choice("quantity", quantity, QUANTITIES)
        loc = getattr(self, f"{quantity}_local")
        glo = getattr(self, f"{quantity}_global")
        if loc is None or glo is None:
            return None
        if quantity == "theta":
            return abs(angle_difference(loc, glo))
        return abs(loc - glo)

    def to_dict(self) -> dict[str, Any]:
        """Plain data with the errors."""
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out.update({f"{k}_error": self.error(k) for k in QUANTITIES})
        return out


@dataclass(frozen=True)
class LocalComparison:
    """Table of the local estimate against the global fixed points over a set of eps.

    Attributes
    ----------
    analysis : LocalAnalysis
    rows : tuple of ComparisonRow
        Ordered by label, then eps.
    offset : float
        parameter = offset + eps (gamma* for the rotor, 0 otherwise).
    """

    analysis: LocalAnalysis
    rows: tuple[ComparisonRow, ...]
    offset: float

    def select(self, label: str) -> tuple[ComparisonRow, ...]:
        """The rows of one orbit.

        Raises
        ------
        ParameterError
            Unless ``label`` is the label of an orbit in the table.
        """
        _check_label("label", label, list(dict.fromkeys(r.label for r in self.rows)))
        return tuple(r for r in self.rows if r.label == label)

    def error_order(self, label: str, quantity: str) -> float:
        """Least-squares slope of log(error) against log|eps| over the rows of ``label``.

        Raises
        ------
        ParameterError
            Unless ``label`` is the label of an orbit in the table and ``quantity`` one of `QUANTITIES`; with
            fewer than two rows with a positive error.
        """
        pts = [(abs(r.eps), r.error(quantity)) for r in self.select(label)]
        pts = [(e, err) for e, err in pts if err is not None and err > 0.0 and e > 0.0]
        if len(pts) < 2:
            raise ParameterError(f"fewer than two positive errors of {quantity} for {label!r}; cannot fit an order")
        x = np.log([p[0] for p in pts])
        y = np.log([p[1] for p in pts])
        return float(np.polyfit(x, y, 1)[0])

    def table(self) -> str:
        """A plain-text table of the comparison."""
        head = (f"{'orbit':<6} {'eps':>10} {'rdot local':>13} {'rdot global':>13} {'err':>9} "
                f"{'thdot local':>13} {'thdot global':>13} {'err':>9} {'theta err':>9}")
        lines = [head, "-" * len(head)]

        def fmt(x, spec=".6e"):
            return "-" if x is None else format(x, spec)

        for r in self.rows:
            lines.append(
                f"{r.label:<6} {r.eps:>10.3e} {fmt(r.rdot_local):>13} {fmt(r.rdot_global):>13} "
                f"{fmt(r.error('rdot'), '.2e'):>9} {fmt(r.thetadot_local):>13} {fmt(r.thetadot_global):>13} "
                f"{fmt(r.error('thetadot'), '.2e'):>9} {fmt(r.error('theta'), '.2e'):>9}"
            )
        return "\n".join(lines)


#: Most values of eps in `compare_local_global`: each finds the global orbits at one eps.
MAX_EPSILONS = 1000


def compare_local_global(
    model: LinearImpactingSystem | Parameters,
    epsilons: Iterable[float] = DEFAULT_EPSILONS,
    labels: Sequence[str] | None = ("B1,a", "B1,b"),
    t_max: float = 12.0,
) -> LocalComparison:
    """Tabulate the first-order estimate against the global fixed points.

    Parameters
    ----------
    model : LinearImpactingSystem or Parameters
        The general system, or the rotor (eps = gamma - gamma*).
    epsilons : iterable of float
        Values of eps (default: five values over the decade [1e-3, 1e-2]).
    labels : sequence of str or None
        Orbits to compare (default B1,a and B1,b); None for every local orbit.
    t_max : float
        End of the period search.

    Returns
    -------
    LocalComparison
    """
    analysis = local_analysis(model, t_max)
    offset = 0.0
    if isinstance(model, Parameters):
        offset = float(boundary_gamma(model))
    eps_arr = real_array(epsilons)
    if eps_arr is None or eps_arr.ndim != 1 or not 1 <= eps_arr.size <= MAX_EPSILONS:
        raise ParameterError(f"epsilons = {epsilons!r} is invalid; allowed: a list of 1 to {MAX_EPSILONS} numbers")
    eps_list = [_check_eps(e) for e in eps_arr.tolist()]
    local = {o.label: o for o in analysis.orbits}
    if labels is None:
        labels = tuple(local)
    elif isinstance(labels, str):
        labels = (labels,)  # one label
    elif not isinstance(labels, (list, tuple)):
        raise ParameterError(f"labels = {labels!r} is invalid; allowed: a list of orbit labels such as ['B1,a'], "
                             "or None")
    for lab in labels:
        _check_label("labels", lab, list(local), given=labels)
    glob = {e: {o.label: o for o in global_fixed_points(model, e, t_max)} for e in eps_list}
    rows = []
    for lab in labels:
        for e in eps_list:
            t, th, rd, td = local[lab].estimate(e)
            g = glob[e].get(lab)
            rows.append(
                ComparisonRow(
                    label=lab, eps=e, parameter=offset + e,
                    T_local=t, theta_local=th, rdot_local=rd, thetadot_local=td,
                    T_global=None if g is None else g.T,
                    theta_global=None if g is None else g.theta,
                    rdot_global=None if g is None else g.rdot,
                    thetadot_global=None if g is None else g.thetadot,
                )
            )
    return LocalComparison(analysis=analysis, rows=tuple(rows), offset=offset)
