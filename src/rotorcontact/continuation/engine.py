"""Pseudo-arclength continuation of a curve F(y) = 0 with event location.

The problem
-----------
``F: R^(n+1) -> R^n`` is smooth; its regular zeros form curves. A point of a
curve is ``y = (x, lambda)``: the unknowns and one parameter, although nothing
here treats the parameter specially except when an event's position is
reported. Folds of the curve in the parameter are ordinary points of the
continuation.

The method
----------
All work is done in scaled coordinates ``z = w * y`` (``weights`` w > 0), so
that components of different size count alike in the arclength.

* **Tangent.** The unit null vector t of the Jacobian F_y, oriented so that
  t . t_prev > 0: it solves the bordered system [F_y; t_prev^T] v = [0; 1].
* **Prediction.** z_pred = z_i + h t_i.
* **Correction.** Newton's method on the bordered system
  F(y) = 0, t_i . (z - z_i) = h, whose Jacobian [F_y; t_i^T] is regular at
  regular points of the curve, folds included.
* **Step control.** A step is accepted when Newton converges within
  ``max_newton`` iterations, the corrected point stays within ``max_drift * h``
  of the prediction and the tangent turns by less than ``max_angle``;
  otherwise h is halved. Quick convergence grows h by ``grow`` up to
  ``max_step``. The continuation stops when h falls below ``min_step``.
* **Bounds.** Every loop has an iteration cap (``max_points`` steps, at most
  ``max_newton`` Newton iterations per correction, ``max_location_iterations``
  per event, themselves bounded by `MAX_POINTS`, `MAX_NEWTON` and
  `MAX_LOCATION_ITERATIONS`), so the continuation always ends.

Events
------
An `EventFunction` g maps a point to a float (``kind="continuous"``) or to an
integer label (``kind="discrete"``), or to None where it is undefined. After
each accepted step, a sign change of a continuous g (or a change of a
discrete g) between the two end points is located on the curve: with the
step's start z_i and tangent t_i, the point at distance s is the corrected
point of the system F(y) = 0, t_i . (z - z_i) = s, and s is found by a
safeguarded secant method (Illinois steps, bisection whenever the bracket
does not halve) for a continuous g, or by bisection for a discrete one,
until the bracket is shorter than ``location_tol`` in the parameter. Each
trial point is re-corrected onto the curve. A continuous g that changes sign
through a pole is recognised (|g| at the located point is not below its
values at the bracket's ends) and flagged ``continuous=False``.

A *terminal* event ends the continuation at its located point; that is how
a domain boundary (a parameter bound, a bound on an unknown) is handled. A
terminal event that changes sign within a step but cannot be located (no trial
point can be corrected onto the curve: a singular point, such as where two
curves cross) ends the continuation at the step's start, inside the domain. A
start a rounding error outside a terminal event's domain (a seed on a parameter bound
that the scaling put just beyond it) counts as on its boundary: a first step further
out ends the continuation at the start. The rounding is that of the start's unknowns carried to the
event's value by its slopes, so an event's scale does not matter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Iterator, Literal, Sequence

import numpy as np

from ..errors import ParameterError
from ..model.validation import (
    check_bool,
    check_choice,
    check_float,
    check_int,
    check_type,
    finite_array,
    quoted,
    real_array,
    settings_or_default,
)

__all__ = [
    "ContinuationSettings",
    "EventFunction",
    "LocatedEvent",
    "ContinuationResult",
    "CorrectionError",
    "numerical_jacobian",
    "null_vector",
    "correct_fixed",
    "continue_curve",
    "TwoWayCurve",
    "continue_both_ways",
    "corrected_crossings",
    "MAX_POINTS",
    "MAX_NEWTON",
    "MAX_LOCATION_ITERATIONS",
    "MAX_GROW",
]

Residual = Callable[[np.ndarray], np.ndarray]
Jacobian = Callable[[np.ndarray], np.ndarray]


#: Most accepted steps of one continuation: each costs at least one residual and one Jacobian, and the
#: points are kept, so a million steps take many minutes and hundreds of megabytes.
MAX_POINTS = 10**6
#: Most Newton iterations per correction: Newton converges quadratically from a good prediction, within a
#: handful of iterations; one that has not converged after 100 is not converging.
MAX_NEWTON = 100
#: Most iterations locating one event: the bracket at least halves every three iterations, so 1000 shrink
#: it far below the resolution of a double.
MAX_LOCATION_ITERATIONS = 1000
#: Largest growth factor of the step after an easy step: a step grown more than tenfold at once leaves the
#: region where the turn of the tangent, which the step control measures, says anything about the next one.
MAX_GROW = 10.0


class CorrectionError(RuntimeError):
    """Newton's method did not converge onto the curve."""


class _ShapeError(ParameterError):
    """A residual or Jacobian returned an array of the wrong shape: bad input, not a point where it is undefined."""


def check_callable(name: str, value, allowed: str, *, optional: bool = False):
    """Return ``value`` if it is callable (or None where ``optional``), else raise `ParameterError`."""
    if (value is None and optional) or callable(value):
        return value
    raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: {allowed}{' or None' if optional else ''}")


def check_max_points(value, name: str = "max_points") -> int:
    """``value`` as a number of continuation steps, 1 to `MAX_POINTS`."""
    return check_int(name, value, 1, MAX_POINTS)


