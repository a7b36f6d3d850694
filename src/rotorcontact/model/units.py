"""Physical quantities written with units, parsed by pint at the edge of the package."""

from __future__ import annotations

import math
from functools import lru_cache

from ..errors import ParameterError

__all__ = ["quantity_in", "registry", "RPM"]

#: rad/s per rpm.
RPM = 2.0 * math.pi / 60.0

# how a unit of the package is spelled for pint
_PINT_SPELLING = {"1": "dimensionless", "N s/m": "N*s/m", "rad/s": "rad/s"}


# angle units: a speed written with one of these is an angular speed; without, a frequency in cycles
_ANGLE_UNITS = {"radian", "degree", "revolution", "rev", "turn", "revolutions_per_minute", "revolutions_per_second",
                "cycle", "arcminute", "arcsecond", "gradian"}


_ANGULAR_SPEEDS = {"rad/s", "rpm"}


@lru_cache(maxsize=1)
def registry():
    """The shared pint unit registry (with ``rev`` for revolution)."""
    import pint

    ureg = pint.UnitRegistry()
    if "rev" not in ureg:
        ureg.define("rev = revolution")
    return ureg


def quantity_in(name: str, text: str, unit: str) -> float:
    """Parse ``text`` (for example ``"0.7 mm"``) and return its magnitude in ``unit``.

    A bare number is taken to be in ``unit`` already.

    Raises
    ------
    ParameterError
        For a malformed quantity, an unknown unit, units of the wrong
        dimension, or a non-finite value.
    """
    import pint

    ureg = registry()
    target = _PINT_SPELLING.get(unit, unit)
    try:
        q = ureg.Quantity(text.strip())
    except pint.errors.UndefinedUnitError as exc:
        raise ParameterError(f"{name} = {text!r}: unknown unit {', '.join(map(str, exc.unit_names))!r}; expected a quantity in {unit}") from None
    except Exception:  # pint raises several parser errors for malformed text
        raise ParameterError(f"{name} = {text!r} is not a quantity; expected a number with units of {unit}") from None
    if not isinstance(q, pint.Quantity):
        q = ureg.Quantity(q, target)
    elif q.dimensionless and q.units == ureg.dimensionless and target != "dimensionless":
        q = ureg.Quantity(q.magnitude, target)
    try:
        unit_names = {unit_name for unit_name, _ in q.to_tuple()[1]}
        if target in _ANGULAR_SPEEDS and not unit_names & _ANGLE_UNITS and q.check("1/[time]"):
            # a frequency such as "50 Hz" or "3000 / minute" counts revolutions
            q = q * ureg.revolution
        value = float(q.to(target).magnitude)
    except pint.errors.DimensionalityError:
        raise ParameterError(
            f"{name} = {text!r} has units of {q.dimensionality}; expected units convertible to {unit}"
        ) from None
    if not math.isfinite(value):
        raise ParameterError(f"{name} = {text!r} is not finite; a finite quantity in {unit} is required")
    return value
