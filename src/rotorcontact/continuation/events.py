"""Event test functions along branches of one-impact orbits, and the typing of located events.

Test functions (all smooth where the orbit is, except the integer count of
extrema), evaluated at a point y = (T, rdot, lambda) of a branch:

* ``fold``: dR1/dT of the regularised equations (`rotorcontact.maps.orbit_system`);
  it has the sign of F1' and vanishes where F1 has a double zero;
* ``ac-coalescence``: dR2/drdot, with the sign of the quadratic's derivative
  at the root; it vanishes at a double root (zero discriminant);
* ``nsfh``: rdot itself;
* ``grazing``: r_max - 1, the largest interior maximum of r less 1;
* ``extrema-change``: the number of interior extrema of r (discrete);
* ``plus-one``, ``minus-one``, ``torus``: det(J - I), det(J + I) and
  prod_{i<j} (z_i z_j - 1) from the multipliers z of the Jacobian J of P_I.

The last five are evaluated on admissible orbits only (None on virtual ones)
unless virtual orbits are asked for. `classify_event` turns a located zero into
a reported type, dropping what is not a bifurcation: a sign change through a
pole (the multipliers grow without bound as rdot -> 0), a zero of rdot away
from the boundary equilibrium (|k| != 1: the resonance point at gamma = 0),
a +1 multiplier at a fold or coalescence (that is the fold), a real pair of
multipliers with product 1 (not a bifurcation).
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .engine import EventFunction, LocatedEvent
from ..maps.impact_map import IDEAL, flight_extrema, impact_map_jacobian
from ..maps.orbit_system import OneImpactSystem, label_of, orbit_angles, regularised_residual
from ..model.validation import check_bool, check_choice, check_float, check_type, complex_array, quoted, real_array
from .results import BranchEvent, check_interval

__all__ = ["BranchAnalyser", "at_turning_point", "bialternate_product", "branch_event_functions", "classify_event",
           "det_minus_identity", "det_plus_identity", "multiplier_kind", "multipliers_resolved", "report_events",
           "rotation_angle", "turning_points", "unit_pair_discriminant"]

# How close a multiplier must be to +-1 or to the unit circle at a located test-function zero.
_MULTIPLIER_TOL = 1e-6
#: Multiples of eps times the largest multiplier within which `multiplier_kind` takes a multiplier as +-1 or on
#: the unit circle: the rounding of the eigenvalues of a Jacobian whose norm is at least that multiplier.
EIGENVALUE_ROUNDING = 64.0
#: Above this rounding of the multipliers (`EIGENVALUE_ROUNDING` eps times the largest: a largest multiplier
#: beyond about 7e11) the others are not resolved, and `multiplier_kind` types no zero of a test function.
UNRESOLVED = 1e-2
# |k|^2 - 1 at a located rdot = 0 for it to be at the boundary equilibrium.
_BOUNDARY_TOL = 1e-7


@dataclass(frozen=True)
class _Core:
    """What the event functions need at a point (no labels, no plausibility).

    ``admissible`` is True also for virtual orbits when they are analysed.
    """

    admissible: bool
    r_max: float | None
    count: int
    multipliers: np.ndarray | None


#: The multiplier test functions: `det_minus_identity`, `det_plus_identity`, `bialternate_product`.
MULTIPLIER_TESTS = ("plus-one", "minus-one", "torus")


class MultiplierTests(abc.ABC):
    """The multiplier test functions at a point y, from ``self.multipliers(y)`` (None where undefined).

    The base of the problems whose branches are followed (`BranchAnalyser`, the system of
    `rotorcontact.continuation.multi_impact_branches`); a subclass provides `multipliers`.
    """

    @abc.abstractmethod
    def multipliers(self, y: np.ndarray) -> np.ndarray | None:
        """The multipliers at the point y, or None where they are not defined."""

    def plus_one(self, y: np.ndarray) -> float | None:
        """det(J - I) = prod (z_i - 1)."""
        z = self.multipliers(y)
        return None if z is None else det_minus_identity(z)

    def minus_one(self, y: np.ndarray) -> float | None:
        """det(J + I) = prod (z_i + 1)."""
        z = self.multipliers(y)
        return None if z is None else det_plus_identity(z)

    def torus(self, y: np.ndarray) -> float | None:
        """prod_{i<j} (z_i z_j - 1): zero where a complex pair is on the unit circle (or z_i z_j = 1)."""
        z = self.multipliers(y)
        return None if z is None else bialternate_product(z)


class BranchAnalyser(MultiplierTests):
    """The test functions along the branches of one system, with a cache per point.

    Parameters
    ----------
    system : OneImpactSystem
    virtual : bool
        Also evaluate the orbit-property functions (grazing, extrema,
        multipliers of the formal impact map) on virtual orbits.

    Raises
    ------
    ParameterError
        Unless ``system`` is a `rotorcontact.maps.orbit_system.OneImpactSystem` and ``virtual`` True or False.
    """

    def __init__(self, system: OneImpactSystem, virtual: bool = False):
        self.system = _check_system(system)
        self.virtual = check_bool("virtual", virtual)
        self._core: dict[bytes, _Core] = {}

    def core(self, y: np.ndarray) -> _Core:
        """Extrema of r and multipliers at the point y = (T, rdot, lambda) (cached)."""
        key = np.asarray(y, dtype=float).tobytes()
        c = self._core.get(key)
        if c is not None:
            return c
        p = self.system.params_at(y[2])
        T, r = float(y[0]), float(y[1])
        theta, thetadot = orbit_angles(p, T, r)
        state = (theta, r, thetadot)
        ext = flight_extrema(p, state, T, law=IDEAL)
        mult = None
        if r > 0.0 or self.virtual:
            _, jac, _ = impact_map_jacobian(p, state, T, law=IDEAL)
            mult = np.linalg.eigvals(jac)
        c = _Core(admissible=r > 0.0 or self.virtual, r_max=ext.r_max, count=ext.count, multipliers=mult)
        if len(self._core) > 20000:
            self._core.clear()
        self._core[key] = c
        return c

    def partials(self, y: np.ndarray) -> np.ndarray:
        """d(R1, R2)/d(T, rdot) of the regularised equations at y."""
        return regularised_residual(self.system.params_at(y[2]), float(y[0]), float(y[1]))[1]

    def multipliers(self, y: np.ndarray) -> np.ndarray | None:
        """The multipliers at y (None where they are not evaluated: virtual orbits)."""
        return self.core(y).multipliers

    # test functions ------------------------------------------------------------

    def fold(self, y: np.ndarray) -> float:
        """dR1/dT: the sign of F1', zero where F1 has a double zero."""
        return float(self.partials(y)[0, 0])

    def coalescence(self, y: np.ndarray) -> float:
        """dR2/drdot: negative at the smaller root, zero at a double root."""
        return float(self.partials(y)[1, 1])

    def rdot(self, y: np.ndarray) -> float:
        """The impact velocity."""
        return float(y[1])

    def grazing(self, y: np.ndarray) -> float | None:
        """r_max - 1 (None without an interior maximum, or on a virtual orbit)."""
        c = self.core(y)
        if not c.admissible or c.r_max is None:
            return None
        return c.r_max - 1.0

    def extrema_count(self, y: np.ndarray) -> int | None:
        """The number of interior extrema of r (None on a virtual orbit)."""
        c = self.core(y)
        return c.count if c.admissible else None



