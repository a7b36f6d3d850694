"""Checks of the arguments of the public functions: one message format for every bad input.

Every message names the argument, the value given and what is allowed, and is raised as a
`ParameterError` (the command line prints it in one line and exits with status 2).
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from ..errors import ParameterError
from .params import Parameters, check_finite, refuse_bool_or_text

__all__ = ["MAX_COUNT", "check_params", "check_machine", "check_machine_params", "check_type", "check_fields",
           "check_broadcast", "finite_array", "quoted", "check_int", "check_float", "check_choice", "real_array",
           "complex_array", "check_bool", "check_path", "check_length", "is_pair", "settings_or_default"]


#: Longest repr of a value quoted in a message; longer ones (a dataset, a long list) are cut.
MAX_QUOTED = 80


def quoted(value: Any) -> str:
    """``repr(value)`` on one line (each line break and the indentation around it one space), cut to
    `MAX_QUOTED` characters: the value as a message quotes it."""
    text = re.sub(r"\s*\n\s*", " ", repr(value))
    return text if len(text) <= MAX_QUOTED else text[: MAX_QUOTED - 3] + "..."


def check_type(name: str, value: Any, kind: type | tuple[type, ...], allowed: str, *, optional: bool = False):
    """Return ``value`` if it is an instance of ``kind`` (or None where ``optional``), else raise
    `ParameterError` naming ``name``, the value and ``allowed``, the object expected in words."""
    if (value is None and optional) or isinstance(value, kind):
        return value
    what = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
    article = "an" if what[0].lower() in "aeiou" else "a"
    raise ParameterError(f"{name} = {quoted(value)} is not {article} {what} object; "
                         f"allowed: {allowed}{' or None' if optional else ''}")


def check_broadcast(**arrays: np.ndarray) -> tuple[int, ...]:
    """The shape that the named arrays broadcast to, or a `ParameterError` naming them and their shapes."""
    try:
        return np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        shapes = " and ".join(f"{name} of shape {a.shape}" for name, a in arrays.items())
        raise ParameterError(f"{shapes} do not match; allowed: the same shape, or shapes numpy broadcasts "
                             "together (one a single value)") from None


def check_fields(name: str, value: Any, fields: Sequence[str], allowed: str):
    """Return ``value`` if it has every attribute in ``fields``, else raise `ParameterError` naming ``name``,
    the value and ``allowed``: the type check of a result defined in a layer above the caller's."""
    if not all(hasattr(value, f) for f in fields):
        raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: {allowed}")
    return value


def check_params(params: Any, name: str = "params"):
    """Return ``params`` if it is a `rotorcontact.model.params.Parameters`, else raise `ParameterError`."""
    return check_type(name, params, Parameters, "rotorcontact.Parameters")


def check_machine(machine: Any, name: str = "machine", optional: bool = True):
    """Return ``machine`` if it is a `rotorcontact.model.params.Machine` (or None where ``optional``), else
    raise `ParameterError`."""
    from .params import Machine

    return check_type(name, machine, Machine, "rotorcontact.Machine", optional=optional)


def check_machine_params(params: Parameters, machine: Any, skip: str | None = None) -> None:
    """Refuse ``params`` that are not ``machine.parameters()`` (to 1e-12; the parameter ``skip``, which a
    study varies, excepted) with a `ParameterError`: SI results would describe another machine. Nothing is
    checked without a machine."""
    if machine is None:
        return
    own = machine.parameters()
    other = [f"{name} = {value!r}" for name, value in params.as_dict().items()
             if name != skip and not math.isclose(value, getattr(own, name), rel_tol=1e-12, abs_tol=1e-300)]
    if other:
        raise ParameterError(
            f"params are not the machine's ({', '.join(other)} against {own}): its SI results would describe "
            "another machine; allowed: machine.parameters(), or no machine"
        )


#: The largest count a kernel takes (numba's int64).
MAX_COUNT = 2**63 - 1
#: Most grid points of an equilibrium branch scan: about a millisecond each, so 10000 take seconds.
MAX_EQUILIBRIUM_POINTS = 10_000


def _holds_bool(value: Any) -> bool:
    if isinstance(value, (list, tuple)):
        return any(_holds_bool(v) for v in value)
    return isinstance(value, (bool, np.bool_))


def _numbers(value: Any, kinds: str, dtype: type) -> np.ndarray | None:
    """``value`` as an array of ``dtype`` if numpy reads it with a kind in ``kinds`` and it holds no bool."""
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        return None
    if raw.dtype.kind not in kinds or _holds_bool(value):
        return None
    return raw.astype(dtype)


def real_array(value: Any) -> np.ndarray | None:
    """``value`` as an array of floats if it holds integers or reals only; None for text, bools (also
    mixed into a list of numbers, where numpy would read them as 0 and 1), complex numbers, ragged lists
    or other objects, which ``np.asarray(value, dtype=float)`` would read or half-read."""
    return _numbers(value, "iuf", float)


def complex_array(value: Any) -> np.ndarray | None:
    """``value`` as an array of complex numbers if it holds integers, reals or complex numbers only; None
    for text, bools, ragged lists or other objects (`real_array`'s rule, complex numbers allowed)."""
    return _numbers(value, "iufc", complex)