def _vector(name: str, value, length: int | None = None, min_length: int = 1) -> np.ndarray:
    """``value`` as a 1-d array of finite floats (of ``length``, or at least ``min_length``), else a
    `ParameterError` naming ``name``."""
    size = f"{length}" if length is not None else f"at least {min_length}"
    return finite_array(name, value, f"a vector of {size} finite numbers", min_rows=min_length, rows=length)


def _check_index(name: str, value, n: int) -> int:
    """``value`` as an index into a vector of ``n`` components (negative counts from the end)."""
    return check_int(name, value, -n, n - 1)


def _check_events(events) -> tuple:
    if not isinstance(events, (list, tuple)) or not all(isinstance(e, EventFunction) for e in events):
        raise ParameterError(f"events = {quoted(events)} is invalid; allowed: a list of EventFunction")
    return tuple(events)


@dataclass(frozen=True)
class ContinuationSettings:
    """Step control, Newton and event-location settings.

    Attributes
    ----------
    step : float
        First step length (scaled arclength).
    min_step, max_step : float
        Bounds of the step length.
    grow : float
        Factor by which the step grows after an easy step (> 1, at most `MAX_GROW`).
    max_points : int
        Largest number of accepted steps (1 to `MAX_POINTS`).
    max_newton : int
        Newton iterations per correction (1 to `MAX_NEWTON`).
    newton_tol : float
        Convergence when the Newton update is below ``newton_tol * (1 + |z|)``
        and the residual below ``residual_tol``.
    residual_tol : float
        Absolute residual accepted at convergence.
    max_angle : float
        Largest turn of the tangent over one step, in radians.
    max_drift : float
        Largest distance of the corrected point from the prediction, as a
        fraction of the step.
    location_tol : float
        Events are located until the bracket is shorter than this in the
        reported parameter.
    max_location_iterations : int
        Iteration cap of the event location (1 to `MAX_LOCATION_ITERATIONS`).
    fd_step : float
        Relative step of the central differences of `numerical_jacobian`.

    The lengths and tolerances are finite numbers > 0 (numpy's too, stored as floats), the counts
    integers, with min_step <= step <= max_step.

    Raises
    ------
    ParameterError
        Naming the first field that is not a number of its kind or lies outside its bounds.
    """

    step: float = 0.02
    min_step: float = 1e-8
    max_step: float = 0.1
    grow: float = 1.5
    max_points: int = 5000
    max_newton: int = 10
    newton_tol: float = 1e-13
    residual_tol: float = 1e-10
    max_angle: float = 0.3
    max_drift: float = 0.5
    location_tol: float = 1e-10
    max_location_iterations: int = 200
    fd_step: float = 1e-7

    def __post_init__(self) -> None:
        positive = ("step", "min_step", "max_step", "newton_tol", "residual_tol", "max_angle", "max_drift",
                    "location_tol", "fd_step")
        for name in positive:
            object.__setattr__(self, name, check_float(name, getattr(self, name), 0.0, low_open=True))
        object.__setattr__(self, "grow", check_float("grow", self.grow, 1.0, MAX_GROW, low_open=True))
        for name, high in (("max_points", MAX_POINTS), ("max_newton", MAX_NEWTON),
                           ("max_location_iterations", MAX_LOCATION_ITERATIONS)):
            object.__setattr__(self, name, check_int(name, getattr(self, name), 1, high))
        if not self.min_step <= self.step <= self.max_step:
            raise ParameterError(
                f"step = {self.step!r} is invalid; allowed: min_step <= step <= max_step "
                f"({self.min_step!r} .. {self.max_step!r})"
            )


@dataclass(frozen=True)
class EventFunction:
    """A function along the curve whose sign changes (or value changes) are events.

    Attributes
    ----------
    name : str
        Name reported with the located event.
    function : callable
        ``function(y) -> float | int | None`` at a point y of the curve
        (unscaled); None where undefined (no event is looked for across it).
    kind : {"continuous", "discrete"}
        ``"continuous"``: an event is a sign change (located by a safeguarded
        secant method). ``"discrete"``: an event is a change of value (the
        jump is located by bisection).
    terminal : bool
        The continuation stops at the located event.

    Raises
    ------
    ParameterError
        Unless ``name`` is text, ``function`` callable, ``kind`` one of the two and ``terminal`` True or False.
    """

    name: str
    function: Callable[[np.ndarray], float | int | None]
    kind: Literal["continuous", "discrete"] = "continuous"
    terminal: bool = False

    def __post_init__(self) -> None:
        check_type("name", self.name, str, "the name of the event (text)")
        check_callable("function", self.function, "a function of a point y of the curve")
        check_choice("kind", self.kind, ("continuous", "discrete"))
        object.__setattr__(self, "terminal", check_bool("terminal", self.terminal))


