"""The steady dry whip of a rotor in a compliant touchdown bearing on springs (MODEL.md §8, dry whip).

Rotor and stator whirl together in sliding contact, z = r e^{i w t}, z_s = zeta e^{i w t}, without unbalance
and with the speed held. With A = k - m w^2 + i c w (k = c = 0 once the magnetic bearing has failed) and
B = k_s - m_s w^2 + i c_s w, zeta = -A r / B and -F_n + i F_t = G rho, G = A B / (A + B), rho = c_r + delta.
Sliding forward (F_t = -mu F_n) gives Im G(w) = mu Re G(w), an equation for w alone whose root just below the
coupled natural frequency sqrt((k + k_s)/(m + m_s)) is the whip; K_c delta^n = -Re G rho fixes its amplitude.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.params import MAX_T_END, Machine
from ..model.units import RPM
from ..model.validation import check_bool, check_float, check_machine

__all__ = ["DryWhip", "steady_dry_whip"]

#: Points of the grid that brackets the whip's root below the coupled frequency (closing in on it
#: geometrically from 1e-12 to 1/2 of it).
GRID_POINTS = 800


@dataclass(frozen=True)
class DryWhip:
    """The steady dry whip of a machine (SI).

    Attributes
    ----------
    machine : Machine
        The machine, at its speed.
    bearing_failed : bool
        Whether the magnetic bearing has failed (k = c = 0) or acts.
    whirl_rate : float
        w, rad/s (negative: backward, against a positive spin).
    coupled_frequency : float
        sqrt((k + k_s)/(m + m_s)), rad/s (k = 0 with the bearing failed).
    rotor_orbit, stator_orbit : complex
        r and zeta at t = 0: the rotor's centre z = r e^{i w t} (r real, m) and the stator's z_s = zeta e^{i w t}.
    normal_force, friction_force : float
        F_n and F_t = -mu F_n on the rotor, N.
    penetration : float
        delta = rho - c_r, m.
    slip_velocity : float
        v_rel = R Omega + w rho at the machine's speed, m/s (> 0: the contact slides forward, as assumed).
    """

    machine: Machine
    bearing_failed: bool
    whirl_rate: float
    coupled_frequency: float
    rotor_orbit: complex
    stator_orbit: complex
    normal_force: float
    friction_force: float
    penetration: float
    slip_velocity: float

    @property
    def whirl_frequency_hz(self) -> float:
        """w / 2 pi, Hz."""
        return self.whirl_rate / (2.0 * math.pi)

    def to_dict(self) -> dict[str, Any]:
        """The ``rotorcontact dry-whip --json`` contract (README)."""
        return {
            "machine": self.machine.as_dict(),
            "speed_rpm": self.machine.speed / RPM,
            "bearing": "failed" if self.bearing_failed else "acting",
            "whirl_rate_rad_per_s": self.whirl_rate,
            "whirl_frequency_hz": self.whirl_frequency_hz,
            "coupled_frequency_hz": self.coupled_frequency / (2.0 * math.pi),
            "rotor_orbit_m": abs(self.rotor_orbit),
            "stator_orbit_m": abs(self.stator_orbit),
            "stator_phase_rad": math.atan2(self.stator_orbit.imag, self.stator_orbit.real),
            "normal_force_N": self.normal_force,
            "friction_force_N": self.friction_force,
            "penetration_m": self.penetration,
            "slip_velocity_m_per_s": self.slip_velocity,
        }

    def state(self, t: float) -> tuple[complex, complex, complex, complex]:
        """(z, z', z_s, z_s') at time t (s), m and m/s.

        Raises
        ------
        ParameterError
            Unless ``t`` is a finite real number over which the whirl turns by at most
            `rotorcontact.model.params.MAX_T_END` radians (|whirl_rate t| <= 1e7: beyond it the angle is not
            resolved to 1e-9 rad).
        """
        t = check_float("t", t)
        rate = abs(self.whirl_rate)
        if rate * abs(t) > MAX_T_END:
            raise ParameterError(f"t = {t!r} s is invalid: the whirl would turn by more than {MAX_T_END:g} rad, where "
                                 f"its angle is not resolved; allowed: |t| <= {MAX_T_END / rate:.6g} s")
        turn = complex(math.cos(self.whirl_rate * t), math.sin(self.whirl_rate * t))
        w = 1j * self.whirl_rate
        return self.rotor_orbit * turn, w * self.rotor_orbit * turn, self.stator_orbit * turn, \
            w * self.stator_orbit * turn


def _support(machine: Machine) -> tuple[float, float]:
    kx, ky, cx, cy = machine.stator_support()
    if kx != ky or cx != cy:
        raise ParameterError(
            f"stator support ({kx!r}, {ky!r}) N/m, ({cx!r}, {cy!r}) N s/m: a circular whirl needs an isotropic "
            "support; allowed: equal stiffness and damping on x and y"
        )
    return kx, cx


def steady_dry_whip(machine: Machine, bearing_failed: bool = True) -> DryWhip:
    """The steady dry whip of ``machine`` at its speed: the root of Im G = mu Re G just below the coupled
    natural frequency (MODEL.md §8).

    Parameters
    ----------
    machine : Machine
        A compliant machine with a stator on springs (isotropic support) and no race, friction > 0;
        unbalance and gravity are left out of the whirl, and its speed is held (with a polar inertia the
        friction torque R F_t slows a free spin, so the whip is then the one of the current speed). Another
        steady whirl of the same equations can lie above the stator's own frequency sqrt(k_s/m_s) (MODEL.md
        §8); it is not the one returned.
    bearing_failed : bool
        True: the magnetic bearing has failed (k = c = 0); False: its k and c (isotropic) act.

    Raises
    ------
    ParameterError
        Without a stator on springs or friction, with an anisotropic support or bearing, where no root lies
        below the coupled frequency, or where the machine's speed is too low (or its rotor_radius 0) for the
        contact to slide forward.
    """
    check_machine(machine, optional=False)
    bearing_failed = check_bool("bearing_failed", bearing_failed)
    if not machine.has_stator:
        raise ParameterError("stator_mass = None: dry whip needs a stator on springs (stator_mass, stator_stiffness)")
    if machine.has_race:
        raise ParameterError(
            f"race_inertia = {machine.race_inertia!r}: the steady dry whip is that of a stator without a turning "
            "race (the race's spin would enter the slip); allowed: a machine without the race keys"
        )
    if not machine.friction > 0.0:
        raise ParameterError(f"friction = {machine.friction!r}: dry whip is driven by friction; allowed: > 0")
    ks, cs = _support(machine)
    if bearing_failed:
        k = c = 0.0
    else:
        if machine.kx != machine.ky or machine.cx != machine.cy:
            raise ParameterError(
                f"bearing_failed = False with an anisotropic bearing (stiffness {machine.kx!r}, {machine.ky!r} N/m, "
                f"damping {machine.cx!r}, {machine.cy!r} N s/m on x, y); a circular whirl needs "
                "stiffness_x = stiffness_y and damping_x = damping_y"
            )
        k, c = machine.kx, machine.cx
    m, ms, mu = machine.mass, machine.stator_mass, machine.friction
    if cs == 0.0 and c == 0.0:
        # G is real: friction, never balanced, makes the whirl grow (MODEL.md §8, dry whip)
        raise ParameterError(
            "stator_damping = 0.0 with no bearing damping: without damping the whip's friction work is never "
            "dissipated and its amplitude grows, so there is no steady whip; allowed: stator_damping > 0"
        )

    def terms(w: float) -> tuple[complex, complex, complex]:
        a = complex(k - m * w * w, c * w)
        b = complex(ks - ms * w * w, cs * w)
        return a * b / (a + b), a, b

    def residual(w: float) -> float:
        g = terms(w)[0]
        return g.imag - mu * g.real

    from scipy.optimize import brentq

    coupled = math.sqrt((k + ks) / (m + ms))
    grid = -coupled * (1.0 - np.geomspace(1e-12, 0.5, GRID_POINTS))
    signs = np.sign([residual(w) for w in grid])
    changes = np.flatnonzero(signs[1:] * signs[:-1] < 0.0)
    if changes.size == 0:
        raise ParameterError(
            f"no steady dry whip within half of the coupled frequency {coupled:.6g} rad/s for friction = {mu!r}, "
            f"stator_damping = {cs!r} and a bearing damping of {c!r}; allowed: less damping or more friction"
        )
    i = int(changes[0])
    w = brentq(residual, grid[i], grid[i + 1], xtol=1e-15 * coupled, rtol=4.0 * np.finfo(float).eps)
    g, a, b = terms(w)
    if not g.real < 0.0:
        raise ParameterError(f"the whirl at {w:.6g} rad/s would pull the surfaces together (Re G = {g.real:.6g} >= 0)")
    kc, n, cr = machine.contact_stiffness, machine.exponent, machine.clearance

    def balance(d: float) -> float:
        return kc * d**n + g.real * (cr + d)

    top = cr
    # K_c delta^n outgrows -Re G (c_r + delta) for n > 1, and for n = 1 where K_c > -Re G; else no balance
    for _ in range(200):
        if balance(top) > 0.0:
            break
        top *= 2.0
    else:
        raise ParameterError(f"contact_stiffness = {kc!r}: no penetration balances the whirl's force (n = {n!r})")
    delta = brentq(balance, 0.0, top, xtol=1e-16 * cr, rtol=4.0 * np.finfo(float).eps)
    rho = cr + delta
    r = rho * abs(b / (a + b))
    slip = machine.rotor_radius * machine.speed + w * rho
    if not slip > 0.0:
        if not machine.rotor_radius > 0.0:
            raise ParameterError(
                f"rotor_radius = {machine.rotor_radius!r} m is invalid: the rotor's surface does not move "
                f"(R Omega = 0), so whatever the speed the contact cannot slide forward against the whirl's "
                f"surface speed {-w * rho:.6g} m/s; allowed: rotor_radius > 0"
            )
        least = -w * rho / machine.rotor_radius
        raise ParameterError(
            f"speed = {machine.speed!r} rad/s: R Omega = {machine.rotor_radius * machine.speed:.6g} m/s is below the "
            f"whirl's surface speed {-w * rho:.6g} m/s, so the contact cannot slide forward; allowed: a speed above "
            f"{least:.6g} rad/s ({least / RPM:.6g} rpm)"
        )
    force = -g.real * rho
    return DryWhip(machine=machine, bearing_failed=bearing_failed, whirl_rate=w, coupled_frequency=coupled,
                   rotor_orbit=complex(r), stator_orbit=-a * r / b,
                   normal_force=force, friction_force=-mu * force, penetration=delta, slip_velocity=slip)