def _multipliers(z, least: int = 1) -> np.ndarray:
    """``z`` as a 1-d complex array of at least ``least`` multipliers, else a `ParameterError` naming z."""
    v = complex_array(z)
    if v is None or v.ndim != 1 or len(v) < least:
        raise ParameterError(f"z = {quoted(z)} is invalid; allowed: the multipliers, a sequence of at least "
                             f"{least} real or complex numbers")
    return v


def det_minus_identity(z: np.ndarray) -> float:
    """det(J - I) = prod (z_i - 1) from the multipliers z of J: zero where a multiplier is +1.

    Raises
    ------
    ParameterError
        Unless ``z`` is a sequence of at least one number.
    """
    return float(np.prod(_multipliers(z) - 1.0).real)


def det_plus_identity(z: np.ndarray) -> float:
    """det(J + I) = prod (z_i + 1) from the multipliers z of J: zero where a multiplier is -1.

    Raises
    ------
    ParameterError
        Unless ``z`` is a sequence of at least one number.
    """
    return float(np.prod(_multipliers(z) + 1.0).real)


def bialternate_product(z: np.ndarray) -> float:
    """prod_{i<j} (z_i z_j - 1), the determinant of the bialternate product J (.) J - I.

    Zero where a complex pair of multipliers lies on the unit circle (a
    Neimark-Sacker point) or where two real multipliers have product 1.

    Raises
    ------
    ParameterError
        Unless ``z`` is a sequence of at least two numbers (a product over pairs).
    """
    z = _multipliers(z, 2)
    prod = 1.0 + 0j
    for i in range(len(z)):
        for j in range(i + 1, len(z)):
            prod *= z[i] * z[j] - 1.0
    return float(prod.real)