@dataclass(frozen=True)
class LocatedEvent:
    """An event located on the curve.

    Attributes
    ----------
    name : str
        Name of the event function.
    index : int
        The event lies between ``points[index]`` and ``points[index + 1]`` of
        the result (for a terminal event, ``points[index + 1]`` is the event
        point itself).
    y : numpy.ndarray
        The located point (on the curve).
    parameter : float
        ``y[param_index]``.
    value : float
        The event function at ``y``.
    before, after : float
        The event function at the two ends of the final bracket.
    y_before, y_after : numpy.ndarray
        The two ends of the final bracket (on the curve).
    bracket : float
        Length of the final bracket in the parameter.
    converged : bool
        The bracket reached ``location_tol`` in the parameter.
    continuous : bool
        For a continuous function: |g| decreased towards the located point
        (False at a sign change through a pole). Always True for a discrete one.
    terminal : bool
        The event ended the continuation.
    """

    name: str
    index: int
    y: np.ndarray = field(repr=False)
    parameter: float
    value: float
    before: float
    after: float
    y_before: np.ndarray = field(repr=False)
    y_after: np.ndarray = field(repr=False)
    bracket: float
    converged: bool
    continuous: bool
    terminal: bool = False


@dataclass(frozen=True)
class ContinuationResult:
    """A computed piece of a solution curve.

    Attributes
    ----------
    points : numpy.ndarray, shape (m, n + 1)
        Points along the curve, in order (unscaled).
    tangents : numpy.ndarray, shape (m, n + 1)
        Unit tangents (scaled coordinates) at the points, in the direction of travel.
    events : tuple of LocatedEvent
        In the order met.
    status : str
        ``"terminal"`` (a terminal event ended it), ``"closed"`` (the curve
        returned to its first point: a closed loop), ``"max-points"``,
        ``"step-failure"`` (the step fell below ``min_step``).
    message : str
        A human-readable account of why the continuation ended.
    param_index : int
        Index of the reported parameter in y.
    """

    points: np.ndarray = field(repr=False)
    tangents: np.ndarray = field(repr=False)
    events: tuple[LocatedEvent, ...]
    status: str
    message: str
    param_index: int = -1

    @property
    def parameter(self) -> np.ndarray:
        """The parameter along the curve."""
        return self.points[:, self.param_index]


# ---------------------------------------------------------------------------
# Linear algebra helpers
# ---------------------------------------------------------------------------


def numerical_jacobian(residual: Residual, y: np.ndarray, rel_step: float = 1e-7) -> np.ndarray:
    """Central-difference Jacobian of ``residual`` at ``y`` (steps ``rel_step * max(1, |y_j|)``).

    Parameters
    ----------
    residual : callable
        ``residual(y)``: a vector of m values.
    y : sequence of float
        The point, n finite numbers.
    rel_step : float
        Relative step, 0 < rel_step <= 1.

    Returns
    -------
    numpy.ndarray, shape (m, n)

    Raises
    ------
    ParameterError
        Unless ``residual`` is callable and returns a vector, ``y`` is a vector of finite numbers and
        ``rel_step`` lies in (0, 1].
    """
    check_callable("residual", residual, "a function of y returning a vector")
    y = _vector("y", y)
    rel_step = check_float("rel_step", rel_step, 0.0, 1.0, low_open=True)
    f0 = residual(y)
    values = real_array(f0)
    if values is None or values.ndim != 1:
        raise _ShapeError(f"residual = {quoted(residual)} is invalid; allowed: a function of y returning a vector of "
                          f"numbers (it returned {quoted(f0)})")
    return _numerical_jacobian(residual, y, rel_step, len(values))


def _returned(name: str, function, value, shape: tuple[int, ...]) -> np.ndarray:
    """``value``, what ``function`` returned, as a float array if it has ``shape``, else a `ParameterError`
    naming ``name``."""
    try:
        value = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        value = np.empty((0,) * (len(shape) + 1))  # not numbers: no shape of numbers
    if value.shape != shape:
        raise _ShapeError(f"{name} = {quoted(function)} is invalid; allowed: a function of y returning an array of "
                          f"shape {shape} (it returned shape {value.shape})")
    return value


def _numerical_jacobian(residual: Residual, y: np.ndarray, rel_step: float, m: int) -> np.ndarray:
    """`numerical_jacobian` of a residual of ``m`` values, its arguments unchecked."""
    jac = np.empty((m, y.shape[0]))
    for j in range(y.shape[0]):
        h = rel_step * max(1.0, abs(y[j]))
        yp = y.copy()
        ym = y.copy()
        yp[j] += h
        ym[j] -= h
        jac[:, j] = (_returned("residual", residual, residual(yp), (m,))
                     - _returned("residual", residual, residual(ym), (m,))) / (2.0 * h)
    return jac


def null_vector(jac: np.ndarray, reference: np.ndarray | None = None) -> np.ndarray:
    """Unit null vector of an n x (n + 1) matrix, oriented along ``reference`` (if given).

    Raises
    ------
    ParameterError
        Unless ``jac`` is an n x (n + 1) matrix of finite numbers (n >= 1) and ``reference`` None or a vector
        of n + 1 finite numbers.
    """
    matrix = real_array(jac)
    if (matrix is None or matrix.ndim != 2 or matrix.shape[0] < 1 or matrix.shape[1] != matrix.shape[0] + 1
            or not np.all(np.isfinite(matrix))):
        raise ParameterError(f"jac = {quoted(jac)} is invalid; allowed: an n x (n + 1) matrix of finite numbers")
    if reference is not None:
        reference = _vector("reference", reference, matrix.shape[1])
    return _null_vector(matrix, reference)


