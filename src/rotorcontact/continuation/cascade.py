"""Period-doubling cascades: the doublings of an orbit, of its doubled orbit, and so on, with Feigenbaum's ratios.

A cascade starts at a period doubling of a seed branch (one-impact branches of
`rotorcontact.continuation.branches`, or p-impact branches of
`rotorcontact.continuation.multi_impact_families`). The branch born there is
followed away from it (branch switching) to its first period doubling, where the
next branch is born, and so on `depth` times. The doublings lambda_0,
lambda_1, ... of a cascade accumulate geometrically; the ratios of successive
intervals

    delta_k = (lambda_k - lambda_{k-1}) / (lambda_{k+1} - lambda_k)

tend to Feigenbaum's constant 4.6692... for a generic cascade of a smooth map.

Where it ends
-------------
* ``"accumulation"``: the last branch followed still has a period doubling;
  the accumulation point is estimated as lambda_n + (lambda_n - lambda_{n-1}) /
  (delta - 1), with delta the last ratio (Feigenbaum's constant where fewer than
  three doublings are known);
* ``"grazing"`` or ``"fold"``: the last branch reaches a grazing (P_I is not
  smooth there) or turns back at a fold before doubling again;
* ``"unresolved"``: the last branch is so unstable that its multipliers beside
  the largest are rounding (`rotorcontact.continuation.events.multipliers_resolved`:
  a largest multiplier beyond about 7e11, 128 impacts deep in a cascade), so its
  doublings cannot be told; the accumulation point is estimated as above from the
  doublings found;
* otherwise the end of the last branch's continuation (``"range"``: it left the
  parameter range; ``"step-failure"``; ``"period-doubling"``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..maps.multi_impact import MAX_ORBIT_IMPACTS, NewtonFailure
from ..model.params import Parameters, check_range
from ..model.validation import check_int, check_params, check_type, quoted, real_array
from .branches import check_n_seeds, orbit_branches
from .multi_impact_branches import check_grid
from .multi_impact_families import (
    MAX_DOUBLINGS,
    MultiImpactBranches,
    multi_impact_branches,
    one_impact_seed,
)
from .events import multipliers_resolved
from .results import BranchEvent, check_events, check_param_range

__all__ = ["FEIGENBAUM_DELTA", "Cascade", "cascades", "cascades_of", "feigenbaum_ratios"]

#: Feigenbaum's constant delta for period doubling of smooth unimodal-type maps.
FEIGENBAUM_DELTA = 4.669201609102990


@dataclass(frozen=True)
class Cascade:
    """One period-doubling cascade.

    Attributes
    ----------
    param : str
        The parameter.
    points : tuple of BranchEvent
        The period doublings, in order (``orbits`` the branch that doubles there).
    labels : tuple of str
        The branches born at the doublings, in order.
    ratios : tuple of float or None
        delta_k of successive intervals (empty with fewer than three points; None where an interval is
        zero).
    end : str
        ``"accumulation"``, ``"unresolved"``, ``"grazing"``, ``"fold"``, ``"range"``, ``"step-failure"`` or
        ``"period-doubling"`` (module docstring).
    end_value : float or None
        The parameter where it ends (the accumulation estimate, the grazing or the fold).
    accumulation : float or None
        The accumulation estimate (``end`` ``"accumulation"`` or ``"unresolved"``).
    """

    param: str
    points: tuple[BranchEvent, ...]
    labels: tuple[str, ...]
    ratios: tuple[float | None, ...]
    end: str
    end_value: float | None
    accumulation: float | None

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of the cascade (the ``cascade --json`` contract)."""
        return {
            "orbits": list(self.labels),
            "points": [{"type": e.kind, "value": e.value, "orbits": list(e.orbits), "impacts": e.impacts}
                       for e in self.points],
            "ratios": list(self.ratios),
            "end": {"type": self.end, "value": self.end_value},
            "accumulation": self.accumulation,
        }


def feigenbaum_ratios(values) -> tuple[float | None, ...]:
    """delta_k = (v_k - v_{k-1}) / (v_{k+1} - v_k) for k = 1 .. n - 2.

    Parameters
    ----------
    values : sequence of float
        The parameter values of successive period doublings.

    Returns
    -------
    tuple of float or None
        The ratios; None where an interval v_{k+1} - v_k is zero (no ratio), or where the ratio overflows.

    Raises
    ------
    ParameterError
        Unless ``values`` is a sequence of finite real numbers.
    """
    v = real_array(values)
    if v is None or v.ndim != 1 or not np.all(np.isfinite(v)):
        raise ParameterError(f"values = {quoted(values)} is invalid; allowed: a sequence of finite real numbers")
    v = v.tolist()  # Python floats: an interval that overflows is inf, without a numpy warning
    out: list[float | None] = []
    for k in range(1, len(v) - 1):
        num, den = v[k] - v[k - 1], v[k + 1] - v[k]
        ratio = num / den if math.isfinite(num) and math.isfinite(den) and den != 0.0 else math.inf
        out.append(ratio if math.isfinite(ratio) else None)
    return tuple(out)


def _end(branch, doublings_left: BranchEvent | None, values: list[float], ratios: tuple[float | None, ...]):
    delta = ratios[-1] if ratios and ratios[-1] is not None and ratios[-1] > 1.0 else FEIGENBAUM_DELTA
    acc = values[-1] + (values[-1] - values[-2]) / (delta - 1.0) if len(values) >= 2 else None
    if doublings_left is not None:
        return "accumulation", acc, acc
    if any(o.multipliers and not multipliers_resolved(o.multipliers) for o in branch.orbits):
        # so unstable that its multipliers beside the largest are rounding: a doubling there cannot be told
        return "unresolved", acc, acc
    for kind in ("fold", "grazing"):
        ev = [e for e in branch.events if e.kind == kind]
        if ev:
            return kind, float(ev[0].value), None
    if branch.status == "terminal":
        return "range", float(branch.values[-1]), None
    return branch.status, float(branch.values[-1]) if len(branch.values) else None, None


