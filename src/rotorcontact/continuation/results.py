"""Result types of the continuation layer: special points and branch results.

`BranchEvent` is the one type of a special point met along a continued curve:
a bifurcation along a branch of orbits (`rotorcontact.continuation.branches`,
`rotorcontact.continuation.multi_impact_branches`), a fold of the zeros of F1
(`rotorcontact.continuation.zero_curves`) or an intersection of curves in a
plane of two parameters (`rotorcontact.continuation.codim2`). `BranchResult`
is the base of every branch result: the continuation parameter(s), the
special points, and one serialisation, `branch_to_dict`.

`OrbitBranches` holds the computed curves of one-impact orbits (`OrbitCurve`:
the orbits along one continuation) and their events. `OrbitBranches.branch`
regroups the points by orbit label (`LabelBranch`), in connected pieces; its
``to_dict`` is the ``rotorcontact branches --json`` contract.
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..maps.impact_map import ImpactOrbit
from ..maps.orbit_system import BRANCH_PARAMETERS
from ..model.params import Parameters, check_finite
from ..model.validation import check_choice, check_params, check_type, quoted

__all__ = [
    "EVENT_TYPES",
    "EVENT_KINDS",
    "POINT_TYPES",
    "ORBIT_COLUMNS",
    "BranchEvent",
    "BranchResult",
    "branch_to_dict",
    "OrbitEvent",
    "OrbitCurve",
    "LabelBranch",
    "OrbitBranches",
    "check_param_range",
    "check_interval",
]

#: Types of the events reported along branches of one-impact orbits.
EVENT_TYPES = (
    "fold",
    "nsfh",
    "grazing",
    "branch-point",
    "period-doubling",
    "neimark-sacker",
    "extrema-change",
    "ac-coalescence",
)
#: Types of the intersection points of curves in a plane of two parameters
#: (`rotorcontact.continuation.codim2`).
POINT_TYPES = ("fold-dib", "grazing-dib", "fold-grazing")
#: Every kind of `BranchEvent`: those of one-impact branches, ``"slip"`` of multi-impact branches (whose
#: other kinds are among the one-impact ones) and the intersection points of two-parameter curves.
EVENT_KINDS = EVENT_TYPES + ("slip",) + POINT_TYPES
#: The orbit attributes of `OrbitCurve.column`: those that are numbers (or True, False or None).
ORBIT_COLUMNS = ("T", "theta", "rdot", "thetadot", "n", "r_max_interior", "interior_extrema", "admissible",
                 "plausible", "slipping", "stable", "friction_reverses")


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


@dataclass(frozen=True)
class BranchEvent:
    """A special point along a continued curve.

    Attributes
    ----------
    kind : str
        What happens there: along branches of one-impact orbits one of
        `EVENT_TYPES`; along branches of multi-impact orbits ``"fold"``,
        ``"period-doubling"``, ``"neimark-sacker"``, ``"grazing"`` or
        ``"slip"``; ``"fold"`` for the zeros of F1; in a plane of two
        parameters one of `rotorcontact.continuation.codim2.POINT_TYPES`.
    value : float or tuple of float
        The continuation parameter there (one value per name of ``param``).
    param : str or tuple of str
        The continuation parameter, or the two parameters of the plane.
    orbits : tuple of str
        Labels of the orbits involved (both sides of a fold or coalescence).
    detail : str
        A short description (for example the stability on either side).
    T : float or None
        Period of the orbit at the event (the double zero for a fold of F1).
    rdot : float or None
        Impact velocity at the event.
    accuracy : float
        Width of the final bracket in the parameter.
    n : int or None
        Index of the pair of zeros of F1 (folds of the zeros of F1).
    orbit : object or None
        The computed orbit at the event (multi-impact branches; None where it
        could not be built).
    impacts : int or None
        Impacts per period of the orbits of the branch (branches of multi-impact
        orbits; written as ``"impacts"`` in JSON when set).

    Raises
    ------
    ParameterError
        Unless ``kind`` is one of `EVENT_KINDS`, ``param`` a parameter name (``value`` then a number) or a
        tuple of names (``value`` a tuple of as many numbers) and ``orbits`` a tuple of labels.
    """

    kind: str
    value: float | tuple[float, ...]
    param: str | tuple[str, ...]
    orbits: tuple[str, ...] = ()
    detail: str = ""
    T: float | None = None
    rdot: float | None = None
    accuracy: float = 0.0
    n: int | None = None
    orbit: Any = field(default=None, repr=False, compare=False)
    impacts: int | None = None

    def __post_init__(self) -> None:
        check_choice("kind", self.kind, EVENT_KINDS)
        if isinstance(self.param, str):
            if not _is_number(self.value):
                raise ParameterError(f"value = {quoted(self.value)} is invalid; allowed: a number, the value of "
                                     f"{self.param} at the event")
        elif not (isinstance(self.param, tuple) and self.param and all(isinstance(q, str) for q in self.param)):
            raise ParameterError(f"param = {quoted(self.param)} is invalid; allowed: a parameter name, or a tuple of "
                                 "names (a plane of two parameters)")
        elif not (isinstance(self.value, tuple) and len(self.value) == len(self.param)
                  and all(_is_number(v) for v in self.value)):
            raise ParameterError(f"value = {quoted(self.value)} is invalid; allowed: a tuple of {len(self.param)} "
                                 f"numbers, the values of {', '.join(self.param)} at the event")
        if not isinstance(self.orbits, tuple) or not all(isinstance(o, str) for o in self.orbits):
            raise ParameterError(f"orbits = {quoted(self.orbits)} is invalid; allowed: a tuple of orbit labels")

    @property
    def type(self) -> str:
        """`kind` (the name used by the JSON output)."""
        return self.kind

    @property
    def params(self) -> tuple[str, ...]:
        """`param` as a tuple (the plane of a two-parameter point)."""
        return (self.param,) if isinstance(self.param, str) else tuple(self.param)

    @property
    def values(self) -> tuple[float, ...]:
        """`value` as a tuple, one entry per name of `params`."""
        return (self.value,) if isinstance(self.param, str) else tuple(self.value)

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of the event (see `event_to_dict`)."""
        return event_to_dict(self)