def _null_vector(jac: np.ndarray, reference: np.ndarray | None = None) -> np.ndarray:
    """`null_vector`, unchecked."""
    n1 = jac.shape[1]
    if reference is not None:
        border = np.vstack([jac, reference[None, :]])
        rhs = np.zeros(n1)
        rhs[-1] = 1.0
        try:
            v = np.linalg.solve(border, rhs)
            if np.all(np.isfinite(v)) and np.linalg.norm(v) > 0:
                v /= np.linalg.norm(v)
                return v if v @ reference >= 0 else -v
        except np.linalg.LinAlgError:
            pass
    _, _, vt = np.linalg.svd(jac)
    v = vt[-1]
    if reference is not None and v @ reference < 0:
        v = -v
    return v / np.linalg.norm(v)


# ---------------------------------------------------------------------------
# The scaled problem
# ---------------------------------------------------------------------------


class _Scaled:
    """F and F_y in scaled coordinates z = w * y, with failures as exceptions.

    F has one value fewer than y; a residual or Jacobian of another shape is refused by name (`_returned`).
    """

    def __init__(self, residual: Residual, jacobian: Jacobian | None, weights: np.ndarray, fd_step: float):
        self.residual = residual
        self.jacobian = jacobian
        self.w = weights
        self.fd_step = fd_step
        n = weights.shape[0]
        self.shapes = ((n - 1,), (n - 1, n))

    def y(self, z: np.ndarray) -> np.ndarray:
        return z / self.w

    def f(self, z: np.ndarray) -> np.ndarray:
        try:
            val = self.residual(self.y(z))
        except (ParameterError, ZeroDivisionError, OverflowError, ValueError) as exc:
            raise CorrectionError(f"residual undefined: {exc}") from None
        val = _returned("residual", self.residual, val, self.shapes[0])
        if not np.all(np.isfinite(val)):
            raise CorrectionError("residual not finite")
        return val

    def jac(self, z: np.ndarray) -> np.ndarray:
        y = self.y(z)
        try:
            if self.jacobian is not None:
                j = _returned("jacobian", self.jacobian, self.jacobian(y), self.shapes[1])
            else:
                j = _numerical_jacobian(self.residual, y, self.fd_step, self.shapes[0][0])
        except _ShapeError:
            raise
        except (ParameterError, ZeroDivisionError, OverflowError, ValueError) as exc:
            raise CorrectionError(f"Jacobian undefined: {exc}") from None
        if not np.all(np.isfinite(j)):
            raise CorrectionError("Jacobian not finite")
        return j / self.w[None, :]


def _newton(prob: _Scaled, z: np.ndarray, t: np.ndarray, z_base: np.ndarray, s: float,
            settings: ContinuationSettings) -> tuple[np.ndarray, int]:
    """Correct z onto F = 0 with t . (z - z_base) = s. Returns (z, iterations)."""
    z = z.copy()
    last = math.inf
    for it in range(1, settings.max_newton + 1):
        f = prob.f(z)
        g = np.append(f, t @ (z - z_base) - s)
        j = np.vstack([prob.jac(z), t[None, :]])
        try:
            dz = np.linalg.solve(j, -g)
        except np.linalg.LinAlgError:
            raise CorrectionError("singular bordered Jacobian") from None
        if not np.all(np.isfinite(dz)):
            raise CorrectionError("Newton update not finite")
        z = z + dz
        size = float(np.linalg.norm(dz))
        if size > 4.0 * last and it > 2:
            raise CorrectionError("Newton diverging")
        last = size
        if size <= settings.newton_tol * (1.0 + float(np.linalg.norm(z))):
            if float(np.max(np.abs(prob.f(z)))) <= settings.residual_tol:
                return z, it
    f = prob.f(z)
    if float(np.max(np.abs(f))) <= settings.residual_tol and last <= 1e3 * settings.newton_tol * (
        1.0 + float(np.linalg.norm(z))
    ):
        return z, settings.max_newton
    raise CorrectionError(f"Newton did not converge in {settings.max_newton} iterations")


def correct_fixed(
    residual: Residual,
    y: Sequence[float],
    index: int,
    *,
    jacobian: Jacobian | None = None,
    settings: ContinuationSettings | None = None,
) -> np.ndarray:
    """Newton's method for F(y) = 0 with the component ``y[index]`` held fixed.

    Parameters
    ----------
    residual : callable
        F: R^(n+1) -> R^n.
    y : sequence of float
        Starting point; ``y[index]`` keeps its value.
    index : int
        The fixed component.
    jacobian : callable, optional
        F_y (n x (n + 1)); central differences when omitted.
    settings : ContinuationSettings, optional

    Returns
    -------
    numpy.ndarray
        The corrected point.

    Raises
    ------
    CorrectionError
        When Newton's method does not converge.
    ParameterError
        Unless ``residual`` (and ``jacobian``) are callable and return arrays of the shapes above, ``y`` is a
        vector of at least two finite numbers, ``index`` an index into it and ``settings`` a
        `ContinuationSettings` or None.
    """
    settings = _check_problem(residual, jacobian, settings)
    y = _vector("y", y, min_length=2)
    return _correct_fixed(residual, y, _check_index("index", index, len(y)), jacobian, settings)


def _correct_fixed(residual: Residual, y: np.ndarray, index: int, jacobian: Jacobian | None,
                   settings: ContinuationSettings) -> np.ndarray:
    """`correct_fixed`, its arguments unchecked."""
    e = np.zeros_like(y)
    e[index] = 1.0
    prob = _Scaled(residual, jacobian, np.ones_like(y), settings.fd_step)
    z, _ = _newton(prob, y, e, y, 0.0, settings)
    return z


