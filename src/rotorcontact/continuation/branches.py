"""Branches of one-impact periodic orbits against one parameter, with their bifurcations.

The orbits B_n,a .. B_n,d of MODEL.md §5 are followed as ``param`` (gamma,
omega, rho, mu or d) varies, by pseudo-arclength continuation
(`rotorcontact.continuation.engine`) of the regularised fixed-point equations in
(T, rdot) of `rotorcontact.maps.orbit_system`. These have the zero set of
(F1, Q) but no pole at the undamped resonances, so a branch passes every
point where its equations are regular: the smooth folds where B_n,a meets
B_n,b and B_n,c meets B_n,d (F1 has a double zero), the coalescence of a and
c (the quadratic's double root, also a fold in the parameter), the NSFH
point, and gamma = 0.

Finding every branch
--------------------
At ``n_seeds`` equally spaced parameter values every one-impact orbit with
T <= t_max is found with a guarantee (`rotorcontact.maps.impact_map.f1_zeros`).
Each orbit not yet met by a computed branch seeds a continuation in both
directions; every crossing of a seed value by a branch is corrected onto the
curve and marks the orbit it meets. Every solution curve that crosses a seed
value inside the box (start <= param <= stop, t_min <= T <= t_max,
|rdot| <= rdot_max) is therefore computed exactly once; a curve confined
strictly between two seed values is not seen. The seeds' default spacing is
no wider than that of 41 over the parameter's default range, whatever the range
followed (`default_seeds`, up to `MAX_SEEDS` values), so that a wider range does
not thin them out.

Events
------
The test functions are those of `rotorcontact.continuation.events`. Along each
branch these are located to ``location_tol`` in the parameter,
with a re-correction onto the curve at every trial point:

* ``fold``: dR1/dT changes sign (F1 has a double zero; a meets b, c meets d);
* ``ac-coalescence``: dR2/drdot changes sign (the discriminant of the quadratic
  vanishes; a meets c, or b meets d);
* ``nsfh``: rdot changes sign at a boundary equilibrium (|k| = 1, checked at
  the located point: gamma = gamma*, and also -gamma* when negative damping is
  in the range; the sign change of rdot through the resonance point at
  gamma = 0, which is not at a boundary equilibrium, is not reported);

and on admissible orbits (rdot > 0):

* ``grazing``: the largest interior maximum of r reaches 1;
* ``extrema-change``: the number of interior extrema of r changes;
* multipliers crossing the unit circle, from the smooth test functions
  det(J - I), det(J + I) and prod_{i<j}(z_i z_j - 1) of the Jacobian J of P_I:
  ``branch-point`` (+1 where the branch does not turn: no fold or
  coalescence at the same point), ``period-doubling`` (-1) and
  ``neimark-sacker`` (a complex pair on |z| = 1; a real pair with product 1 is
  not a bifurcation and is skipped). A sign change through a pole of a test
  function (the multipliers grow without bound as rdot -> 0) is not reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .events import BranchAnalyser, at_turning_point, branch_event_functions, report_events, turning_points
from .results import (
    EVENT_TYPES,
    BranchEvent,
    LabelBranch,
    OrbitBranches,
    OrbitCurve,
    OrbitEvent,
    check_interval,
    check_param_range,
)
from .engine import (
    ContinuationResult,
    ContinuationSettings,
    CorrectionError,
    LocatedEvent,
    continue_both_ways,
    correct_fixed,
    corrected_crossings,
)
from ..errors import ParameterError
from ..maps.impact_map import f1_zeros, rdot_roots
from ..maps.orbit_system import BRANCH_PARAMETERS, OneImpactSystem, orbit_with_extrema
from ..model.params import Parameters, check_range
from ..model.validation import check_bool, check_choice, check_int, check_params, settings_or_default

__all__ = [
    "EVENT_TYPES",
    "BRANCH_PARAMETERS",
    "BranchEvent",
    "OrbitEvent",
    "OrbitCurve",
    "LabelBranch",
    "OrbitBranches",
    "orbit_branches",
    "refine_branches",
    "default_settings",
    "default_seeds",
    "DEFAULT_RANGES",
    "DEFAULT_SEEDS",
]


MAX_SEEDS = 2000  # seed values along the parameter; bounds the run time
#: The range of each parameter that `branches` follows by default.
DEFAULT_RANGES = {
    "gamma": (-0.6, 0.25),
    "omega": (0.6, 1.25),
    "rho": (0.05, 1.0),
    "mu": (0.0, 0.5),
    "d": (0.5, 1.0),
}
#: Seed values over a parameter's default range; other ranges get seeds at least as dense (`default_seeds`).
DEFAULT_SEEDS = 41


def default_seeds(param: str, start: float, stop: float) -> int:
    """Seed values for ``[start, stop]``: spaced no wider than `DEFAULT_SEEDS` over the default range of
    ``param`` (`DEFAULT_RANGES`), at least `DEFAULT_SEEDS` and at most `MAX_SEEDS`.

    A curve confined between two seed values is not seen, so a wider range keeps the spacing rather
    than the count (the seeds of two ranges need not coincide; a curve narrower than the spacing can
    still fall between them).

    Raises
    ------
    ParameterError
        Unless ``param`` is one of `DEFAULT_RANGES` and start < stop are finite numbers.
    """
    lo, hi = DEFAULT_RANGES[check_choice("param", param, tuple(DEFAULT_RANGES))]
    start, stop = check_interval(start, stop)
    spacing = (hi - lo) / (DEFAULT_SEEDS - 1)
    return int(min(MAX_SEEDS, max(DEFAULT_SEEDS, math.ceil((stop - start) / spacing - 1e-9) + 1)))



def check_n_seeds(n_seeds, param: str, start: float, stop: float) -> int:
    """``n_seeds`` as an int from 2 to `MAX_SEEDS`, or `default_seeds` where it is None."""
    return default_seeds(param, start, stop) if n_seeds is None else check_int("n_seeds", n_seeds, 2, MAX_SEEDS)


def default_settings() -> ContinuationSettings:
    """Continuation settings for branches (steps in the scaled norm of `orbit_branches`)."""
    return ContinuationSettings(step=0.01, min_step=1e-9, max_step=0.05, max_points=20000, location_tol=1e-10)


@dataclass
class _Seed:
    value: float
    T: float
    rdot: float
    covered: bool = False


def _seeds(system: OneImpactSystem, values: np.ndarray, t_max: float, rdot_max: float) -> list[_Seed]:
    out = []
    for v in values:
        p = system.params_at(v)
        for z in f1_zeros(p, t_max):
            disc, roots = rdot_roots(p, z.T)
            for r in roots:
                if abs(r) <= rdot_max:
                    out.append(_Seed(float(v), z.T, r))
    return out


def _mark_covered(system: OneImpactSystem, points: np.ndarray, seeds: list[_Seed], settings) -> None:
    """Mark the seeds that lie on the computed curve (its crossings of the seed values, corrected)."""
    by_value: dict[float, list[_Seed]] = {}
    for s in seeds:
        if not s.covered:
            by_value.setdefault(s.value, []).append(s)
    for v, group in by_value.items():
        hits = list(corrected_crossings(system.residual, points, 2, v, jacobian=system.jacobian, settings=settings))
        for s in group:
            for h in hits:
                if abs(h[0] - s.T) <= 1e-6 * (1.0 + s.T) and abs(h[1] - s.rdot) <= 1e-6 * (1.0 + abs(s.rdot)):
                    s.covered = True
                    break


def _insert_events(result: ContinuationResult, weights: np.ndarray) -> tuple[list[np.ndarray], list[str | None]]:
    """The points of a run with its located (non-terminal) event points inserted in order."""
    pts = [p for p in result.points]
    kinds: list[str | None] = [None] * len(pts)
    extra: dict[int, list[tuple[float, np.ndarray, str]]] = {}
    turning = turning_points(result.events)
    for e in result.events:
        if e.terminal or (e.name == "plus-one" and at_turning_point(e.y, turning)):
            # a multiplier +1 at a fold or coalescence is that point, not another one
            continue
        base = result.points[e.index]
        dist = float(np.linalg.norm(weights * (e.y - base)))
        extra.setdefault(e.index, []).append((dist, e.y, e.name))
    out_p: list[np.ndarray] = []
    out_k: list[str | None] = []
    n_pts = len(pts)
    for i in range(n_pts):
        out_p.append(pts[i])
        out_k.append(kinds[i])
        if i in extra:
            for dist, y, name in sorted(extra[i], key=lambda item: item[0]):
                out_p.append(y)
                out_k.append(name)
    if result.status == "terminal":
        out_k[-1] = "end"
    return out_p, out_k


def orbit_branches(
    params: Parameters,
    param: str = "gamma",
    start: float = -0.6,
    stop: float = 0.25,
    *,
    t_max: float = 12.0,
    t_min: float = 0.02,
    rdot_max: float = 5.0,
    n_seeds: int | None = None,
    settings: ContinuationSettings | None = None,
    events_on_virtual: bool = False,
) -> OrbitBranches:
    """Follow every one-impact orbit with T <= t_max as ``param`` goes from ``start`` to ``stop``.

    Parameters
    ----------
    params : Parameters
        The other parameters (the value of ``param`` in it is not used).
    param : str
        One of ``"gamma"``, ``"omega"``, ``"rho"``, ``"mu"``, ``"d"``. Negative
        gamma is allowed.
    start, stop : float
        The range, start < stop.
    t_max, t_min : float
        Periods followed: t_min <= T <= t_max.
    rdot_max : float
        Branches are followed while |rdot| <= rdot_max (some run off to
        infinite impact velocity where a12(T) = 0).
    n_seeds : int, optional
        Number of parameter values at which orbits are found to seed the
        continuation (2 to `MAX_SEEDS`). Default: `default_seeds`, as dense
        as 41 over the parameter's default range (`DEFAULT_RANGES`), however
        wide the range; a curve confined between two seed values is not seen.
    settings : ContinuationSettings, optional
        Continuation settings; the arclength is measured in
        (T, rdot, (param - start) / (stop - start)).
    events_on_virtual : bool
        Also report grazing, extrema changes and multiplier crossings of
        virtual orbits (rdot < 0), whose impact map is the formal one.

    Returns
    -------
    OrbitBranches

    Raises
    ------
    ParameterError
        On an unknown parameter, an empty or invalid range, or invalid options.
    """
    check_params(params)
    system = OneImpactSystem(params, param)
    start, stop = check_param_range(param, params, start, stop)
    system.bounds = (start, stop)
    t_max = check_range("t_max", t_max, low=0.0, low_open=True)
    t_min = check_range("t_min", t_min, low=0.0, low_open=True, high=t_max, high_open=True)
    rdot_max = check_range("rdot_max", rdot_max, low=0.0, low_open=True)
    n_seeds = check_n_seeds(n_seeds, param, start, stop)
    span = stop - start
    settings = settings_or_default(settings, ContinuationSettings, default_settings)
    events_on_virtual = check_bool("events_on_virtual", events_on_virtual)
    weights = np.array([1.0, 1.0, 1.0 / span])
    an = BranchAnalyser(system, virtual=events_on_virtual)
    funcs = branch_event_functions(an, start, stop, t_min, t_max, rdot_max)
    seeds = _seeds(system, np.linspace(start, stop, int(n_seeds)), t_max, rdot_max)
    seeds = [s for s in seeds if t_min <= s.T <= t_max]

    curves: list[OrbitCurve] = []
    raw_events: list[LocatedEvent] = []
    for seed in seeds:
        if seed.covered:
            continue
        seed.covered = True
        y0 = np.array([seed.T, seed.rdot, seed.value])
        both = continue_both_ways(system.residual, y0, jacobian=system.jacobian, events=funcs, settings=settings,
                                  weights=weights, param_index=2)
        if both is None:
            continue
        for res in both.runs:
            _mark_covered(system, res.points, seeds, settings)
        curve, evs = _assemble(system, list(both.runs), weights, param)
        curves.append(curve)
        raw_events.extend(evs)

    events = report_events(raw_events, an, system)
    return OrbitBranches(param=param, events=events, start=start, stop=stop, base=params, t_max=t_max,
                         curves=tuple(curves))


def _assemble(system: OneImpactSystem, runs: list[ContinuationResult], weights: np.ndarray,
              param: str) -> tuple[OrbitCurve, list[LocatedEvent]]:
    """Join the runs of one seed (backward reversed, then forward) into a curve."""
    fwd_p, fwd_k = _insert_events(runs[0], weights)
    ends = [runs[0].message, ""]
    if len(runs) > 1:
        bwd_p, bwd_k = _insert_events(runs[1], weights)
        ends[1] = runs[1].message
        pts = bwd_p[::-1][:-1] + fwd_p
        kinds = bwd_k[::-1][:-1] + fwd_k
        all_events = list(runs[1].events) + list(runs[0].events)
    else:
        pts, kinds = fwd_p, fwd_k
        all_events = list(runs[0].events)
    lo, hi = system.bounds
    keep = []
    for i, y in enumerate(pts):
        if not lo <= y[2] <= hi:
            # a terminal point a rounding error past a bound; where the parameter is not valid there,
            # put it on the bound
            try:
                system.base.replace(**{param: float(y[2])})
            except ParameterError:
                y = y.copy()
                y[2] = min(max(y[2], lo), hi)
                try:
                    pts[i] = correct_fixed(system.residual, y, 2, jacobian=system.jacobian)
                except CorrectionError:
                    continue
        keep.append(i)
    orbits = []
    extrema = []
    index = []
    for i in keep:
        point = _curve_point(system, pts[i])
        if point is None:
            continue  # a singular end point (the undamped resonance at gamma = 0 exactly)
        index.append(i)
        orbits.append(point[0])
        extrema.append(point[1])
    new_pos = {old: new for new, old in enumerate(index)}
    pts = [pts[i] for i in index]
    event_index = tuple((new_pos[i], k) for i, k in enumerate(kinds)
                        if k is not None and k != "end" and i in new_pos)
    curve = OrbitCurve(
        param=param,
        values=np.array([y[2] for y in pts]),
        orbits=tuple(orbits),
        extrema=tuple(extrema),
        event_index=event_index,
        ends=(ends[1], ends[0]),
    )
    return curve, all_events


def _curve_point(system: OneImpactSystem, y: np.ndarray):
    """The orbit at the point y = (T, rdot, lambda) of a curve and the interior extrema of r along its flight
    (radii, which are maxima), or None where it cannot be computed (a singular point)."""
    try:
        o, ext = orbit_with_extrema(system.params_at(y[2]), float(y[0]), float(y[1]))
    except (ZeroDivisionError, ParameterError, RuntimeError):
        return None
    return o, (ext.radii.copy(), ext.maxima.copy())


#: Most points `refine_branches` puts between two points of a curve.
MAX_REFINE = 2000


def refine_branches(branches: OrbitBranches, view: tuple[float, float], points: int = 400) -> OrbitBranches:
    """``branches`` with points added inside ``view`` so that consecutive points are at most (hi - lo) / points
    apart in the parameter there (none outside it): for drawing, where the continuation's steps are coarse
    beside a bifurcation.

    Each point added is corrected onto its curve at its parameter value (Newton's method on the fixed-point
    equations from the chord between its neighbours) and computed as the continuation computes its points
    (`rotorcontact.maps.orbit_system.orbit_with_extrema`); one that does not converge, or lands farther from the
    chord than the two neighbours are from each other, is left out.

    Raises
    ------
    ParameterError
        Unless ``branches`` is an `OrbitBranches`, ``view`` two finite numbers lo < hi and ``points`` a whole
        number from 2 to 100,000.
    """
    from ..model.validation import check_type, quoted, real_array

    check_type("branches", branches, OrbitBranches, "the OrbitBranches of orbit_branches")
    ends = real_array(view) if isinstance(view, (tuple, list)) else None
    if ends is None or ends.shape != (2,) or not np.all(np.isfinite(ends)) or not ends[0] < ends[1]:
        raise ParameterError(f"view = {quoted(view)} is invalid; allowed: (lo, hi), two finite numbers lo < hi")
    lo, hi = float(ends[0]), float(ends[1])
    points = check_int("points", points, 2, 100_000)
    system = OneImpactSystem(branches.base, branches.param)
    step = (hi - lo) / points
    curves = []
    for curve in branches.curves:
        values, orbits, extrema, where = [], [], [], {}
        for i in range(len(curve.values)):
            where[i] = len(values)
            values.append(float(curve.values[i]))
            orbits.append(curve.orbits[i])
            extrema.append(curve.extrema[i])
            if i + 1 == len(curve.values):
                break
            a, b = float(curve.values[i]), float(curve.values[i + 1])
            # the part of the segment inside the view, cut into pieces of at most `step`
            v0, v1 = max(min(a, b), lo), min(max(a, b), hi)
            if not v0 < v1:
                continue
            pieces = min(math.ceil((v1 - v0) / step), MAX_REFINE)
            fractions = [(v - a) / (b - a) for v in np.linspace(v0, v1, pieces + 1)]
            if b < a:
                fractions.reverse()
            ya = np.array([curve.orbits[i].T, curve.orbits[i].rdot, a])
            yb = np.array([curve.orbits[i + 1].T, curve.orbits[i + 1].rdot, b])
            span = float(np.max(np.abs(yb[:2] - ya[:2])))
            for s in fractions:
                if not 0.0 < s < 1.0:
                    continue  # the segment's own ends
                chord = ya + (yb - ya) * s
                try:
                    y = correct_fixed(system.residual, chord, 2, jacobian=system.jacobian)
                except CorrectionError:
                    continue
                point = None if np.max(np.abs(y[:2] - chord[:2])) > span else _curve_point(system, y)
                if point is None:
                    continue  # onto another curve, or singular
                values.append(float(y[2]))
                orbits.append(point[0])
                extrema.append(point[1])
        curves.append(OrbitCurve(param=curve.param, values=np.array(values), orbits=tuple(orbits),
                                 extrema=tuple(extrema), event_index=tuple((where[k], kind)
                                                                           for k, kind in curve.event_index),
                                 ends=curve.ends))
    return replace(branches, curves=tuple(curves))
