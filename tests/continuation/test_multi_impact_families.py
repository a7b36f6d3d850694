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