def cascades_of(family: MultiImpactBranches, one_impact: tuple[BranchEvent, ...] = ()) -> tuple[Cascade, ...]:
    """The cascades in a computed family of branches (with its links of branch switching).

    Parameters
    ----------
    family : MultiImpactBranches
        From `multi_impact_branches` with ``doublings`` > 0.
    one_impact : tuple of BranchEvent
        The period doublings of one-impact branches the family was switched at.

    Raises
    ------
    ParameterError
        Unless ``family`` is a `MultiImpactBranches` and ``one_impact`` a sequence of `BranchEvent`.
    """
    check_type("family", family, MultiImpactBranches, "a MultiImpactBranches (multi_impact_branches)")
    one_impact = check_events("one_impact", one_impact)
    out = []
    n = len(family.branches)
    children = {i: [j for j in range(n) if family.parents[j] == i] for i in range(-1, n)}
    firsts = [j for j in range(n) if family.depth[j] == 1]
    for first in firsts:
        chain = [first]
        while True:
            last = chain[-1]
            kids = [j for j in children[last] if family.born_at[j] is not None]
            if not kids:
                break
            start = float(family.branches[last].values[0])
            chain.append(min(kids, key=lambda j: abs(family.born_at[j] - start)))
        points: list[BranchEvent] = []
        parent = family.parents[first]
        if parent >= 0:
            src = family.branches[parent].events
        else:
            src = one_impact
        born = family.born_at[first]
        points.append(min((e for e in src if e.kind == "period-doubling"), key=lambda e: abs(e.value - born)))
        for j in chain[1:]:
            par = family.branches[family.parents[j]]
            points.append(min((e for e in par.events if e.kind == "period-doubling"
                               and e.orbits == (par.orbits[0].label,)), key=lambda e: abs(e.value - family.born_at[j])))
        deepest = family.branches[chain[-1]]
        label = deepest.orbits[0].label if deepest.orbits else ""
        more = [e for e in deepest.events if e.kind == "period-doubling" and e.orbits == (label,)]
        if more:
            points.append(more[0])
        values = [float(e.value) for e in points]
        ratios = feigenbaum_ratios(values)
        end, end_value, acc = _end(deepest, more[0] if more else None, values, ratios)
        out.append(Cascade(param=family.param, points=tuple(points),
                           labels=tuple(family.branches[j].orbits[0].label for j in chain),
                           ratios=ratios, end=end, end_value=end_value, accumulation=acc))
    return tuple(out)


def _with_orbit(params: Parameters, event: BranchEvent) -> BranchEvent:
    """A one-impact period doubling with its orbit (as an orbit of one impact), where the impact map has it."""
    try:
        return replace(event, orbit=one_impact_seed(params, event))
    except NewtonFailure:
        return event


def cascades(
    params: Parameters,
    param: str,
    start: float,
    stop: float,
    *,
    impacts: int = 1,
    depth: int = 5,
    t_max: float = 12.0,
    n_seeds: int | None = None,
    grid: tuple[int, int, int] | None = None,
) -> tuple[Cascade, ...]:
    """The period-doubling cascades of the orbits with ``impacts`` impacts per period in [start, stop].

    Parameters
    ----------
    params : Parameters
        Base parameters (for ``impacts`` >= 2 the value of ``param`` must lie in the range: the seeds are
        found there).
    param : str
    start, stop : float
    impacts : int
        p >= 1; for p = 1 the cascades start at the period doublings of the one-impact branches.
    depth : int
        Levels of branch switching followed (1 to `MAX_DOUBLINGS`).
    t_max, n_seeds : float, int or None
        Options of `rotorcontact.continuation.branches.orbit_branches` (p = 1).
    grid : (int, int, int), optional
        Grid of seeds (p >= 2).

    Returns
    -------
    tuple of Cascade

    Raises
    ------
    ParameterError
        Naming the first argument that is not of the kind above; ``t_max`` and ``n_seeds`` are checked for
        p >= 2 and ``grid`` for p = 1 too, where they are not used.
    """
    check_params(params)
    p = check_int("impacts", impacts, 1, MAX_ORBIT_IMPACTS)
    depth = check_int("depth", depth, 1, MAX_DOUBLINGS)
    if p * 2**depth > MAX_ORBIT_IMPACTS:
        raise ParameterError(f"impacts = {p} doubled depth = {depth} times makes orbits of {p * 2**depth} impacts; "
                             f"allowed: impacts * 2^depth <= {MAX_ORBIT_IMPACTS}")
    start, stop = check_param_range(param, params, start, stop)
    t_max = check_range("t_max", t_max, low=0.0, low_open=True)
    n_seeds = check_n_seeds(n_seeds, param, start, stop)
    grid = check_grid(grid)
    if p == 1:
        one = orbit_branches(params, param, start, stop, t_max=t_max, n_seeds=n_seeds)
        events = tuple(_with_orbit(params, replace(e, impacts=1)) for e in one.events if e.kind == "period-doubling")
        base = params.replace(**{param: start})
        family = multi_impact_branches(base, 1, param, start, stop, doublings=depth, one_impact_events=events)
        return cascades_of(family, events)
    family = multi_impact_branches(params, p, param, start, stop, doublings=depth, grid=grid)
    return cascades_of(family)