def _check_problem(residual, jacobian, settings) -> ContinuationSettings:
    """The checks shared by the entry points: F and F_y callable, and the settings (default where None)."""
    check_callable("residual", residual, "a function F(y) returning a vector of one value fewer than y")
    check_callable("jacobian", jacobian, "a function F_y(y) returning an n x (n + 1) array", optional=True)
    return settings_or_default(settings, ContinuationSettings, ContinuationSettings)


# ---------------------------------------------------------------------------
# Event location
# ---------------------------------------------------------------------------


def _sign_change(kind: str, a, b) -> bool:
    """Whether an event lies between two values of an event function (0 counts as positive)."""
    if a is None or b is None:
        return False
    if kind == "discrete":
        return a != b
    return (a < 0) != (b < 0)


class _Locator:
    """Points on the curve at distance s along the step's tangent, with a cache."""

    def __init__(self, prob: _Scaled, z0: np.ndarray, t0: np.ndarray, z1: np.ndarray, s1: float,
                 settings: ContinuationSettings):
        self.prob = prob
        self.z0 = z0
        self.t0 = t0
        self.z1 = z1
        self.s1 = s1
        self.settings = settings
        self.cache: dict[float, np.ndarray] = {0.0: z0, s1: z1}

    def point(self, s: float) -> np.ndarray:
        if s in self.cache:
            return self.cache[s]
        # predictor: linear interpolation between the corrected ends (second order along the chord)
        frac = s / self.s1 if self.s1 != 0 else 0.0
        guess = self.z0 + frac * (self.z1 - self.z0)
        z, _ = _newton(self.prob, guess, self.t0, self.z0, s, self.settings)
        self.cache[s] = z
        return z


def _locate(
    ev: EventFunction,
    loc: _Locator,
    g0: float,
    g1: float,
    param_index: int,
    weight: float,
    settings: ContinuationSettings,
) -> tuple[float, np.ndarray, float, np.ndarray, float, np.ndarray, float, bool, bool] | None:
    """Locate the event of ``ev`` in s in [0, s1]. Returns None if a trial point fails."""
    prob = loc.prob
    discrete = ev.kind == "discrete"

    def value(s: float):
        z = loc.point(s)
        return ev.function(prob.y(z)), z

    a, b = 0.0, loc.s1
    fa, fb = g0, g1
    if not discrete and g0 == 0:
        y_start = prob.y(loc.z0)
        return 0.0, y_start, 0.0, y_start, 0.0, y_start, 0.0, True, True
    za, zb = loc.z0, loc.z1
    side = 0
    width = abs(b - a)
    converged = False
    for it in range(settings.max_location_iterations):
        lam_gap = abs(prob.y(zb)[param_index] - prob.y(za)[param_index])
        if lam_gap <= settings.location_tol and abs(b - a) * (1.0 / weight) <= 1e3 * settings.location_tol:
            converged = True
            break
        if abs(b - a) <= 1e-15 * (1.0 + abs(a) + abs(b)):
            converged = lam_gap <= settings.location_tol
            break
        if discrete or it % 3 == 2 and abs(b - a) > 0.5 * width:
            c = 0.5 * (a + b)
        else:
            c = b - fb * (b - a) / (fb - fa) if fb != fa else 0.5 * (a + b)
            lo, hi = min(a, b), max(a, b)
            margin = 1e-3 * (hi - lo)
            if not lo + margin < c < hi - margin:
                c = min(max(c, lo + margin), hi - margin)
        if it % 3 == 0:
            width = abs(b - a)
        try:
            fc, zc = value(c)
        except CorrectionError:
            return None
        if fc is None:
            # undefined inside the bracket: fall back to bisection towards a defined side
            c = 0.5 * (a + b)
            try:
                fc, zc = value(c)
            except CorrectionError:
                return None
            if fc is None:
                return None
        if discrete:
            if fc == fa:
                a, fa, za = c, fc, zc
            else:
                b, fb, zb = c, fc, zc
            continue
        if fc == 0.0:
            a, b, fa, fb, za, zb = c, c, fc, fc, zc, zc
            converged = True
            break
        if (fc < 0) == (fa < 0):
            a, fa, za = c, fc, zc
            if side == -1:
                fb *= 0.5
            side = -1
        else:
            b, fb, zb = c, fc, zc
            if side == 1:
                fa *= 0.5
            side = 1
    # Illinois scaling changed fa/fb: re-evaluate the ends for reporting
    ya, yb = prob.y(za), prob.y(zb)
    ga = ev.function(ya)
    gb = ev.function(yb)
    if discrete:
        z_best = 0.5 * (za + zb)
        try:
            s_mid = float(loc.t0 @ (z_best - loc.z0))
            z_best = loc.point(s_mid)
        except CorrectionError:
            z_best = za
        gv = ev.function(prob.y(z_best))
        continuous = True
    else:
        if ga is None or gb is None:
            return None
        z_best = za if abs(ga) <= abs(gb) else zb
        if za is not zb and ga != gb:
            # secant estimate between the final bracket ends
            sa = float(loc.t0 @ (za - loc.z0))
            sb = float(loc.t0 @ (zb - loc.z0))
            s_est = sa - ga * (sb - sa) / (gb - ga)
            if min(sa, sb) < s_est < max(sa, sb):
                try:
                    z_est = loc.point(s_est)
                    g_est = ev.function(prob.y(z_est))
                    if g_est is not None and abs(g_est) <= min(abs(ga), abs(gb)):
                        z_best = z_est
                except CorrectionError:
                    pass
        gv = ev.function(prob.y(z_best))
        # through a pole |g| grows at the sign change; at a root it falls, if not below an end a rounding
        # error from 0 (a start on the bound), then far below the other
        continuous = gv is not None and (abs(gv) < min(abs(g0), abs(g1))
                                         or abs(gv) <= 1e-6 * max(abs(g0), abs(g1)))
    lam_gap = abs(yb[param_index] - ya[param_index])
    converged = converged or lam_gap <= settings.location_tol
    return (
        float(gv) if gv is not None else math.nan,
        prob.y(z_best),
        float(ga) if ga is not None else math.nan,
        ya,
        float(gb) if gb is not None else math.nan,
        yb,
        lam_gap,
        converged,
        continuous,
    )


