"""Grids of initial states for basins of attraction: displacement planes and velocity kicks at x_R.

`parse_grid` reads the grid syntax of the command line (`GRID_SYNTAX`); a
`BasinGrid` gives the initial states of its points for given parameters.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.params import MAX_VELOCITY, Parameters, check_finite
from ..model.validation import check_int, real_array

__all__ = ["AXIS_ATTRS", "GRID_KINDS", "GRID_SYNTAX", "MAX_GRID_POINTS", "BasinGrid", "displacement_grid",
           "shock_grid", "parse_grid"]

GRID_KINDS = ("displacement", "shock")
_AXES = {"displacement": ("x", "y"), "shock": ("amplitude", "direction")}
#: The NetCDF attributes of each grid axis.
AXIS_ATTRS = {
    "x": dict(long_name="initial displacement, real part of U(0)", units="1"),
    "y": dict(long_name="initial displacement, imaginary part of U(0)", units="1"),
    "amplitude": dict(long_name="amplitude of the velocity kick |U'(0)| applied at x_R", units="1"),
    "direction": dict(long_name="direction of the kick from the outward radial direction of x_R", units="rad"),
}

GRID_SYNTAX = """\
Grid of initial states, one of:
  x=X0:X1:NX,y=Y0:Y1:NY               displacement plane U(0) = x + i y at U'(0) = 0
                                      (points with |U(0)| > 1 are outside and not simulated)
  amplitude=A0:A1:NA,direction=B0:B1:NB
                                      velocity kicks U'(0) = A exp(i (arg k + B)) from the
                                      contact-free whirl x_R (U(0) = k); B = 0 points at the
                                      stator, B = pi/2 is a forward tangential kick
  plane:N                             short for x=-1:1:N,y=-1:1:N
  shock:N                             short for amplitude=0:1:N,direction=-pi:pi:N
