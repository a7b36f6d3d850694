"""The general machine in SI (MODEL.md §7): per-axis flight coefficients, the impact law with spin.

Free flight, per unit mass, along each axis a in {x, y}:

    a'' + gamma_a a' + w2_a a = Re(H_a (w2_a - Omega^2 + i gamma_a Omega) e^{i Omega s}) + b_a,

with gamma_a = c_a/m, w2_a = k_a/m, the unbalance forcing e Omega^2 (cos psi, sin psi), psi = psi0 + Omega s,
and b = (0, F_s/m - g). Its exact solution is a = Re(H_a e^{i Omega s}) + P_a(s) + h_a(s): the harmonic
response H_a (`harmonic_response`), a polynomial of degree <= 2 for the constant force (`constant_response`)
and the homogeneous motion h_a, written e^{-gamma s/2}(C(s) h0 + S(s)(gamma h0/2 + h0')) as in
`rotorcontact.model.flow.scaled_cs` (which covers k = 0 and k = c = 0: free fall).

At |z| = c_r the impact law (`impact_with_spin`) applies Newton restitution to the normal velocity and a
Coulomb impulse against the relative surface velocity v_rel = v_t + R Omega - R_b Omega_b, bounded so that
v_rel never reverses, with the effective inverse mass 1/m + R^2/I_p + R_b^2/I_b (`effective_mass_factor`).
With 1/I_p = 1/I_b = 0 it is `rotorcontact.model.impact_law.apply_reset` in SI.

The compiled functions are kernels for the simulator's loops and take their arguments unchecked (NaN
gives NaN; text is a numba typing error); `rotorcontact.Machine` checks a machine's values. The Python
functions of the compliant law (`impact_duration_factor`, `elastic_impact_duration`, `hertz_rebound`,
`restitution_damping`) check theirs.
"""

from __future__ import annotations

import cmath
import math

from functools import lru_cache
from typing import Any

from numba import njit

from ..interpreted import complex_quotient
from .validation import check_float
from .impact_law import slip_bound, sticks

__all__ = [
    "rolling_fixed_coefficients",
    "harmonic_response",
    "constant_response",
    "effective_mass_factor",
    "surface_velocity",
    "impact_with_spin",
    "impact_dissipation",
    "race_spin",
    "unbalance_amplitudes",
    "kinetic_energy",
    "angular_momentum",
    "rolling_whirl_rate",
    "contact_accelerations",
    "compliant_normal_force",
    "elastic_impact_duration",
    "impact_duration",
    "impact_duration_factor",
    "hertz_rebound",
    "restitution_damping",
]


@njit(cache=True)
def harmonic_response(gamma: float, w2: float, spin: float, amplitude: complex) -> complex:
    """H with a_p = Re(H e^{i Omega s}) solving a'' + gamma a' + w2 a = Re(amplitude e^{i Omega s}) (MODEL.md §7).

    H = amplitude / (w2 - Omega^2 + i gamma Omega); zero when there is no forcing. The undamped
    resonance w2 = Omega^2, gamma = 0 with forcing has no bounded response and gives nan (refused
    by the callers' checks).
    """
    if amplitude == 0.0:
        return 0j
    den = complex(w2 - spin * spin, gamma * spin)
    if den == 0.0:
        return complex(math.nan, math.nan)
    return complex_quotient(amplitude, den)


@njit(cache=True)
def constant_response(gamma: float, w2: float, b: float) -> tuple[float, float, float]:
    """(p0, p1, p2) of P(s) = p0 + p1 s + p2 s^2/2 solving P'' + gamma P' + w2 P = b (MODEL.md §7).

    b/w2 with a spring; b s/gamma with damping only; b s^2/2 in free fall (k = c = 0).
    """
    if w2 > 0.0:
        return b / w2, 0.0, 0.0
    if gamma > 0.0:
        return 0.0, b / gamma, 0.0
    return 0.0, 0.0, b


