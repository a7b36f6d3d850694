"""SI values of dimensionless results, for a `rotorcontact.model.params.Machine`.

The model is dimensionless (MODEL.md §2): lengths in clearances c_r, time
t = Omega tau, forces and impulses per unit mass. A machine sets the scales
(`Machine.length_scale`, `time_scale`, `force_scale`, `impulse_scale`); this
module turns the results of the analyses into the units engineers use:
micrometres, seconds, metres per second, newtons, newton seconds, watts.

Each function returns a plain dict whose keys carry their unit as a suffix
(``T_s``, ``normal_force_N``, ``amplitude_um``, ``rdot_m_per_s``, ...), the
convention of the ``--json`` outputs with ``--machine``; values that do not
exist are None.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ..errors import ParameterError
from .validation import check_fields, check_machine

if TYPE_CHECKING:
    from ..analysis.equilibria import Equilibria, PseudoEquilibrium, RegularEquilibrium
    from ..maps.impact_map import ImpactOrbit
    from .params import Machine

__all__ = [
    "MICROMETRE",
    "velocity_scale",
    "rate_scale",
    "scaled_list",
    "scaled_each",
    "parameter_si",
    "orbit_si",
    "regular_si",
    "pseudo_si",
    "equilibria_si",
    "times_si",
]

#: Micrometres per metre.
MICROMETRE = 1e6

# the SI field each dimensionless parameter stands for, at the machine's other values:
# name -> (key with unit, function of (machine, value))
_PARAMETER_SI = {
    "gamma": ("damping_Ns_per_m", lambda m, v: v * m.mass * m.speed),  # gamma = c / (m Omega)
    "omega": ("stiffness_N_per_m", lambda m, v: v * v * m.mass * m.speed**2),  # omega^2 = k / (m Omega^2)
    "rho": ("eccentricity_m", lambda m, v: v * m.clearance),  # rho = e_c / c_r
    "r_ratio": ("rotor_radius_m", lambda m, v: v * m.clearance),  # r_ratio = R / c_r
}


def velocity_scale(machine: "Machine") -> float:
    """Metres per second per unit of dimensionless velocity (c_r Omega)."""
    check_machine(machine, optional=False)
    return machine.length_scale / machine.time_scale


def rate_scale(machine: "Machine") -> float:
    """Per second per unit of dimensionless rate (Omega): angular velocities, exponents, frequencies."""
    check_machine(machine, optional=False)
    return 1.0 / machine.time_scale


def _scaled(value: float | None, scale: float) -> float | None:
    if value is None or not math.isfinite(value):
        return None
    return float(value) * scale


def _value(name: str, value: Any) -> float | None:
    """``value`` as a float, or None where it is None or not finite (a value that does not exist); a
    `ParameterError` for text, bools and other objects. A 0-d array (an xarray or numpy scalar) is its
    value."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: a real number or None")
    return float(value) if math.isfinite(value) else None


def parameter_si(machine: "Machine", name: str, value: float | None) -> dict[str, float | None]:
    """The SI value a dimensionless parameter stands for, the machine's other values held.

    Parameters
    ----------
    machine : Machine
        The machine (its mass, speed and clearance set the scales).
    name : str
        ``"gamma"`` (damping, N s/m), ``"omega"`` (stiffness, N/m), ``"rho"``
        (eccentricity, m) or ``"r_ratio"`` (rotor radius, m); ``"mu"``, ``"d"``
        and ``"phi"`` are the same in SI and give an empty dict.
    value : float or None
        The dimensionless value.

    Returns
    -------
    dict
        ``{"damping_Ns_per_m": c}`` and the like; empty for ``mu``, ``d``, ``phi``.

    Raises
    ------
    ParameterError
        For an unknown parameter name, a value that is not a number or None, or an object that is not a
        `Machine`.
    """
    check_machine(machine, optional=False)
    value = _value("value", value)
    if name in ("mu", "d", "phi"):
        return {}
    if name not in _PARAMETER_SI:
        raise ParameterError(
            f"parameter = {name!r} is unknown; allowed: {', '.join([*_PARAMETER_SI, 'mu', 'd', 'phi'])}"
        )
    key, convert = _PARAMETER_SI[name]
    if value is None:
        return {key: None}
    return {key: float(convert(machine, value))}


def times_si(machine: "Machine", **times: float | None) -> dict[str, float | None]:
    """Dimensionless times in seconds: ``times_si(m, T=2.8)`` gives ``{"T_s": ...}``."""
    check_machine(machine, optional=False)
    return {f"{name}_s": _scaled(_value(name, t), machine.time_scale) for name, t in times.items()}


