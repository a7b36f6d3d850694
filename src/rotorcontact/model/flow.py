"""Exact free flight in closed form (MODEL.md §3).

With V = U - k the deviation from the regular equilibrium k, the co-rotating
flow is w' = A w with A = [[0, 1], [b, -2a]], where

    a = (gamma + 2i) / 2,   b = 1 - omega^2 - i gamma.

Writing m = tr(A)/2 = -a and h^2 = (gamma^2 - 4 omega^2) / 4 (a real number),
(A - m I)^2 = h^2 I, so

    e^{A t} = e^{-gamma t/2} e^{-i t} [C(t) I + S(t) (A + a I)],
    C = cosh(h t),  S = sinh(h t) / h,

with C and S real: cos / sin(nu t)/nu when underdamped (h = i nu), cosh /
sinh(kappa t)/kappa when overdamped, and 1 / t at critical damping. This form
has no eigenvector cancellation near gamma = 2 omega, and the factor e^{-it}
is exactly the rotation between the co-rotating and the inertial frame.

`free_flight` and `to_inertial` are the checked Python entry points. The other functions are compiled
kernels, the one home of each formula for the compiled loops: they take floats and complex numbers
unchecked (NaN gives NaN; text is a numba typing error).
"""

from __future__ import annotations

import cmath
import math

import numpy as np
from numba import njit

from ..errors import ParameterError
from ..interpreted import call_kernel, complex_quotient
from .params import Parameters

__all__ = [
    "half_discriminant",
    "flight_coefficients",
    "flight_accel",
    "propagate",
    "free_flight",
    "to_inertial",
    "equilibrium_point",
    "has_regular_equilibrium",
    "period_closed_form",
]


@njit(cache=True)
def half_discriminant(gamma: float, omega: float) -> float:
    """h^2 = gamma^2/4 - omega^2, the squared half-difference of the flight's eigenvalues (MODEL.md §3)."""
    return 0.25 * gamma * gamma - omega * omega


@njit(cache=True)
def flight_coefficients(gamma: float, omega: float) -> tuple[complex, complex]:
    """a = (gamma + 2i)/2 and b = 1 - omega^2 - i gamma of the co-rotating flow w' = [[0, 1], [b, -2a]] w."""
    return complex(0.5 * gamma, 1.0), complex(1.0 - omega * omega, -gamma)


@njit(cache=True)
def flight_accel(u: complex, du: complex, k: complex, gamma: float, omega: float) -> complex:
    """U'' of free flight (MODEL.md §3): -(gamma + 2i) U' + (1 - omega^2 - i gamma) (U - k)."""
    return -complex(gamma, 2.0) * du + complex(1.0 - omega * omega, -gamma) * (u - k)


@njit(cache=True)
def scaled_cs(t: float, gamma: float, h2: float) -> tuple[float, float]:
    """Return e^{-gamma t/2} C(t) and e^{-gamma t/2} S(t) for h^2 = h2."""
    g2 = 0.5 * gamma
    if h2 < 0.0:
        nu = math.sqrt(-h2)
        e = math.exp(-g2 * t)
        return e * math.cos(nu * t), e * math.sin(nu * t) / nu
    if h2 > 0.0:
        kap = math.sqrt(h2)
        x = kap * t
        if abs(x) < 20.0:
            e = math.exp(-g2 * t)
            return e * math.cosh(x), e * math.sinh(x) / kap
        ep = math.exp((kap - g2) * t)
        em = math.exp((-kap - g2) * t)
        return 0.5 * (ep + em), 0.5 * (ep - em) / kap
    e = math.exp(-g2 * t)
    return e, e * t


@njit(cache=True)
def propagate(v0: complex, dv0: complex, t: float, gamma: float, omega: float) -> tuple[complex, complex]:
    """Exact flow of the homogeneous part: (V, V') at time t from (V, V') = (v0, dv0) at 0."""
    a, b = flight_coefficients(gamma, omega)
    h2 = half_discriminant(gamma, omega)
    c, s = scaled_cs(t, gamma, h2)
    rot = complex(math.cos(t), -math.sin(t))
    v = rot * (c * v0 + s * (a * v0 + dv0))
    dv = rot * (c * dv0 + s * (b * v0 - a * dv0))
    return v, dv