@njit(cache=True)
def effective_mass_factor(mass: float, radius: float, inv_polar: float, race_radius: float,
                          inv_race: float) -> float:
    """kappa = m (1/m + R^2/I_p + R_b^2/I_b): a tangential impulse P changes v_rel by kappa P/m (MODEL.md §7).

    ``inv_polar`` = 1/I_p (0 with the speed held), ``inv_race`` = 1/I_b (0 for a fixed stator).
    """
    return 1.0 + mass * (radius * radius * inv_polar + race_radius * race_radius * inv_race)


@njit(cache=True)
def surface_velocity(v_t: float, radius: float, spin: float, race_radius: float, race: float) -> float:
    """v_rel = v_t + R Omega - R_b Omega_b, the slip of the rotor's surface on the race's (MODEL.md §7).

    In units of c_r Omega this is `rotorcontact.model.impact_law.relative_velocity` with the race at rest.
    """
    return v_t + radius * spin - race_radius * race


@njit(cache=True)
def impact_with_spin(z: complex, v: complex, spin: float, race: float, mass: float, d: float, mu: float,
                     radius: float, inv_polar: float, race_radius: float, inv_race: float):
    """State just after an impact at z (on |z| = c_r) of the general machine (MODEL.md §7).

    Returns
    -------
    v_plus : complex
        Velocity of the centre after the impact, m/s.
    spin_plus, race_plus : float
        Spin of the rotor and of the race after, rad/s.
    v_n, v_rel : float
        Normal velocity (outward) and relative surface velocity before, m/s.
    p_n, p_t : float
        Normal impulse (magnitude) and tangential impulse on the rotor along +theta, N s.
    """
    e = complex_quotient(z, abs(z))
    w = e.conjugate() * v
    v_n = w.real
    v_t = w.imag
    v_rel = surface_velocity(v_t, radius, spin, race_radius, race)
    kappa = effective_mass_factor(mass, radius, inv_polar, race_radius, inv_race)
    slip = slip_bound(d, mu, v_n)  # mu (1 + d) v_n: the Coulomb bound per unit mass
    # the impulse per unit mass that brings v_rel to 0 is v_rel / kappa: the slip bound of MODEL.md §2
    if sticks(v_rel / kappa, slip):
        q_t = -v_rel / kappa
    else:
        q_t = -math.copysign(slip, v_rel)
    v_plus = e * complex(-d * v_n, v_t + q_t)
    spin_plus = spin + mass * radius * q_t * inv_polar
    race_plus = race - mass * race_radius * q_t * inv_race
    return v_plus, spin_plus, race_plus, v_n, v_rel, mass * (1.0 + d) * v_n, mass * q_t


@njit(cache=True)
def impact_dissipation(mass: float, d: float, v_n: float, v_rel: float, p_t: float, kappa: float) -> float:
    """Energy an impact of `impact_with_spin` dissipates in the touchdown bearing, J (MODEL.md §7).

    (1 - d^2) m v_n^2 / 2 by restitution plus the friction work |P_t| (|v_rel-| + |v_rel+|) / 2, with
    v_rel+ = v_rel- + kappa P_t / m on the same side of 0 as v_rel- (or at 0: a sticking impact). It equals
    the loss of m |z'|^2/2 + I_p Omega^2/2 + I_b Omega_b^2/2 (plus the motor's work with the speed held)
    without differencing those energies, so it keeps its relative accuracy however large the spin energies
    are. Never negative.

    Parameters
    ----------
    mass, d : float
        m (kg) and the restitution.
    v_n, v_rel : float
        Normal velocity (outward) and relative surface velocity before the impact, m/s.
    p_t : float
        Tangential impulse on the rotor, N s.
    kappa : float
        `effective_mass_factor` of the impact.
    """
    slip_after = max(0.0, abs(v_rel) - kappa * abs(p_t) / mass)  # |v_rel+|: friction never reverses v_rel
    return 0.5 * (1.0 - d * d) * mass * v_n * v_n + 0.5 * abs(p_t) * (abs(v_rel) + slip_after)


