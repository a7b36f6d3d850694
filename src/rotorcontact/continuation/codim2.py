"""Two-parameter diagrams: fold, NSFH/DIB and grazing curves, their intersections, regions R1-R4.

Three kinds of curve in a plane of two parameters (p1, p2), any two of gamma,
omega, rho, mu, d, each continued by pseudo-arclength
(`rotorcontact.continuation.engine`) of its defining equations:

* **fold_n**, the smooth fold gamma_F,n of the pair n of one-impact orbits
  (B_n,a meets B_n,b, B_n,c meets B_n,d): F1 has a double zero. Unknowns
  (T, p1, p2), equations R1 = 0 and dR1/dT = 0 with R1 the regularised F1 of
  `rotorcontact.maps.orbit_system` (same zeros, no pole at the undamped
  resonances).
* **dib**, the boundary equilibrium (discontinuity-induced bifurcation, where
  the NSFH happens): |k|^2 = 1, written rho^2 - gamma^2 - (1 - omega^2)^2 = 0
  (no pole at the undamped resonance), unknowns (p1, p2). In the (gamma,
  omega) plane this is gamma_DIB(omega) = sqrt(rho^2 - (1 - omega^2)^2).
* **coalescence_ac_n**, **coalescence_bd_n**, where B_n,a meets B_n,c (or
  B_n,b meets B_n,d): the quadratic in rdot has a double root at their shared
  zero of F1, and beyond the curve neither orbit exists. Unknowns
  (T, rdot, p1, p2), equations R1 = R2 = 0 and dR2/drdot = 0.
* **grazing_<orbit>**, where the largest interior maximum of r of a chosen
  orbit (for example B1,d) reaches 1. Unknowns (T, rdot, t_g, p1, p2):
  R1 = R2 = 0 (the orbit), |U(t_g)|^2 = 1 and Re(conj(U) U')(t_g) = 0 (a
  maximum of r touching the clearance at the time t_g after the impact), with
  U(t) the exact free flight from the post-impact state. The curve ends where
  the orbit changes label (at a fold of F1 or a coalescence of roots), where
  it turns virtual, or where t_g leaves (0, T).

Seeds are found at ``n_seeds`` values of p2 by scanning p1 (existence of the
pair n for folds, sign of |k|^2 - 1, sign of r_max - 1 of the orbit) and
locating the crossing exactly; every seed not met by an already computed curve
starts a continuation in both directions inside the box.

Intersections are located as events along the curves, to ``location_tol``:
``fold-dib`` (the DIB function changes sign along a fold curve), ``grazing-dib``
(along a grazing curve) and ``fold-grazing`` (the grazing orbit reaches the
fold where it ceases to exist).

Regions (MODEL.md §5, pseudo-equilibria aside), from the orbits of the pair
n = 1 and the regular equilibrium at a point:

* R1: x_R virtual (|k| > 1), B1,a and B1,b virtual, B1,c and B1,d admissible;
* R2: no one-impact orbit of the pair 1, x_R virtual;
* R3: no one-impact orbit of the pair 1, x_R admissible;
* R4: x_R and every B1,m admissible.

Points fitting none of these (for example |k| < 1 with virtual B1 orbits, or
only two of the four B1 orbits, past an a-c or b-d coalescence curve) get
None, so the region boundaries follow the coalescence curves too.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from collections.abc import Mapping
from typing import Callable, Sequence

import numpy as np
from scipy.optimize import brentq

from .engine import (
    ContinuationSettings,
    CorrectionError,
    EventFunction,
    check_callable,
    continue_both_ways,
    continue_curve,
    correct_fixed,
    corrected_crossings,
)
from ..errors import ParameterError
from .results import POINT_TYPES, BranchEvent, BranchResult
from ..model.flow import propagate
from ..maps.impact_map import (
    IDEAL,
    IsolationLimit,
    _check_t_max,
    f1_zeros,
    flight_extrema,
    one_impact_orbits,
    post_impact_state,
    rdot_roots,
)
from ..maps.orbit_system import BRANCH_PARAMETERS, orbit_angles, regularised_residual, with_parameters
from ..model.params import Parameters, check_finite
from ..model.validation import check_int, check_params, check_type, is_pair, quoted, settings_or_default

__all__ = [
    "DEFAULT_RANGES",
    "POINT_TYPES",
    "REGIONS",
    "Codim2Curve",
    "Codim2Point",
    "Codim2Diagram",
    "fold_curve",
    "coalescence_curve",
    "coalescence_curves",
    "dib_curve",
    "grazing_curve",
    "codim2_diagram",
    "region",
    "classify_plane",
    "dib_function",
    "dib_labels",
]

#: Default ranges of the parameters in two-parameter diagrams.
DEFAULT_RANGES = {
    "gamma": (0.0, 0.5),
    "omega": (0.6, 1.25),
    "rho": (0.05, 1.0),
    "mu": (0.0, 0.5),
    "d": (0.5, 1.0),
}

#: Region names (MODEL.md §5).
REGIONS = ("R1", "R2", "R3", "R4")


#: Most scan lines per axis (``n_seeds``) and points per line (``n_scan``) of the seed scans; they bound the run time.
MAX_SEEDS = 2000
MAX_SCAN = 10_000
#: Most points on a side of `classify_plane`'s grid: each point finds the orbits of one parameter set
#: (a few milliseconds), so 1000 x 1000 take an hour or more.
MAX_PLANE_SIDE = 1000
#: Largest pair index n of a fold or coalescence curve (as the command line's ``--folds``): the pairs of
#: zeros of F1 lie about 2 pi / (1 + omega) apart in T, so pair 100 needs periods of hundreds, far
#: beyond the orbits a diagram follows.
MAX_PAIR = 100


def _check_pair(name: str, n) -> int:
    """``n`` as the index of a pair of zeros of F1, 1 to `MAX_PAIR`."""
    return check_int(name, n, 1, MAX_PAIR)


def _check_scan(n_seeds, n_scan) -> tuple[int, int]:
    """The scan lines per axis (1 to `MAX_SEEDS`) and points per line (2 to `MAX_SCAN`) of the seed scans."""
    return check_int("n_seeds", n_seeds, 1, MAX_SEEDS), check_int("n_scan", n_scan, 2, MAX_SCAN)


def _settings() -> ContinuationSettings:
    return ContinuationSettings(step=0.01, min_step=1e-9, max_step=0.04, max_points=4000, location_tol=1e-10)


# ---------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------


#: An intersection of two curves is a `BranchEvent`: ``kind`` one of `POINT_TYPES`, ``param`` the plane
#: (p1, p2), ``value`` (p1, p2) at the point, ``T`` the period of the orbit involved (None without one).
Codim2Point = BranchEvent


def _point(kind: str, params: tuple[str, str], v1: float, v2: float, T: float | None = None) -> BranchEvent:
    """The intersection point of type ``kind`` at (p1, p2) = (v1, v2)."""
    return BranchEvent(kind=kind, value=(v1, v2), param=params, T=T)


@dataclass(frozen=True)
class Codim2Curve:
    """A curve in the (p1, p2) plane, in connected pieces.

    Attributes
    ----------
    name : str
        ``"fold_1"``, ``"dib"``, ``"grazing_B1d"``, ...
    kind : str
        ``"fold"``, ``"dib"`` or ``"grazing"``.
    params : tuple of str
        (p1, p2).
    pieces : tuple of numpy.ndarray
        Each an (m, k) array of the unknowns along one piece; the last two
        columns are (p1, p2) (before them: T for folds; T, rdot, t_g for grazing).
    ends : tuple of str
        Why each piece ended (both directions).
    """

    name: str
    kind: str
    params: tuple[str, str]
    pieces: tuple[np.ndarray, ...] = field(repr=False)
    ends: tuple[str, ...] = ()

    def xy(self) -> np.ndarray:
        """All (p1, p2) points, pieces separated by a row of NaN."""
        rows = []
        for i, piece in enumerate(self.pieces):
            if i:
                rows.append(np.full((1, 2), np.nan))
            rows.append(piece[:, -2:])
        return np.vstack(rows) if rows else np.empty((0, 2))

    def to_list(self) -> list:
        """[[p1, p2], ...] with null between pieces (the ``codim2 --json`` contract)."""
        out: list = []
        for i, piece in enumerate(self.pieces):
            if i:
                out.append(None)
            out.extend([[float(a), float(b)] for a, b in piece[:, -2:]])
        return out


@dataclass(frozen=True)
class Codim2Diagram(BranchResult):
    """Curves and their intersections in a plane of two parameters.

    Attributes
    ----------
    param : tuple of str
        The plane (p1, p2).
    events : tuple of BranchEvent
        The intersection points.
    ranges : tuple of (float, float)
        The box.
    base : Parameters
        The other parameters.
    curves : dict of str -> Codim2Curve
    """

    ranges: tuple[tuple[float, float], tuple[float, float]]
    base: Parameters
    curves: dict[str, Codim2Curve] = field(repr=False)

    @property
    def params(self) -> tuple[str, str]:
        """The plane (`param`)."""
        return self.param  # type: ignore[return-value]

    @property
    def points(self) -> tuple[BranchEvent, ...]:
        """The intersection points (`events`)."""
        return self.events

    def curves_dict(self) -> dict[str, list]:
        """Per curve, [[p1, p2], ...] with null between pieces."""
        return {name: c.to_list() for name, c in self.curves.items()}


# ---------------------------------------------------------------------------
# Shared machinery
# ---------------------------------------------------------------------------


def dib_function(p: Parameters) -> float:
    """rho^2 - gamma^2 - (1 - omega^2)^2: zero on the DIB curve |k| = 1, positive where |k| > 1.

    It equals (|k|^2 - 1)(gamma^2 + (1 - omega^2)^2), without the pole of |k| at the
    undamped resonance.
    """
    check_params(p, "p")
    return p.rho**2 - p.gamma**2 - (1.0 - p.omega**2) ** 2


class _Plane:
    """Parameters at (p1, p2) for a plane of two parameters (extended beyond physical bounds)."""

    def __init__(self, base: Parameters, params: Sequence[str], ranges):
        check_params(base)
        given = params
        params = tuple(params) if is_pair(params) else ()
        if len(params) != 2 or params[0] == params[1]:
            raise ParameterError(f"param = {given!r} is invalid; allowed: two different parameters, as a pair")
        for p in params:
            if p not in BRANCH_PARAMETERS:
                raise ParameterError(
                    f"parameter {p!r} is not a diagram parameter; allowed: {', '.join(BRANCH_PARAMETERS)}"
                )
        if ranges is None:
            ranges = (DEFAULT_RANGES[params[0]], DEFAULT_RANGES[params[1]])
        elif isinstance(ranges, Mapping):
            if set(ranges) != set(params):
                raise ParameterError(f"ranges = {ranges!r} is invalid; allowed: a range for each of {params[0]!r} "
                                     f"and {params[1]!r} and no other")
            ranges = (ranges[params[0]], ranges[params[1]])
        elif not is_pair(ranges):
            raise ParameterError(f"ranges = {ranges!r} is invalid; allowed: two ranges (low, high), one for "
                                 f"{params[0]!r} and one for {params[1]!r}")
        checked = []
        for name, rng in zip(params, ranges):
            if not is_pair(rng):
                raise ParameterError(f"range of {name} = {rng!r} is invalid; allowed: (low, high)")
            lo, hi = (check_finite(f"range of {name}", v) for v in rng)
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise ParameterError(f"range of {name} = {rng!r} is invalid; allowed: finite low < high")
            base.replace(**{name: lo})
            base.replace(**{name: hi})
            checked.append((lo, hi))
        self.base = base
        self.params = params
        self.ranges = tuple(checked)
        self._cache: dict[tuple[float, float], Parameters] = {}

    def at(self, v1: float, v2: float) -> Parameters:
        key = (float(v1), float(v2))
        p = self._cache.get(key)
        if p is None:
            p = with_parameters(self.base, {self.params[0]: key[0], self.params[1]: key[1]}, extend=True)
            if len(self._cache) > 8192:
                self._cache.clear()
            self._cache[key] = p
        return p

    def check_t_max(self, t_max) -> float:
        """``t_max`` as a float if it is a period that F1 and the flight are evaluated for at every point of the
        box: at its corners, where the flight grows fastest (the largest |gamma| and the smallest omega).

        Raises
        ------
        ParameterError
            Naming ``t_max`` and the bound at the corner that refuses it.
        """
        for v1 in self.ranges[0]:
            for v2 in self.ranges[1]:
                t_max = _check_t_max(self.at(v1, v2), t_max)
        return t_max

    def span(self, i: int) -> float:
        lo, hi = self.ranges[i]
        return hi - lo

    def box_events(self) -> list[EventFunction]:
        (a1, b1), (a2, b2) = self.ranges
        return [
            EventFunction("p1-low", lambda y: y[-2] - a1, terminal=True),
            EventFunction("p1-high", lambda y: b1 - y[-2], terminal=True),
            EventFunction("p2-low", lambda y: y[-1] - a2, terminal=True),
            EventFunction("p2-high", lambda y: b2 - y[-1], terminal=True),
        ]

    def dib_value(self, y) -> float:
        return dib_function(self.at(y[-2], y[-1]))


def _trace(
    residual: Callable[[np.ndarray], np.ndarray],
    seeds: list[tuple[np.ndarray, int]],
    events: list[EventFunction],
    weights: np.ndarray,
    settings: ContinuationSettings,
) -> tuple[list[np.ndarray], list[str], list]:
    """Continue from every seed not met by an earlier curve; returns pieces, end messages, events.

    A seed is (y, index): a point of a curve found with the component ``y[index]``
    (p1 or p2) held at a scan value.
    """
    covered = [False] * len(seeds)
    pieces: list[np.ndarray] = []
    ends: list[str] = []
    found = []
    for i, (seed, _) in enumerate(seeds):
        if covered[i]:
            continue
        covered[i] = True
        both = continue_both_ways(residual, seed, events=events, settings=settings, weights=weights,
                                  param_index=-1, correct_start=False)
        if both is None:
            continue
        pts = both.points
        # a seed on the box's edge ends its outward run at once, on itself: one point, not two
        pts = pts[np.concatenate(([True], np.any(pts[1:] != pts[:-1], axis=1)))]
        pieces.append(pts)
        ends.extend(both.messages)
        found.extend(both.events)
        _cover(residual, pts, seeds, covered, settings)
    return pieces, ends, found


def _cover(residual, pts: np.ndarray, seeds: list[tuple[np.ndarray, int]], covered: list[bool], settings) -> None:
    """Mark seeds met by a computed curve (its crossings of the seed's scan value, corrected there)."""
    for i, (seed, index) in enumerate(seeds):
        if covered[i]:
            continue
        for g in corrected_crossings(residual, pts, index, seed[index], settings=settings):
            if np.all(np.abs(g - seed) <= 1e-6 * (1.0 + np.abs(seed))):
                covered[i] = True
                break


def _scan_lines(plane: "_Plane", n_seeds: int, n_scan: int):
    """Scan lines (fixed value, grid, axis): p1 scanned at fixed p2 values and p2 at fixed p1 values.

    ``axis`` is the component scanned (0: p1, 1: p2).
    """
    (a1, b1), (a2, b2) = plane.ranges
    g1 = np.linspace(a1, b1, n_scan)
    g2 = np.linspace(a2, b2, n_scan)
    for v2 in np.linspace(a2, b2, n_seeds):
        yield float(v2), g1, 0
    for v1 in np.linspace(a1, b1, n_seeds):
        yield float(v1), g2, 1


def _held(y: np.ndarray, axis: int) -> int:
    """Index in y of the parameter held fixed on a scan line along ``axis`` (0: p1 scanned, p2 held)."""
    return len(y) - 1 if axis == 0 else len(y) - 2


def _brackets(func: Callable[[float], float | None], grid: np.ndarray) -> list[tuple[float, float]]:
    vals = [func(v) for v in grid]
    out = []
    for (a, fa), (b, fb) in zip(zip(grid, vals), zip(grid[1:], vals[1:])):
        if fa is not None and fb is not None and (fa < 0) != (fb < 0):
            out.append((float(a), float(b)))
    return out


# ---------------------------------------------------------------------------
# Fold curves
# ---------------------------------------------------------------------------


def _pair_exists(p: Parameters, n: int, t_max: float) -> bool:
    try:
        zeros = f1_zeros(p, t_max)
    except (ParameterError, RuntimeError):
        return False
    return sum(1 for z in zeros if z.n == n) >= 2


def _fold_seed(plane: _Plane, n: int, fixed: float, axis: int, a: float, b: float, t_max: float,
               settings: ContinuationSettings) -> tuple[np.ndarray, int] | None:
    """The fold of pair n on a scan line between a and b of the scanned parameter (pair n exists at one end).

    The zero T0,n,a is followed along the scan line (fixed other parameter) by
    continuation of R1 = 0 in (T, scanned parameter) until dR1/dT = 0.
    """

    def at(v: float) -> Parameters:
        return plane.at(v, fixed) if axis == 0 else plane.at(fixed, v)

    exists_a = _pair_exists(at(a), n, t_max)
    v_exist = a if exists_a else b
    zeros = [z for z in f1_zeros(at(v_exist), t_max) if z.n == n]
    if not zeros:
        return None

    def res1(y):
        return np.array([regularised_residual(at(y[1]), float(y[0]), 0.0)[0][0]])

    def slope(y):
        return float(regularised_residual(at(y[1]), float(y[0]), 0.0)[1][0, 0])

    lo, hi = min(a, b), max(a, b)
    events = [
        EventFunction("fold", slope, terminal=True),
        EventFunction("lo", lambda y: y[1] - lo, terminal=True),
        EventFunction("hi", lambda y: hi - y[1], terminal=True),
        EventFunction("t", lambda y: t_max - y[0], terminal=True),
    ]
    direction = 1.0 if v_exist == a else -1.0
    try:
        res = continue_curve(res1, [zeros[0].T, v_exist], direction=direction, events=events, settings=settings,
                             weights=[1.0, 1.0 / (hi - lo)], param_index=1)
    except CorrectionError:
        return None
    folds = [e for e in res.events if e.name == "fold" and e.continuous]
    if not folds:
        return None
    T, v = folds[-1].y
    y = np.array([T, v, fixed]) if axis == 0 else np.array([T, fixed, v])
    return y, _held(y, axis)


def fold_curve(
    params: Parameters,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    *,
    n: int = 1,
    t_max: float = 12.0,
    n_seeds: int = 7,
    n_scan: int = 41,
    settings: ContinuationSettings | None = None,
) -> tuple[Codim2Curve, tuple[BranchEvent, ...]]:
    """The fold curve of the pair n (gamma_F,n in the (gamma, omega) plane), and where it meets the DIB curve.

    Parameters
    ----------
    params : Parameters
        The other parameters.
    param : (str, str)
        The plane (p1, p2).
    ranges : ((float, float), (float, float)), optional
        The box; `DEFAULT_RANGES` when omitted.
    n : int
        Index of the pair of zeros of F1.
    t_max : float
        Largest period considered.
    n_seeds : int
        Number of p2 values at which folds are searched along p1.
    n_scan : int
        Grid of p1 values scanned for the existence of the pair.
    settings : ContinuationSettings, optional

    Returns
    -------
    curve : Codim2Curve
    points : tuple of BranchEvent
        The ``fold-dib`` points.

    Raises
    ------
    ParameterError
        Naming the first argument that is not of the kind above: ``n`` from 1 to `MAX_PAIR`, ``t_max`` a
        period within the limit of the flight at every corner of the box (`_Plane.check_t_max`),
        ``n_seeds`` from 1 to `MAX_SEEDS`, ``n_scan`` from 2 to `MAX_SCAN`.
    """
    plane = _Plane(params, param, ranges)
    n = _check_pair("n", n)
    t_max = plane.check_t_max(t_max)
    settings = settings_or_default(settings, ContinuationSettings, _settings)
    n_seeds, n_scan = _check_scan(n_seeds, n_scan)
    seeds = []
    for fixed, grid, axis in _scan_lines(plane, n_seeds, n_scan):
        ex = [_pair_exists(plane.at(v, fixed) if axis == 0 else plane.at(fixed, v), n, t_max) for v in grid]
        for i in range(len(grid) - 1):
            if ex[i] != ex[i + 1]:
                s = _fold_seed(plane, n, fixed, axis, float(grid[i]), float(grid[i + 1]), t_max, settings)
                if s is not None:
                    seeds.append(s)

    def residual(y):
        r, j = regularised_residual(plane.at(y[1], y[2]), float(y[0]), 0.0)
        return np.array([r[0], j[0, 0]])

    events = plane.box_events() + [
        EventFunction("t-max", lambda y: t_max - y[0], terminal=True),
        EventFunction("t-min", lambda y: y[0] - 1e-3, terminal=True),
        EventFunction("dib", plane.dib_value),
    ]
    weights = np.array([1.0, 1.0 / plane.span(0), 1.0 / plane.span(1)])
    pieces, ends, found = _trace(residual, seeds, events, weights, settings)
    points = tuple(
        _point("fold-dib", plane.params, float(e.y[1]), float(e.y[2]), float(e.y[0]))
        for e in found
        if e.name == "dib" and e.continuous and not e.terminal
    )
    curve = Codim2Curve(name=f"fold_{n}", kind="fold", params=plane.params, pieces=tuple(pieces), ends=tuple(ends))
    return curve, _unique(points)


# ---------------------------------------------------------------------------
# Coalescence curves (a with c, b with d)
# ---------------------------------------------------------------------------

#: The coalescences: the zero of F1 the two orbits share (kind of `rotorcontact.maps.impact_map.F1Zero`).
COALESCENCES = {"ac": "a", "bd": "b"}


def _zero_of(p: Parameters, n: int, kind: str, t_max: float):
    try:
        zeros = f1_zeros(p, t_max)
    except (ParameterError, RuntimeError):
        return None
    return next((z for z in zeros if z.n == n and z.kind == kind), None)


def coalescence_curves(
    params: Parameters,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    *,
    n: int = 1,
    t_max: float = 12.0,
    n_seeds: int = 7,
    n_scan: int = 41,
    settings: ContinuationSettings | None = None,
) -> tuple[Codim2Curve, Codim2Curve]:
    """Where B_n,a meets B_n,c and where B_n,b meets B_n,d: the roots of the quadratic in rdot merge.

    The two orbits of a coalescence share a zero T of F1 and are the two roots in
    rdot of the quadratic Q (MODEL.md §5); they coalesce where its discriminant
    vanishes, and beyond the curve neither exists. Unknowns (T, rdot, p1, p2),
    equations R1 = R2 = 0 and dR2/drdot = 0 of the regularised system of
    `rotorcontact.maps.orbit_system` (the ``ac-coalescence`` test function of
    the one-impact branches). Seeds: sign changes of the discriminant at the
    zero T0,n,a (or T0,n,b) along the scan lines. The solution curve passes
    smoothly through the fold of F1 where T0,n,a and T0,n,b merge, so one curve
    can be a-c on one side and b-d on the other; its points are split by the
    kind of their zero (the sign of dR1/dT), the fold of F1 lying between the
    last point of one part and the first of the other.

    Parameters as in `fold_curve`.

    Returns
    -------
    (Codim2Curve, Codim2Curve)
        ``"coalescence_ac_<n>"`` and ``"coalescence_bd_<n>"``, of kind ``"coalescence"``.

    Raises
    ------
    ParameterError
        As `fold_curve`.
    """
    plane = _Plane(params, param, ranges)
    n = _check_pair("n", n)
    t_max = plane.check_t_max(t_max)
    settings = settings_or_default(settings, ContinuationSettings, _settings)
    n_seeds, n_scan = _check_scan(n_seeds, n_scan)

    def residual(y):
        r, j = regularised_residual(plane.at(y[2], y[3]), float(y[0]), float(y[1]))
        return np.array([r[0], r[1], j[1, 1]])

    seeds = []
    for kind in COALESCENCES.values():
        for fixed, grid, axis in _scan_lines(plane, n_seeds, n_scan):
            def at(v, fixed=fixed, axis=axis):
                return plane.at(v, fixed) if axis == 0 else plane.at(fixed, v)

            def disc(v, at=at, kind=kind):
                z = _zero_of(at(v), n, kind, t_max)
                return None if z is None else rdot_roots(at(v), z.T)[0]

            for lo, hi in _brackets(disc, grid):
                v_in = lo if disc(lo) > 0.0 else hi  # the side where the two roots exist
                z = _zero_of(at(v_in), n, kind, t_max)
                roots = rdot_roots(at(v_in), z.T)[1]
                y = np.concatenate([[z.T, 0.5 * (roots[0] + roots[-1])], [v_in, fixed] if axis == 0 else [fixed, v_in]])
                index = _held(y, axis)
                try:
                    y = correct_fixed(residual, y, index, settings=settings)
                except CorrectionError:
                    continue
                seeds.append((y, index))
    events = plane.box_events() + [
        EventFunction("t-max", lambda y: t_max - y[0], terminal=True),
        EventFunction("t-min", lambda y: y[0] - 1e-3, terminal=True),
    ]
    weights = np.array([1.0, 1.0, 1.0 / plane.span(0), 1.0 / plane.span(1)])
    pieces, ends, _ = _trace(residual, seeds, events, weights, settings)
    split: dict[str, list[np.ndarray]] = {"ac": [], "bd": []}
    for piece in pieces:
        kinds = ["ac" if regularised_residual(plane.at(y[2], y[3]), float(y[0]), float(y[1]))[1][0, 0] < 0.0
                 else "bd" for y in piece]
        start = 0
        for i in range(1, len(piece) + 1):
            if i == len(piece) or kinds[i] != kinds[start]:
                split[kinds[start]].append(piece[start:i])
                start = i
    return tuple(Codim2Curve(name=f"coalescence_{pair}_{n}", kind="coalescence", params=plane.params,
                             pieces=tuple(split[pair]), ends=tuple(ends)) for pair in ("ac", "bd"))


def coalescence_curve(params: Parameters, param: Sequence[str] = ("gamma", "omega"), ranges=None, *,
                      pair: str = "ac", **kw) -> Codim2Curve:
    """One of `coalescence_curves`: ``pair`` ``"ac"`` or ``"bd"``.

    Raises
    ------
    ParameterError
        Unless ``pair`` is one of the two; otherwise as `coalescence_curves`.
    """
    if pair not in COALESCENCES:
        raise ParameterError(f"pair = {pair!r} is invalid; allowed: 'ac', 'bd'")
    ac, bd = coalescence_curves(params, param, ranges, **kw)
    return ac if pair == "ac" else bd


# ---------------------------------------------------------------------------
# The DIB curve
# ---------------------------------------------------------------------------


def dib_curve(
    params: Parameters,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    *,
    n_seeds: int = 7,
    n_scan: int = 41,
    settings: ContinuationSettings | None = None,
) -> Codim2Curve:
    """The boundary-equilibrium (NSFH/DIB) curve |k|^2 = 1 in the plane (p1, p2).

    In the (gamma, omega) plane it is gamma_DIB(omega) = sqrt(rho^2 - (1 - omega^2)^2).
    Parameters as in `fold_curve`.

    Raises
    ------
    ParameterError
        As `fold_curve`.
    """
    plane = _Plane(params, param, ranges)
    settings = settings_or_default(settings, ContinuationSettings, _settings)
    seeds = []
    for fixed, grid, axis in _scan_lines(plane, *_check_scan(n_seeds, n_scan)):
        def g(v, fixed=fixed, axis=axis):
            return dib_function(plane.at(v, fixed) if axis == 0 else plane.at(fixed, v))

        for lo, hi in _brackets(g, grid):
            v = brentq(g, lo, hi, xtol=1e-14, rtol=4 * np.finfo(float).eps)
            y = np.array([v, fixed] if axis == 0 else [fixed, v])
            seeds.append((y, _held(y, axis)))

    def residual(y):
        return np.array([dib_function(plane.at(y[0], y[1]))])

    weights = np.array([1.0 / plane.span(0), 1.0 / plane.span(1)])
    pieces, ends, _ = _trace(residual, seeds, plane.box_events(), weights, settings)
    return Codim2Curve(name="dib", kind="dib", params=plane.params, pieces=tuple(pieces), ends=tuple(ends))


# ---------------------------------------------------------------------------
# Grazing curves
# ---------------------------------------------------------------------------


def _orbit_of(p: Parameters, label: str, t_max: float):
    for o in one_impact_orbits(p, t_max):
        if o.label == label:
            return o
    return None


def _grazing_residual(plane: _Plane):
    def residual(y):
        T, r, tg, v1, v2 = (float(x) for x in y)
        p = plane.at(v1, v2)
        res, _ = regularised_residual(p, T, r)
        theta, thetadot = orbit_angles(p, T, r)
        u0, du0 = post_impact_state(p, (theta, r, thetadot), law=IDEAL)
        k = p.k
        v, dv = propagate(u0 - k, du0, tg, p.gamma, p.omega)
        u = k + v
        return np.array([res[0], res[1], abs(u) ** 2 - 1.0, (u.conjugate() * dv).real])

    return residual


def grazing_curve(
    params: Parameters,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    *,
    orbit: str = "B1,d",
    t_max: float = 12.0,
    n_seeds: int = 7,
    n_scan: int = 41,
    settings: ContinuationSettings | None = None,
) -> tuple[Codim2Curve, tuple[BranchEvent, ...]]:
    """The grazing curve of one orbit: its largest interior maximum of r equals 1.

    Parameters as in `fold_curve`, and

    orbit : str
        The orbit label, ``"B1,d"`` etc.

    Returns
    -------
    curve : Codim2Curve
        Named ``"grazing_B1d"`` (the label without its comma).
    points : tuple of BranchEvent
        ``grazing-dib`` and ``fold-grazing`` points.

    Raises
    ------
    ParameterError
        As `fold_curve`, and unless ``orbit`` is an orbit label.
    """
    plane = _Plane(params, param, ranges)
    t_max = plane.check_t_max(t_max)
    settings = settings_or_default(settings, ContinuationSettings, _settings)
    _check_label(orbit)
    seeds = []
    for fixed, grid, axis in _scan_lines(plane, *_check_scan(n_seeds, n_scan)):
        def at(v, fixed=fixed, axis=axis):
            return plane.at(v, fixed) if axis == 0 else plane.at(fixed, v)

        def g(v, at=at):
            o = _orbit_of(at(v), orbit, t_max)
            if o is None or not o.admissible or o.r_max_interior is None:
                return None
            return o.r_max_interior - 1.0

        def g_nan(v, g=g):
            val = g(v)
            return math.nan if val is None else val

        for lo, hi in _brackets(g, grid):
            try:
                v = brentq(g_nan, lo, hi, xtol=1e-13)
            except (ValueError, RuntimeError):
                continue
            p = at(v)
            o = _orbit_of(p, orbit, t_max)
            if o is None:
                continue
            ext = flight_extrema(p, o.state, o.T, law=IDEAL)
            if not np.any(ext.maxima):
                continue
            i = int(np.argmax(np.where(ext.maxima, ext.radii, -np.inf)))
            pv = (v, fixed) if axis == 0 else (fixed, v)
            y = np.array([o.T, o.rdot, float(ext.times[i]), pv[0], pv[1]])
            seeds.append((y, _held(y, axis)))

    residual = _grazing_residual(plane)

    def slope(y):
        return float(regularised_residual(plane.at(y[3], y[4]), float(y[0]), float(y[1]))[1][0, 0])

    def root_side(y):
        return float(regularised_residual(plane.at(y[3], y[4]), float(y[0]), float(y[1]))[1][1, 1])

    events = plane.box_events() + [
        EventFunction("t-max", lambda y: t_max - y[0], terminal=True),
        EventFunction("virtual", lambda y: y[1], terminal=True),
        EventFunction("tg-low", lambda y: y[2], terminal=True),
        EventFunction("tg-high", lambda y: y[0] - y[2], terminal=True),
        EventFunction("fold", slope, terminal=True),
        EventFunction("coalescence", root_side, terminal=True),
        EventFunction("dib", plane.dib_value),
    ]
    weights = np.array([1.0, 1.0, 1.0, 1.0 / plane.span(0), 1.0 / plane.span(1)])
    pieces, ends, found = _trace(residual, seeds, events, weights, settings)
    points = []
    for e in found:
        if not e.continuous:
            continue
        if e.name == "dib":
            points.append(_point("grazing-dib", plane.params, float(e.y[3]), float(e.y[4]), float(e.y[0])))
        elif e.name == "fold":
            points.append(_point("fold-grazing", plane.params, float(e.y[3]), float(e.y[4]), float(e.y[0])))
    name = "grazing_" + orbit.replace(",", "")
    curve = Codim2Curve(name=name, kind="grazing", params=plane.params, pieces=tuple(pieces), ends=tuple(ends))
    return curve, _unique(tuple(points))


# ---------------------------------------------------------------------------
# The diagram
# ---------------------------------------------------------------------------


def codim2_diagram(
    params: Parameters,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    *,
    folds: Sequence[int] = (1,),
    grazing: Sequence[str] = ("B1,d",),
    t_max: float = 12.0,
    n_seeds: int = 7,
    n_scan: int = 41,
    settings: ContinuationSettings | None = None,
) -> Codim2Diagram:
    """Fold curves of the pairs ``folds``, the DIB curve and the grazing curves of ``grazing``, with intersections.

    Parameters
    ----------
    params : Parameters
        The other parameters.
    param : (str, str)
        The plane, default (gamma, omega).
    ranges : ((float, float), (float, float)) or dict, optional
        The box: a (low, high) for p1 and one for p2, or a dict of them by parameter name;
        `DEFAULT_RANGES` when omitted.
    folds : sequence of int
        Pairs n whose fold curves are computed.
    grazing : sequence of str
        Orbits whose grazing curves are computed.
    t_max, n_seeds, n_scan, settings
        As in `fold_curve`.

    Returns
    -------
    Codim2Diagram

    Raises
    ------
    ParameterError
        As `fold_curve`, and unless ``folds`` lists pair indices (1 to `MAX_PAIR`) and ``grazing`` orbit
        labels.
    """
    plane = _Plane(params, param, ranges)
    t_max = plane.check_t_max(t_max)
    if isinstance(folds, (int, np.integer)) and not isinstance(folds, bool):
        folds = (folds,)  # one pair
    if isinstance(grazing, str):
        grazing = (grazing,)  # one orbit
    for name, given, example in (("folds", folds, "[1, 2]"), ("grazing", grazing, "['B1,d']")):
        if not isinstance(given, (list, tuple)):
            raise ParameterError(f"{name} = {given!r} is invalid; allowed: a list such as {example} (empty for none)")
    for label in grazing:
        _check_label(label)
    for n in folds:
        _check_pair("folds", n)
    curves: dict[str, Codim2Curve] = {}
    points: list[BranchEvent] = []
    kw = dict(t_max=t_max, n_seeds=n_seeds, n_scan=n_scan, settings=settings)
    for n in folds:
        c, pts = fold_curve(params, plane.params, plane.ranges, n=n, **kw)
        curves[c.name] = c
        points.extend(pts)
    curves["dib"] = dib_curve(params, plane.params, plane.ranges, n_seeds=n_seeds, n_scan=n_scan,
                              settings=settings)
    for label in grazing:
        c, pts = grazing_curve(params, plane.params, plane.ranges, orbit=label, **kw)
        curves[c.name] = c
        points.extend(pts)
    pts = sorted(_unique(tuple(points)), key=lambda q: (q.kind, q.value))
    return Codim2Diagram(param=plane.params, events=tuple(pts), ranges=plane.ranges, base=params, curves=curves)


def dib_labels(
    diagram: Codim2Diagram,
    t_max: float,
    beb_kind: Callable[[Parameters], str | None],
) -> list[tuple[str, float, float]]:
    """What happens along the DIB curve: (text, p1, p2) at the middle of each run of equal kind.

    At a point of the DIB curve where the one-impact orbits of the first pair
    exist, the kind is ``"NSFH"`` (they are born there); elsewhere it is the
    boundary equilibrium bifurcation of the equilibria given by ``beb_kind``:
    ``"NSF"`` for ``"nonsmooth-fold"``, ``"Pers"`` for ``"persistence"``.
    Runs shorter than two points, and points of no kind, are not labelled.

    Parameters
    ----------
    diagram : Codim2Diagram
    t_max : float
        Largest period of the orbits looked for.
    beb_kind : callable
        ``beb_kind(params)``: the kind of the boundary equilibrium bifurcation at
        a point (`rotorcontact.analysis.equilibria.classify_beb_analytic`).

    Returns
    -------
    list of (str, float, float)

    Raises
    ------
    ParameterError
        Unless ``diagram`` is a `Codim2Diagram`, ``t_max`` a period within the limit of the flight over its
        box (`_Plane.check_t_max`) and ``beb_kind`` callable, returning text or None.
    """
    check_type("diagram", diagram, Codim2Diagram, "a Codim2Diagram (codim2_diagram)")
    t_max = _Plane(diagram.base, diagram.param, diagram.ranges).check_t_max(t_max)
    check_callable("beb_kind", beb_kind, "a function of the parameters returning the kind of the boundary "
                   "equilibrium bifurcation (text or None)")
    out: list[tuple[str, float, float]] = []
    curve = diagram.curves.get("dib")
    if curve is None:
        return out
    for piece in curve.pieces:
        kinds = []
        for v1, v2 in piece[:, -2:]:
            p = diagram.base.replace(**{diagram.param[0]: v1, diagram.param[1]: v2})
            if any(z.n == 1 for z in f1_zeros(p, t_max)):
                kinds.append("NSFH")
            else:
                kind = beb_kind(p)
                if not (kind is None or isinstance(kind, str)):
                    raise ParameterError(f"beb_kind = {quoted(beb_kind)} is invalid; allowed: a function returning "
                                         f"text or None (it returned {quoted(kind)})")
                kinds.append({"nonsmooth-fold": "NSF", "persistence": "Pers"}.get(kind, ""))
        i0 = 0
        for i in range(1, len(kinds) + 1):
            if i == len(kinds) or kinds[i] != kinds[i0]:
                if kinds[i0] and i - i0 >= 2:
                    mid = (i0 + i - 1) // 2
                    out.append((kinds[i0], float(piece[mid, -2]), float(piece[mid, -1])))
                i0 = i
    return out


# ---------------------------------------------------------------------------
# Regions
# ---------------------------------------------------------------------------


def region(params: Parameters, t_max: float = 12.0) -> str | None:
    """The region R1-R4 (module docstring) of the point ``params``, or None if it fits none."""
    check_params(params)
    t_max = _check_t_max(params, t_max)  # a bad t_max is refused, not taken for a point in no region
    xr_admissible = dib_function(params) < 0.0  # |k| < 1
    orbits = []  # (small root?, rdot) of the orbits of the pair 1
    try:
        zeros = f1_zeros(params, t_max)
    except IsolationLimit:
        raise  # a t_max too large for this point: not a point in no region
    except ParameterError:
        return None  # the undamped resonance (gamma = 0, omega = 1): no regular equilibrium at all
    for z in zeros:
        if z.n == 1:
            roots = rdot_roots(params, z.T)[1]
            if not roots:
                # past an a-c or b-d coalescence curve the two orbits of this zero no longer exist: none of R1-R4
                return None
            orbits.extend([(True, roots[0]), (False, roots[-1])])
    if not orbits:
        return "R3" if xr_admissible else "R2"
    if not xr_admissible and all((r < 0.0) == small for small, r in orbits):
        return "R1"
    if xr_admissible and all(r > 0.0 for _, r in orbits):
        return "R4"
    return None


def classify_plane(
    params: Parameters,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    shape: tuple[int, int] = (81, 81),
    t_max: float = 12.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Regions R1-R4 on a grid of the plane.

    Returns
    -------
    v1, v2 : numpy.ndarray
        The grid values of p1 and p2.
    labels : numpy.ndarray of object, shape (len(v2), len(v1))
        ``"R1"`` .. ``"R4"`` or None.
    """
    plane = _Plane(params, param, ranges)
    if not is_pair(shape):
        raise ParameterError(f"shape = {shape!r} is invalid; allowed: (n1, n2), two whole numbers >= 2")
    n1, n2 = (check_int(f"shape[{i}]", s, 2, MAX_PLANE_SIDE) for i, s in enumerate(shape))
    v1 = np.linspace(*plane.ranges[0], n1)
    v2 = np.linspace(*plane.ranges[1], n2)
    labels = np.empty((n2, n1), dtype=object)
    for j, b in enumerate(v2):
        for i, a in enumerate(v1):
            labels[j, i] = region(params.replace(**{plane.params[0]: a, plane.params[1]: b}), t_max)
    return v1, v2, labels


# ---------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------


def _check_label(orbit) -> str:
    if not isinstance(orbit, str) or re.fullmatch(r"B[1-9][0-9]*,[abcd]", orbit) is None:
        raise ParameterError(f"orbit = {orbit!r} is not an orbit label; allowed: 'B<n>,<a|b|c|d>', e.g. 'B1,d'")
    return orbit


def _unique(points: tuple[BranchEvent, ...]) -> tuple[BranchEvent, ...]:
    out: list[BranchEvent] = []
    for p in points:
        if any(q.kind == p.kind and abs(q.value[0] - p.value[0]) <= 1e-8 * (1 + abs(p.value[0]))
               and abs(q.value[1] - p.value[1]) <= 1e-8 * (1 + abs(p.value[1])) for q in out):
            continue
        out.append(p)
    return tuple(out)