# ---------------------------------------------------------------------------
# The continuation
# ---------------------------------------------------------------------------


def _check_direction(direction, n: int) -> float | np.ndarray:
    """``direction`` as a sign (+1.0 or -1.0) if it is a number, or as a vector of ``n`` values."""
    v = real_array(direction)
    if v is not None and v.ndim == 0 and np.isfinite(v) and v != 0:
        return 1.0 if v > 0 else -1.0
    if v is not None and v.shape == (n,) and np.all(np.isfinite(v)) and np.any(v != 0):
        return v
    raise ParameterError(f"direction = {quoted(direction)} is invalid; allowed: a finite number other than 0 (the "
                         f"sign of the first change of the last component) or a vector of {n} finite numbers, "
                         "not all 0")


def _initial_tangent(prob: _Scaled, z0: np.ndarray, direction: float | np.ndarray) -> np.ndarray:
    t = _null_vector(prob.jac(z0))
    if isinstance(direction, float):
        if t[-1] * direction < 0 or (t[-1] == 0 and direction < 0):
            t = -t
        return t
    ref = direction * prob.w
    if t @ ref < 0:
        t = -t
    return t


def _within_rounding_outside(event: EventFunction, y: np.ndarray, g: float | int | None) -> bool:
    """Whether a terminal event's value g < 0 at y is within the rounding error of y: 16 eps (1 + |y_j|) in
    each unknown, carried to g by its slopes (one-sided differences), so that the test is in g's own scale."""
    if not (event.terminal and event.kind == "continuous" and g is not None and g < 0):
        return False
    eps = np.finfo(float).eps
    spread = 0.0
    for j in range(y.size):
        step = math.sqrt(eps) * (1.0 + abs(y[j]))
        shifted = y.copy()
        shifted[j] += step
        g_shifted = event.function(shifted)
        if g_shifted is None:
            return False
        spread += abs(g_shifted - g) / step * 16.0 * eps * (1.0 + abs(y[j]))
    return -g <= spread


