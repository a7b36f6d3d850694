"""Parameters of the rotor model: dimensionless `Parameters` and the SI `Machine`.

The dimensionless groups are those of MODEL.md §2::

    gamma = c / (m Omega),  omega**2 = k / (m Omega**2),  rho = e_c / c_r,

together with the friction coefficient mu, the restitution d, the unbalance
phase phi and r_ratio = R / c_r, which sets the direction of the friction force
through v_rel = r_ratio + 1 + thetadot.
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import asdict, dataclass, fields, replace
from importlib import resources
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..errors import ParameterError

__all__ = [
    "Parameters",
    "Machine",
    "reference_machine",
    "load_machine",
    "check_finite",
    "check_range",
    "check_parameter_rows",
    "check_velocity",
    "check_machine_value",
    "MAX_SPEED",
    "MAX_GRAVITY",
    "MAX_CONTACT_FORCE",
    "MAX_MAGNITUDE",
    "MIN_CLEARANCE",
    "MAX_CLEARANCE",
    "MAX_VELOCITY",
    "OPTIONAL_MACHINE_KEYS",
    "PAPER_MACHINE_KEYS",
    "RACE_KEYS",
    "CONTACT_LAWS",
]

#: Largest magnitude of a dimensionless parameter (|gamma|, omega, rho, mu, |phi|, r_ratio).
#: The groups of a real rotor are of order one (MODEL.md §2: the reference rig has gamma 0.15,
#: omega 0.76, rho 0.43, r_ratio 57); 1e6 still covers a rig turning at 1e-4 rad/s or a clearance of
#: a micrometre under a 1 m rotor. Beyond it the closed-form flight, whose fast time scale is 1/omega
#: (or 1/gamma), cannot be resolved in double precision over a run, and its squares and exponentials
#: approach overflow.
MAX_MAGNITUDE = 1e6
#: Largest magnitude of an initial velocity U'(0), in clearances per unit of dimensionless time
#: (c_r Omega: about 0.13 m/s on the reference rig). A million of them is a shock far beyond any
#: touchdown; beyond it the impact search, whose steps scale like 1/|U'|, cannot finish.
MAX_VELOCITY = 1e6
#: Largest final time of a run of the dimensionless model: the spacing of doubles near 1e7 is 2e-9,
#: so impact and switching times are still resolved to about 1e-9; beyond it they are not.
MAX_T_END = 1e7


def refuse_bool_or_text(name: str, value: Any, required: str) -> None:
    """Raise `ParameterError` if ``value`` is a bool or text, which ``float`` and ``complex`` would read.

    ``True`` is not a value of a physical parameter, whatever ``float(True)`` says; text is a number only
    where it is parsed with its units (the command line, `rotorcontact.Machine`), and Python code gives
    numbers. ``required`` ends the message: what is required instead.
    """
    if isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} = {value!r} is a bool, not a number; {required}")
    if isinstance(value, (str, bytes)) or (isinstance(value, np.ndarray) and value.dtype.kind in "SU"):
        raise ParameterError(f"{name} = {value!r} is text, not a number; {required}")


def check_finite(name: str, value: Any) -> float:
    """Return ``value`` as a float, or raise `ParameterError` if it is not a finite real number.

    A bool and text are refused (`refuse_bool_or_text`).
    """
    refuse_bool_or_text(name, value, "a finite real number is required")
    if isinstance(value, (complex, np.complexfloating)) or (isinstance(value, np.ndarray) and value.dtype.kind == "c"):
        raise ParameterError(f"{name} = {value!r} is complex; a finite real number is required")
    if not isinstance(value, (int, float)):
        try:
            value = float(value)
        except (TypeError, ValueError):
            raise ParameterError(
                f"{name} = {value!r} is not a number; a finite real number is required"
            ) from None
    value = float(value)
    if not math.isfinite(value):
        raise ParameterError(f"{name} = {value!r} is not finite; a finite real number is required")
    return value


def check_range(
    name: str,
    value: Any,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    why: str | None = None,
    unit: str | None = None,
    given: str | None = None,
) -> float:
    """Check that ``value`` is finite and lies in the given interval; return it as a float.

    Parameters
    ----------
    name : str
        Name of the value, as the user knows it (shown in the error).
    value : Any
        The value to check.
    low, high : float, optional
        Bounds of the interval (None: unbounded on that side).
    low_open, high_open : bool
        Whether the bound itself is excluded.
    why : str, optional
        Reason for the upper bound, appended in parentheses to the error of
        a value above it.
    unit : str, optional
        Unit of ``value`` and of the bounds, shown in the error.
    given : str, optional
        The text the value was parsed from (``"-12000rpm"``), shown in the error beside the value.

    Returns
    -------
    float
        ``value`` as a float.

    Raises
    ------
    ParameterError
        If ``value`` is not a finite number or lies outside the interval; the
        message names ``name``, the value and the allowed interval.
    """
    v = check_finite(name, value)
    lo_bad, hi_bad = _beyond(v, low, high, low_open, high_open)
    if lo_bad or hi_bad:
        left = "(" if low_open else "["
        right = ")" if high_open else "]"
        lo = "-inf" if low is None else f"{low:g}"
        hi = "inf" if high is None else f"{high:g}"
        if low is None:
            left = "("
        if high is None:
            right = ")"
        reason = f" ({why})" if why and hi_bad else ""
        units = f" {unit}" if unit else ""
        shown = f"{v!r}" if given is None else f"{given!r} ({v:g}{units})"
        raise ParameterError(f"{name} = {shown} is out of range; allowed: {left}{lo}, {hi}{right}{units}{reason}")
    return v


def _beyond(value: Any, low: float | None, high: float | None, low_open: bool, high_open: bool) -> tuple[Any, Any]:
    """Whether ``value`` (a float, or elementwise an array) lies below the interval, and whether above it."""
    lo_bad = False if low is None else (value <= low if low_open else value < low)
    hi_bad = False if high is None else (value >= high if high_open else value > high)
    return lo_bad, hi_bad


def check_velocity(name: str, value: complex) -> complex:
    """Check that an initial velocity has magnitude at most `MAX_VELOCITY`; return it.

    Raises
    ------
    ParameterError
        If ``|value| > MAX_VELOCITY`` (or it is not finite), or ``value`` is not a number (a bool and text
        are refused).
    """
    refuse_bool_or_text(name, value, "a (complex) number is required")
    try:
        value = complex(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} = {value!r} is not a number; a (complex) number is required") from None
    speed = abs(value)
    if not speed <= MAX_VELOCITY:
        raise ParameterError(
            f"{name} = {value.real!r},{value.imag!r} is too fast (|{name}| = {speed:.3g}); allowed: "
            f"|{name}| <= {MAX_VELOCITY:g} clearances per unit time (far beyond any touchdown shock)"
        )
    return complex(value)


_WHY = "dimensionless groups of a rotor are of order one; larger magnitudes are beyond the model's numerics"
#: The range of each dimensionless parameter (`check_range` keywords), in the order of `Parameters`' fields.
_PARAMETER_RULES: dict[str, dict[str, Any]] = {
    "gamma": dict(low=-MAX_MAGNITUDE, high=MAX_MAGNITUDE, why=_WHY),
    "omega": dict(low=0.0, high=MAX_MAGNITUDE, low_open=True, why=_WHY),
    "rho": dict(low=0.0, high=MAX_MAGNITUDE, why=_WHY),
    "mu": dict(low=0.0, high=MAX_MAGNITUDE, why=_WHY),
    "d": dict(low=0.0, high=1.0),
    "phi": dict(low=-MAX_MAGNITUDE, high=MAX_MAGNITUDE, why=_WHY),
    "r_ratio": dict(low=0.0, high=MAX_MAGNITUDE, why=_WHY),
}


def check_parameter_rows(rows: np.ndarray) -> None:
    """Raise the `ParameterError` of the `Parameters` constructor for the first of ``rows`` that holds a value
    out of its range.

    ``rows`` is a finite float array of shape (n, 7), the fields in the order of `Parameters`. Checked as
    arrays, so that many parameter sets (a sweep's, a basin's) cost no more than a few.
    """
    bad = np.zeros(rows.shape[0], dtype=bool)
    for j, name in enumerate(_PARAMETER_RULES):
        rule = _PARAMETER_RULES[name]
        lo_bad, hi_bad = _beyond(rows[:, j], rule.get("low"), rule.get("high"), rule.get("low_open", False),
                                 rule.get("high_open", False))
        bad |= lo_bad | hi_bad
    if bad.any():
        Parameters(*rows[int(np.argmax(bad))].tolist())  # raises, naming the parameter
        raise AssertionError("a row out of range passed the constructor")  # pragma: no cover


#: The parameters a branch, a curve or a scan may be followed in (phi and r_ratio enter the model too, but no
#: continuation varies them).
BRANCH_PARAMETERS = ("gamma", "omega", "rho", "mu", "d")


@dataclass(frozen=True)
class Parameters:
    """Dimensionless parameters of the co-rotating model (MODEL.md §2).

    Attributes
    ----------
    gamma : float
        Damping c / (m Omega), in [-1e6, 1e6]; negative values are allowed for
        the analysis of orbits, not for a physical machine.
    omega : float
        Stiffness ratio sqrt(k / (m Omega^2)), in (0, 1e6].
    rho : float
        Eccentricity over clearance e_c / c_r, in [0, 1e6].
    mu : float
        Coulomb friction coefficient, in [0, 1e6].
    d : float
        Newton restitution coefficient, in [0, 1].
    phi : float
        Unbalance phase in radians, in [-1e6, 1e6].
    r_ratio : float
        Rotor radius over clearance R / c_r, in [0, 1e6]; sets sgn(v_rel).

    The bound 1e6 on magnitudes is `MAX_MAGNITUDE` (the groups of a real rotor
    are of order one); a `ParameterError` names the parameter otherwise.
    """

    gamma: float
    omega: float
    rho: float
    mu: float
    d: float
    phi: float = 0.0
    r_ratio: float = 0.0

    def __post_init__(self) -> None:
        values = {name: check_finite(name, getattr(self, name)) for name in _PARAMETER_RULES}
        for name, value in values.items():
            object.__setattr__(self, name, value)
        for name, value in values.items():
            check_range(name, value, **_PARAMETER_RULES[name])

    @classmethod
    def reference(cls) -> "Parameters":
        """The dimensionless parameters of the built-in reference machine."""
        return reference_machine().parameters()

    def replace(self, **changes: float) -> "Parameters":
        """Return a copy with some parameters changed (the changed ones validated as by the constructor)."""
        unknown = set(changes) - set(_PARAMETER_RULES)
        if unknown:
            name = sorted(unknown)[0]
            raise ParameterError(f"{name} = {changes[name]!r} is not a parameter (unknown parameter {name!r}); "
                                 f"allowed: {', '.join(_PARAMETER_RULES)}")
        checked = {name: check_finite(name, changes[name]) for name in _PARAMETER_RULES if name in changes}
        for name, value in checked.items():
            check_range(name, value, **_PARAMETER_RULES[name])
        return self.unchecked_replace(**checked)  # the others were checked when this object was made

    def unchecked_replace(self, **changes: float) -> "Parameters":
        """A new object with some parameters changed, without validating them.

        For the points of a continuation just beyond a physical bound (`rotorcontact.maps.orbit_system.
        with_parameters`) and for `replace` once it has checked the changes. The new object computes its
        own k (a copy would keep the cached one).
        """
        new = object.__new__(type(self))
        new.__dict__.update({name: getattr(self, name) for name in _PARAMETER_RULES}, **changes)
        return new

    def as_dict(self) -> dict[str, float]:
        """The parameters as a plain dict of floats."""
        return asdict(self)

    @property
    def k(self) -> complex:
        """Regular equilibrium U = k = rho e^{i phi} / (omega^2 - 1 + i gamma) (MODEL.md §3).

        The value of `rotorcontact.model.flow.equilibrium_point`, which the simulator uses
        (computed once per parameter set).
        """
        k = self.__dict__.get("_k")
        if k is None:
            from ..interpreted import call_kernel  # kernels: loaded on first use, not with the parameters
            from .flow import equilibrium_point

            k = complex(call_kernel(equilibrium_point, self.gamma, self.omega, self.rho, self.phi))
            object.__setattr__(self, "_k", k)
        return k


#: Largest spin speed, rad/s (about 9.5 million rpm): ten times the fastest rotors built (about 1e5 rad/s);
#: far beyond it the drop's first flight cannot even start (a speed of 1e30 rpm fails at t = 0).
MAX_SPEED = 1e6
#: Largest gravity, m/s^2 (about 1e5 g): beyond any shock test; far beyond it (1e15 m/s^2) the drop's contact
#: phases no longer end, and at 1e300 it fails at t = 0.
MAX_GRAVITY = 1e6
#: Smallest clearance of a machine, m (1 nm): far below it a drop's squared positions underflow (1e-200 m ran
#: without end).
MIN_CLEARANCE = 1e-9
#: Largest clearance of a machine, m: touchdown clearances are tenths of a millimetre, so a clearance of metres
#: is a slip of units ("0.7 Mm", 700 km, ran as a machine).
MAX_CLEARANCE = 1.0
#: Largest force of the compliant law at a penetration of one clearance, K_c c_r^n, N (steel on steel: about
#: 1e5 N). Beyond it the penetrations (below 1e-7 of the clearance at 1e15 N) near the rounding of |z| and the
#: episodes' steps grow without end; at K_c = 1e300 the forces overflow into nan. The rigid law is that limit.
MAX_CONTACT_FORCE = 1e15

_MACHINE_RULES: dict[str, dict[str, Any]] = {
    "mass": dict(low=0.0, low_open=True, unit="kg"),
    "damping": dict(low=0.0, unit="N s/m"),
    "stiffness": dict(low=0.0, low_open=True, unit="N/m"),
    "eccentricity": dict(low=0.0, unit="m"),
    "clearance": dict(low=MIN_CLEARANCE, high=MAX_CLEARANCE, unit="m",
                      why="m: touchdown clearances are tenths of a millimetre; is the unit right?"),
    "rotor_radius": dict(low=0.0, unit="m"),
    "unbalance_phase": dict(unit="rad"),
    "speed": dict(low=0.0, low_open=True, high=MAX_SPEED, unit="rad/s",
                  why="rad/s: about 9.5e6 rpm, ten times the fastest rotors; beyond it the simulation cannot start"),
    "friction": dict(low=0.0, unit="1"),
    "restitution": dict(low=0.0, high=1.0, unit="1"),
    # the general machine (MODEL.md §7); absent (None): the paper's machine of MODEL.md §1
    "stiffness_x": dict(low=0.0, low_open=True, unit="N/m"),
    "stiffness_y": dict(low=0.0, low_open=True, unit="N/m"),
    "damping_x": dict(low=0.0, unit="N s/m"),
    "damping_y": dict(low=0.0, unit="N s/m"),
    "gravity": dict(low=0.0, high=MAX_GRAVITY, unit="m/s^2",
                    why="m/s^2: about 1e5 g, beyond any shock; far beyond it the drop's contact phases no longer end"),
    "static_force": dict(unit="N"),
    "polar_inertia": dict(low=0.0, low_open=True, unit="kg m^2"),
    "race_inertia": dict(low=0.0, low_open=True, unit="kg m^2"),
    "race_drag_torque": dict(low=0.0, unit="N m"),
    "race_drag_coefficient": dict(low=0.0, unit="N m s"),
    # the compliant contact law (MODEL.md §8); absent: the rigid impact law
    "contact": dict(unit=""),
    "contact_stiffness": dict(low=0.0, low_open=True, unit="N/m^n"),
    "contact_exponent": dict(low=0.0, low_open=True, high=10.0, unit="1"),
    # the stator on springs of the compliant law (MODEL.md §8); absent: a fixed stator
    "stator_mass": dict(low=0.0, low_open=True, unit="kg"),
    "stator_stiffness": dict(low=0.0, low_open=True, unit="N/m"),
    "stator_stiffness_x": dict(low=0.0, low_open=True, unit="N/m"),
    "stator_stiffness_y": dict(low=0.0, low_open=True, unit="N/m"),
    "stator_damping": dict(low=0.0, unit="N s/m"),
    "stator_damping_x": dict(low=0.0, unit="N s/m"),
    "stator_damping_y": dict(low=0.0, unit="N s/m"),
}
#: The contact laws of the key ``contact`` (MODEL.md §7: rigid, §8: compliant).
CONTACT_LAWS = ("rigid", "compliant")

#: Keys of the general machine (MODEL.md §7), optional in machine files; absent, each keeps the meaning of
#: the paper's machine (isotropic bearing, no gravity, speed held, fixed stator).
OPTIONAL_MACHINE_KEYS = (
    "stiffness_x", "stiffness_y", "damping_x", "damping_y", "gravity", "static_force", "polar_inertia",
    "race_inertia", "race_drag_torque", "race_drag_coefficient", "contact", "contact_stiffness", "contact_exponent",
    "stator_mass", "stator_stiffness", "stator_stiffness_x", "stator_stiffness_y", "stator_damping",
    "stator_damping_x", "stator_damping_y",
)
#: The keys of the stator on springs (MODEL.md §8), given with ``stator_mass`` only.
STATOR_KEYS = ("stator_mass", "stator_stiffness", "stator_stiffness_x", "stator_stiffness_y", "stator_damping",
               "stator_damping_x", "stator_damping_y")
#: The race keys, given all three or none.
RACE_KEYS = ("race_inertia", "race_drag_torque", "race_drag_coefficient")


def check_machine_value(name: str, value: Any, label: str | None = None) -> float:
    """Check one value of a machine key against its range (`Machine`'s rules); return it in SI units.

    ``value`` is a number in the key's SI unit, or a string with its unit (``"12000 rpm"``; a unit is
    required unless the key has none). ``label``: the value's name in errors where it is not the key
    itself (a command-line option such as ``"--speed"``, or ``"speeds[3]"``).

    Raises
    ------
    ParameterError
        Naming the key (or ``label``), the value and the allowed range.
    """
    rule = {k: v for k, v in _MACHINE_RULES[name].items() if k != "unit"}
    if isinstance(value, str):
        from .units import quantity_in

        unit = _si_unit(name)
        text = value
        value = quantity_in(label or name, text, unit, unit_required=unit != "1")
        return check_range(label or name, value, **rule, unit=None if unit == "1" else unit, given=text)
    return check_range(label or name, value, **rule)


def _si_unit(name: str, exponent: Any = None) -> str:
    """The SI unit of a machine key for pint; K_c is in N/m^n (n = ``exponent``, 1.5 when absent or invalid)."""
    if name != "contact_stiffness":
        return _MACHINE_RULES[name]["unit"]
    valid = isinstance(exponent, (int, float)) and not isinstance(exponent, bool) and 0.0 < exponent <= 10.0
    return f"N/m**{float(exponent if valid else 1.5)!r}"  # an invalid n is refused under its own name


def to_si(name: str, raw: Any, unit: str, source: str = "machine") -> float:
    """A value in the SI unit ``unit``: a number (already SI) or a string with units ("0.7 mm", "12000 rpm").

    Raises
    ------
    ParameterError
        For an unknown unit, units of the wrong dimension, or a malformed value.
    """
    if name == "contact":
        return raw  # a word, checked by `Machine`
    label = f"{source}: {name}" if source else name  # a file names itself first, as compilers do
    if isinstance(raw, np.ndarray) and raw.ndim == 0:
        raw = raw[()]
    if isinstance(raw, (bool, np.bool_)) or not isinstance(raw, (int, float, np.integer, np.floating, str)):
        raise ParameterError(
            f"{label} = {raw!r} is not a number; a finite real number in {unit}, "
            f"or a string with units such as '1.5 {unit}', is required"
        )
    if not isinstance(raw, str):
        return float(raw)
    from .units import quantity_in

    # a number is in SI units; a string carries its own (a bare "12000" could as well be meant in rpm)
    return quantity_in(label, raw, unit, unit_required=unit != "1")


@dataclass(frozen=True)
class Machine:
    """A rotor in its touchdown bearing, in SI units (MODEL.md §1).

    Each value may be given as a number in SI units or, as in machine files, as
    a string with units parsed by pint (``Machine(..., speed="12000 rpm")``);
    it is stored in SI units.

    Attributes
    ----------
    mass : float
        Rotor mass m in kg, > 0.
    damping : float
        Bearing damping c in N s/m, >= 0.
    stiffness : float
        Bearing stiffness k in N/m, > 0.
    eccentricity : float
        Unbalance eccentricity e_c in m, >= 0.
    clearance : float
        Radial clearance c_r in m, > 0.
    rotor_radius : float
        Rotor radius R in m, >= 0.
    unbalance_phase : float
        Unbalance phase phi in rad.
    speed : float
        Spin speed Omega in rad/s, > 0.
    friction : float
        Coulomb friction coefficient mu, >= 0.
    restitution : float
        Newton restitution coefficient d, in [0, 1].
    stiffness_x, stiffness_y : float or None
        Bearing stiffness along x and y in N/m, > 0 (None: ``stiffness``).
    damping_x, damping_y : float or None
        Bearing damping along x and y in N s/m, >= 0 (None: ``damping``).
    gravity : float or None
        Gravitational acceleration g in m/s^2 along -y, >= 0 (None: 0).
    static_force : float or None
        The magnetic bearing's static force F_s in N along +y while levitated
        (None: m g, which balances gravity).
    polar_inertia : float or None
        Rotor polar moment of inertia I_p in kg m^2, > 0 (None: the speed is
        held by the motor).
    race_inertia, race_drag_torque, race_drag_coefficient : float or None
        The touchdown bearing's inner race: inertia I_b in kg m^2 (> 0), the
        constant drag torque in N m and the viscous drag coefficient in N m s
        (>= 0) of its own rolling bearing. All three or none (None: the stator
        does not turn).
    contact : str or None
        The contact law: ``"rigid"`` (None: the impact law of MODEL.md §7) or
        ``"compliant"`` (MODEL.md §8), which needs ``contact_stiffness`` and a
        restitution > 0.
    contact_stiffness : float or None
        K_c of the compliant law F_n = K_c delta^n (1 + D delta'), N/m^n, > 0.
    contact_exponent : float or None
        n of the compliant law, in (0, 10] (None: 1.5, Hertz).
    stator_mass : float or None
        Mass m_s of the touchdown bearing on its support springs, kg (> 0;
        None: a fixed stator). With the compliant law only.
    stator_stiffness, stator_stiffness_x, stator_stiffness_y : float or None
        Stiffness of the stator's support, N/m (> 0): per axis, each falling back
        to ``stator_stiffness``; both axes need a value when ``stator_mass`` is given.
    stator_damping, stator_damping_x, stator_damping_y : float or None
        Damping of the stator's support, N s/m (>= 0; None: 0), per axis as the
        stiffness.

    The optional fields describe the general machine of MODEL.md §7; a
    machine without them is the paper's machine of MODEL.md §1.
    """

    mass: float
    damping: float
    stiffness: float
    eccentricity: float
    clearance: float
    rotor_radius: float
    unbalance_phase: float
    speed: float
    friction: float
    restitution: float
    stiffness_x: float | None = None
    stiffness_y: float | None = None
    damping_x: float | None = None
    damping_y: float | None = None
    gravity: float | None = None
    static_force: float | None = None
    polar_inertia: float | None = None
    race_inertia: float | None = None
    race_drag_torque: float | None = None
    race_drag_coefficient: float | None = None
    contact: str | None = None
    contact_stiffness: float | None = None
    contact_exponent: float | None = None
    stator_mass: float | None = None
    stator_stiffness: float | None = None
    stator_stiffness_x: float | None = None
    stator_stiffness_y: float | None = None
    stator_damping: float | None = None
    stator_damping_x: float | None = None
    stator_damping_y: float | None = None

    def __post_init__(self) -> None:
        self._check_contact()
        # the exponent first: a K_c given with units is converted to N/m^n with this machine's n
        for f in sorted(fields(self), key=lambda f: f.name != "contact_exponent"):
            if f.name == "contact":
                continue
            value = getattr(self, f.name)
            if value is None and f.name in OPTIONAL_MACHINE_KEYS:
                continue
            if isinstance(value, str):  # a quantity with units, as in machine files: "12000 rpm"
                value = to_si(f.name, value, self._unit(f.name), source="")
            object.__setattr__(self, f.name, check_machine_value(f.name, value))
        for key in ("rotor_radius", "eccentricity"):
            # the lengths in clearances are the model's groups r_ratio and rho, bounded as in Parameters: far
            # beyond, positions are not resolved (a clearance of 1e-300 m ran without end)
            ratio = getattr(self, key) / self.clearance
            if not ratio <= MAX_MAGNITUDE:
                raise ParameterError(
                    f"{key} = {getattr(self, key)!r} m is {ratio:.3g} clearances (clearance = {self.clearance!r} m); "
                    f"allowed: at most {MAX_MAGNITUDE:g} clearances, as the groups r_ratio and rho of the model"
                )
        given = [key for key in RACE_KEYS if getattr(self, key) is not None]
        if given and len(given) < len(RACE_KEYS):
            missing = [key for key in RACE_KEYS if getattr(self, key) is None][0]
            raise ParameterError(
                f"{missing} = None while {given[0]} = {getattr(self, given[0])!r}; the race needs "
                f"all of {', '.join(RACE_KEYS)} (or none: a fixed stator)"
            )
        if given and self.polar_inertia is None:
            raise ParameterError(
                f"race_inertia = {self.race_inertia!r} with polar_inertia = None; a turning race needs the "
                "rotor's polar_inertia (kg m^2): with the speed held the race would spin up without bound"
            )
        self._check_compliant()
        self._check_stator()

    def _unit(self, name: str) -> str:
        """The SI unit a string value of ``name`` is converted to (N/m^n with this machine's n for K_c)."""
        return _si_unit(name, self.contact_exponent)

    def _check_contact(self) -> None:
        law = self.contact
        if law is not None and law not in CONTACT_LAWS:
            raise ParameterError(f"contact = {law!r} is not a contact law; allowed: {', '.join(CONTACT_LAWS)}")

    def _check_compliant(self) -> None:
        if self.contact == "compliant":
            if self.contact_stiffness is None:
                raise ParameterError(
                    "contact_stiffness = None with contact = 'compliant'; the compliant law needs K_c in N/m^n (> 0)"
                )
            force = self.contact_stiffness * self.clearance ** self.exponent
            if not force <= MAX_CONTACT_FORCE:
                raise ParameterError(
                    f"contact_stiffness = {self.contact_stiffness!r} N/m^{self.exponent:g} is out of range for "
                    f"clearance = {self.clearance:g} m: its force at a penetration of one clearance, K_c c_r^n = "
                    f"{force:.3g} N; allowed: K_c c_r^n <= {MAX_CONTACT_FORCE:g} N, K_c <= "
                    f"{MAX_CONTACT_FORCE / self.clearance ** self.exponent:.3g} N/m^{self.exponent:g} (stiffer "
                    "contacts penetrate less than the rounding of the position resolves; contact = 'rigid' is "
                    "their limit)"
                )
            from .machine_model import MIN_COMPLIANT_RESTITUTION

            if self.restitution < MIN_COMPLIANT_RESTITUTION:
                raise ParameterError(
                    f"restitution = {self.restitution!r} with contact = 'compliant'; allowed: "
                    f"[{MIN_COMPLIANT_RESTITUTION:.4g}, 1] (a compliant contact that keeps no rebound needs "
                    "infinite damping, and one that keeps almost none creeps for ever)"
                )
        elif self.contact_stiffness is not None or self.contact_exponent is not None:
            given = "contact_stiffness" if self.contact_stiffness is not None else "contact_exponent"
            raise ParameterError(
                f"{given} = {getattr(self, given)!r} with contact = {self.contact!r}; it applies to "
                "contact = 'compliant' only"
            )

    def _check_stator(self) -> None:
        given = [key for key in STATOR_KEYS if getattr(self, key) is not None]
        if not given:
            return
        if self.stator_mass is None:
            raise ParameterError(
                f"{given[0]} = {getattr(self, given[0])!r} with stator_mass = None; the stator's support keys need "
                "the stator_mass (kg, > 0) of a stator on springs"
            )
        if not self.compliant:
            raise ParameterError(
                f"stator_mass = {self.stator_mass!r} with contact = {self.contact!r}; a stator on springs needs "
                "contact = 'compliant'"
            )
        for axis in "xy":
            if getattr(self, f"stator_stiffness_{axis}") is None and self.stator_stiffness is None:
                raise ParameterError(
                    f"stator_stiffness_{axis} = None with stator_stiffness = None; a stator on springs needs its "
                    "support's stiffness (N/m, > 0): give stator_stiffness or both stator_stiffness_x and _y"
                )

    @property
    def has_stator(self) -> bool:
        """The touchdown bearing moves on its support springs (``stator_mass`` given, MODEL.md §8)."""
        return self.stator_mass is not None

    def stator_support(self) -> tuple[float, float, float, float]:
        """(k_sx, k_sy, c_sx, c_sy) of the stator's support, N/m and N s/m (zeros for a fixed stator)."""
        if not self.has_stator:
            return 0.0, 0.0, 0.0, 0.0
        k = self.stator_stiffness
        c = 0.0 if self.stator_damping is None else self.stator_damping
        pick = (lambda value, default: default if value is None else value)
        return (pick(self.stator_stiffness_x, k), pick(self.stator_stiffness_y, k),
                pick(self.stator_damping_x, c), pick(self.stator_damping_y, c))

    @property
    def compliant(self) -> bool:
        """The compliant contact law of MODEL.md §8 (``contact = "compliant"``)."""
        return self.contact == "compliant"

    @property
    def exponent(self) -> float:
        """n of the compliant law (default 1.5)."""
        return 1.5 if self.contact_exponent is None else self.contact_exponent

    @staticmethod
    def units() -> dict[str, str]:
        """SI unit of each field."""
        return {name: rule["unit"] for name, rule in _MACHINE_RULES.items()}

    # The general machine (MODEL.md §7): the values the optional fields stand for.
    @property
    def kx(self) -> float:
        """Bearing stiffness along x, N/m."""
        return self.stiffness if self.stiffness_x is None else self.stiffness_x

    @property
    def ky(self) -> float:
        """Bearing stiffness along y, N/m."""
        return self.stiffness if self.stiffness_y is None else self.stiffness_y

    @property
    def cx(self) -> float:
        """Bearing damping along x, N s/m."""
        return self.damping if self.damping_x is None else self.damping_x

    @property
    def cy(self) -> float:
        """Bearing damping along y, N s/m."""
        return self.damping if self.damping_y is None else self.damping_y

    @property
    def g(self) -> float:
        """Gravitational acceleration along -y, m/s^2."""
        return 0.0 if self.gravity is None else self.gravity

    @property
    def fs(self) -> float:
        """The bearing's static force along +y while levitated, N (default m g)."""
        return self.mass * self.g if self.static_force is None else self.static_force

    @property
    def free_speed(self) -> bool:
        """The spin is a state (``polar_inertia`` given), not held by the motor."""
        return self.polar_inertia is not None

    @property
    def has_race(self) -> bool:
        """The touchdown bearing's inner race turns (the race keys are given)."""
        return self.race_inertia is not None

    @property
    def race_radius(self) -> float:
        """Radius of the race's contact surface R_b = R + c_r, m."""
        return self.rotor_radius + self.clearance

    @property
    def needs_general_model(self) -> bool:
        """The machine is not the paper's machine of MODEL.md §1: it needs the model of MODEL.md §7."""
        return (
            self.kx != self.ky or self.cx != self.cy or self.g != 0.0 or self.fs != 0.0
            or self.free_speed or self.has_race or self.compliant
        )

    @property
    def general_keys(self) -> tuple[str, ...]:
        """The optional keys of MODEL.md §7-8 this machine gives, where it needs that model
        (`needs_general_model`); empty for the paper's machine of MODEL.md §1.

        The paper's dimensionless model (`parameters`) has none of them: a computation on it ignores these.
        """
        if not self.needs_general_model:
            return ()
        return tuple(key for key in OPTIONAL_MACHINE_KEYS if getattr(self, key) is not None)

    def parameters(self) -> Parameters:
        """Convert to the dimensionless `Parameters` (MODEL.md §2)."""
        m, om = self.mass, self.speed
        if not (m * om * om > 0.0 and math.isfinite(m * om * om)):
            raise ParameterError(
                f"speed = {om!r} with mass = {m!r} puts m Omega^2 = {m * om * om!r} outside floating-point "
                "range; choose SI values whose products are representable"
            )
        return Parameters(
            gamma=self.damping / (m * om),
            omega=math.sqrt(self.stiffness / (m * om * om)),
            rho=self.eccentricity / self.clearance,
            mu=self.friction,
            d=self.restitution,
            phi=self.unbalance_phase,
            r_ratio=self.rotor_radius / self.clearance,
        )

    def with_speed(self, speed: float) -> "Machine":
        """The same machine at another spin speed (rad/s)."""
        return replace(self, speed=speed)

    # Scales that turn dimensionless results into SI (MODEL.md §2: u = c_r U, t = Omega tau).
    @property
    def length_scale(self) -> float:
        """Metres per unit of U (the clearance c_r)."""
        return self.clearance

    @property
    def time_scale(self) -> float:
        """Seconds per unit of dimensionless time (1 / Omega)."""
        return 1.0 / self.speed

    @property
    def force_scale(self) -> float:
        """Newtons per unit of dimensionless force per unit mass (m c_r Omega^2)."""
        return self.mass * self.clearance * self.speed**2

    @property
    def impulse_scale(self) -> float:
        """Newton seconds per unit of dimensionless impulse per unit mass (m c_r Omega)."""
        return self.mass * self.clearance * self.speed

    def as_dict(self) -> dict[str, Any]:
        """The machine as a plain dict of SI floats (``contact``: a word); optional fields that are absent are
        left out."""
        return {k: v for k, v in asdict(self).items() if v is not None}

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any], source: str = "machine") -> "Machine":
        """Build a machine from a mapping of field names to values.

        Values are numbers in SI units, or strings with units parsed by pint
        (for example ``"0.7 mm"``, ``"12000 rpm"``, ``"1.4 kN*s/m"``).

        Raises
        ------
        ParameterError
            On unknown or missing keys, or invalid values.
        """
        if not isinstance(data, Mapping):
            raise ParameterError(f"{source}: expected a table of machine parameters, got {type(data).__name__}")
        allowed = [f.name for f in fields(cls)]
        required = [key for key in allowed if key not in OPTIONAL_MACHINE_KEYS]
        unknown = [key for key in data if key not in allowed]
        if unknown:
            raise ParameterError(
                f"{source}: unknown key {unknown[0]!r}; allowed keys: {', '.join(allowed)}"
            )
        missing = [key for key in required if key not in data]
        if missing:
            raise ParameterError(
                f"{source}: missing key {missing[0]!r}; required keys: {', '.join(required)}"
            )
        exponent = data.get("contact_exponent")
        if isinstance(exponent, str):
            exponent = to_si("contact_exponent", exponent, "1", source)
        values = {key: to_si(key, data[key], _si_unit(key, exponent), source) for key in data}
        try:
            return cls(**values)
        except ParameterError as exc:
            raise ParameterError(f"{source}: {exc}") from None