@njit(cache=True)
def race_spin(race0: float, s: float, inertia: float, torque: float, coefficient: float) -> float:
    """Spin of the race a time s after race0, free of contact: I_b Omega_b' = -T sgn(Omega_b) - c_b Omega_b.

    Closed form: exponential approach to -T/c_b (c_b > 0) or linear decay (c_b = 0), held at rest once it
    stops (the constant torque is static friction there).
    """
    if race0 == 0.0:
        return 0.0
    sgn = 1.0 if race0 > 0.0 else -1.0
    w0 = abs(race0)
    if coefficient > 0.0:
        floor = torque / coefficient
        w = (w0 + floor) * math.exp(-coefficient * s / inertia) - floor
    else:
        w = w0 - torque * s / inertia
    return sgn * max(w, 0.0)


@njit(cache=True)
def kinetic_energy(mass: float, v: complex, polar: float, spin: float, race_inertia: float, race: float) -> float:
    """(m |v|^2 + I_p Omega^2 + I_b Omega_b^2) / 2, J (``polar``, ``race_inertia``: 0 for held / fixed)."""
    return 0.5 * (mass * (v.real * v.real + v.imag * v.imag) + polar * spin * spin + race_inertia * race * race)


@njit(cache=True)
def angular_momentum(mass: float, z: complex, v: complex, polar: float, spin: float, race_inertia: float,
                     race: float) -> float:
    """m Im(conj(z) v) + I_p Omega + I_b Omega_b, about the stator centre, kg m^2/s (MODEL.md §7)."""
    return mass * (z.real * v.imag - z.imag * v.real) + polar * spin + race_inertia * race


@njit(cache=True)
def unbalance_amplitudes(eccentricity: float, spin: float, psi: float) -> tuple[complex, complex]:
    """Complex amplitudes (F_x, F_y) of the unbalance forcing e Omega^2 (cos, sin)(psi + Omega s) per unit mass."""
    f = eccentricity * spin * spin * cmath.exp(1j * psi)
    return f, -1j * f



@njit(cache=True)
def rolling_whirl_rate(radius: float, clearance: float, spin: float, race_radius: float, race: float) -> float:
    """Theta' of rolling contact, v_rel = c_r Theta' + R Omega - R_b Omega_b = 0 (MODEL.md §7): -(R/c_r) Omega on a
    fixed stator (race = 0)."""
    return (race_radius * race - radius * spin) / clearance


@njit(cache=True)
def contact_accelerations(f_n: float, f_t: float, sd: float, cd: float, ecc: float, clearance: float, thetadot: float,
                          mu: float, sgn: float, rolling: bool, mass: float, radius: float, inv_polar: float,
                          race_radius: float, inv_race: float, race_drag: float):
    """Accelerations in continuous contact on |z| = c_r of the general machine (MODEL.md §7).

    Parameters
    ----------
    f_n, f_t : float
        Normal (outward) and tangential components of the external force per unit mass without the
        unbalance's -i e Omega' e^{i psi} term (bearing, static force, gravity, e Omega^2 e^{i psi}).
    sd, cd : float
        sin(delta), cos(delta) of delta = psi - theta, the unbalance angle relative to the contact point.
    ecc, clearance, thetadot : float
        e, c_r and the whirl rate theta'.
    mu, sgn : float
        Friction coefficient and sgn(v_rel) while sliding.
    rolling : bool
        v_rel = 0 held (rolling) instead of sliding.
    mass, radius, inv_polar, race_radius, inv_race : float
        m, R, 1/I_p (0: speed held), R_b, 1/I_b (0: fixed stator).
    race_drag : float
        The race's drag torque T_b sgn(Omega_b) + c_b Omega_b, N m.

    Returns
    -------
    thetadd, spin_dot, race_dot : float
        theta'', Omega', Omega_b'.
    n, q : float
        Normal and tangential contact force per unit mass (N/m, F_t/m; q along +theta on the rotor).
    """
    a = mass * radius * inv_polar  # Omega' = a q
    b = mass * race_radius * inv_race  # Omega_b' = -b q - drag / I_b
    drag = race_drag * inv_race
    base_n = f_n + clearance * thetadot * thetadot
    if rolling:
        # c theta'' = f_t - e Omega' cos(delta) + q and c theta'' + R Omega' - R_b Omega_b' = 0
        q = -(f_t + race_radius * drag) / (1.0 + radius * a + race_radius * b - ecc * a * cd)
        n = base_n + ecc * a * q * sd
    else:
        # n = base_n + e Omega' sin(delta), q = -mu sgn n
        n = base_n / (1.0 + ecc * a * mu * sgn * sd)
        q = -mu * sgn * n
    spin_dot = a * q
    thetadd = (f_t - ecc * spin_dot * cd + q) / clearance
    race_dot = -b * q - drag
    return thetadd, spin_dot, race_dot, n, q