Each axis is START:STOP:COUNT (COUNT >= 1, both ends included). Numbers may be
written with pi: pi, -pi, pi/2, 2pi, 0.5pi."""


MAX_GRID_POINTS = 16_000_000  # 4000 x 4000; beyond this the arrays alone need gigabytes


@dataclass(frozen=True)
class BasinGrid:
    """A grid of initial states.

    Attributes
    ----------
    kind : {"displacement", "shock"}
        See the module docstring.
    axis0, axis1 : numpy.ndarray
        Values along the first (image columns: x or amplitude) and second
        (image rows: y or direction) axis.
    """

    kind: str
    axis0: np.ndarray = field(repr=False)
    axis1: np.ndarray = field(repr=False)

    def __post_init__(self) -> None:
        if self.kind not in GRID_KINDS:
            raise ParameterError(f"grid kind {self.kind!r} is invalid; allowed: {', '.join(GRID_KINDS)}")
        for name in ("axis0", "axis1"):
            arr = real_array(getattr(self, name))
            if arr is None or arr.size == 0 or not np.all(np.isfinite(arr)):
                raise ParameterError(f"grid {name} = {getattr(self, name)!r} is invalid; allowed: finite real values")
            arr = arr.reshape(-1)
            object.__setattr__(self, name, arr)
        if self.kind == "shock" and np.any(self.axis0 < 0):
            raise ParameterError("grid amplitude values must be >= 0")
        if self.kind == "shock" and np.any(self.axis0 > MAX_VELOCITY):
            raise ParameterError(
                f"grid amplitude {float(self.axis0.max())!r} is too large; allowed: amplitudes <= {MAX_VELOCITY:g} "
                "clearances per unit time (far beyond any touchdown shock)"
            )
        points = self.axis0.size * self.axis1.size
        if points > MAX_GRID_POINTS:
            raise ParameterError(
                f"grid of {self.axis0.size} x {self.axis1.size} = {points} points is too large; "
                f"allowed: at most {MAX_GRID_POINTS} points"
            )

    @property
    def names(self) -> tuple[str, str]:
        """Names of the two axes."""
        return _AXES[self.kind]

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, columns) = (len(axis1), len(axis0))."""
        return self.axis1.size, self.axis0.size

    def describe(self) -> str:
        """The grid in the syntax of `parse_grid`."""
        a, b = self.names
        f = lambda v: f"{v[0]:.17g}:{v[-1]:.17g}:{v.size}"  # noqa: E731
        return f"{a}={f(self.axis0)},{b}={f(self.axis1)}"

    def initial_states(self, params: Parameters) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(u0, du0, inside): complex arrays shaped `shape`, and where |u0| <= 1.

        Raises
        ------
        ParameterError
            For a shock grid where x_R is virtual (|k| >= 1).
        """
        c0, c1 = np.meshgrid(self.axis0, self.axis1)
        if self.kind == "displacement":
            u0 = c0 + 1j * c1
            du0 = np.zeros_like(u0)
            inside = np.abs(u0) <= 1.0
        else:
            k = params.k
            if abs(k) >= 1.0:
                raise ParameterError(
                    f"shock grid: the contact-free whirl x_R is virtual at these parameters (|k| = {abs(k):.6g} >= 1)"
                )
            u0 = np.full(c0.shape, complex(k))
            du0 = c0 * np.exp(1j * (np.angle(k) + c1))
            inside = np.ones(c0.shape, dtype=bool)
        return u0, du0, inside


def _axis(name: str, spec: Any) -> np.ndarray:
    if not (isinstance(spec, (tuple, list)) or (isinstance(spec, np.ndarray) and spec.ndim == 1)) or len(spec) != 3:
        raise ParameterError(f"{name} = {spec!r} is invalid; allowed: (start, stop, count)")
    lo, hi, n = spec.tolist() if isinstance(spec, np.ndarray) else spec
    if isinstance(spec, np.ndarray) and isinstance(n, float) and n.is_integer():
        n = int(n)  # a numpy triple holds its count as a float
    lo = check_finite(f"{name} start", lo)
    hi = check_finite(f"{name} stop", hi)
    n = check_int(f"{name} count", n, 1, MAX_GRID_POINTS)
    if n > 1 and not lo < hi:
        raise ParameterError(f"{name} = {spec!r} is invalid: start {lo!r} must be smaller than stop {hi!r}; allowed: "
                             "(start, stop, count) with start < stop, or count 1")
    return np.linspace(lo, hi, int(n))


def displacement_grid(x: tuple[float, float, int] = (-1.0, 1.0, 101),
                      y: tuple[float, float, int] = (-1.0, 1.0, 101)) -> BasinGrid:
    """Initial displacements U(0) = x + i y at zero velocity; ``x`` and ``y`` are (start, stop, count)."""
    return BasinGrid("displacement", _axis("x", x), _axis("y", y))


def shock_grid(amplitude: tuple[float, float, int] = (0.0, 1.0, 101),
               direction: tuple[float, float, int] = (-math.pi, math.pi, 101)) -> BasinGrid:
    """Velocity kicks at x_R: amplitude and direction from the outward radial direction, each (start, stop, count)."""
    return BasinGrid("shock", _axis("amplitude", amplitude), _axis("direction", direction))


#: The forms of a grid, in one line (the syntax in full: `GRID_SYNTAX`, shown by ``--help``).
_FORMS = "plane:N, shock:N, x=X0:X1:NX,y=Y0:Y1:NY or amplitude=A0:A1:NA,direction=B0:B1:NB"

_PI = re.compile(r"^([+-]?(?:\d+\.?\d*|\.\d+)?)\*?pi(?:/(\d+\.?\d*))?$")


def _number(text: str, where: str, option: str) -> float:
    s = text.strip().lower()
    m = _PI.match(s)
    if m:
        factor = m.group(1)
        f = 1.0 if factor in ("", "+") else (-1.0 if factor == "-" else float(factor))
        value = f * math.pi / (float(m.group(2)) if m.group(2) else 1.0)
    else:
        try:
            value = float(s)
        except ValueError:
            raise ParameterError(f"{option}: {where}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise ParameterError(f"{option}: {where}: {text!r} is not finite")
    return value


def parse_grid(text: str, option: str = "grid") -> BasinGrid:
    """Parse a grid specification (`GRID_SYNTAX`); ``option`` names it in errors (``"--grid"`` on the
    command line).

    Raises
    ------
    ParameterError
        With a one-line message that names the faulty part and the forms allowed.
    """
    if not isinstance(text, str):
        raise ParameterError(f"{option} = {text!r} is not text; allowed: {_FORMS}")
    if not text.strip():
        raise ParameterError(f"{option} = {text!r} is empty; allowed: {_FORMS}")
    s = text.strip().replace(" ", "")
    short = re.fullmatch(r"(plane|shock):(.*)", s)
    if short:
        try:
            n = int(short.group(2))
        except ValueError:
            raise ParameterError(f"{option} = {text!r}: the count {short.group(2)!r} is not an integer") from None
        if n < 1:
            raise ParameterError(f"{option} = {text!r}: the count must be >= 1")
        if short.group(1) == "plane":
            return displacement_grid((-1.0, 1.0, n), (-1.0, 1.0, n))
        return shock_grid((0.0, 1.0, n), (-math.pi, math.pi, n))
    parts = s.split(",")
    axes: dict[str, tuple[float, float, int]] = {}
    for part in parts:
        if "=" not in part:
            raise ParameterError(f"{option} = {text!r}: {part!r} is not NAME=START:STOP:COUNT; allowed: {_FORMS}")
        name, spec = part.split("=", 1)
        if name not in ("x", "y", "amplitude", "direction"):
            raise ParameterError(
                f"{option} = {text!r}: unknown axis {name!r}; allowed: x, y (displacement) or amplitude, "
                "direction (shock)"
            )
        if name in axes:
            raise ParameterError(f"{option} = {text!r}: axis {name!r} given twice")
        fields_ = spec.split(":")
        if len(fields_) != 3:
            raise ParameterError(f"{option} = {text!r}: {part!r} is not NAME=START:STOP:COUNT; allowed: {_FORMS}")
        lo = _number(fields_[0], name, option)
        hi = _number(fields_[1], name, option)
        try:
            n = int(fields_[2])
        except ValueError:
            raise ParameterError(f"{option} = {text!r}: {name} count {fields_[2]!r} is not an integer") from None
        axes[name] = (lo, hi, n)
    if set(axes) == {"x", "y"}:
        return displacement_grid(axes["x"], axes["y"])
    if set(axes) == {"amplitude", "direction"}:
        return shock_grid(axes["amplitude"], axes["direction"])
    raise ParameterError(
        f"{option} = {text!r}: give both x and y, or both amplitude and direction; allowed: {_FORMS}"
    )

