"""Branches of periodic orbits with p >= 2 impacts per period, and all such orbits at given parameters.

Continuation
------------
`continue_multi_impact` follows an orbit of `rotorcontact.maps.multi_impact`
(a fixed point of P_I^p) in one parameter with the pseudo-arclength
continuation of `rotorcontact.continuation.engine` (folds are passed), on the
unknowns (x_0, ..., x_{p-1}, lambda), and locates the events of MODEL.md §5
along the branch: a multiplier leaving the unit circle (classified as fold at
+1, period doubling at -1 or Neimark-Sacker for a complex pair), grazing of an
interior maximum of r, and a change of the slipping condition. The
continuation stops at a grazing (P_I is discontinuous there).

All orbits
----------
`multi_impact_orbits` combines the stable orbits found by long simulations
(`rotorcontact.maps.multi_impact.orbits_from_simulation`) with, for p = 2,
the period-doubled branch of each one-impact orbit whose multiplier has
passed -1, continued from the period doubling to the given parameters.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..errors import ParameterError
from ..maps.impact_map import SLIP_BOUNDED, ImpactOrbit, flight_extrema, one_impact_orbits
from ..maps.multi_impact import (
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
    find_period_doubling,
    orbits_from_simulation,
    period_doubled_orbit,
    periodic_residual,
    solve_multi_impact,
)
from ..model.params import Parameters, check_range
from ..model.validation import check_int, check_params
from .engine import ContinuationSettings, CorrectionError, EventFunction, continue_curve
from .results import BranchEvent, BranchResult

__all__ = [
    "BranchEvent",
    "MultiImpactBranch",
    "continue_multi_impact",
    "multi_impact_orbits",
    "PARAMETER_WEIGHT",
    "GRAZING_MARGIN",
]

#: Weight of the parameter in the arclength (the unknowns are of order one), so that steps move it.
PARAMETER_WEIGHT = 100.0
#: A failed step with an interior maximum of r within this of 1 is reported as a grazing.
GRAZING_MARGIN = 1e-2


@dataclass(frozen=True)
class MultiImpactBranch(BranchResult):
    """A continued branch of orbits with p impacts per period.

    Attributes
    ----------
    param : str
        The continuation parameter.
    events : tuple of BranchEvent
        Located events, in order: ``kind`` ``"fold"``, ``"period-doubling"``,
        ``"neimark-sacker"`` (a multiplier leaves or enters the unit circle at
        +1, -1, or as a complex pair), ``"grazing"`` (an interior maximum of r
        reaches 1) or ``"slip"`` (the slipping condition changes); ``orbit``
        the orbit there (None where it could not be built).
    values : numpy.ndarray
        The parameter along the branch.
    orbits : tuple of MultiImpactOrbit
        The orbits at those values.
    status, message : str
        How the continuation ended: the statuses of
        `rotorcontact.continuation.engine.ContinuationResult`, or ``"grazing"`` when
        the steps failed with an interior maximum of r within
        `GRAZING_MARGIN` of 1.
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


class _System:
    """(x_0 .. x_{p-1}, lambda) -> G as a continuation problem."""

    def __init__(self, base: Parameters, param: str, p: int, fd_step: float = 1e-7):
        self.base = base
        self.param = param
        self.p = p
        self.fd_step = fd_step

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

    def max_multiplier(self, y: np.ndarray) -> float | None:
        try:
            _im, _t, jacs, _s = _chain(self.params_at(y[-1]), y[:-1].reshape(self.p, 3))
        except (_MapFailure, ParameterError):
            return None
        m = np.eye(3)
        for j in jacs:
            m = j @ m
        return float(np.max(np.abs(np.linalg.eigvals(m)))) - 1.0

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