@njit(cache=True)
def rolling_fixed_coefficients(cos_theta: float, sd: float, cd: float, f_y: float, ecc: float, clearance: float,
                               mass: float, radius: float, inv_polar: float) -> tuple[float, float]:
    """(P, Q) of rolling on a fixed stator with a free speed under a constant force f_y (per unit mass, +y)
    and the unbalance: d(theta'^2)/d theta = P + Q theta'^2 (MODEL.md §7, rolling reduced to theta), at
    cos(theta) and sd, cd = sin(delta), cos(delta), delta = psi - theta.

    With Omega = -(c_r/R) theta', the rolling branch of `contact_accelerations` gives
    c_r theta'' = K f_t, K = R a / (1 + R a - e a cos(delta)), a = m R / I_p, and
    f_t = f_y cos(theta) + e (c_r/R)^2 theta'^2 sin(delta).
    """
    a = mass * radius * inv_polar
    k = radius * a / (1.0 + radius * a - ecc * a * cd)
    return 2.0 * k * f_y * cos_theta / clearance, 2.0 * k * ecc * clearance * sd / (radius * radius)


@njit(cache=True)
def compliant_normal_force(delta: float, delta_dot: float, stiffness: float, exponent: float,
                           damping: float) -> tuple[float, float]:
    """(F_n, F_el) of the compliant law F_n = max(0, K_c delta^n (1 + D delta')) (MODEL.md §8), N.

    F_el = K_c delta^n is its elastic part; both are 0 out of contact (delta <= 0). F_n never pulls: where
    1 + D delta' < 0 (fast separation) it is 0 and the surfaces part while delta > 0.
    """
    if delta <= 0.0:
        return 0.0, 0.0
    f_el = stiffness * delta ** exponent
    return max(0.0, f_el * (1.0 + damping * delta_dot)), f_el


#: Largest Hunt-Crossley damping chi of `hertz_rebound`: the rebound is about 1/chi for large chi, so this
#: covers restitution down to `MIN_COMPLIANT_RESTITUTION`; the overdamped creep takes tau ~ 100 chi^2.
MAX_CHI = 1e3
#: Smallest restitution of a compliant contact: chi in [0, 2/d + 2] stays within `MAX_CHI`.
MIN_COMPLIANT_RESTITUTION = 2.0 / (MAX_CHI - 2.0)
#: Largest exponent of the compliant law, as `rotorcontact.Machine` allows.
MAX_EXPONENT = 10.0


def _exponent(exponent: Any) -> float:
    return check_float("exponent", exponent, 0.0, MAX_EXPONENT, low_open=True)


def impact_duration_factor(exponent: float) -> float:
    """2 B(1/(n+1), 1/2)/(n+1), the factor of `impact_duration` (MODEL.md §8).

    Plain Python, passed to the kernels: numba's math.gamma (C's tgamma) and Python's differ in the last bits.
    """
    exponent = _exponent(exponent)
    a = 1.0 / (exponent + 1.0)
    return 2.0 * a * math.gamma(a) * math.sqrt(math.pi) / math.gamma(a + 0.5)


@njit(cache=True)
def impact_duration(mass: float, v0: float, stiffness: float, exponent: float, factor: float) -> float:
    """T_c = factor delta_max/v0, delta_max = ((n+1) m v0^2/(2 K_c))^(1/(n+1)), ``factor`` of
    `impact_duration_factor` (MODEL.md §8), s."""
    d_max = ((exponent + 1.0) * mass * v0 * v0 / (2.0 * stiffness)) ** (1.0 / (exponent + 1.0))
    return factor * d_max / v0


