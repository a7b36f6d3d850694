"""Physical quantities written with units, parsed by pint at the edge of the package."""

from __future__ import annotations

import math
import re
from functools import lru_cache

from ..errors import ParameterError

__all__ = ["option_quantity", "quantity_in", "registry", "RPM"]

#: rad/s per rpm.
RPM = 2.0 * math.pi / 60.0

# how a unit of the package is spelled for pint
_PINT_SPELLING = {"1": "dimensionless", "N s/m": "N*s/m", "rad/s": "rad/s"}


_ANGULAR_SPEEDS = {"rad/s", "rpm"}

# what a quantity of a unit is, and how one is written, for the message asking for its unit
_WRITTEN = {
    "rad/s": ("an angular speed", "12000rpm or 1250rad/s"),
    "rpm": ("an angular speed", "12000rpm or 1250rad/s"),
    "m/s": ("a speed", "5mm/s or 0.005m/s"),
}

# a quantity's text starts with its magnitude (pint alone would read "rpm" as 1 rpm)
_MAGNITUDE = re.compile(r"\s*[-+]?(\d|\.\d|nan|inf)", re.IGNORECASE)
# "mil" is an angle to pint (1/6400 of a turn); in machinery, and wherever no angle is expected, it is the
# thousandth of an inch (pint's "thou"), in which clearances and orbits are given
_MIL = re.compile(r"\bmils?\b")


@lru_cache(maxsize=1)
def registry():
    """The shared pint unit registry (with ``rev`` for revolution)."""
    import pint

    ureg = pint.UnitRegistry()
    if "rev" not in ureg:
        ureg.define("rev = revolution")
    return ureg


def _has_angle(q) -> bool:
    """Whether the units of ``q`` hold an angle (rad, degree, revolution, rpm, krpm, ...), read from its root units."""
    return any(name == "radian" for name, _ in q.to_root_units().to_tuple()[1])


def _spelling(ureg, name: str) -> str | None:
    """How an unknown unit written in the wrong case is spelt (``RPM`` -> ``rpm``, ``MHZ`` -> ``MHz``), or None.

    The prefix keeps its case where that is a unit (``MRPM`` -> ``Mrpm``, not milli-rpm), else is lowered
    (``KRPM`` -> ``krpm``)."""
    if name.lower().endswith("hz"):
        variants = (name[:-2] + "Hz", name[:-2].lower() + "Hz")
    else:
        variants = (name[:1] + name[1:].lower(), name.lower())
    for variant in dict.fromkeys(variants):
        if variant and variant != name:
            try:
                ureg.parse_units(variant)
            except Exception:  # not a unit either
                continue
            return variant
    return None


def quantity_in(name: str, text: str, unit: str, *, unit_required: bool = False) -> float:
    """Parse ``text`` (for example ``"0.7 mm"``) and return its magnitude in ``unit``.

    A bare number is taken to be in ``unit`` already, unless ``unit_required``.
    For an angular speed (``unit`` rad/s or rpm), a frequency in hertz
    (``"50 Hz"``) counts revolutions; any other rate without an angle
    (``"184.2 1/s"``, ``"3000/min"``) is refused, being as often meant in
    rad/s as in revolutions. Elsewhere ``mil`` is the thousandth of an inch
    (``"27.6 mil"``), not pint's angle.

    Raises
    ------
    ParameterError
        For a malformed quantity, one without a number (or, with
        ``unit_required``, without a unit), an unknown unit, units of the wrong
        dimension, or a non-finite value.
    """
    import pint

    if not isinstance(text, str):
        raise ParameterError(f"{name} = {text!r} is not text; expected a number with units of {unit}, such as "
                             f"'1.5 {unit}'")
    if not _MAGNITUDE.match(text):
        raise ParameterError(f"{name} = {text!r} has no number; expected a number with units of {unit}")
    if unit_required:
        try:
            float(text)
        except ValueError:
            pass
        else:
            what, example = _WRITTEN.get(unit, ("a quantity", f"a number followed by {unit}"))
            raise ParameterError(f"{name} = {text!r} has no unit; allowed: {what} with its unit, such as {example}")
    ureg = registry()
    target = _PINT_SPELLING.get(unit, unit)
    read = text.strip() if target in _ANGULAR_SPEEDS else _MIL.sub("thou", text.strip())
    try:
        q = ureg.Quantity(read)
    except pint.errors.UndefinedUnitError as exc:
        names = [str(n) for n in exc.unit_names] if isinstance(exc.unit_names, (list, tuple)) else [str(exc.unit_names)]
        hint = "".join(f" ({n!r} is written {_spelling(ureg, n)!r})" for n in names if _spelling(ureg, n))
        raise ParameterError(f"{name} = {text!r}: unknown unit {', '.join(names)!r}{hint}; expected a quantity in "
                             f"{unit}") from None
    except pint.errors.OffsetUnitCalculusError:
        raise ParameterError(f"{name} = {text!r} has a unit with an offset (a temperature); expected a number with "
                             f"units of {unit}") from None
    except Exception:  # pint raises several parser errors for malformed text
        raise ParameterError(f"{name} = {text!r} is not a quantity; expected a number with units of {unit}") from None
    try:
        if not isinstance(q, pint.Quantity):
            q = ureg.Quantity(q, target)
        elif q.dimensionless and q.units == ureg.dimensionless and target != "dimensionless":
            q = ureg.Quantity(q.magnitude, target)
        if target == "dimensionless" and isinstance(q, pint.Quantity) and _has_angle(q):
            # pint counts an angle as dimensionless: "0.15 deg" would be a friction coefficient of 0.0026
            raise ParameterError(f"{name} = {text!r} is an angle; allowed: a plain number (or a ratio such as %)")
        if target in _ANGULAR_SPEEDS and q.check("1/[time]") and not _has_angle(q):
            if "hertz" not in str(q.units):
                # "184.2 1/s" is rad/s in SI, but as often meant as revolutions: ambiguous, as a bare number is
                raise ParameterError(
                    f"{name} = {text!r} is a rate without an angle: rad/s or revolutions per second? allowed: an "
                    "angular speed with its unit (rpm, rev/min, rev/s, rad/s) or a frequency of rotation in Hz"
                )
            # a frequency of rotation such as "50 Hz" counts revolutions
            q = q * ureg.revolution
        value = float(q.to(target).magnitude)
    except pint.errors.DimensionalityError:
        raise ParameterError(
            f"{name} = {text!r} has units of {q.dimensionality}; expected units convertible to {unit}"
        ) from None
    except (OverflowError, ZeroDivisionError):
        value = math.inf
    if not math.isfinite(value):
        raise ParameterError(f"{name} = {text!r} is not finite; a finite quantity in {unit} is required")
    return value


def option_quantity(option: str, text: str, unit: str) -> float:
    """A command-line option's quantity in ``unit``, as `quantity_in`; an angular speed must carry its unit.

    A bare ``--speed 30000`` is as likely meant in rpm as in rad/s, a factor of
    ten apart: it is refused rather than guessed. Other bare numbers are in ``unit``.
    """
    return quantity_in(option, text, unit, unit_required=unit in _ANGULAR_SPEEDS)