#: The keys of a machine that its dimensionless `Parameters` (the paper's model, MODEL.md §1-2) depend on; the
#: others (`OPTIONAL_MACHINE_KEYS`) belong to the general model of MODEL.md §7-8 only.
PAPER_MACHINE_KEYS = tuple(f.name for f in fields(Machine) if f.name not in OPTIONAL_MACHINE_KEYS)


def _machine_file(name: str) -> Path:
    return Path(str(resources.files("rotorcontact").joinpath("machines", f"{name}.toml")))


def load_machine(path: str | Path) -> Machine:
    """Load a `Machine` from a TOML file, or a built-in machine by name (``"reference"``).

    The file holds the fields of `Machine` as top-level keys, or under a
    ``[machine]`` table: numbers in SI units, or strings with units such as
    ``"0.7 mm"`` or ``"12000 rpm"``.

    Raises
    ------
    ParameterError
        If the file is missing, is not valid TOML, or its keys or values are invalid.
    """
    if not isinstance(path, (str, os.PathLike)) or not str(path).strip():
        raise ParameterError(f"machine = {path!r} is not a path; give a TOML file or the built-in name 'reference'")
    path_str = str(path)
    if path_str == "reference":
        path = _machine_file("reference")
    path = Path(path)
    if path.is_dir():
        raise ParameterError(
            f"machine = {path_str!r} is a folder, not a file; give a TOML file or the built-in name 'reference'"
        )
    if not path.is_file():
        what = "not a regular file" if path.exists() else "no such file"
        raise ParameterError(f"machine = {path_str!r}: {what}; give a TOML file or the built-in name 'reference'")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ParameterError(f"{path}: malformed TOML ({exc})") from None
    if "machine" in data and isinstance(data["machine"], Mapping) and len(data) == 1:
        data = data["machine"]
    return Machine.from_mapping(data, source=str(path))


def reference_machine() -> Machine:
    """The experimental rig of MODEL.md §1, the built-in ``reference`` machine."""
    return load_machine("reference")