def _rounding(z: np.ndarray) -> float:
    """The rounding of multipliers computed beside the largest of ``z``: `EIGENVALUE_ROUNDING` eps times it."""
    return EIGENVALUE_ROUNDING * np.finfo(float).eps * float(np.max(np.abs(z)))


def multipliers_resolved(z: np.ndarray) -> bool:
    """Whether the multipliers ``z`` (eigenvalues of one Jacobian) are resolved beside the largest: their
    rounding, `EIGENVALUE_ROUNDING` eps times the largest, is at most `UNRESOLVED`.

    Raises
    ------
    ParameterError
        Unless ``z`` is a sequence of at least one number.
    """
    return _rounding(_multipliers(z)) <= UNRESOLVED


def unit_pair_discriminant(z: np.ndarray) -> float:
    """(z_i + z_j)^2 - 4 z_i z_j of the pair of multipliers whose product is nearest 1: negative for a complex
    pair (on the unit circle: 4 cos^2 theta - 4), positive for a real pair, zero where the pair meets on the real
    axis (at -1 or +1 on a Neimark-Sacker curve: a strong resonance).

    Raises
    ------
    ParameterError
        Unless ``z`` is a sequence of at least two numbers.
    """
    z = _multipliers(z, 2)
    i, j = min(((i, j) for i in range(len(z)) for j in range(i + 1, len(z))),
               key=lambda ij: abs(z[ij[0]] * z[ij[1]] - 1.0))
    s, q = z[i] + z[j], z[i] * z[j]
    return float((s * s - 4.0 * q).real)


def multiplier_kind(name: str, z: np.ndarray, tol: float = 1e-6) -> str | None:
    """What a located zero of a multiplier test function is, from the multipliers z there.

    ``name`` is ``"plus-one"`` (det(J - I)), ``"minus-one"`` (det(J + I)) or
    ``"torus"`` (the bialternate product). Returns ``"plus-one"`` when a
    multiplier is within ``tol`` of +1, ``"period-doubling"`` when one is
    within ``tol`` of -1, ``"neimark-sacker"`` when a complex pair is within
    ``tol`` of the unit circle, and None otherwise (a sign change through a
    pole, or a real pair with product 1: not a bifurcation). ``tol`` is
    widened to `EIGENVALUE_ROUNDING` eps times the largest multiplier, the
    rounding of the others beside it; where that exceeds `UNRESOLVED`, None
    (the multipliers cannot tell).

    Raises
    ------
    ParameterError
        Unless ``name`` is one of the three, ``z`` a sequence of at least one number and ``tol`` a finite
        number > 0.
    """
    name = check_choice("name", name, MULTIPLIER_TESTS)
    z = _multipliers(z)
    tol = check_float("tol", tol, 0.0, low_open=True)
    # the eigenvalues of J are computed to about eps |J|, and the largest multiplier is at most |J|: beside a
    # strongly unstable one (a long orbit deep in a cascade, 1e11) no multiplier is known to tol
    if not multipliers_resolved(z):
        return None  # the multipliers beside the largest are rounding: no bifurcation can be told
    tol = max(tol, _rounding(z))
    if name == "plus-one":
        return "plus-one" if np.min(np.abs(z - 1.0)) <= tol else None
    if name == "minus-one":
        return "period-doubling" if np.min(np.abs(z + 1.0)) <= tol else None
    pair = [x for x in z if abs(x.imag) > 1e-9 and abs(abs(x) - 1.0) <= tol]
    return "neimark-sacker" if pair else None