@njit(cache=True)
def equilibrium_point(gamma: float, omega: float, rho: float, phi: float) -> complex:
    """k = rho e^{i phi} / (omega^2 - 1 + i gamma), the regular equilibrium (MODEL.md §3).

    `Parameters.k` is this value; `has_regular_equilibrium` tells where it is finite.
    """
    return complex_quotient(rho * cmath.exp(1j * phi), complex(omega * omega - 1.0, gamma))


@njit(cache=True)
def has_regular_equilibrium(gamma: float, omega: float) -> bool:
    """omega^2 - 1 + i gamma != 0: k of `equilibrium_point` is finite (not at omega = 1 with gamma = 0)."""
    return omega * omega - 1.0 != 0.0 or gamma != 0.0


@njit(cache=True)
def period_closed_form(t: float, gamma: float, h2: float):
    """The closed forms behind [a_ij(T)] = (e^{-AT} - I)^{-1} (MODEL.md §5), and their T-derivatives.

    With m = -(gamma/2 + i), C = cosh(hT), S = sinh(hT)/h (h^2 = ``h2``):

        D = 2 (cosh(mT) - C),   P = C + mS - e^{mT},

    so that a12 = S/D and a22 = P/D.

    Returns
    -------
    c, s : float
        C and S at T = ``t``.
    em, chm : complex
        e^{mT} and cosh(mT).
    d0, d1, d2, p0, p1, p2 : complex
        D, P and their first and second derivatives in T.
    """
    c, s = scaled_cs(t, 0.0, h2)
    m = complex(-0.5 * gamma, -1.0)
    em = cmath.exp(m * t)
    chm = cmath.cosh(m * t)
    shm = cmath.sinh(m * t)
    d0 = 2.0 * (chm - c)
    d1 = 2.0 * (m * shm - h2 * s)
    d2 = 2.0 * (m * m * chm - h2 * c)
    p0 = c + m * s - em
    p1 = h2 * s + m * c - m * em
    p2 = h2 * c + m * h2 * s - m * m * em
    return c, s, em, chm, d0, d1, d2, p0, p1, p2


@njit(cache=True)
def _flow_many(u0: complex, du0: complex, t: np.ndarray, gamma: float, omega: float, k: complex):
    u = np.empty(t.shape[0], dtype=np.complex128)
    du = np.empty(t.shape[0], dtype=np.complex128)
    for i in range(t.shape[0]):
        v, dv = propagate(u0 - k, du0, t[i], gamma, omega)
        u[i] = k + v
        du[i] = dv
    return u, du


def free_flight(params: Parameters, u0: complex, du0: complex, t) -> tuple[np.ndarray, np.ndarray]:
    """Contact-free motion from (U, U') = (u0, du0) at t = 0, evaluated exactly at times ``t``.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    u0, du0 : complex
        Position and velocity in the co-rotating frame at t = 0.
    t : array_like
        Dimensionless times (any sign).

    Returns
    -------
    U, dU : numpy.ndarray
        Complex position and velocity in the co-rotating frame, shaped like ``t``.
    """
    from .validation import check_params, complex_value, real_array

    check_params(params)
    u0, du0 = complex_value("u0", u0), complex_value("du0", du0)
    tt = real_array(t)
    if tt is None or not np.all(np.isfinite(tt)):
        raise ParameterError(f"t = {t!r} is invalid; allowed: finite real numbers")
    u, du = call_kernel(_flow_many, u0, du0, np.ascontiguousarray(tt.ravel()), params.gamma, params.omega, params.k)
    if not (np.all(np.isfinite(u)) and np.all(np.isfinite(du))):
        raise ParameterError(
            f"t = {t!r} reaches times where the contact-free motion overflows (it grows like e^(gamma |t| / 2) "
            f"backwards, gamma = {params.gamma!r}); allowed: times nearer 0"
        )
    return u.reshape(tt.shape), du.reshape(tt.shape)


def to_inertial(u, t):
    """Inertial-frame position Z = U e^{i t} (MODEL.md §2).

    Raises
    ------
    ParameterError
        Unless ``u`` holds finite numbers and ``t`` finite real numbers, of shapes that broadcast together.
    """
    from .validation import check_broadcast, complex_array, real_array

    uu = complex_array(u)
    tt = real_array(t)
    if uu is None or not np.all(np.isfinite(uu)):
        raise ParameterError(f"u = {u!r} is invalid; allowed: finite (complex) numbers")
    if tt is None or not np.all(np.isfinite(tt)):
        raise ParameterError(f"t = {t!r} is invalid; allowed: finite real numbers")
    check_broadcast(u=uu, t=tt)
    return uu * np.exp(1j * tt)