def _classify_stability_event(orbit: MultiImpactOrbit) -> str:
    """The kind of a multiplier crossing the unit circle: at +1, at -1 or as a complex pair."""
    m = min(orbit.multipliers, key=lambda z: abs(abs(z) - 1.0))
    if abs(m.imag) > 1e-6 * (1.0 + abs(m)):
        return "neimark-sacker"
    return "fold" if m.real > 0.0 else "period-doubling"


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
        First and largest step of the (scaled) arclength.
    max_points : int
        Largest number of steps (>= 1).

    Returns
    -------
    MultiImpactBranch
    """
    if not isinstance(orbit, MultiImpactOrbit):
        raise ParameterError(f"orbit = {orbit!r} is not a MultiImpactOrbit")
    param = _check_parameter(param)
    stop = check_range("stop", stop)
    step = check_range("step", step, low=0.0, low_open=True)
    max_step = max(check_range("max_step", max_step, low=0.0, low_open=True), step)
    max_points = check_int("max_points", max_points, 1)
    p = orbit.impacts
    base = orbit.params
    start = float(getattr(base, param))
    if stop == start:
        return MultiImpactBranch(param=param, events=(), values=np.array([start]), orbits=(orbit,),
                                 status="terminal", message="already at stop")
    system = _System(base, param, p)
    y0 = np.append(orbit.states.ravel(), start)
    direction = 1.0 if stop > start else -1.0
    events = [
        EventFunction("stop", lambda y: direction * (stop - y[-1]), terminal=True),
        EventFunction("stability", system.max_multiplier),
        EventFunction("grazing", system.grazing, terminal=True),
        EventFunction("slip", system.slipping, kind="discrete"),
    ]
    settings = ContinuationSettings(
        step=min(step, max_step),
        min_step=1e-9,
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
    orbits = []
    values = []
    for y in result.points:
        try:
            orbits.append(system.orbit(y, orbit.label))
            values.append(float(y[-1]))
        except (_MapFailure, ParameterError):
            break
    located = []
    for ev in result.events:
        if ev.name == "stop":
            continue
        try:
            o = system.orbit(ev.y, orbit.label)
        except (_MapFailure, ParameterError):
            o = None
        kind = ev.name
        if ev.name == "stability":
            kind = _classify_stability_event(o) if o is not None else "stability"
        located.append(_event(kind, float(ev.parameter), param, orbit.label, o))
    status, message = result.status, result.message
    if status == "step-failure" and orbits:
        # the map is continuous but not smooth at a grazing (square-root singularity): steps
        # fail as an interior maximum of r approaches 1
        last = orbits[-1]
        if last.r_max_interior is not None and 1.0 - last.r_max_interior < GRAZING_MARGIN:
            located.append(_event("grazing", values[-1], param, orbit.label, last))
            status = "grazing"
            message = (
                f"the branch approaches a grazing at {param} = {values[-1]:.10g} "
                f"(interior maximum r = {last.r_max_interior:.6g}); {message}"
            )
    return MultiImpactBranch(
        param=param,
        events=tuple(located),
        values=np.array(values),
        orbits=tuple(orbits),
        status=status,
        message=message,
    )


def _event(kind: str, value: float, param: str, label: str, orbit: MultiImpactOrbit | None) -> BranchEvent:
    """An event of a multi-impact branch, with the orbit there (None where it could not be built)."""
    return BranchEvent(kind=kind, value=value, param=param, orbits=(label,),
                       T=None if orbit is None else orbit.period, orbit=orbit)


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

    Orbits found by both are reported once, with the branch label.

    Returns
    -------
    tuple of MultiImpactOrbit
        Branch-switched orbits first, then the others by period.
    """
    check_params(params)
    p = check_int("impacts", impacts, 2)
    scan_width = check_range("scan_width", scan_width, low=0.0, low_open=True)
    out: list[MultiImpactOrbit] = []
    if p == 2 and period_doubling:
        for parent in one_impact_orbits(params, t_max):
            if not (parent.admissible and _has_real_flip(parent)):
                continue
            orbit = _pd_branch_orbit(params, parent, scan_width, t_max)
            if orbit is not None and not any(_same_orbit(orbit, o) for o in out):
                out.append(orbit)
    brute = orbits_from_simulation(params, p, starts=starts)
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