def elastic_impact_duration(mass: float, v0: float, stiffness: float, exponent: float) -> float:
    """Duration of an isolated elastic impact (d = 1) at normal velocity v0 under F_n = K_c delta^n, s:
    T_c = 2 (delta_max/v0) B(1/(n+1), 1/2)/(n+1), delta_max = ((n+1) m v0^2/(2 K_c))^(1/(n+1)) (MODEL.md §8).

    Raises
    ------
    ParameterError
        Unless the mass, v0 and the stiffness are finite numbers > 0 and the exponent in (0, 10].
    """
    for name, value in (("mass", mass), ("v0", v0), ("stiffness", stiffness)):
        check_float(name, value, 0.0, low_open=True)
    return float(impact_duration(mass, v0, stiffness, exponent, impact_duration_factor(exponent)))


def hertz_rebound(chi: float, exponent: float, rtol: float = 1e-12) -> float:
    """Rebound ratio of an isolated impact under F_n = max(0, K_c delta^n (1 + chi delta'/v_0)) (MODEL.md §8).

    In the units delta = L u, t = (L/v_0) tau with L = (m v_0^2/K_c)^(1/(n+1)) the impact obeys
    u'' = -u^n max(0, 1 + chi u'), u(0) = 0, u'(0) = 1, with no other parameter: the rebound -u' at the
    return to u = 0 depends on chi and n only (not on m, K_c or v_0). Integrated by scipy's DOP853.

    Raises
    ------
    ParameterError
        Unless chi is in [0, `MAX_CHI`], the exponent in (0, 10] and rtol in [1e-14, 1e-3].
    """
    from scipy.integrate import solve_ivp

    chi = check_float("chi", chi, 0.0, MAX_CHI)
    exponent = _exponent(exponent)
    rtol = check_float("rtol", rtol, 1e-14, 1e-3)

    def rates(_t, y):
        u = max(y[0], 0.0)
        return (y[1], -u ** exponent * max(0.0, 1.0 + chi * y[1]))

    def back(_t, y):
        return y[0]

    back.terminal = True
    back.direction = -1.0
    # the free return takes tau = 2 u_max, u_max = (n + 1)^(1/(n+1)) at chi = 0; damping lengthens it
    # at most to the overdamped creep at u' = -1/chi
    span = 100.0 * (1.0 + chi) ** 2
    sol = solve_ivp(rates, (0.0, span), (0.0, 1.0), method="DOP853", rtol=rtol, atol=rtol * 1e-3, events=back)
    if sol.t_events[0].size == 0:
        raise RuntimeError(f"the impact with chi = {chi!r} did not end within tau = {span!r}")
    return float(-sol.y_events[0][0][1])


@lru_cache(maxsize=64)
def restitution_damping(restitution: float, exponent: float) -> float:
    """chi(d, n) with D = chi / v_0: the Hunt-Crossley damping whose isolated impact rebounds with d (MODEL.md §8).

    Solved for chi by Brent's method on `hertz_rebound` (to 1e-13 in chi), so the rebound ratio is d at
    every impact speed, mass and stiffness, not only near d = 1. The rebound falls from 1 at chi = 0 to
    about 1/chi as chi grows (the overdamped creep at u' = -1/chi), so chi lies in [0, 2/d + 2].

    Raises
    ------
    ParameterError
        For d outside [`MIN_COMPLIANT_RESTITUTION`, 1] (d = 0 needs infinite damping), or an exponent outside
        (0, 10].
    """
    from scipy.optimize import brentq

    restitution = check_float("restitution", restitution, MIN_COMPLIANT_RESTITUTION, 1.0)
    exponent = _exponent(exponent)
    if restitution == 1.0:
        return 0.0
    top = min(2.0 / restitution + 2.0, MAX_CHI)  # equal at the smallest restitution, but for rounding
    return float(brentq(lambda chi: hertz_rebound(chi, exponent) - restitution, 0.0, top, xtol=1e-13, rtol=1e-13))