def rotation_angle(z: np.ndarray) -> float:
    """The angle in (0, pi) of the complex multiplier nearest the unit circle (a Neimark-Sacker point).

    Raises
    ------
    ParameterError
        Unless ``z`` is a sequence of numbers with at least one that is not real.
    """
    complex_ones = [x for x in _multipliers(z) if abs(x.imag) > 1e-9]
    if not complex_ones:
        raise ParameterError(f"z = {quoted(z)} is invalid; allowed: multipliers with a complex pair (a "
                             "Neimark-Sacker point)")
    pair = min(complex_ones, key=lambda x: abs(abs(x) - 1.0))
    return abs(math.atan2(pair.imag, pair.real))


def _check_system(system) -> OneImpactSystem:
    return check_type("system", system, OneImpactSystem, "a rotorcontact.maps.orbit_system.OneImpactSystem")


def _check_analyser(an) -> "BranchAnalyser":
    return check_type("an", an, BranchAnalyser, "a BranchAnalyser")


def _check_located(raw) -> list[LocatedEvent]:
    if not isinstance(raw, (list, tuple)) or not all(isinstance(e, LocatedEvent) for e in raw):
        raise ParameterError(f"raw = {quoted(raw)} is invalid; allowed: a list of LocatedEvent (the events of a "
                             "continuation)")
    return list(raw)


def _point(name: str, y) -> np.ndarray:
    """``y`` as a point (T, rdot, lambda) of a branch, else a `ParameterError` naming ``name``."""
    v = real_array(y)
    if v is None or v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ParameterError(f"{name} = {quoted(y)} is invalid; allowed: a point (T, rdot, lambda) of a branch, "
                             "three finite numbers")
    return v


def branch_event_functions(an: BranchAnalyser, start: float, stop: float, t_min: float, t_max: float,
                           rdot_max: float) -> list[EventFunction]:
    """Terminal events of the box (parameter range, t_min <= T <= t_max, |rdot| <= rdot_max) and the tests.

    Raises
    ------
    ParameterError
        Unless ``an`` is a `BranchAnalyser`, start < stop, 0 < t_min < t_max and rdot_max > 0 (finite numbers).
    """
    _check_analyser(an)
    start, stop = check_interval(start, stop)
    t_min = check_float("t_min", t_min, 0.0, low_open=True)
    t_max = check_float("t_max", t_max, t_min, low_open=True)
    rdot_max = check_float("rdot_max", rdot_max, 0.0, low_open=True)
    return [
        EventFunction("lower", lambda y: y[2] - start, terminal=True),
        EventFunction("upper", lambda y: stop - y[2], terminal=True),
        EventFunction("t-max", lambda y: t_max - y[0], terminal=True),
        EventFunction("t-min", lambda y: y[0] - t_min, terminal=True),
        EventFunction("rdot-max", lambda y: rdot_max - abs(y[1]), terminal=True),
        EventFunction("fold", an.fold),
        EventFunction("ac-coalescence", an.coalescence),
        EventFunction("nsfh", an.rdot),
        EventFunction("grazing", an.grazing),
        EventFunction("extrema-change", an.extrema_count, kind="discrete"),
        EventFunction("plus-one", an.plus_one),
        EventFunction("minus-one", an.minus_one),
        EventFunction("torus", an.torus),
    ]


def classify_event(e: LocatedEvent, an: BranchAnalyser, system: OneImpactSystem) -> tuple[str, str] | None:
    """The reported type of a located event and a detail string, or None to drop it.

    Raises
    ------
    ParameterError
        Unless ``e`` is a `LocatedEvent`, ``an`` a `BranchAnalyser` and ``system`` a `OneImpactSystem`.
    """
    check_type("e", e, LocatedEvent, "a LocatedEvent of a continuation")
    _check_analyser(an)
    _check_system(system)
    return _classify(e, an, system)


