"""Branches of periodic orbits with p >= 2 impacts per period, and all such orbits at given parameters.

Continuation
------------
`continue_multi_impact` follows an orbit of `rotorcontact.maps.multi_impact`
(a fixed point of P_I^p) in one parameter with the pseudo-arclength
continuation of `rotorcontact.continuation.engine` (folds are passed), on the
unknowns (x_0, ..., x_{p-1}, lambda), and locates the events of MODEL.md §5
along the branch with the test functions of one-impact branches
(`rotorcontact.continuation.events`), of the Jacobian M of P_I^p: det(M - I)
(a ``fold`` where the parameter turns over the step, a ``branch-point``
otherwise), det(M + I) (``period-doubling``) and the bialternate product
(``neimark-sacker`` where a complex pair is on the unit circle); a turning of
the parameter that no zero of det(M - I) explains is still a fold. Also
grazing of an interior maximum of r (terminal: P_I is discontinuous there) and
a change of the slipping condition. A period-doubled branch followed back to
the doubling it was born at passes through a pitchfork of P_I^p and would come
back along the same orbits with their points shifted by p/2; the
continuation stops there (status ``"period-doubling"``) and reports it.

All orbits
----------
`multi_impact_orbits` combines the stable orbits found by long simulations
(`rotorcontact.maps.multi_impact.orbits_from_simulation`) with, for p = 2,
the period-doubled branch of each one-impact orbit whose multiplier has
passed -1, continued from the period doubling to the given parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Sequence

import numpy as np

from ..errors import ParameterError
from ..maps.impact_map import (SLIP_BOUNDED, ImpactOrbit, _check_t_max, flight_extrema, one_impact_orbits,
                               searchable_t_max)
from ..maps.multi_impact import (
    MAX_GRID_POINTS,
    MAX_ORBIT_IMPACTS,
    MAX_STARTS,
    NEWTON_TOL,
    MultiImpactOrbit,
    NewtonFailure,
    _build_orbit,
    _chain,
    _check_parameter,
    _has_real_flip,
    _MapFailure,
    _newton,
    _relabel,
    _same_orbit,
    check_starts,
    find_period_doubling,
    multipliers_at,
    orbits_from_grid,
    orbits_from_simulation,
    period_doubled_orbit,
    periodic_residual,
    solve_multi_impact,
)
from ..model.params import Parameters, check_range
from ..model.validation import check_bool, check_float, check_int, check_params, check_type, quoted
from .engine import (
    ContinuationSettings,
    CorrectionError,
    EventFunction,
    check_max_points,
    continue_curve,
)
from .events import MultiplierTests, multiplier_kind, rotation_angle
from .results import BranchEvent, BranchResult, check_param_value

__all__ = [
    "BranchEvent",
    "MultiImpactBranch",
    "continue_multi_impact",
    "multi_impact_orbits",
    "PARAMETER_WEIGHT",
    "GRAZING_MARGIN",
    "MAX_STEP",
    "MAX_STARTS",
    "MAX_SCAN_WIDTH",
]

#: Weight of the parameter in the arclength (the unknowns are of order one), so that steps move it.
PARAMETER_WEIGHT = 100.0
#: A failed step with an interior maximum of r within this of 1, or an impact velocity below it, is reported as a
#: grazing.
GRAZING_MARGIN = 1e-2
#: How close a multiplier must be to +-1 or to the unit circle at a located test-function zero.
MULTIPLIER_TOL = 1e-6
#: The branch's own period doubling is looked for while max |x_0 - x_{p/2}| is below this.
HALF_PERIOD_MARGIN = 0.05
#: Across its own period doubling x_0 - x_{p/2} of a branch reverses: the cosine of its two sides' angle is
#: below minus this.
PITCHFORK_COSINE = 0.8
#: Smallest step of the scaled arclength of `continue_multi_impact`, below which a step counts as failed.
MIN_STEP = 1e-9
#: Largest step of the scaled arclength of `continue_multi_impact`: the unknowns are of order one (angles in
#: radians, velocities in clearances per unit time) and the parameter weighted by `PARAMETER_WEIGHT`, so a
#: step of 1 already moves a state by a radian or the parameter by 0.01, beyond where the predictor holds.
MAX_STEP = 1.0
#: Widest gamma window of `multi_impact_orbits` in which a period doubling is looked for: gamma of a
#: rotor is of order 0.1 (`rotorcontact.continuation.branches.DEFAULT_RANGES`), and the doubled branch is
#: continued across the window.
MAX_SCAN_WIDTH = 1.0


def check_grid(grid) -> tuple[int, int, int] | None:
    """``grid`` as three ints (each >= 1, a product of at most `MAX_GRID_POINTS`), or None.

    The shape of the grid of impact states of `rotorcontact.maps.multi_impact.orbits_from_grid`.
    """
    if grid is None:
        return None
    allowed = f"three integers >= 1 with a product of at most {MAX_GRID_POINTS}, or None"
    listed = isinstance(grid, (list, tuple)) or (isinstance(grid, np.ndarray) and grid.ndim == 1)
    if not listed or len(grid) != 3:
        raise ParameterError(f"grid = {quoted(grid)} is invalid; allowed: {allowed}")
    shape = tuple(check_int(f"grid[{i}]", n, 1, MAX_GRID_POINTS) for i, n in enumerate(grid))
    if math.prod(shape) > MAX_GRID_POINTS:
        raise ParameterError(f"grid = {quoted(grid)} is invalid; allowed: {allowed}")
    return shape


def check_orbit(orbit) -> MultiImpactOrbit:
    """``orbit`` if it is a `MultiImpactOrbit`, else a `ParameterError` naming it."""
    return check_type("orbit", orbit, MultiImpactOrbit, "a rotorcontact.maps.multi_impact.MultiImpactOrbit")


@dataclass(frozen=True)
class MultiImpactBranch(BranchResult):
    """A continued branch of orbits with p impacts per period.

    Attributes
    ----------
    param : str
        The continuation parameter.
    events : tuple of BranchEvent
        Located events: ``kind`` ``"fold"``, ``"branch-point"``,
        ``"period-doubling"``, ``"neimark-sacker"`` (module docstring),
        ``"grazing"`` (an interior maximum of r reaches 1) or ``"slip"`` (the
        slipping condition changes); ``orbit`` the orbit there (None where it
        could not be built), ``impacts`` p.
    values : numpy.ndarray
        The parameter along the branch.
    orbits : tuple of MultiImpactOrbit
        The orbits at those values.
    status, message : str
        How the continuation ended: the statuses of
        `rotorcontact.continuation.engine.ContinuationResult`, ``"grazing"`` when
        the steps failed with an interior maximum of r within
        `GRAZING_MARGIN` of 1, or ``"period-doubling"`` when the branch
        returned onto the orbit it doubles from.
    """

    values: np.ndarray = field(repr=False)
    orbits: tuple[MultiImpactOrbit, ...] = field(repr=False)
    status: str
    message: str

    @property
    def parameter(self) -> str:
        """`param` (its former name)."""
        return self.param  # type: ignore[return-value]

    def curves_dict(self) -> dict[str, dict[str, list]]:
        """The branch under its label: the parameter, the period, stability and plausibility along it."""
        label = self.orbits[0].label if self.orbits else ""
        return {label: {self.param: [float(v) for v in self.values],
                        "period": [o.period for o in self.orbits],
                        "stable": [o.stable for o in self.orbits],
                        "plausible": [o.plausible for o in self.orbits]}}


class _System(MultiplierTests):
    """(x_0 .. x_{p-1}, lambda) -> G as a continuation problem."""

    def __init__(self, base: Parameters, param: str, p: int, fd_step: float = 1e-7,
                 start: np.ndarray | None = None):
        self.base = base
        self.param = param
        self.p = p
        self.fd_step = fd_step
        self._mult: dict[bytes, np.ndarray | None] = {}
        self.direction_half = None
        if start is not None and p % 2 == 0:
            diff = start[0] - start[p // 2]
            diff[0] = math.remainder(diff[0], 2.0 * math.pi)
            if np.linalg.norm(diff) > 0:
                self.direction_half = diff / np.linalg.norm(diff)

    def params_at(self, value: float) -> Parameters:
        return self.base.replace(**{self.param: float(value)})

    def residual(self, y: np.ndarray) -> np.ndarray:
        return periodic_residual(self.params_at(y[-1]), y[:-1].reshape(self.p, 3))[0]

    def jacobian(self, y: np.ndarray) -> np.ndarray:
        lam = float(y[-1])
        x = y[:-1].reshape(self.p, 3)
        _res, jx = periodic_residual(self.params_at(lam), x)
        h = self.fd_step * max(1.0, abs(lam))
        rp = periodic_residual(self.params_at(lam + h), x)[0]
        rm = periodic_residual(self.params_at(lam - h), x)[0]
        return np.column_stack([jx, (rp - rm) / (2.0 * h)])

    def orbit(self, y: np.ndarray, label: str) -> MultiImpactOrbit:
        params = self.params_at(y[-1])
        x = y[:-1].reshape(self.p, 3).copy()
        try:
            x = _newton(params, x, NEWTON_TOL, 8)
        except NewtonFailure:
            pass
        return _build_orbit(params, x, label)

    def multipliers(self, y: np.ndarray) -> np.ndarray | None:
        """Eigenvalues of the Jacobian of P_I^p at the point y (cached; None where the map fails)."""
        key = np.asarray(y, dtype=float).tobytes()
        if key in self._mult:
            return self._mult[key]
        try:
            z = multipliers_at(self.params_at(y[-1]), y[:-1].reshape(self.p, 3))
        except (_MapFailure, ParameterError):
            z = None
        if len(self._mult) > 20000:
            self._mult.clear()
        self._mult[key] = z
        return z

    def half_difference(self, y: np.ndarray) -> np.ndarray | None:
        """x_0 - x_{p/2} (the angle's difference wrapped) near the orbit of p/2 impacts that this one doubles:
        None where a component exceeds `HALF_PERIOD_MARGIN`, or p is odd."""
        if self.p % 2 or self.direction_half is None:
            return None
        x = y[:-1].reshape(self.p, 3)
        diff = x[0] - x[self.p // 2]
        diff[0] = math.remainder(diff[0], 2.0 * math.pi)
        return None if np.max(np.abs(diff)) > HALF_PERIOD_MARGIN else diff

    def asymmetry(self, y: np.ndarray) -> float | None:
        """e . (x_0 - x_{p/2}) near the orbit of p/2 impacts that this one doubles (None elsewhere, or p odd).

        It changes sign where the branch passes through its own period
        doubling: there x_0 = x_{p/2}, and beyond it the same orbits come again
        with their points shifted by p/2.
        """
        diff = self.half_difference(y)
        return None if diff is None else float(self.direction_half @ diff)

    def grazing(self, y: np.ndarray) -> float | None:
        params = self.params_at(y[-1])
        x = y[:-1].reshape(self.p, 3)
        try:
            _im, times, _j, _s = _chain(params, x)
            r_max = None
            for i in range(self.p):
                ext = flight_extrema(params, x[i], float(times[i]), law=SLIP_BOUNDED)
                if ext.r_max is not None:
                    r_max = ext.r_max if r_max is None else max(r_max, ext.r_max)
        except (_MapFailure, ParameterError, RuntimeError):
            return None
        return None if r_max is None else 1.0 - r_max

    def slipping(self, y: np.ndarray) -> int | None:
        params = self.params_at(y[-1])
        x = y[:-1].reshape(self.p, 3)
        return int(np.all(params.r_ratio + 1.0 + x[:, 2] > params.mu * (1.0 + params.d) * x[:, 1]))


def continue_multi_impact(
    orbit: MultiImpactOrbit,
    param: str,
    stop: float,
    *,
    step: float = 1e-3,
    max_step: float = 0.02,
    max_points: int = 2000,
) -> MultiImpactBranch:
    """Follow a multi-impact orbit in one parameter up to ``stop``.

    Pseudo-arclength continuation (`rotorcontact.continuation.engine.continue_curve`)
    of (x_0, ..., x_{p-1}, lambda), starting in the direction of ``stop``.
    It ends at ``stop`` (a terminal event), at a grazing (terminal: P_I
    is discontinuous there), or when the step fails (for example where the
    branch returns onto a one-impact orbit at a period doubling).

    Parameters
    ----------
    orbit : MultiImpactOrbit
        Starting orbit.
    param : str
        One of `rotorcontact.maps.multi_impact.CONTINUATION_PARAMETERS`.
    stop : float
        The parameter value to reach.
    step, max_step : float
        First and largest step of the (scaled) arclength, from `MIN_STEP` to `MAX_STEP` (a smaller
        ``max_step`` is raised to ``step``).
    max_points : int
        Largest number of steps (1 to `rotorcontact.continuation.engine.MAX_POINTS`).

    Returns
    -------
    MultiImpactBranch

    Raises
    ------
    ParameterError
        Unless ``orbit`` is a `MultiImpactOrbit`, ``param`` a continuation parameter, ``stop`` a value it may
        take and the steps and ``max_points`` within their bounds.
    """
    check_orbit(orbit)
    param = _check_parameter(param)
    stop = check_param_value("stop", orbit.params, param, check_range("stop", stop))
    step = check_float("step", step, MIN_STEP, MAX_STEP)
    max_step = max(check_float("max_step", max_step, MIN_STEP, MAX_STEP), step)
    max_points = check_max_points(max_points)
    p = orbit.impacts
    base = orbit.params
    start = float(getattr(base, param))
    if stop == start:
        return MultiImpactBranch(param=param, events=(), values=np.array([start]), orbits=(orbit,),
                                 status="terminal", message="already at stop")
    system = _System(base, param, p, start=orbit.states)
    y0 = np.append(orbit.states.ravel(), start)
    direction = 1.0 if stop > start else -1.0
    events = [
        EventFunction("stop", lambda y: direction * (stop - y[-1]), terminal=True),
        EventFunction("plus-one", system.plus_one),
        EventFunction("minus-one", system.minus_one),
        EventFunction("torus", system.torus),
        EventFunction("grazing", system.grazing, terminal=True),
        EventFunction("slip", system.slipping, kind="discrete"),
    ]
    settings = ContinuationSettings(
        step=min(step, max_step),
        min_step=MIN_STEP,
        max_step=max_step,
        max_points=max_points,
        residual_tol=1e-10,
        location_tol=1e-10,
    )
    # unknowns of order one; the parameter weighted up so that steps move it
    weights = np.ones(3 * p + 1)
    weights[-1] = PARAMETER_WEIGHT
    result = continue_curve(
        system.residual,
        y0,
        jacobian=system.jacobian,
        direction=direction,
        events=events,
        settings=settings,
        weights=weights,
        param_index=-1,
        correct_start=False,
    )
    own = _own_doubling(result, system)
    if own is not None:
        # the points beyond it repeat the branch with the points shifted by p/2
        result = replace(result, points=result.points[: own[0] + 1], tangents=result.tangents[: own[0] + 1],
                         events=tuple(e for e in result.events if e.index < own[0]))
    orbits = []
    values = []
    for y in result.points:
        try:
            orbits.append(system.orbit(y, orbit.label))
            values.append(float(y[-1]))
        except (_MapFailure, ParameterError):
            break
    located = _typed_events(result, system, orbit.label)
    status, message = result.status, result.message
    if status == "step-failure" and orbits:
        # the map is continuous but not smooth at a grazing (square-root singularity): steps fail as an
        # interior maximum of r approaches 1, or as an impact's velocity falls to 0 (the impact becomes
        # tangential: the same grazing, seen from the side where the orbit has that impact)
        last = orbits[-1]
        slowest = float(np.min(last.states[:, 1]))
        how = None
        if last.r_max_interior is not None and 1.0 - last.r_max_interior < GRAZING_MARGIN:
            how = f"interior maximum r = {last.r_max_interior:.6g}"
        elif slowest < GRAZING_MARGIN:
            how = f"an impact at rdot = {slowest:.3g}, becoming tangential"
        if how is not None:
            located.append(_event("grazing", values[-1], param, orbit.label, last, p,
                                  f"where the continuation ends ({how}): the grazing lies just beyond it"))
            status = "grazing"
            message = f"the branch approaches a grazing at {param} = {values[-1]:.10g} ({how}); {message}"
    grazings = [e.value for e in located if e.kind == "grazing"]
    # P_I is not smooth at a grazing (a square-root singularity): a multiplier +1 located there is the
    # grazing, where the branch may turn, not a smooth fold
    located = [e for e in located if not (e.kind in ("fold", "branch-point")
                                         and any(abs(e.value - g) <= 1e-8 for g in grazings))]
    if own is not None:
        i, value, accuracy = own
        located.append(_event("period-doubling", value, param, orbit.label, None, p,
                              "the branch returns onto the orbit it doubles from; continuation stops", accuracy,
                              (_parent_label(orbit.label, system, result.points[i], value), orbit.label)))
        status = "period-doubling"
        message = (f"the branch returned onto the orbit it doubles from, at its period doubling "
                   f"{param} = {value:.12g}; beyond it come the same orbits with their points shifted by {p // 2}")
    return MultiImpactBranch(
        param=param,
        events=tuple(located),
        values=np.array(values),
        orbits=tuple(orbits),
        status=status,
        message=message,
    )


def _event(kind: str, value: float, param: str, label: str, orbit: MultiImpactOrbit | None, p: int,
           detail: str = "", accuracy: float = 0.0, orbits: tuple[str, ...] | None = None) -> BranchEvent:
    """An event of a multi-impact branch, with the orbit there (None where it could not be built)."""
    return BranchEvent(kind=kind, value=value, param=param, orbits=orbits or (label,), detail=detail,
                       T=None if orbit is None else orbit.period, orbit=orbit, impacts=p, accuracy=accuracy)


def _turns(result, index: int) -> bool:
    """Whether the parameter turns over the step from point ``index`` to ``index + 1`` (tangents' signs)."""
    t = result.tangents
    if index + 1 >= len(t):
        return False
    return bool(t[index][-1] * t[index + 1][-1] < 0.0)


def _parent_label(label: str, system: _System, y: np.ndarray, value: float) -> str:
    """The label of the orbit a branch doubles from, where it returns onto it at ``value`` (``y`` the point
    before): ``"B1,d"`` for ``"B1,d/PD"`` (or ``/PD2``, ...); for a branch found otherwise with two impacts,
    the one-impact orbit at ``value`` whose impact state is nearest y's first (within `HALF_PERIOD_MARGIN`
    in each component, with half y's period within 10 %); else ``"<p/2>-impact orbit"``."""
    stem, sep, tail = label.rpartition("/PD")
    if sep and (tail == "" or tail.isdigit()):
        return stem
    unnamed = f"{system.p // 2}-impact orbit"
    if system.p != 2:
        return unnamed
    params = system.params_at(value)
    x = y[:-1].reshape(system.p, 3)
    try:
        half = 0.5 * float(np.sum(_chain(system.params_at(y[-1]), x)[1]))
        found = one_impact_orbits(params, searchable_t_max(params, 1.25 * half))
    except (_MapFailure, ParameterError):
        return unnamed
    best, nearest = unnamed, HALF_PERIOD_MARGIN
    for o in found:
        gap = max(abs(math.remainder(o.theta - x[0, 0], 2.0 * math.pi)), abs(o.rdot - x[0, 1]),
                  abs(o.thetadot - x[0, 2]))
        if gap <= nearest and abs(o.T - half) <= 0.1 * half:
            best, nearest = o.label, gap
    return best


def _own_doubling(result, system: _System) -> tuple[int, float, float] | None:
    """Where the branch passes through its own period doubling: (index before it, parameter, accuracy).

    Between two consecutive points near the orbit of p/2 impacts (max |x_0 - x_{p/2}| below
    `HALF_PERIOD_MARGIN`) e . (x_0 - x_{p/2}) changes sign and x_0 - x_{p/2} reverses (the cosine of the
    angle between its values is below -`PITCHFORK_COSINE`): the branch has passed through the pitchfork
    of P_I^p where it meets the orbit it doubles from. The curve is singular there (two branches cross), so
    the point is not corrected onto it; the parameter is that of the pitchfork from a least-squares fit
    lambda = lambda_0 + c_1 a + c_2 a^2 to the nearest points (a the signed asymmetry), and its accuracy
    the largest residual of the fit.
    """
    if system.p % 2:
        return None
    diffs = [system.half_difference(y) for y in result.points]
    asym = [system.asymmetry(y) for y in result.points]
    for i in range(len(asym) - 1):
        a0, a1 = asym[i], asym[i + 1]
        if a0 is None or a1 is None or not a0 * a1 < 0.0:
            continue
        d0, d1 = diffs[i], diffs[i + 1]
        if not d0 @ d1 <= -PITCHFORK_COSINE * np.linalg.norm(d0) * np.linalg.norm(d1):
            # through the pitchfork x_0 - x_{p/2} shrinks to 0 along one direction and comes back reversed; a
            # projection that changes sign while the difference turns aside is no passage through it
            continue
        near = [j for j in range(max(0, i - 2), min(len(asym), i + 4)) if asym[j] is not None]
        a = np.array([asym[j] for j in near])
        lam = np.array([result.points[j][-1] for j in near])
        basis = np.column_stack([np.ones_like(a), a, a * a])
        coef, *_ = np.linalg.lstsq(basis, lam, rcond=None)
        accuracy = float(np.max(np.abs(basis @ coef - lam)))
        return i, float(coef[0]), accuracy
    return None


def _stability_change(system: _System, e, param: str) -> str:
    """``"loss of stability as <param> increases"`` (or gain), or "" where it does not change."""
    ends = sorted((e.y_before, e.y_after), key=lambda yy: yy[-1])
    stab = []
    for yy in ends:
        z = system.multipliers(yy)
        stab.append(None if z is None else bool(np.all(np.abs(z) < 1.0)))
    if None in stab or stab[0] == stab[1]:
        return ""
    return f"{'gain' if stab[1] else 'loss'} of stability as {param} increases"


def _typed_events(result, system: _System, label: str) -> list[BranchEvent]:
    """The events of a multi-impact branch from the located zeros of its test functions.

    The multiplier test functions are those of one-impact branches
    (`rotorcontact.continuation.events`): det(M - I), det(M + I) and the
    bialternate product, of the Jacobian M of P_I^p. A zero of det(M - I) is
    a ``fold`` where the parameter turns over the step (the sign of the
    tangent's parameter component changes), a ``branch-point`` otherwise;
    at the branch's own period doubling (the terminal ``own-doubling``
    event) it is that point instead. A turning of the parameter that no
    zero of det(M - I) explains is still reported as a fold, located to the
    step.
    """
    param, p = system.param, system.p
    out: list[BranchEvent] = []
    explained: set[int] = set()
    for e in result.events:
        if e.name == "stop" or not e.continuous:
            continue
        try:
            o = system.orbit(e.y, label)
        except (_MapFailure, ParameterError):
            o = None
        value = float(e.parameter)
        if e.name in ("grazing", "slip"):
            out.append(_event(e.name, value, param, label, o, p, "", e.bracket))
            continue
        z = system.multipliers(e.y)
        if z is None:
            continue
        kind = multiplier_kind(e.name, z, MULTIPLIER_TOL)
        if kind is None:
            continue
        if kind == "plus-one":
            # the turn may show in a neighbouring step when the zero lies at a step's end
            turned = [j for j in (e.index - 1, e.index, e.index + 1) if j >= 0 and _turns(result, j)]
            if turned:
                explained.update(turned)
                out.append(_event("fold", value, param, label, o, p, "", e.bracket))
            else:
                out.append(_event("branch-point", value, param, label, o, p, _stability_change(system, e, param),
                                  e.bracket))
            continue
        detail = _stability_change(system, e, param)
        if kind == "neimark-sacker":
            detail = detail + ("; " if detail else "") + f"angle {rotation_angle(z):.6g} rad"
        out.append(_event(kind, value, param, label, o, p, detail, e.bracket))
    last = len(result.points) - 1
    for i in range(last):
        if i in explained or not _turns(result, i):
            continue
        if i + 3 >= last and result.status != "terminal":
            # the last steps before a failure (a grazing, where P_I has a square-root singularity): the
            # tangent there is not trusted
            continue
        # the parameter increases along the tangent at i before a maximum, decreases before a minimum
        pair = (result.points[i], result.points[i + 1])
        sign = 1.0 if result.tangents[i][-1] > 0 else -1.0
        y = max(pair, key=lambda yy: sign * yy[-1])
        try:
            o = system.orbit(y, label)
        except (_MapFailure, ParameterError):
            o = None
        out.append(_event("fold", float(y[-1]), param, label, o, p, "located from the turning of the parameter",
                          abs(float(result.points[i + 1][-1] - result.points[i][-1]))))
    return out


# ---------------------------------------------------------------------------
# All orbits at given parameters
# ---------------------------------------------------------------------------


def multi_impact_orbits(
    params: Parameters,
    impacts: int,
    *,
    starts: Sequence[tuple[complex, complex]] | None = None,
    period_doubling: bool = True,
    scan_width: float = 0.05,
    t_max: float = 12.0,
    grid: tuple[int, int, int] | None = None,
) -> tuple[MultiImpactOrbit, ...]:
    """Periodic orbits with ``impacts`` (>= 2) impacts per period at given parameters.

    Two sources are combined:

    * the stable orbits found by `rotorcontact.maps.multi_impact.orbits_from_simulation`;
    * for ``impacts == 2`` and ``period_doubling``: for each admissible
      one-impact orbit with a real multiplier below -1, the period doubling
      where that multiplier passes -1 is located in gamma within
      ``scan_width`` of the given gamma
      (`rotorcontact.maps.multi_impact.find_period_doubling`), and the
      period-2 orbit born there is continued to the given gamma
      (`continue_multi_impact`); it is labelled ``"B<n>,<m>/PD"``.

    With ``grid`` (a shape of `rotorcontact.maps.multi_impact.orbits_from_grid`)
    the fixed points that Newton's method finds from that grid of impact states
    are added, unstable ones included. Orbits found twice are reported once,
    with the branch label.

    Parameters
    ----------
    params : Parameters
    impacts : int
        p, 2 to `rotorcontact.maps.multi_impact.MAX_ORBIT_IMPACTS`.
    starts : sequence of (u0, du0), optional
        Initial states of the simulations (at most `MAX_STARTS`), each as `rotorcontact.simulate` takes
        them; default those of `rotorcontact.maps.multi_impact.orbits_from_simulation`.
    period_doubling : bool
        Add the period-doubled branches of the one-impact orbits (p = 2).
    scan_width : float
        Half-width of the gamma window of the period doublings, 0 < scan_width <= `MAX_SCAN_WIDTH`.
    t_max : float
        Largest period of the one-impact orbits.
    grid : (int, int, int), optional
        Shape of the grid of impact states (each >= 1, a product of at most
        `rotorcontact.maps.multi_impact.MAX_GRID_POINTS`).

    Returns
    -------
    tuple of MultiImpactOrbit
        Branch-switched orbits first, then the others by period.

    Raises
    ------
    ParameterError
        Naming the first argument that is not of the kind above (every one is checked, used or not).
    """
    check_params(params)
    p = check_int("impacts", impacts, 2, MAX_ORBIT_IMPACTS)
    starts = check_starts(starts)
    period_doubling = check_bool("period_doubling", period_doubling)
    scan_width = check_float("scan_width", scan_width, 0.0, MAX_SCAN_WIDTH, low_open=True)
    t_max = _check_t_max(params, t_max)
    grid = check_grid(grid)
    out: list[MultiImpactOrbit] = []
    if p == 2 and period_doubling:
        for parent in one_impact_orbits(params, t_max):
            if not (parent.admissible and _has_real_flip(parent)):
                continue
            orbit = _pd_branch_orbit(params, parent, scan_width, t_max)
            if orbit is not None and not any(_same_orbit(orbit, o) for o in out):
                out.append(orbit)
    brute = list(orbits_from_simulation(params, p, starts=starts))
    if grid is not None:
        for o in orbits_from_grid(params, p, shape=grid):
            if not any(_same_orbit(o, b) for b in brute):
                brute.append(o)
        brute.sort(key=lambda o: (o.period, o.points[0].theta))
    n = 0
    for o in brute:
        if any(_same_orbit(o, b) for b in out):
            continue
        n += 1
        out.append(_relabel(o, f"M{p}-{n}"))
    return tuple(out)


def _pd_branch_orbit(params: Parameters, parent: ImpactOrbit, width: float, t_max: float) -> MultiImpactOrbit | None:
    """The period-2 orbit of the period-doubled branch of ``parent`` at ``params``, if it reaches them."""
    g = params.gamma
    for lo, hi in ((g, g + width), (g - width, g)):
        try:
            pd = find_period_doubling(params, parent.label, "gamma", lo=lo, hi=hi, t_max=t_max)
        except ParameterError:
            continue
        # the branch is born on one side of the bifurcation; the orbit at params lies on the side of g
        side = 1.0 if g > pd.value else -1.0
        offset = side * min(1e-4, 0.5 * abs(g - pd.value))
        try:
            start = period_doubled_orbit(pd, offset, t_max=t_max)
        except (NewtonFailure, ParameterError):
            continue
        try:
            branch = continue_multi_impact(start, "gamma", g)
        except (CorrectionError, ParameterError):
            continue
        if branch.orbits and abs(branch.values[-1] - g) <= 1e-9 * (1.0 + abs(g)):
            last = branch.orbits[-1]
            try:
                return solve_multi_impact(params, last.states, label=last.label)
            except NewtonFailure:
                return None
    return None