def event_to_dict(event: BranchEvent) -> dict[str, Any]:
    """The JSON object of a special point.

    Along one parameter (the ``branches --json`` contract) ``{"type", "value",
    "orbits"}`` (and ``"impacts"`` on branches of multi-impact orbits); in a
    plane of two parameters (the ``codim2 --json`` contract) ``{"type", p1:
    value1, p2: value2}``.
    """
    out: dict[str, Any] = {"type": event.kind}
    if isinstance(event.param, str):
        out["value"] = event.value
        out["orbits"] = list(event.orbits)
        if event.impacts is not None:
            out["impacts"] = event.impacts
    else:
        out.update(zip(event.param, event.value))
    return out


#: The former name of `BranchEvent` along branches of one-impact orbits.
OrbitEvent = BranchEvent


@dataclass(frozen=True)
class BranchResult(abc.ABC):
    """What every branch result holds: the continuation parameter(s) and the special points.

    An abstract base: each result provides `curves_dict`.

    Attributes
    ----------
    param : str or tuple of str
        The continuation parameter (a tuple of two names for a plane of two parameters).
    events : tuple of BranchEvent
        The special points, in the order of the result.
    """

    param: str | tuple[str, ...]
    events: tuple[BranchEvent, ...]

    @abc.abstractmethod
    def curves_dict(self) -> Any:
        """The curves in JSON form (the part of `to_dict` beside the special points)."""

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON (`branch_to_dict`)."""
        return branch_to_dict(self)


def branch_to_dict(result: BranchResult) -> dict[str, Any]:
    """The JSON object of a branch result.

    Along one parameter: ``{"param", "events", "branches"}`` (the ``branches
    --json`` contract for `OrbitBranches`); in a plane of two parameters:
    ``{"curves", "points"}`` (the ``codim2 --json`` contract). Events are
    written by `event_to_dict`.

    Raises
    ------
    ParameterError
        Unless ``result`` is a `BranchResult`.
    """
    check_type("result", result, BranchResult, "a branch result (OrbitBranches, MultiImpactBranches, "
               "F1ZeroCurves, Codim2Diagram ...)")
    events = [event_to_dict(e) for e in result.events]
    curves = result.curves_dict()
    if isinstance(result.param, str):
        return {"param": result.param, "events": events, "branches": curves}
    return {"curves": curves, "points": events}


@dataclass(frozen=True)
class OrbitCurve:
    """One computed solution curve: a sequence of orbits along the parameter.

    Attributes
    ----------
    param : str
        The parameter varied.
    values : numpy.ndarray
        The parameter at each point (located event points included).
    orbits : tuple of ImpactOrbit
        The orbit at each point.
    extrema : tuple of (numpy.ndarray, numpy.ndarray)
        Radii of the interior extrema of r at each point, and which are maxima.
    event_index : tuple of (int, str)
        Positions of located event points in the sequence, with the event type.
    ends : tuple of str
        Why the continuation ended in each direction (``"terminal: t-max"``, ...).
    """

    param: str
    values: np.ndarray = field(repr=False)
    orbits: tuple[ImpactOrbit, ...] = field(repr=False)
    extrema: tuple[tuple[np.ndarray, np.ndarray], ...] = field(repr=False)
    event_index: tuple[tuple[int, str], ...]
    ends: tuple[str, str]

    def column(self, name: str) -> np.ndarray:
        """An orbit attribute along the curve as an array (None -> nan).

        Raises
        ------
        ParameterError
            Unless ``name`` is one of `ORBIT_COLUMNS`.
        """
        check_choice("name", name, ORBIT_COLUMNS)
        out = [getattr(o, name) for o in self.orbits]
        return np.array([math.nan if v is None else v for v in out], dtype=float)

    @property
    def labels(self) -> tuple[str, ...]:
        """Orbit label at each point."""
        return tuple(o.label for o in self.orbits)


@dataclass(frozen=True)
class LabelBranch:
    """All points of one orbit label, in pieces separated by NaN (None for ``stable``).

    Attributes
    ----------
    label : str
    values, T, theta, rdot, thetadot, r_max_interior, max_multiplier : numpy.ndarray
        NaN marks a break between pieces (and r_max / multipliers that do not exist).
    admissible, plausible : numpy.ndarray of bool
        False at breaks.
    stable : numpy.ndarray of object
        True / False, None where virtual and at breaks.
    interior_extrema : numpy.ndarray of int
        -1 at breaks.
    extrema : list
        Per point, (radii, maxima) of the interior extrema of r (None at breaks).
    """

    label: str
    values: np.ndarray = field(repr=False)
    T: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    rdot: np.ndarray = field(repr=False)
    thetadot: np.ndarray = field(repr=False)
    admissible: np.ndarray = field(repr=False)
    plausible: np.ndarray = field(repr=False)
    stable: np.ndarray = field(repr=False)
    r_max_interior: np.ndarray = field(repr=False)
    interior_extrema: np.ndarray = field(repr=False)
    max_multiplier: np.ndarray = field(repr=False)
    extrema: list = field(repr=False)

    def pieces(self) -> list[slice]:
        """Slices of the connected pieces."""
        breaks = np.flatnonzero(np.isnan(self.values))
        out, start = [], 0
        for b in list(breaks) + [len(self.values)]:
            if b > start:
                out.append(slice(start, b))
            start = b + 1
        return out


@dataclass(frozen=True)
class OrbitBranches(BranchResult):
    """Branches of one-impact orbits along a parameter range, with their events.

    Attributes
    ----------
    param : str
    events : tuple of BranchEvent
        Sorted by value.
    start, stop : float
        The parameter range.
    base : Parameters
        The other parameters.
    t_max : float
        Largest period followed.
    curves : tuple of OrbitCurve
    """

    start: float
    stop: float
    base: Parameters
    t_max: float
    curves: tuple[OrbitCurve, ...] = field(repr=False)

    def params_at(self, value: float) -> Parameters:
        """The parameters at ``value`` of the varied parameter."""
        return self.base.replace(**{self.param: value})

    @property
    def labels(self) -> tuple[str, ...]:
        """Every orbit label met, by pair n then branch letter."""
        found = {o.label: (o.n, o.branch) for c in self.curves for o in c.orbits}
        return tuple(sorted(found, key=lambda lab: found[lab]))

    def select(self, type: str | None = None, orbit: str | None = None) -> tuple[BranchEvent, ...]:
        """The events of one type and/or involving one orbit.

        Raises
        ------
        ParameterError
            Unless ``type`` is None or one of `EVENT_TYPES` and ``orbit`` None or an orbit label.
        """
        if type is not None:
            check_choice("type", type, EVENT_TYPES)
        check_type("orbit", orbit, str, "an orbit label such as 'B1,d'", optional=True)
        return tuple(
            e for e in self.events if (type is None or e.kind == type) and (orbit is None or orbit in e.orbits)
        )

    def branch(self, label: str) -> LabelBranch:
        """The points of one label, in pieces (see `LabelBranch`).

        Raises
        ------
        ParameterError
            Unless ``label`` is the label of an orbit met (one of `labels`).
        """
        check_type("label", label, str, "an orbit label such as 'B1,d'")
        rows: list[tuple | None] = []
        for curve in self.curves:
            pieces = _label_pieces(curve, label)
            for idx in pieces:
                if rows:
                    rows.append(None)
                for i in idx:
                    rows.append((curve.values[i], curve.orbits[i], curve.extrema[i]))
        if not rows:
            raise ParameterError(f"label = {label!r} is invalid; allowed: an orbit with a branch here: "
                                 f"{', '.join(self.labels) or 'none'}")

        def col(fn, empty=math.nan, dtype=float):
            return np.array([empty if r is None else fn(r) for r in rows], dtype=dtype)

        def mm(o: ImpactOrbit) -> float:
            return math.nan if o.multipliers is None else max(abs(z) for z in o.multipliers)

        return LabelBranch(
            label=label,
            values=col(lambda r: r[0]),
            T=col(lambda r: r[1].T),
            theta=col(lambda r: r[1].theta),
            rdot=col(lambda r: r[1].rdot),
            thetadot=col(lambda r: r[1].thetadot),
            admissible=col(lambda r: r[1].admissible, False, bool),
            plausible=col(lambda r: r[1].plausible, False, bool),
            stable=col(lambda r: r[1].stable, None, object),
            r_max_interior=col(lambda r: math.nan if r[1].r_max_interior is None else r[1].r_max_interior),
            interior_extrema=col(lambda r: r[1].interior_extrema, -1, int),
            max_multiplier=col(lambda r: mm(r[1])),
            extrema=[None if r is None else r[2] for r in rows],
        )

    def curves_dict(self) -> dict[str, dict[str, list]]:
        """Per label: the parameter, T, rdot, thetadot and stable along it (breaks between pieces as null)."""
        branches = {}
        for label in self.labels:
            b = self.branch(label)
            branches[label] = {
                self.param: [None if math.isnan(v) else float(v) for v in b.values],
                "T": [None if math.isnan(v) else float(v) for v in b.T],
                "rdot": [None if math.isnan(v) else float(v) for v in b.rdot],
                "thetadot": [None if math.isnan(v) else float(v) for v in b.thetadot],
                "stable": [None if s is None else bool(s) for s in b.stable],
            }
        return branches


def check_interval(start, stop) -> tuple[float, float]:
    """``(start, stop)`` as floats if they are finite numbers with start < stop.

    Raises
    ------
    ParameterError
        Naming the bad end (``stop`` where the range is empty).
    """
    start = check_finite("start", start)
    stop = check_finite("stop", stop)
    if not start < stop:
        raise ParameterError(f"stop = {stop!r} is invalid; allowed: a number > start = {start!r} (a range start .. "
                             "stop)")
    return start, stop


def check_param_value(name: str, base: Parameters, param: str, value: float) -> float:
    """``value`` if ``param`` may take it in ``base``, else a `ParameterError` naming ``name``."""
    try:
        base.replace(**{param: value})
    except ParameterError as exc:
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: a value that {param} may take ({exc})") from None
    return value


def check_param_range(param: str, base: Parameters, start, stop) -> tuple[float, float]:
    """``(start, stop)`` as floats if they are finite, start < stop and ``param`` may take both values.

    Raises
    ------
    ParameterError
        Unless ``param`` is one of `rotorcontact.maps.orbit_system.BRANCH_PARAMETERS` and ``base`` a
        `Parameters`; naming the bad end, or ``stop`` where the range is empty.
    """
    param = check_choice("param", param, BRANCH_PARAMETERS)
    check_params(base, "base")
    start, stop = check_interval(start, stop)
    return check_param_value("start", base, param, start), check_param_value("stop", base, param, stop)


def check_events(name: str, events) -> tuple[BranchEvent, ...]:
    """``events`` as a tuple if it is a list or tuple of `BranchEvent`, else a `ParameterError` naming ``name``."""
    if not isinstance(events, (tuple, list)) or not all(isinstance(e, BranchEvent) for e in events):
        raise ParameterError(f"{name} = {quoted(events)} is invalid; allowed: a tuple of BranchEvent (the period "
                             "doublings of one-impact branches)")
    return tuple(events)


def _label_pieces(curve: OrbitCurve, label: str) -> list[list[int]]:
    """Runs of consecutive points with ``label``; a fold or coalescence point joins both sides."""
    labels = curve.labels
    joins = {i for i, kind in curve.event_index if kind in ("fold", "ac-coalescence")}
    pieces: list[list[int]] = []
    current: list[int] = []
    for i, lab in enumerate(labels):
        if lab == label:
            if not current and i > 0 and (i - 1) in joins and labels[i - 1] != label:
                current.append(i - 1)
            current.append(i)
        elif current:
            if i in joins:
                current.append(i)
            pieces.append(current)
            current = []
    if current:
        pieces.append(current)
    return [p for p in pieces if len(p) >= 1]