def _classify(e: LocatedEvent, an: BranchAnalyser, system: OneImpactSystem) -> tuple[str, str] | None:
    """`classify_event`, its arguments unchecked."""
    if e.terminal:
        return None
    increasing = e.y_before[2] <= e.y_after[2]
    if e.name == "extrema-change":
        lo, hi = (e.before, e.after) if increasing else (e.after, e.before)
        return "extrema-change", f"{int(lo)} -> {int(hi)} interior extrema as {system.param} increases"
    if not e.continuous:
        return None
    y = e.y
    if e.name in ("fold", "ac-coalescence", "grazing"):
        return e.name, ""
    if e.name == "nsfh":
        p = system.params_at(y[2])
        if abs(abs(p.k) ** 2 - 1.0) > _BOUNDARY_TOL:
            return None
        return "nsfh", ""
    z = an.multipliers(y)
    if z is None:
        return None
    stab = []
    for yy in ((e.y_before, e.y_after) if increasing else (e.y_after, e.y_before)):
        zz = an.multipliers(yy)
        stab.append(None if zz is None else bool(np.all(np.abs(zz) < 1.0)))
    change = "" if stab[0] == stab[1] or None in stab else (
        f"{'gain' if stab[1] else 'loss'} of stability as {system.param} increases")
    kind = multiplier_kind(e.name, z, _MULTIPLIER_TOL)
    if kind is None:
        return None
    if kind == "plus-one":
        return "branch-point", change
    if kind == "neimark-sacker":
        return "neimark-sacker", (change + ("; " if change else "") + f"angle {rotation_angle(z):.6g} rad")
    return kind, change


def turning_points(raw: list[LocatedEvent]) -> list[np.ndarray]:
    """The located folds and coalescences among ``raw``: where the branch turns in the parameter.

    Raises
    ------
    ParameterError
        Unless ``raw`` is a list of `LocatedEvent`.
    """
    return [e.y for e in _check_located(raw) if e.name in ("fold", "ac-coalescence") and e.continuous]


def at_turning_point(y: np.ndarray, turning: list[np.ndarray]) -> bool:
    """Whether the point y = (T, rdot, lambda) is one of the turning points (relative distance 1e-6).

    A multiplier +1 located there is the fold itself, not a separate branch point.

    Raises
    ------
    ParameterError
        Unless ``y`` and every item of the list ``turning`` are points (T, rdot, lambda).
    """
    y = _point("y", y)
    if not isinstance(turning, (list, tuple)):
        raise ParameterError(f"turning = {quoted(turning)} is invalid; allowed: a list of points (T, rdot, lambda) "
                             "(turning_points)")
    turning = [_point(f"turning[{i}]", t) for i, t in enumerate(turning)]
    return any(np.linalg.norm((y - t) / np.array([1.0 + abs(t[0]), 1.0 + abs(t[1]), 1.0])) < 1e-6
               for t in turning)


def report_events(raw: list[LocatedEvent], an: BranchAnalyser, system: OneImpactSystem) -> tuple[BranchEvent, ...]:
    """The reported events (typed, labelled, sorted by value, without duplicates) from the located ones.

    Raises
    ------
    ParameterError
        Unless ``raw`` is a list of `LocatedEvent`, ``an`` a `BranchAnalyser` and ``system`` a
        `OneImpactSystem`.
    """
    turning = turning_points(raw)
    _check_analyser(an)
    _check_system(system)
    out: list[BranchEvent] = []
    for e in raw:
        kind = _classify(e, an, system)
        if kind is None:
            continue
        typ, detail = kind
        if typ in ("grazing", "extrema-change", "branch-point", "period-doubling", "neimark-sacker"):
            if not an.virtual and not (e.y[1] > 0.0):
                continue
        if typ == "branch-point" and at_turning_point(e.y, turning):
            continue
        labels = set()
        for yy in (e.y_before, e.y_after):
            p = system.params_at(yy[2])
            n, b = label_of(p, float(yy[0]), float(yy[1]))
            labels.add((n, b))
        orbits = tuple(f"B{n},{b}" for n, b in sorted(labels))
        out.append(BranchEvent(kind=typ, value=float(e.parameter), param=system.param, orbits=orbits,
                               T=float(e.y[0]), rdot=float(e.y[1]), detail=detail, accuracy=float(e.bracket)))
    # the same event met by two runs (a seed's two directions share their start)
    out.sort(key=lambda ev: (ev.value, ev.kind, ev.orbits))
    unique: list[BranchEvent] = []
    for ev in out:
        if any(u.kind == ev.kind and u.orbits == ev.orbits and abs(u.value - ev.value) <= 1e-8
               and abs(u.T - ev.T) <= 1e-6 * (1.0 + abs(ev.T)) for u in unique):
            continue
        unique.append(ev)
    return tuple(unique)
