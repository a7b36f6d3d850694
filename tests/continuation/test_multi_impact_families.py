"""Every branch of p-impact orbits over a range, and branch switching at period doubling.

The claims: each period-doubled branch starts at the period doubling of its
parent (its parameter within the switching amplitude's reach of the located
doubling, its period twice the parent's there, its points alternating about
the parent's), carries twice the parent's impacts and is labelled from it; K
levels of doublings give labels with K "/PD"; a seed given twice is followed
once; the base value must lie in the range.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation.multi_impact_families import multi_impact_branches
from rotorcontact.maps.multi_impact import orbits_from_grid
from reference_parameters import REF

BASE = REF.replace(gamma=0.0818)


@pytest.fixture(scope="module")
def family():
    return multi_impact_branches(BASE, 2, "gamma", 0.075, 0.09, doublings=2)


def test_seeds_and_labels(family):
    assert family.impacts == 2
    seeds = [b for b, d in zip(family.branches, family.depth) if d == 0]
    assert [b.orbits[0].label for b in seeds] == [f"M2-{j + 1}" for j in range(len(seeds))]
    for b, d in zip(family.branches, family.depth):
        label = b.orbits[0].label
        assert label.count("/PD") == d
        assert all(o.impacts == 2 * 2**d for o in b.orbits)
    assert max(family.depth) == 2
    data = family.to_dict()
    assert data["impacts"] == 2 and set(data) == {"param", "events", "branches", "impacts"}
    for e in data["events"]:
        assert {"type", "value", "orbits", "impacts"} <= set(e)


def test_doubled_branches_start_at_the_parent_doubling(family):
    by_label = {b.orbits[0].label: b for b in family.branches}
    children = [lab for lab in by_label if lab.endswith("/PD")]
    assert children
    for lab in children:
        parent = by_label[lab[:-3]]
        child = by_label[lab]
        pds = [e for e in parent.events if e.kind == "period-doubling" and e.orbits == (lab[:-3],)]
        pd = min(pds, key=lambda e: abs(e.value - child.values[0]))
        first = child.orbits[0]
        assert abs(child.values[0] - pd.value) < 1e-4
        assert first.period == pytest.approx(2 * pd.orbit.period, rel=1e-3)
        q = pd.orbit.impacts
        x = first.states
        # the two halves lie on either side of the parent's points, close to them
        d = x[:q] - x[q:]
        d[:, 0] = np.remainder(d[:, 0] + math.pi, 2 * math.pi) - math.pi
        assert 1e-5 < np.max(np.abs(d)) < 1e-1


def test_a_branch_ending_where_an_impact_becomes_tangential_ends_at_a_grazing():
    """Three-impact branches whose continuation fails as one impact's velocity falls to 0 end at a grazing: the
    grazing of the two-impact orbit B1,d/PD, seen from the side where the orbit has a third impact (the engine
    locates that one on the two-impact branch, where an interior maximum of r reaches 1)."""
    from rotorcontact.continuation.multi_impact_branches import GRAZING_MARGIN, continue_multi_impact
    from rotorcontact.maps.multi_impact import find_period_doubling, period_doubled_orbit

    base = REF.replace(gamma=0.0845)
    three = multi_impact_branches(base, 3, "gamma", 0.07, 0.1, grid=(6, 3, 3))
    for b in three.branches:  # no end where an impact is all but tangential is left a step failure
        assert not (b.status == "step-failure" and np.min(b.orbits[-1].states[:, 1]) < GRAZING_MARGIN)
    tangential = [e.value for e in three.events if e.kind == "grazing" and "tangential" in e.detail]
    pd = find_period_doubling(REF.replace(gamma=0.1), "B1,d", "gamma", lo=0.08, hi=0.09)
    two = continue_multi_impact(period_doubled_orbit(pd, -3e-4), "gamma", 0.07)
    (g,) = [e.value for e in two.events if e.kind == "grazing"]
    assert any(0.0 < value - g < 1e-4 for value in tangential)


def test_a_seed_given_twice_is_followed_once():
    seeds = orbits_from_grid(BASE, 2)[:1]
    res = multi_impact_branches(BASE, 2, "gamma", 0.08, 0.083, seeds=seeds * 2)
    assert len(res.branches) == 1 and res.depth == (0,)


def test_bad_input():
    with pytest.raises(ParameterError, match="outside the range"):
        multi_impact_branches(BASE, 2, "gamma", 0.09, 0.1)
    with pytest.raises(ParameterError, match="doublings"):
        multi_impact_branches(BASE, 2, "gamma", 0.08, 0.09, doublings=99)
    with pytest.raises(ParameterError, match="impacts"):
        multi_impact_branches(BASE, 0, "gamma", 0.08, 0.09)


# ---------------------------------------------------------------------------
# arguments refused by name, before any continuation
# ---------------------------------------------------------------------------


def _doubling(**kw):
    from rotorcontact.continuation.results import BranchEvent

    args = dict(kind="period-doubling", value=0.0845, param="gamma", orbits=("B1,d",))
    args.update(kw)
    return BranchEvent(**args)


@pytest.mark.parametrize("kw, match", [
    (dict(one_impact_events="x"), r"^one_impact_events = 'x' is invalid; allowed: a tuple of BranchEvent"),
    (dict(one_impact_events=[1]), r"^one_impact_events = \[1\] is invalid"),
    (dict(one_impact_events=None), r"^one_impact_events = None is invalid"),
    (dict(max_points=10**12), r"^max_points = 1000000000000 is invalid; allowed: an integer from 1 to 1000000"),
    (dict(max_points=0), r"^max_points = 0 is invalid"),
    (dict(grid=(1.5, 1, 1)), r"^grid\[0\] = 1.5 is invalid"),
    (dict(seeds="x"), r"^seeds = 'x' is invalid; allowed: a tuple of MultiImpactOrbit"),
])
def test_the_family_refuses_bad_options_by_name(kw, match):
    # one impact: no seeds are searched, so nothing is computed before the options are checked
    with pytest.raises(ParameterError, match=match):
        multi_impact_branches(BASE, 1, "gamma", 0.08, 0.09, **kw)


def test_the_family_takes_numpy_scalars():
    a = multi_impact_branches(BASE, np.int64(1), "gamma", np.float64(0.08), np.float32(0.09), doublings=np.int64(1),
                              max_points=np.int64(10), grid=(np.int64(2), 2, 2))
    assert a.impacts == 1 and a.branches == () and a.start == 0.08


@pytest.mark.parametrize("args, match", [
    ((None, None), r"^params = None is not a Parameters object"),
    ((REF, None), r"^event = None is not a BranchEvent object"),
    ((REF, "x"), r"^event = 'x' is not a BranchEvent object"),
    ((REF, "no T"), r"^event = .* is invalid; allowed: an event of a one-impact branch, .* with its T and rdot"),
])
def test_one_impact_seed_needs_an_event_of_a_one_impact_branch(args, match):
    from rotorcontact.continuation.multi_impact_families import one_impact_seed

    params, event = args
    event = _doubling() if event == "no T" else event
    with pytest.raises(ParameterError, match=match):
        one_impact_seed(params, event)


@pytest.mark.parametrize("args, match", [
    ((None, "B1,d/PD", "gamma", 0.08, 0.09), r"^event = None is not a BranchEvent object"),
    (("fold", "B1,d/PD", "gamma", 0.08, 0.09), r"^event = .* is invalid; allowed: a period doubling"),
    (("pd", 1, "gamma", 0.08, 0.09), r"^label = 1 is not a str object"),
    (("pd", "B1,d/PD", "phi", 0.08, 0.09), r"^param = 'phi' is invalid"),
    (("pd", "B1,d/PD", "gamma", 0.09, 0.08), r"^stop = 0.08 is invalid; allowed: a number > start = 0.09"),
    (("pd", "B1,d/PD", "gamma", 0.08, 0.09, 10**12), r"^max_points = 1000000000000 is invalid"),
])
def test_switching_checks_its_arguments_even_without_an_orbit(args, match):
    from rotorcontact.continuation.multi_impact_families import switch_at_doubling

    event = {"pd": _doubling(), "fold": _doubling(kind="fold")}.get(args[0], args[0])
    with pytest.raises(ParameterError, match=match):
        switch_at_doubling(event, *args[1:])
    assert switch_at_doubling(_doubling(), "B1,d/PD", "gamma", np.float64(0.08), 0.09, np.int64(5)) is None


def test_seed_orbits_name_their_grid():
    from rotorcontact.continuation.multi_impact_families import seed_orbits

    for grid, match in (((1.5, 1, 1), r"^grid\[0\] = 1.5 is invalid"), ("x", r"^grid = 'x' is invalid")):
        with pytest.raises(ParameterError, match=match):
            seed_orbits(BASE, 2, grid)
    with pytest.raises(ParameterError, match=r"^impacts = 0 is invalid"):
        seed_orbits(BASE, 0)
