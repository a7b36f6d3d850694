"""A drop of the general machine (MODEL.md §7): levitated whirl, bearing failure, impacts; its result object.

`drop` starts from the levitated steady state (the contact-free whirl with gravity, `levitated_state`),
fails the magnetic bearing at ``fail_at`` and runs `drop.drop_kernel` to ``t_end``. `DropResult.to_dict`
is the ``rotorcontact drop --json`` contract (README).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..interpreted import call_kernel
from ..model.machine_model import (
    compliant_normal_force, constant_response, harmonic_response, impact_duration_factor, restitution_damping,
    unbalance_amplitudes,
)
from ..model.params import MAX_SPEED, MAX_T_END as MAX_RUN_TIME, Machine, check_machine_value, check_range
from ..model.units import RPM
from ..model.validation import (MAX_COUNT, check_choice, check_int, check_machine, complex_value, is_pair, quoted,
                                real_array)
from .drop import COMPLIANT_FIELDS, CONTACT_KINDS, IMPACT_FIELDS, STATUS_NAMES, drop_kernel

__all__ = ["DropResult", "drop", "run_general", "levitated_state", "check_drop_speed", "contact_force_history", "RPM",
           "MAX_T_END"]

#: Largest final time of a drop in ``rotorcontact drop`` and of each drop of a drop map, s.
MAX_T_END = 1e4

#: Normal velocity (in units of sqrt(g c_r), or c_r Omega without gravity) below which impacts are taken to
#: accumulate into contact.
CHATTER_VELOCITY = 1e-6
#: Normal velocity, relative to the centre's speed, below which impacts are taken to accumulate into contact.
#: A rotor sliding round the wall at speed v bounces over flights of length ~ v_n c_r / v^2, whose
#: |z|^2 - 1 ~ (v_n / v)^2 reaches the rounding of |z|^2 at v_n / v ~ 1e-8: the bounces below resolve
#: nothing but rounding (MODEL.md §7, accumulation).
CHATTER_RELATIVE = 1e-6
#: The rotor is at rest once its energy above rest (kinetic energy of whirl and spin, and potential energy above
#: the bottom of the wall) falls to this fraction of its kinetic energy at the start (of m g c_r, its weight's fall
#: across the clearance, for a rotor started at rest and not spinning).
REST_FRACTION = 1e-8
#: The compliant law's damping D = chi / v_0 takes v_0 no smaller than this fraction of the velocity scale:
#: episodes that start slower rebound less damped than d (MODEL.md §8).
DAMPING_VELOCITY_FRACTION = 1e-3
#: Relative tolerance of the compliant contact episodes (MODEL.md §8).
EPISODE_TOL = 1e-10
#: Fastest initial rotor velocity of a run, m/s: a kilometre a second is beyond any rotor in its bearing (the
#: fastest touchdown shocks are metres a second), and the event search's steps shrink like 1/|v|.
MAX_START_VELOCITY = 1e3
#: Deepest start inside the stator of the compliant law, in clearances beyond the clearance: its
#: penetrations are micrometres, a clearance deep is already far beyond any contact force it models.
MAX_START_DEPTH = 1.0
#: Most times of a force history: each reruns the drop up to it.
MAX_FORCE_TIMES = 1000
_COL = {name: i for i, name in enumerate(IMPACT_FIELDS)}


def levitated_state(machine: Machine, speed: float, *, name: str = "speed") -> tuple[complex, complex]:
    """(z, z') in m and m/s at t = 0 of the steady levitated whirl at ``speed`` (rad/s) (MODEL.md §7).

    The particular solution of the levitated flight: the harmonic response to the unbalance at phase
    ``unbalance_phase`` plus the static deflection (F_s - m g)/k_y. A whirl that reaches the wall
    later in its period impacts before the failure (the kernel finds those impacts). ``name``: the
    speed's name in errors (a command-line option such as ``"--speed"``).

    Raises
    ------
    ParameterError
        At an undamped resonance, or where the whirl does not start inside the clearance: naming the static
        force and gravity where their sag alone reaches the wall (no speed helps), else the speed and the
        clearance.
    """
    check_machine(machine, optional=False)
    speed = check_machine_value("speed", speed, label=name)
    m = machine.mass
    fx, fy = call_kernel(unbalance_amplitudes, machine.eccentricity, speed, machine.unbalance_phase)
    whirl = 0j  # the unbalance's part
    sag = 0.0  # the constant force's part, along y
    v = 0j
    for axis, (k, c, f, b) in enumerate(((machine.kx, machine.cx, fx, 0.0),
                                         (machine.ky, machine.cy, fy, machine.fs / m - machine.g))):
        h = complex(call_kernel(harmonic_response, c / m, k / m, speed, f))
        p0, _p1, _p2 = call_kernel(constant_response, c / m, k / m, b)
        unit = 1.0 if axis == 0 else 1j
        whirl += unit * h.real
        sag += p0
        v += unit * (1j * speed * h).real
    z = whirl + 1j * sag
    if not (math.isfinite(abs(z)) and math.isfinite(abs(v))):
        raise ParameterError(f"{name} = {speed!r} rad/s is an undamped resonance of the bearing; no steady whirl")
    cr = machine.clearance
    if abs(sag) >= cr:
        fs = "static_force" if machine.static_force is not None else "static_force (default m g)"
        raise ParameterError(
            f"{fs} = {machine.fs:g} N with gravity = {machine.g:g} m/s^2: the levitated rotor sags by "
            f"(F_s - m g)/k_y = {sag:.4g} m (m = {m:g} kg, k_y = {machine.ky:g} N/m), not inside the clearance "
            f"{cr:g} m, at any speed; allowed: |F_s - m g| < k_y c_r = {machine.ky * cr:.4g} N"
        )
    if abs(z) >= cr:
        raise ParameterError(
            f"{name} = {speed / RPM:.6g} rpm: the levitated whirl starts at |z| = {abs(z):.4g} m (unbalance "
            f"response {abs(whirl):.4g} m from eccentricity = {machine.eccentricity:g} m, static sag {sag:.4g} m), "
            f"not inside the clearance = {cr:g} m; allowed: a speed whose levitated whirl starts inside it, "
            "or a larger clearance"
        )
    return z, v


def check_failure_before_end(fail_at: float, t_end: float) -> None:
    """Refuse a drop whose bearing fails at or after its final time (it would stay levitated)."""
    if fail_at >= t_end:
        raise ParameterError(f"fail_at = {fail_at!r} s is not before t_end = {t_end!r} s: the bearing would not "
                             "fail in the run; allowed: fail_at < t_end")


def check_drop_speed(machine: Machine, speed: Any, name: str = "speed") -> float:
    """Check the spin speed (rad/s) a drop of ``machine`` starts at; return it as a float.

    Every drop (`drop`, each point of a drop map, ``rotorcontact drop`` and ``drop-map``) starts here: the speed
    must be finite, above 0 and at most `rotorcontact.model.params.MAX_SPEED` (the bound of a machine's own
    speed), and its levitated whirl (`levitated_state`) must exist and start inside the clearance.

    Parameters
    ----------
    machine : Machine
    speed : float or str
        Spin speed: a number in rad/s, or a string with units (``"12000 rpm"``).
    name : str
        The speed's name in errors: ``"speed"``, ``"speeds[3]"`` or a command-line option such as ``"--speed"``.

    Returns
    -------
    float

    Raises
    ------
    ParameterError
        Naming ``name``, the speed and what is allowed.
    """
    v = check_machine_value("speed", speed, label=name)
    levitated_state(machine, v, name=name)
    return v


@dataclass(frozen=True)
class DropResult:
    """A drop of the general machine.

    Attributes
    ----------
    machine : Machine
    speed : float
        Spin speed at the start, rad/s.
    fail_at, t_end : float
        Failure time and final time, s.
    status : str
        ``"completed"`` (reached t_end), ``"at-rest"`` (the rotor came to rest, `REST_FRACTION`),
        ``"chatter"`` (impacts accumulate into continuous contact, where the run stops), ``"max-events"``
        or ``"failed"``.
    t_stop : float
        Time the run stopped, s.
    impacts : numpy.ndarray
        One row per impact, columns `rotorcontact.simulation.drop.IMPACT_FIELDS` (SI, rad/s); with the
        compliant law one row per contact episode, whose `rotorcontact.simulation.drop.COMPLIANT_FIELDS`
        (nan for rigid impacts) give its duration, peak force, peak penetration and rebound ratio.
    final_state : numpy.ndarray
        t, x, y, vx, vy, spin, race at the stop (SI), the energy dissipated in the touchdown bearing, J
        (`DropResult.energy_dissipated`), and the stator's x, y, vx, vy (SI; zeros for a fixed stator).
    contacts : numpy.ndarray
        One row per contact phase, columns `rotorcontact.simulation.drop.CONTACT_FIELDS` (SI); with the
        compliant law one row per episode that lasts (`rotorcontact.simulation.drop.LASTING_CONTACT`), the
        friction mode it spent most of its time in as its kind.
    """

    machine: Machine
    speed: float
    fail_at: float
    t_end: float
    status: str
    t_stop: float
    impacts: np.ndarray
    final_state: np.ndarray
    contacts: np.ndarray = field(default_factory=lambda: np.zeros((0, 5)))

    @property
    def energy_dissipated(self) -> float:
        """Energy dissipated in the touchdown bearing, J: at impacts (restitution and friction, with the
        motor's work where the speed is held), by friction in sliding contact, by the race's drag and by the
        damping of a stator's support."""
        return float(self.final_state[7])

    @property
    def time_to_rest(self) -> float | None:
        """Time the rotor came to rest (its energy above rest down to `REST_FRACTION` of its kinetic energy at
        the start, or of m g c_r from rest), s; None if it did not within the run."""
        return self.t_stop if self.status == "at-rest" else None

    def column(self, name: str) -> np.ndarray:
        """One column of the impact table by its name in `IMPACT_FIELDS` (a `ParameterError` for another)."""
        check_choice("name", name, IMPACT_FIELDS)
        return self.impacts[:, _COL[name]]

    @property
    def message(self) -> str:
        n = len(self.impacts)
        c = len(self.contacts)
        if self.status == "completed":
            return f"Reached t_end = {self.t_end:g} s after {n} impacts and {c} contact phases."
        if self.status == "at-rest":
            return f"The rotor came to rest at t = {self.t_stop:.6g} s after {n} impacts and {c} contact phases."
        if self.status == "chatter":
            return (f"Impacts accumulate into continuous contact at t = {self.t_stop:.6g} s after {n} impacts; "
                    "the run stops there.")
        if self.status == "max-events":
            return f"Stopped after the maximum number of events at t = {self.t_stop:.6g} s ({n} impacts)."
        return f"The run failed at t = {self.t_stop:.6g} s after {n} impacts and {c} contact phases."

    @property
    def backward_whirl_onset(self) -> float | None:
        """Onset of backward whirl, s: the start of the first contact phase whose mean whirl rate is against
        the spin, or the first impact after which every impact leaves the centre whirling against the spin
        (at least two impacts), whichever is earlier; None if neither, or without spin."""
        if self.speed == 0.0:
            return None  # no spin: no whirl against it
        onsets = []
        direction = 1.0 if self.speed > 0.0 else -1.0
        backward = np.flatnonzero(self.contacts[:, 4] * direction < 0.0) if len(self.contacts) else []
        if len(backward):
            onsets.append(float(self.contacts[backward[0], 0]))
        if len(self.impacts) >= 2:
            angle = self.column("angle_rad")
            v_plus = self.column("vx_plus") + 1j * self.column("vy_plus")
            v_t = (np.exp(-1j * angle) * v_plus).imag * direction
            forward = np.flatnonzero(v_t >= 0.0)
            first = 0 if forward.size == 0 else forward[-1] + 1
            if first <= len(v_t) - 2:
                onsets.append(float(self.column("t_s")[first]))
        return min(onsets) if onsets else None

    @property
    def regime(self) -> str:
        """``"failed"`` (the run failed: what it reached is no outcome), ``"levitated"`` (no impact, no contact),
        ``"backward-whirl"``, ``"contact"`` (continuous contact, or impacts that accumulate) or ``"bouncing"``."""
        if self.status == "failed":
            return "failed"
        if len(self.impacts) == 0 and len(self.contacts) == 0:
            return "levitated"
        if self.backward_whirl_onset is not None:
            return "backward-whirl"
        return "contact" if self.status == "chatter" or len(self.contacts) else "bouncing"

    def contact_intervals(self) -> list[dict[str, Any]]:
        """The contact phases as in the JSON contract: t_start_s, t_end_s, kind, max_normal_force_N and
        whirl_frequency_hz (mean whirl rate of the centre over the phase / 2 pi, negative when backward)."""
        return [{"t_start_s": float(r[0]), "t_end_s": float(r[1]), "kind": CONTACT_KINDS[int(r[2])],
                 "max_normal_force_N": float(r[3]), "whirl_frequency_hz": float(r[4] / (2.0 * math.pi))}
                for r in self.contacts]

    def stator_final(self) -> dict[str, float] | None:
        """The stator's position (m) and velocity (m/s) at the stop, for a stator on springs; None otherwise."""
        if not self.machine.has_stator:
            return None
        x, y, vx, vy = (float(a) for a in self.final_state[8:12])
        return {"x_m": x, "y_m": y, "vx_m_per_s": vx, "vy_m_per_s": vy}

    def to_dict(self) -> dict[str, Any]:
        """The ``rotorcontact drop --json`` contract (README)."""
        race = self.machine.has_race
        rows = [
            {
                "t_s": float(r[_COL["t_s"]]),
                "angle_rad": float(r[_COL["angle_rad"]]),
                "normal_velocity_m_per_s": float(r[_COL["normal_velocity_m_per_s"]]),
                "normal_impulse_Ns": float(r[_COL["normal_impulse_Ns"]]),
                "tangential_impulse_Ns": float(r[_COL["tangential_impulse_Ns"]]),
                "spin_rpm_before": float(r[_COL["spin_before"]] / RPM),
                "spin_rpm_after": float(r[_COL["spin_after"]] / RPM),
                "race_rpm_after": float(r[_COL["race_after"]] / RPM) if race else None,
            }
            for r in self.impacts
        ]
        if self.machine.compliant:
            for row, r in zip(rows, self.impacts):
                for name in COMPLIANT_FIELDS[:-1]:
                    value = float(r[_COL[name]])
                    row[name] = value if math.isfinite(value) else None  # an episode still going at the stop
                row["kind"] = CONTACT_KINDS[int(r[_COL["kind"]])]
        p_n = self.column("normal_impulse_Ns")
        forces = [float(self.contacts[:, 3].max())] if len(self.contacts) else []
        if self.machine.compliant and len(self.impacts):
            forces.append(float(self.column("max_force_N").max()))
        return {
            "machine": self.machine.as_dict(),
            "speed_rpm": self.speed / RPM,
            "status": self.status,
            "message": self.message,
            "impacts": rows,
            "contact_intervals": self.contact_intervals(),
            "summary": {
                "regime": self.regime,
                "backward_whirl_onset_s": self.backward_whirl_onset,
                "max_normal_impulse_Ns": float(p_n.max()) if p_n.size else None,
                "max_contact_force_N": max(forces) if forces else None,
                "final_spin_rpm": float(self.final_state[5] / RPM),
                "energy_dissipated_J": self.energy_dissipated,
                "time_to_rest_s": self.time_to_rest,
                "stator_final": self.stator_final(),
            },
        }


def drop(machine: Machine, speed: float | str | None = None, fail_at: float = 0.0, t_end: float = 2.0, *,
         max_events: int = 1_000_000) -> DropResult:
    """Drop the machine: levitated at ``speed``, the magnetic bearing failing at ``fail_at`` (MODEL.md §7).

    Parameters
    ----------
    machine : Machine
        The machine (its optional keys of MODEL.md §7 give gravity, anisotropy, spin inertia, race).
    speed : float or str, optional
        Spin speed at the start: a number in rad/s, or a string with units such as ``"12000 rpm"``
        (default: ``machine.speed``); at most
        `rotorcontact.model.params.MAX_SPEED` and with a levitated whirl inside the clearance (`check_drop_speed`).
    fail_at : float
        Time of the bearing failure, s (>= 0).
    t_end : float
        Final time, s (> 0).
    max_events : int
        Largest number of flights.

    Returns
    -------
    DropResult
    """
    # `check_drop_speed`, keeping the levitated state it computes
    check_machine(machine, optional=False)
    speed = check_machine_value("speed", machine.speed if speed is None else speed)
    z0, v0 = levitated_state(machine, speed)
    fail_at = check_range("fail_at", fail_at, low=0.0)
    t_end = check_range("t_end", t_end, low=0.0, high=MAX_T_END, low_open=True)
    check_failure_before_end(fail_at, t_end)
    max_events = check_int("max_events", max_events, low=1, high=MAX_COUNT)
    return run_general(machine, z0, v0, speed, fail_at, t_end, max_events=max_events)


def run_general(machine: Machine, z0: complex, v0: complex, speed: float, fail_at: float, t_end: float, *,
                max_events: int = 1_000_000, tol: float = EPISODE_TOL,
                stator_start: tuple[complex, complex] = (0j, 0j)) -> DropResult:
    """Run the general machine from (z0, z0') (m, m/s) at spin ``speed`` (rad/s), failing at ``fail_at``.

    ``fail_at = inf``: the magnetic bearing holds throughout (``rotorcontact simulate --machine``).
    The unbalance angle starts at ``machine.unbalance_phase``; the race starts at rest. With the compliant
    law the rotor may start in contact (|z0 - z_s| > c_r): an episode starts at once. A run whose
    ``fail_at`` is at or after ``t_end`` stays levitated (`drop` refuses that; this function does not).

    Parameters
    ----------
    machine : Machine
        The machine (its optional keys of MODEL.md §7 give gravity, anisotropy, spin inertia, race, the
        compliant law and a stator on springs).
    z0 : complex
        Position of the rotor's centre at the start, m: a complex number x + iy, or a pair (x, y). Within
        the clearance c_r of the stator's centre z_s (to a relative 1e-12); with the compliant law up to
        (1 + `MAX_START_DEPTH`) c_r from it.
    v0 : complex
        Velocity of the rotor's centre at the start, m/s: a complex number or a pair, with
        |v0| <= `MAX_START_VELOCITY`.
    speed : float
        Spin speed at the start, rad/s, in [-`rotorcontact.model.params.MAX_SPEED`,
        `rotorcontact.model.params.MAX_SPEED`]: negative (backwards) and zero spin are allowed here.
    fail_at : float
        Time of the bearing failure, s: >= 0, or ``math.inf`` (a float) for a bearing that never fails.
    t_end : float
        Final time, s: > 0 and at most `MAX_T_END`, or at most `rotorcontact.model.params.MAX_T_END` radians
        of spin (``MAX_T_END / |speed|`` of that module, s) where that is longer.
    max_events : int
        Largest number of flights, 1 to `rotorcontact.model.validation.MAX_COUNT`.
    tol : float
        The relative tolerance of compliant contact episodes (MODEL.md §8), in [1e-14, 1e-3]; default
        `EPISODE_TOL`.
    stator_start : tuple of two complex
        The position (m) and velocity (m/s) of a stator on springs at the start, (z_s, v_s), each a complex
        number or a pair (default: at rest at its centre). Only (0, 0) for a fixed stator (no
        ``stator_mass``).

    Returns
    -------
    DropResult
        The run; its status is ``"failed"`` where the arithmetic lost a value (nan, inf) of the final state
        or of the impact table.

    Raises
    ------
    ParameterError
        If ``machine`` is not a Machine; ``max_events`` is not an integer in its range; ``tol``, ``speed`` or
        ``t_end`` is not a finite number in its range; ``fail_at`` is neither ``math.inf`` nor a finite number
        >= 0; ``z0``, ``v0`` or an item of ``stator_start`` is not a finite complex number (text and bools
        refused); |v0| exceeds
        `MAX_START_VELOCITY`; ``stator_start`` is not a tuple, list or array of two items, or is not (0, 0)
        for a fixed stator; or ``z0`` lies beyond the clearance round z_s (rigid law) or deeper than
        `MAX_START_DEPTH` clearances inside the stator (compliant law).
    """
    check_machine(machine, optional=False)
    max_events = check_int("max_events", max_events, low=1, high=MAX_COUNT)
    tol = check_range("tol", tol, low=1e-14, high=1e-3)
    # the spin may be negative (backwards) or zero here
    speed = check_range("speed", speed, low=-MAX_SPEED, high=MAX_SPEED, unit="rad/s")
    # inf: the bearing never fails
    never = isinstance(fail_at, (float, np.floating)) and fail_at == math.inf
    fail_at = math.inf if never else check_range("fail_at", fail_at, low=0.0)
    # a drop's longest run, or as many radians of spin as the dimensionless model's longest run
    longest = max(MAX_T_END, MAX_RUN_TIME / abs(speed)) if speed != 0.0 else MAX_T_END
    t_end = check_range("t_end", t_end, low=0.0, high=longest, low_open=True, unit="s",
                        why=f"{MAX_T_END:g} s, or {MAX_RUN_TIME:g} radians of spin where that is longer")
    z0, v0 = complex_value("z0", z0), complex_value("v0", v0)
    if not abs(v0) <= MAX_START_VELOCITY:
        raise ParameterError(f"v0 = {v0!r} m/s is too fast (|v0| = {abs(v0):.3g} m/s); allowed: |v0| <= "
                             f"{MAX_START_VELOCITY:g} m/s")
    if not (isinstance(stator_start, (tuple, list, np.ndarray)) and np.shape(stator_start) == (2,)):
        raise ParameterError(f"stator_start = {stator_start!r} is invalid; allowed: (z_s, v_s), two complex numbers")
    m = machine
    zb0, vb0 = complex_value("stator_start[0]", stator_start[0]), complex_value("stator_start[1]", stator_start[1])
    if (zb0 != 0.0 or vb0 != 0.0) and not m.has_stator:
        raise ParameterError(f"stator_start = {stator_start!r} for a fixed stator; allowed: (0, 0) without stator_mass")
    if not abs(z0 - zb0) <= m.clearance * (1.0 + 1e-12) and not m.compliant:
        raise ParameterError(f"z0 = {z0!r} m lies outside the clearance {m.clearance:g} m round the stator's centre "
                             f"{zb0!r} m; allowed: |z0 - z_s| <= c_r (beyond it: in contact, compliant law only)")
    if not abs(z0 - zb0) <= m.clearance * (1.0 + MAX_START_DEPTH):
        deepest = m.clearance * (1.0 + MAX_START_DEPTH)
        raise ParameterError(f"z0 = {z0!r} m lies {abs(z0 - zb0) - m.clearance:.3g} m inside the stator; allowed: "
                             f"|z0 - z_s| <= {1.0 + MAX_START_DEPTH:g} c_r = {deepest:g} m")
    v_scale = _velocity_scale(m, speed)
    race_args = (m.race_inertia, m.race_drag_torque, m.race_drag_coefficient) if m.has_race else (0.0, 0.0, 0.0)
    polar = m.polar_inertia or 0.0
    kinetic = 0.5 * (m.mass * abs(v0) ** 2 + polar * speed * speed)
    # a rotor started at rest and not spinning: the scale is its weight's fall across the clearance
    rest_energy = REST_FRACTION * (kinetic if kinetic > 0.0 else m.mass * m.g * m.clearance)
    # the compliant law's K_c, n, chi, the floor of v_0 in D, tolerance and elastic impact's duration factor;
    # K_c = 0: the rigid law
    compliant = (float(m.contact_stiffness or 0.0), m.exponent,
                 restitution_damping(m.restitution, m.exponent) if m.compliant else 0.0,
                 DAMPING_VELOCITY_FRACTION * v_scale, tol, impact_duration_factor(m.exponent) if m.compliant else 0.0)
    impacts, contacts, status, t_stop, state = call_kernel(
        drop_kernel, m.mass, m.clearance, m.eccentricity, m.rotor_radius, m.friction, m.restitution, m.kx, m.ky,
        m.cx, m.cy, m.fs, m.g, polar, *race_args, complex(z0), complex(v0), m.unbalance_phase, speed, 0.0,
        fail_at, t_end, max_events, CHATTER_VELOCITY * v_scale, True, rest_energy, CHATTER_RELATIVE, *compliant,
        float(m.stator_mass or 0.0), *m.stator_support(), zb0, vb0)
    status = STATUS_NAMES[int(status)]
    if not (np.all(np.isfinite(state)) and np.all(np.isfinite(impacts[:, :_COL["duration_s"]]))):
        status = "failed"  # a value the arithmetic lost (nan, inf) is never reported as a result
    return DropResult(machine, speed, fail_at, t_end, status, float(t_stop), impacts, state, contacts)




def _velocity_scale(machine: Machine, speed: float) -> float:
    """sqrt(g c_r) with gravity, else c_r Omega, m/s: the scale of the chatter and damping floors."""
    return math.sqrt(machine.g * machine.clearance) if machine.g > 0.0 else machine.clearance * abs(speed)


def contact_force_history(machine: Machine, speed: float, fail_at: float, times,
                          start: tuple[complex, complex] | None = None) -> np.ndarray:
    """The compliant normal force F_n (N) of a drop (`drop`) at each of ``times`` (s, > 0), 0 out of contact;
    ``start`` = (z0, v0) in m and m/s runs `run_general` from there instead of the levitated state.

    Each value comes from the drop run to that time (the integration up to it is the same as in the
    whole run: only its last step is cut short) and the law of MODEL.md §8 with the damping of the episode
    in progress. Each time reruns the drop up to it, hence at most `MAX_FORCE_TIMES` of them.

    Parameters
    ----------
    machine : Machine
        The machine, with the compliant contact law (``contact = "compliant"``).
    speed : float or str
        Spin speed at the start: rad/s, or without ``start`` also text with units (``"12000 rpm"``). Without
        ``start`` it is checked as by `drop` (`check_drop_speed`: > 0, at most
        `rotorcontact.model.params.MAX_SPEED`, with a levitated whirl inside the clearance); with it as by
        `run_general` (|speed| at most `rotorcontact.model.params.MAX_SPEED`, rad/s).
    fail_at : float
        Time of the bearing failure, s (>= 0). Without ``start`` it must be before each of ``times`` (a
        drop's ``t_end``); with it, ``math.inf`` is allowed too (the bearing never fails).
    times : array_like of float
        The times of the force, s: 1 to `MAX_FORCE_TIMES` finite times > 0, a single number or a 1-D
        array. Each is the ``t_end`` of a run, within the range `drop` or `run_general` allows.
    start : tuple of two complex, optional
        (z0, v0): position (m) and velocity (m/s) of the rotor's centre at the start, each a complex number
        or a pair, as `run_general` takes them. Default: the levitated state at ``speed`` (`drop`).

    Returns
    -------
    numpy.ndarray
        F_n at each of ``times``, N: a 1-D array of as many floats (0 where the rotor is out of contact).

    Raises
    ------
    ParameterError
        For a machine that is not a Machine or is without the compliant law, ``times`` that are not 1 to
        `MAX_FORCE_TIMES` finite times > 0, or a ``start`` that is not a pair (z0, v0); and for what `drop`
        (without ``start``) or `run_general` (with it) refuses of ``speed``, ``fail_at``, a time as its
        ``t_end``, or ``start``'s z0 and v0.
    """
    check_machine(machine, optional=False)
    if not machine.compliant:
        raise ParameterError(f"contact = {machine.contact!r}; a force history needs contact = 'compliant'")
    at = real_array(times)
    if (at is None or at.ndim > 1 or not 1 <= at.size <= MAX_FORCE_TIMES
            or not np.all(np.isfinite(at) & (at > 0.0))):
        raise ParameterError(f"times = {quoted(times)} is invalid; allowed: 1 to {MAX_FORCE_TIMES} finite times > 0, s")
    if start is not None and not is_pair(start):
        raise ParameterError(f"start = {quoted(start)} is invalid; allowed: (z0, v0) in m and m/s, or None")
    if start is None:
        speed = check_drop_speed(machine, speed, "speed")
    else:
        speed = check_range("speed", speed, low=-MAX_SPEED, high=MAX_SPEED, unit="rad/s")
    chi = restitution_damping(machine.restitution, machine.exponent)
    floor = DAMPING_VELOCITY_FRACTION * _velocity_scale(machine, speed)
    out = []
    for t in at.reshape(-1):
        if start is None:
            r = drop(machine, speed, fail_at, float(t))
        else:
            r = run_general(machine, start[0], start[1], speed, fail_at, float(t))
        # the rotor relative to the stator's centre (at 0 for a fixed stator)
        x, y, vx, vy = r.final_state[1:5] - r.final_state[8:12]
        dist = math.hypot(x, y)
        if not len(r.impacts) or dist <= machine.clearance:
            out.append(0.0)
            continue
        v0 = r.impacts[-1, _COL["normal_velocity_m_per_s"]]
        f, _el = compliant_normal_force(dist - machine.clearance, (x * vx + y * vy) / dist,
                                        machine.contact_stiffness, machine.exponent, chi / max(v0, floor))
        out.append(f)
    return np.array(out)