def finite_array(name: str, value: Any, allowed: str, *, ndims: tuple[int, ...] = (1,), min_rows: int = 1,
                 rows: int | None = None) -> np.ndarray:
    """``value`` as an array of floats if it holds finite real numbers only (`real_array`), with one of
    ``ndims`` dimensions and at least ``min_rows`` rows (exactly ``rows`` if given); else a `ParameterError`
    naming ``name``, the value and ``allowed``."""
    arr = real_array(value)
    if (arr is None or arr.ndim not in ndims or (arr.ndim and arr.shape[0] < min_rows)
            or (rows is not None and (arr.ndim == 0 or arr.shape[0] != rows)) or not np.all(np.isfinite(arr))):
        raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: {allowed}")
    return arr


def check_length(name: str, values: Any, most: int) -> None:
    """Refuse a sized ``values`` (list, range, array ...) of more than ``most`` items before numpy reads it
    (``range(10**12)`` would fill the memory first), naming ``name``; anything without a length passes."""
    try:
        count = len(values)
    except TypeError:
        return
    if count > most:
        raise ParameterError(f"{name} = {quoted(values)} holds {count} values; allowed: at most {most}")


def is_pair(value: Any) -> bool:
    """A sequence (a list, tuple, array ...) of two items, not text, which is a sequence too."""
    if isinstance(value, np.ndarray):
        return value.ndim >= 1 and len(value) == 2
    return isinstance(value, Sequence) and not isinstance(value, (str, bytes)) and len(value) == 2


def _scalar(value: Any) -> Any:
    """The value of a 0-d array (as numpy and xarray give for one number); anything else unchanged."""
    return value[()] if isinstance(value, np.ndarray) and value.ndim == 0 else value


def check_int(name: str, value: Any, low: int | None = None, high: int | None = None) -> int:
    """Return ``value`` as an int if it is an integer (not a bool) within [low, high].

    Raises
    ------
    ParameterError
        Naming ``name``, the value and the allowed range.
    """
    value = _scalar(value)
    ok = not isinstance(value, bool) and isinstance(value, (int, np.integer))
    if ok:
        value = int(value)
        ok = (low is None or value >= low) and (high is None or value <= high)
    if not ok:
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: an integer{_range(low, high)}")
    return value


def check_float(name: str, value: Any, low: float | None = None, high: float | None = None, *,
                low_open: bool = False, high_open: bool = False) -> float:
    """Return ``value`` as a float if it is a finite real number within the given bounds.

    ``low_open`` and ``high_open`` exclude the bounds themselves.
    """
    value = _scalar(value)
    ok = not isinstance(value, bool) and isinstance(value, (int, float, np.integer, np.floating))
    if ok:
        value = float(value)
        ok = math.isfinite(value)
        if ok and low is not None:
            ok = value > low if low_open else value >= low
        if ok and high is not None:
            ok = value < high if high_open else value <= high
    if not ok:
        lo = "" if low is None else f" {'>' if low_open else '>='} {low:g}"
        hi = "" if high is None else f" {'<' if high_open else '<='} {high:g}"
        bounds = f"{lo}{' and' if lo and hi else ''}{hi}"
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: a finite number{bounds}")
    return value


def check_path(name: str, value: Any) -> Path:
    """``value`` as a `pathlib.Path` if it is a non-empty path (text or os.PathLike), else a `ParameterError`:
    an empty name would mean the current folder. ``Path("")`` is ``Path(".")`` itself, the current folder
    named explicitly, and is taken as such."""
    if not isinstance(value, (str, os.PathLike)) or not str(value).strip() or "\0" in str(value):
        raise ParameterError(f"{name} = {value!r} is not a path; allowed: a non-empty file or folder name (without "
                             "NUL characters)")
    return Path(value)


def check_bool(name: str, value: Any) -> bool:
    """Return ``value`` if it is True or False (numpy's too), else raise `ParameterError`: a yes/no flag
    given as text such as ``"False"`` would otherwise read as true."""
    value = _scalar(value)
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: True or False")
    return bool(value)


def check_choice(name: str, value: Any, allowed: Sequence[str]) -> str:
    """Return ``value`` if it is one of ``allowed``, else raise `ParameterError` listing them."""
    if not isinstance(value, str) or value not in allowed:
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: {', '.join(map(repr, allowed))}")
    return value


def settings_or_default(value: Any, kind: type, default: Callable[[], Any], name: str = "settings"):
    """``value`` if it is a ``kind``, ``default()`` if it is None, else a `ParameterError` naming ``name``."""
    if value is None:
        return default()
    return check_type(name, value, kind, f"a {kind.__name__}", optional=True)


def _range(low: int | None, high: int | None) -> str:
    if low is not None and high is not None:
        return f" from {low} to {high}"
    if low is not None:
        return f" >= {low}"
    if high is not None:
        return f" <= {high}"
    return ""


def complex_value(name: str, value: Any) -> complex:
    """``value`` as a finite complex number: a number, or a pair (RE, IM); a `ParameterError` naming ``name``
    for text, bools, other objects or values that are not finite."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    refuse_bool_or_text(name, value, "give a complex number or RE,IM")
    if isinstance(value, (tuple, list, np.ndarray)) and len(value) == 2:
        re, im = value
    else:
        try:
            z = complex(value)
        except (TypeError, ValueError):
            raise ParameterError(f"{name} = {value!r} is not a complex number; give RE,IM") from None
        re, im = z.real, z.imag
    return complex(check_finite(f"{name} (real part)", re), check_finite(f"{name} (imaginary part)", im))