def continue_curve(
    residual: Residual,
    y0: Sequence[float],
    *,
    jacobian: Jacobian | None = None,
    direction: float | Sequence[float] = 1.0,
    events: Sequence[EventFunction] = (),
    settings: ContinuationSettings | None = None,
    weights: Sequence[float] | None = None,
    param_index: int = -1,
    correct_start: bool = True,
) -> ContinuationResult:
    """Follow the curve F(y) = 0 through ``y0`` by pseudo-arclength continuation.

    Parameters
    ----------
    residual : callable
        F: R^(n+1) -> R^n. It may raise `ParameterError` (or return non-finite
        values) where undefined; such points are treated as failed steps.
    y0 : sequence of float
        A point on (or close to) the curve.
    jacobian : callable, optional
        F_y, an n x (n + 1) array; central differences when omitted.
    direction : float or sequence of float
        A number other than 0: the sign of the last component of the first
        tangent (+1: the last component increases). A vector (not all 0): the
        first tangent points along it.
    events : list of EventFunction
        Functions whose sign changes (or value changes) are located.
    settings : ContinuationSettings, optional
    weights : sequence of float, optional
        Scale factors w of the components (arclength is measured in w * y).
    param_index : int
        Component reported as the parameter of the located events, and in
        which ``location_tol`` is measured (negative counts from the end).
    correct_start : bool
        Correct ``y0`` onto the curve first (holding the component
        ``param_index`` fixed).

    Returns
    -------
    ContinuationResult

    Raises
    ------
    ParameterError
        Naming the first argument that is not of the kind above: ``residual`` or ``jacobian`` not callable
        (or returning arrays of other shapes), ``y0`` not a vector of at least two finite numbers,
        ``direction`` 0 or not finite, ``events`` not a list of `EventFunction`, ``weights`` not positive,
        ``param_index`` not an index into y0, ``correct_start`` not True or False.
    CorrectionError
        When ``y0`` cannot be corrected onto the curve, or no tangent is found there.
    """
    settings = _check_problem(residual, jacobian, settings)
    y0 = _vector("y0", y0, min_length=2)
    n = y0.shape[0]
    direction = _check_direction(direction, n)
    events = _check_events(events)
    w = np.ones_like(y0) if weights is None else real_array(weights)
    if w is None or w.shape != y0.shape or not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise ParameterError(f"weights = {quoted(weights)} is invalid; allowed: {n} finite numbers > 0 or None")
    pidx = _check_index("param_index", param_index, n) % n
    correct_start = check_bool("correct_start", correct_start)
    prob = _Scaled(residual, jacobian, w, settings.fd_step)
    z0 = w * y0
    if correct_start:
        e = np.zeros_like(z0)
        e[pidx] = 1.0
        z0, _ = _newton(prob, z0, e, z0, 0.0, settings)
    t0 = _initial_tangent(prob, z0, direction)

    zs = [z0]
    ts = [t0]
    # a start a rounding error outside the domain of a terminal event (a seed on the boundary of a box, put
    # beyond it by the scaling or the correction) is taken as on its boundary: heading out, the curve ends
    # at once; a value further below 0 is a sign the continuation is to watch change (a fold's slope)
    y_start = prob.y(z0)
    gvals = [ev.function(y_start) for ev in events]
    gvals = [0.0 if _within_rounding_outside(ev, y_start, g) else g for ev, g in zip(events, gvals)]
    located: list[LocatedEvent] = []
    h = settings.step
    status, message = "max-points", f"stopped after {settings.max_points} steps"
    z, t = z0, t0
    far_from_start = False
    for _step in range(settings.max_points):
        # one accepted step, with halving on failure
        accepted = False
        while h >= settings.min_step:
            try:
                z_new, iters = _newton(prob, z + h * t, t, z, h, settings)
                t_new = _null_vector(prob.jac(z_new), t)
            except CorrectionError:
                h *= 0.5
                continue
            drift = float(np.linalg.norm(z_new - (z + h * t)))
            angle = math.acos(max(-1.0, min(1.0, float(t_new @ t))))
            if drift > settings.max_drift * h or angle > settings.max_angle:
                h *= 0.5
                continue
            accepted = True
            break
        if not accepted:
            status = "step-failure"
            message = f"step fell below min_step = {settings.min_step:g} at y = {prob.y(z).tolist()}"
            break
        step_taken = h
        if iters <= 3 and angle < 0.5 * settings.max_angle:
            h = min(h * settings.grow, settings.max_step)

        # events on this step
        g_new = [ev.function(prob.y(z_new)) for ev in events]
        changes = [i for i, ev in enumerate(events) if _sign_change(ev.kind, gvals[i], g_new[i])]
        step_events: list[tuple[float, LocatedEvent]] = []
        unlocated_end = None  # a terminal event that changed sign but could not be located on the curve
        if changes:
            loc = _Locator(prob, z, t, z_new, step_taken, settings)
            for i in changes:
                ev = events[i]
                res = _locate(ev, loc, gvals[i], g_new[i], pidx, w[pidx], settings)
                if res is None:
                    if ev.terminal and unlocated_end is None:
                        unlocated_end = ev.name
                    continue
                gv, y_ev, ga, ya, gb, yb, gap, conv, cont = res
                s_ev = float(t @ (w * y_ev - z))
                step_events.append(
                    (
                        s_ev,
                        LocatedEvent(
                            name=ev.name,
                            index=len(zs) - 1,
                            y=y_ev,
                            parameter=float(y_ev[pidx]),
                            value=gv,
                            before=ga,
                            after=gb,
                            y_before=ya,
                            y_after=yb,
                            bracket=gap,
                            converged=conv,
                            continuous=cont,
                            terminal=ev.terminal,
                        ),
                    )
                )
        step_events.sort(key=lambda item: item[0])
        terminal = next((item for item in step_events if item[1].terminal and item[1].continuous), None)
        if terminal is None and unlocated_end is not None:
            # the curve leaves its domain within this step, where no trial point could be corrected (a
            # singular point such as a crossing of curves): it ends at the step's start, inside
            status = "terminal"
            message = (f"terminal event {unlocated_end!r} between parameter {prob.y(z)[pidx]:.12g} and "
                       f"{prob.y(z_new)[pidx]:.12g} (not located: the curve is singular there)")
            break
        if terminal is not None:
            s_term = terminal[0]
            # events at the terminal point itself (within the location accuracy) belong to this piece
            slack = 1e3 * settings.location_tol * float(w[pidx]) + 1e-12
            located.extend(e for s, e in step_events if s <= s_term + slack and e is not terminal[1])
            located.append(terminal[1])
            z_end = w * terminal[1].y
            zs.append(z_end)
            ts.append(_null_vector(prob.jac(z_end), t))
            status = "terminal"
            message = f"terminal event {terminal[1].name!r} at parameter {terminal[1].parameter:.12g}"
            break
        located.extend(e for s, e in step_events)

        # closed loop: the step passes the first point again
        dist0 = float(np.linalg.norm(z_new - z0))
        if dist0 > 4.0 * max(h, step_taken):
            far_from_start = True
        if far_from_start and len(zs) > 3:
            seg = z_new - z
            u = float(np.clip((z0 - z) @ seg / (seg @ seg), 0.0, 1.0))
            if np.linalg.norm(z + u * seg - z0) < 0.1 * step_taken and t @ t0 > 0.9:
                zs.append(z0)
                ts.append(t0)
                status = "closed"
                message = "the curve closed on its first point"
                break

        zs.append(z_new)
        ts.append(t_new)
        gvals = g_new
        z, t = z_new, t_new

    points = np.array([prob.y(zz) for zz in zs])
    return ContinuationResult(
        points=points,
        tangents=np.array(ts),
        events=tuple(located),
        status=status,
        message=message,
        param_index=pidx,
    )