def orbit_si(machine: "Machine", orbit: "ImpactOrbit") -> dict[str, Any]:
    """SI values of a one-impact orbit (`rotorcontact.maps.impact_map.ImpactOrbit`).

    Returns
    -------
    dict
        ``T_s`` (period), ``impact_rate_hz`` (impacts per second), ``rdot_m_per_s``
        and ``thetadot_rad_per_s`` (just before the impact), ``amplitude_um``
        (the whirl radius c_r), ``r_max_interior_um``, ``normal_impulse_Ns``,
        ``friction_impulse_Ns`` (magnitude, the slip-bounded Coulomb law of
        MODEL.md §2) and ``friction_power_W`` (mean power dissipated by
        friction). The impulses and power are None for a virtual orbit.
    """
    check_machine(machine, optional=False)
    check_fields("orbit", orbit, ("params", "T", "rdot", "thetadot", "r_max_interior", "admissible"),
                 "an ImpactOrbit (rotorcontact.maps.impact_map)")
    p = orbit.params
    period_s = orbit.T * machine.time_scale
    out: dict[str, Any] = {
        "T_s": period_s,
        "impact_rate_hz": 1.0 / period_s,
        "rdot_m_per_s": orbit.rdot * velocity_scale(machine),
        "thetadot_rad_per_s": orbit.thetadot * rate_scale(machine),
        "amplitude_um": machine.clearance * MICROMETRE,
        "r_max_interior_um": _scaled(orbit.r_max_interior, machine.clearance * MICROMETRE),
        "normal_impulse_Ns": None,
        "friction_impulse_Ns": None,
        "friction_power_W": None,
    }
    if orbit.admissible:
        q_n = (1.0 + p.d) * orbit.rdot  # normal impulse per unit mass
        v_minus = p.r_ratio + 1.0 + orbit.thetadot
        p_t = min(p.mu * q_n, abs(v_minus))  # the friction impulse stops at v_rel = 0
        v_plus = v_minus - math.copysign(p_t, v_minus)
        # work of an impulsive Coulomb force: impulse times the mean slip velocity (v_rel is linear in it)
        energy = p_t * 0.5 * (abs(v_minus) + abs(v_plus)) * machine.impulse_scale * velocity_scale(machine)
        out.update(
            normal_impulse_Ns=q_n * machine.impulse_scale,
            friction_impulse_Ns=p_t * machine.impulse_scale,
            friction_power_W=energy / period_s,
        )
    return out


def regular_si(machine: "Machine", regular: "RegularEquilibrium") -> dict[str, Any]:
    """SI value of the regular equilibrium x_R: ``amplitude_um``, the whirl radius |k| c_r."""
    check_machine(machine, optional=False)
    check_fields("regular", regular, ("r",), "a RegularEquilibrium (the regular field of an Equilibria)")
    return {"amplitude_um": _scaled(regular.r, machine.clearance * MICROMETRE)}


def pseudo_si(machine: "Machine", pseudo: "PseudoEquilibrium") -> dict[str, Any]:
    """SI values of a pseudo-equilibrium (a forward rub, thetadot = 0).

    Returns
    -------
    dict
        ``normal_force_N`` (the contact force N m c_r Omega^2) and
        ``friction_power_W`` (mu N v_rel with v_rel = R Omega + c_r Omega); None
        where it does not exist.
    """
    check_machine(machine, optional=False)
    check_fields("pseudo", pseudo, ("normal_force",),
                 "a PseudoEquilibrium (an item of the pseudo field of an Equilibria)")
    force = _scaled(pseudo.normal_force, machine.force_scale)
    if force is None:
        return {"normal_force_N": None, "friction_power_W": None}
    p = machine.parameters()
    v_rel = (p.r_ratio + 1.0) * velocity_scale(machine)
    return {"normal_force_N": force, "friction_power_W": p.mu * force * v_rel}


def equilibria_si(machine: "Machine", eq: "Equilibria") -> dict[str, Any]:
    """SI values of all equilibria, shaped like `Equilibria.to_dict` (to merge into it).

    Returns
    -------
    dict
        ``{"regular": regular_si, "pseudo": [pseudo_si, ...], "boundary":
        {"damping_star_Ns_per_m": c*}}`` with c* the damping at gamma*.
    """
    check_fields("eq", eq, ("regular", "pseudo", "boundary"), "an Equilibria (rotorcontact.analysis.equilibria)")
    star = parameter_si(machine, "gamma", eq.boundary.gamma_star)["damping_Ns_per_m"]
    return {
        "regular": regular_si(machine, eq.regular),
        "pseudo": [pseudo_si(machine, pe) for pe in eq.pseudo],
        "boundary": {"damping_star_Ns_per_m": star},
    }


def scaled_list(values: Sequence[float | None], scale: float) -> list[float | None]:
    """``values`` times ``scale``, with None (and non-finite values) kept as None."""
    return [_scaled(v, scale) for v in values]


def scaled_each(values: Sequence[float | None], scales: Sequence[float]) -> list[float | None]:
    """Each of ``values`` times its own scale (the scale at each value of a parameter path), with None (and
    non-finite values) kept as None."""
    if len(values) != len(scales):
        raise ParameterError(f"{len(values)} values and {len(scales)} scales; allowed: one scale per value")
    return [_scaled(v, s) for v, s in zip(values, scales)]
