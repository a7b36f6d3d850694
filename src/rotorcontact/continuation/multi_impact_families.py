"""Every branch of orbits with p impacts per period over a parameter range, with branch switching at period doubling.

Seeds
-----
At the base parameters the orbits with p impacts per period are those that
attract long simulations (`rotorcontact.maps.multi_impact.orbits_from_simulation`)
and every fixed point of P_I^p that Newton's method finds from a grid of
impact states on the section (`rotorcontact.maps.multi_impact.orbits_from_grid`),
unstable ones included; they are deduplicated. For p = 1 the one-impact
branches of `rotorcontact.continuation.branches` are used instead.

Branches
--------
Each seed is continued from the base value to both ends of the range
(`rotorcontact.continuation.multi_impact_branches.continue_multi_impact`); a seed
that an earlier branch passes through at the base value is not continued again.

Branch switching
----------------
With ``doublings = K``, at each period doubling located along a branch the
period-doubled branch is entered by its amplitude
(`rotorcontact.maps.multi_impact.doubled_orbit_at_amplitude`) and continued away
from the doubling to the end of the range; its period doublings are followed in
turn, K levels deep, so a cascade is followed from one call. A doubled branch is
labelled from its parent: ``"B1,d/PD"``, ``"M2-1/PD/PD"``; a second doubling of
the same parent adds its rank (``"M2-1/PD2"``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..maps.multi_impact import (
    MAX_ORBIT_IMPACTS,
    MultiImpactOrbit,
    NewtonFailure,
    _same_orbit,
    doubled_orbit_at_amplitude,
    orbits_from_grid,
    orbits_from_simulation,
    period_doubling_at,
    solve_multi_impact,
)
from ..maps.multi_impact import _check_parameter
from ..maps.orbit_system import orbit_angles
from ..model.params import Parameters
from ..model.validation import check_int, check_params, check_type, quoted
from .engine import check_max_points
from .limits import MAX_DOUBLINGS
from .multi_impact_branches import MultiImpactBranch, check_grid, continue_multi_impact
from .results import BranchEvent, BranchResult, check_events, check_interval, check_param_range

__all__ = ["MAX_DOUBLINGS", "MultiImpactBranches", "multi_impact_branches", "one_impact_seed", "seed_orbits",
           "switch_at_doubling"]

#: Amplitude v . (x_0 - x_q) / 2 at which a period-doubled branch is entered.
SWITCH_AMPLITUDE = 1e-3
#: The amplitude is divided by 4 (at most `SWITCH_HALVINGS` times) until the entry orbit has a multiplier
#: within this of +1.
SWITCH_MULTIPLIER = 0.05
SWITCH_HALVINGS = 6


@dataclass(frozen=True)
class MultiImpactBranches(BranchResult):
    """Branches of orbits with p impacts per period (and of their period doublings) over a parameter range.

    Attributes
    ----------
    param : str
        The continuation parameter.
    events : tuple of BranchEvent
        Every located event, sorted by value (``impacts`` set on each).
    impacts : int
        p, the impacts per period of the seeds.
    start, stop : float
        The range.
    base : Parameters
        The base parameters (the seeds are found there).
    branches : tuple of MultiImpactBranch
        The computed branches; a branch's label is that of its orbits.
    depth : tuple of int
        For each branch, the number of period doublings from its seed (0 for a seed).
    parents : tuple of int
        For each branch, the index of the branch it doubles from (-1 for a seed,
        and for a branch born on a one-impact branch).
    born_at : tuple of float or None
        For each branch, the period doubling it was born at (None for a seed).
    """

    impacts: int
    start: float
    stop: float
    base: Parameters = field(repr=False)
    branches: tuple[MultiImpactBranch, ...] = field(repr=False)
    depth: tuple[int, ...] = ()
    parents: tuple[int, ...] = ()
    born_at: tuple[float | None, ...] = ()

    @property
    def labels(self) -> tuple[str, ...]:
        """The labels of the branches, in order."""
        return tuple(_label(b) for b in self.branches)

    def curves_dict(self) -> dict[str, dict[str, Any]]:
        """Per label: the parameter, T (the period), rdot and thetadot at the first impact, stable, impacts."""
        out: dict[str, dict[str, Any]] = {}
        for b in self.branches:
            if not b.orbits:
                continue
            out[_label(b)] = {
                self.param: [float(v) for v in b.values],
                "T": [o.period for o in b.orbits],
                "rdot": [o.points[0].rdot for o in b.orbits],
                "thetadot": [o.points[0].thetadot for o in b.orbits],
                "stable": [o.stable for o in b.orbits],
                "plausible": [o.plausible for o in b.orbits],
                "impacts": b.orbits[0].impacts,
                "end": b.status,
            }
        return out

    def to_dict(self) -> dict[str, Any]:
        """The ``branches --impacts p --json`` object: that of one-impact branches with ``"impacts"`` added."""
        data = super().to_dict()
        data["impacts"] = self.impacts
        return data


def _label(branch: MultiImpactBranch) -> str:
    return branch.orbits[0].label if branch.orbits else ""


def _joined(orbit: MultiImpactOrbit, param: str, start: float, stop: float, max_points: int) -> MultiImpactBranch:
    """The branch through ``orbit`` from ``start`` to ``stop``: the run down reversed, then the run up."""
    runs = [continue_multi_impact(orbit, param, end, max_points=max_points) for end in (start, stop)]
    down, up = runs
    values = np.concatenate([down.values[::-1], up.values[1:]])
    orbits = tuple(down.orbits[::-1]) + tuple(up.orbits[1:])
    events = tuple(sorted(down.events + up.events, key=lambda e: e.value))
    ends = [r for r in runs if r.status != "terminal"]
    status = ends[0].status if ends else "terminal"
    message = "; ".join(f"towards {param} = {end:g}: {r.message}" for end, r in zip((start, stop), runs))
    return MultiImpactBranch(param=param, events=events, values=values, orbits=orbits, status=status,
                             message=message)


def _passes_through(branch: MultiImpactBranch, orbit: MultiImpactOrbit, param: str) -> bool:
    """Whether the computed branch meets ``orbit`` (at its parameter value): its crossings there, corrected."""
    if branch.orbits and branch.orbits[0].impacts != orbit.impacts:
        return False
    value = float(getattr(orbit.params, param))
    v = branch.values
    for i in range(len(v)):
        if v[i] == value and _same_orbit(branch.orbits[i], orbit, 1e-6):
            return True
    for i in range(len(v) - 1):
        if (v[i] - value) * (v[i + 1] - value) >= 0.0:
            continue
        w = (value - v[i]) / (v[i + 1] - v[i])
        a, b = branch.orbits[i].states, branch.orbits[i + 1].states
        d = b - a
        d[:, 0] = np.remainder(d[:, 0] + math.pi, 2.0 * math.pi) - math.pi
        try:
            hit = solve_multi_impact(orbit.params, a + w * d, canonical=False, max_iter=10)
        except NewtonFailure:
            continue
        if _same_orbit(hit, orbit, 1e-6):
            return True
    return False


def seed_orbits(params: Parameters, impacts: int, grid: tuple[int, int, int] | None = None
                ) -> tuple[MultiImpactOrbit, ...]:
    """The orbits with ``impacts`` impacts per period at ``params`` that seed the branches (module docstring).

    Those of long simulations and of Newton's method from a grid of impact
    states, deduplicated, sorted by period and labelled ``"M<p>-<j>"``.

    Raises
    ------
    ParameterError
        Unless ``params`` is a `Parameters`, ``impacts`` a number of impacts per period and ``grid`` None or
        a shape of `rotorcontact.continuation.multi_impact_branches.check_grid`.
    """
    check_params(params)
    impacts = check_int("impacts", impacts, 1, MAX_ORBIT_IMPACTS)
    grid = check_grid(grid)
    kw = {} if grid is None else {"shape": grid}
    found = list(orbits_from_simulation(params, impacts))
    for o in orbits_from_grid(params, impacts, **kw):
        if not any(_same_orbit(o, f) for f in found):
            found.append(o)
    found.sort(key=lambda o: (o.period, o.points[0].theta))
    return tuple(replace(o, label=f"M{impacts}-{j + 1}") for j, o in enumerate(found))


def one_impact_seed(params: Parameters, event: BranchEvent) -> MultiImpactOrbit:
    """The one-impact orbit of an event of `rotorcontact.continuation.branches.orbit_branches`, as a 1-impact orbit.

    Raises
    ------
    NewtonFailure
        When the simulator's impact map has no fixed point there (a virtual orbit, or friction that reverses).
    ParameterError
        Unless ``params`` is a `Parameters` and ``event`` a `BranchEvent` along one parameter with the
        period ``T`` and impact velocity ``rdot`` of its one-impact orbit.
    """
    check_params(params)
    check_type("event", event, BranchEvent, "a BranchEvent of rotorcontact.continuation.branches.orbit_branches")
    if not isinstance(event.param, str) or event.T is None or event.rdot is None:
        raise ParameterError(f"event = {quoted(event)} is invalid; allowed: an event of a one-impact branch, along "
                             "one parameter, with its T and rdot (orbit_branches)")
    p = params.replace(**{event.param: event.value})
    theta, thetadot = orbit_angles(p, float(event.T), float(event.rdot))
    label = event.orbits[0] if event.orbits else "M1"
    return solve_multi_impact(p, [[theta, float(event.rdot), thetadot]], label=label)


def switch_at_doubling(event: BranchEvent, label: str, param: str, start: float, stop: float,
                       max_points: int = 2000) -> MultiImpactBranch | None:
    """The period-doubled branch born at a located period doubling, continued away from it to the range's end.

    Returns None when the branch cannot be entered (no orbit at the event, or
    Newton fails at the switching amplitude).

    Raises
    ------
    ParameterError
        Unless ``event`` is a period-doubling `BranchEvent` (its orbit a `MultiImpactOrbit` or None), ``label``
        text, ``param`` a continuation parameter, start < stop and ``max_points`` a number of steps; all are
        checked whether the branch can be entered or not.
    """
    _check_doubling(event)
    check_type("label", label, str, "the label of the doubled branch, such as 'B1,d/PD'")
    param = _check_parameter(param)
    start, stop = check_interval(start, stop)
    max_points = check_max_points(max_points)
    orbit = event.orbit
    if orbit is None:
        return None
    try:
        pd = period_doubling_at(orbit, param)
    except ParameterError:
        return None
    first = None
    amplitude = SWITCH_AMPLITUDE
    for _ in range(SWITCH_HALVINGS):
        try:
            trial = doubled_orbit_at_amplitude(pd, amplitude)
        except NewtonFailure:
            amplitude *= 0.25
            continue
        first = trial
        # close enough to the doubling that the multiplier born at +1 is still near it (deep in a cascade the
        # next doubling follows within a short distance)
        if np.min(np.abs(np.array(trial.multipliers) - 1.0)) <= SWITCH_MULTIPLIER:
            break
        amplitude *= 0.25
    if first is None:
        return None
    first = replace(first, label=label)
    side = getattr(first.params, param) - pd.value
    end = stop if side > 0.0 else start
    if not start <= getattr(first.params, param) <= stop:
        return None
    return continue_multi_impact(first, param, end, max_points=max_points)


def _check_doubling(event) -> BranchEvent:
    check_type("event", event, BranchEvent, "a period doubling located along a branch (BranchEvent)")
    if event.kind != "period-doubling" or not (event.orbit is None or isinstance(event.orbit, MultiImpactOrbit)):
        raise ParameterError(f"event = {quoted(event)} is invalid; allowed: a period doubling (kind "
                             "'period-doubling') whose orbit is a MultiImpactOrbit or None")
    return event


def multi_impact_branches(
    params: Parameters,
    impacts: int,
    param: str = "gamma",
    start: float = 0.0,
    stop: float = 0.25,
    *,
    doublings: int = 0,
    seeds: tuple[MultiImpactOrbit, ...] | None = None,
    one_impact_events: tuple[BranchEvent, ...] = (),
    grid: tuple[int, int, int] | None = None,
    max_points: int = 2000,
) -> MultiImpactBranches:
    """Continue every orbit with ``impacts`` impacts per period found at ``params`` over [start, stop].

    Parameters
    ----------
    params : Parameters
        Base parameters; the value of ``param`` must lie in [start, stop].
    impacts : int
        p >= 1. For p = 1 no seeds are searched: the branches are those born
        at ``one_impact_events`` (the period doublings of one-impact branches).
    param : str
        The continuation parameter.
    start, stop : float
        The range.
    doublings : int
        Levels of branch switching at period doubling (0 to `MAX_DOUBLINGS`).
    seeds : tuple of MultiImpactOrbit, optional
        Seeds to use instead of the search.
    one_impact_events : tuple of BranchEvent
        Period doublings of one-impact branches to switch at (p = 1).
    grid : (int, int, int), optional
        Shape of the grid of `rotorcontact.maps.multi_impact.orbits_from_grid`.
    max_points : int
        Largest number of steps of each continuation run (1 to
        `rotorcontact.continuation.engine.MAX_POINTS`).

    Returns
    -------
    MultiImpactBranches

    Raises
    ------
    ParameterError
        Naming the first argument that is not of the kind above (every one is checked, used or not), or
        when the base value of ``param`` lies outside the range.
    """
    check_params(params)
    p = check_int("impacts", impacts, 1, MAX_ORBIT_IMPACTS)
    doublings = check_int("doublings", doublings, 0, MAX_DOUBLINGS)
    if p * 2**doublings > MAX_ORBIT_IMPACTS:
        raise ParameterError(f"impacts = {p} doubled doublings = {doublings} times makes orbits of "
                             f"{p * 2**doublings} impacts; allowed: impacts * 2^doublings <= {MAX_ORBIT_IMPACTS}")
    start, stop = check_param_range(param, params, start, stop)
    if seeds is not None and (not isinstance(seeds, (list, tuple))
                              or not all(isinstance(o, MultiImpactOrbit) for o in seeds)):
        raise ParameterError(f"seeds = {quoted(seeds)} is invalid; allowed: a tuple of MultiImpactOrbit, or None")
    one_impact_events = check_events("one_impact_events", one_impact_events)
    grid = check_grid(grid)
    max_points = check_max_points(max_points)
    base_value = float(getattr(params, param))
    if not start <= base_value <= stop:
        raise ParameterError(f"{param} = {base_value!r} is outside the range {start!r} .. {stop!r}; allowed: a base "
                             "value inside the range (the orbits are found there)")
    branches: list[MultiImpactBranch] = []
    depth: list[int] = []
    parents: list[int] = []
    born_at: list[float | None] = []
    if p >= 2:
        if seeds is None:
            seeds = seed_orbits(params, p, grid)
        for seed in seeds:
            if any(_passes_through(b, seed, param) for b in branches):
                continue
            branches.append(_joined(seed, param, start, stop, max_points))
            depth.append(0)
            parents.append(-1)
            born_at.append(None)
    # branch switching, level by level
    pending: list[tuple[BranchEvent, str, int, int]] = []
    for e in one_impact_events:
        if e.kind == "period-doubling":
            pending.append((e, e.orbits[0] if e.orbits else "M1", 1, -1))
    for i, (b, d) in enumerate(zip(list(branches), list(depth))):
        pending.extend(_doublings_of(b, d + 1, i))
    while pending:
        event, parent, level, parent_index = pending.pop(0)
        if level > doublings:
            continue
        if event.orbit is None and p == 1 and event.T is not None:
            try:
                event = replace(event, orbit=one_impact_seed(params, event))
            except NewtonFailure:
                continue
        taken = sum(1 for lab in (_label(b) for b in branches) if lab.startswith(f"{parent}/PD")
                    and "/" not in lab[len(parent) + 3:])
        label = f"{parent}/PD" if taken == 0 else f"{parent}/PD{taken + 1}"
        child = switch_at_doubling(event, label, param, start, stop, max_points)
        if child is None or not child.orbits:
            continue
        branches.append(child)
        depth.append(level)
        parents.append(parent_index)
        born_at.append(float(event.value))
        pending.extend(_doublings_of(child, level + 1, len(branches) - 1))
    events = sorted((e for b in branches for e in b.events), key=lambda e: (e.value, e.kind, e.orbits))
    return MultiImpactBranches(param=param, events=tuple(events), impacts=p, start=start, stop=stop, base=params,
                               branches=tuple(branches), depth=tuple(depth), parents=tuple(parents),
                               born_at=tuple(born_at))


def _doublings_of(branch: MultiImpactBranch, level: int, index: int) -> list[tuple[BranchEvent, str, int, int]]:
    """The period doublings along a branch to switch at (not the branch's own, where it was born)."""
    label = _label(branch)
    return [(e, label, level, index) for e in branch.events
            if e.kind == "period-doubling" and e.orbits == (label,) and e.orbit is not None]