# ---------------------------------------------------------------------------
# Both directions from a seed, and the seeds a computed curve meets
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class TwoWayCurve:
    """The continuation of one seed in both directions.

    Attributes
    ----------
    runs : tuple of ContinuationResult
        The runs that started, in the order tried: the run in the direction
        ``+1`` first, then the one in ``-1``; the second is missing when the
        first closed on its start (a loop) or when one could not start.
    points : numpy.ndarray
        The whole curve: the second run reversed, then the first one (their
        shared start once).
    """

    runs: tuple[ContinuationResult, ...]
    points: np.ndarray = field(repr=False)

    @property
    def messages(self) -> tuple[str, ...]:
        """Why each run ended, in the order of `runs`."""
        return tuple(r.message for r in self.runs)

    @property
    def events(self) -> tuple[LocatedEvent, ...]:
        """The located events of the runs, in the order of `runs`."""
        return tuple(e for r in self.runs for e in r.events)


def continue_both_ways(
    residual: Residual,
    y0: Sequence[float],
    *,
    jacobian: Jacobian | None = None,
    events: Sequence[EventFunction] = (),
    settings: ContinuationSettings | None = None,
    weights: Sequence[float] | None = None,
    param_index: int = -1,
    correct_start: bool = True,
) -> TwoWayCurve | None:
    """Follow the curve through ``y0`` in both directions, and join the two runs.

    `continue_curve` is run with ``direction=+1`` and then ``direction=-1``
    (skipped when the first run closed on its start: the loop is complete). A
    direction whose start fails to correct is left out.

    Parameters
    ----------
    residual, y0, jacobian, events, settings, weights, param_index, correct_start
        As in `continue_curve`.

    Returns
    -------
    TwoWayCurve or None
        None when neither run could start.

    Raises
    ------
    ParameterError
        As `continue_curve`.
    """
    runs: list[ContinuationResult] = []
    for direction in (1.0, -1.0):
        try:
            res = continue_curve(residual, y0, jacobian=jacobian, direction=direction, events=events,
                                 settings=settings, weights=weights, param_index=param_index,
                                 correct_start=correct_start)
        except CorrectionError:
            continue
        runs.append(res)
        if res.status == "closed":
            break
    if not runs:
        return None
    if len(runs) == 2:
        points = np.vstack([runs[1].points[::-1], runs[0].points[1:]])
    else:
        points = runs[0].points
    return TwoWayCurve(runs=tuple(runs), points=points)


def corrected_crossings(
    residual: Residual,
    points: np.ndarray,
    index: int,
    value: float,
    *,
    jacobian: Jacobian | None = None,
    settings: ContinuationSettings | None = None,
) -> Iterator[np.ndarray]:
    """The points where a computed curve meets the hyperplane ``y[index] = value``, corrected onto the curve.

    Points of ``points`` within 1e-9 (relative) of the hyperplane come first,
    then the linear interpolations across each segment that crosses it; each
    is put on the hyperplane and corrected with `correct_fixed` (holding
    ``y[index]``). A guess whose correction fails is yielded uncorrected. The
    points are produced one at a time, so a caller that stops early corrects
    no more than it uses.

    Parameters
    ----------
    residual : callable
        F of the curve.
    points : numpy.ndarray, shape (m, n + 1)
        The computed curve.
    index : int
        The component held (negative counts from the end).
    value : float
        Its value on the hyperplane.
    jacobian : callable, optional
    settings : ContinuationSettings, optional

    Yields
    ------
    numpy.ndarray

    Raises
    ------
    ParameterError
        At the call, before any point is yielded: unless ``residual`` (and ``jacobian``) are callable,
        ``points`` is an (m, n + 1) array of numbers (m >= 1, n >= 1), ``index`` an index into a point,
        ``value`` a finite number and ``settings`` a `ContinuationSettings` or None.
    """
    settings = _check_problem(residual, jacobian, settings)
    pts = real_array(points)
    if pts is None or pts.ndim != 2 or pts.shape[0] < 1 or pts.shape[1] < 2:
        raise ParameterError(f"points = {quoted(points)} is invalid; allowed: an (m, n + 1) array of numbers, "
                             "the points of a curve")
    index = _check_index("index", index, pts.shape[1]) % pts.shape[1]
    value = check_float("value", value)
    return _crossings(residual, pts, index, value, jacobian, settings)


def _crossings(residual: Residual, points: np.ndarray, index: int, value: float, jacobian: Jacobian | None,
               settings: ContinuationSettings) -> Iterator[np.ndarray]:
    """`corrected_crossings`, its arguments checked (``index`` >= 0)."""
    lam = points[:, index]
    near = np.abs(lam - value) <= 1e-9 * (1.0 + abs(value))
    side = np.where(near, 0.0, np.sign(lam - value))
    guesses = [points[j].copy() for j in np.flatnonzero(near)]
    for j in np.flatnonzero(side[:-1] * side[1:] < 0):
        a, b = points[j], points[j + 1]
        guesses.append(a + (value - a[index]) / (b[index] - a[index]) * (b - a))
    for guess in guesses:
        guess[index] = value
        try:
            yield _correct_fixed(residual, guess, index, jacobian, settings)
        except CorrectionError:
            yield guess
