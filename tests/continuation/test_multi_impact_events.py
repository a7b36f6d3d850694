"""Bifurcations along branches of multi-impact orbits, checked with an independent Newton on P_I^p.

The reference: the p-th iterate of the simulator's impact map (`impact_map`, no
Jacobian), solved by Newton's method on P_I^p(x) = x in the three coordinates of
one point (single shooting), its Jacobian and the multipliers by central
differences. At each reported event the orbit found that way has the multiplier
the event's type requires: +1 at a fold (where the branch's parameter is extreme),
-1 at a period doubling, a complex pair on the unit circle at a Neimark-Sacker
point. The six-impact branch at the reference parameters turns back near
gamma = 0.08204 with a complex pair already outside the unit circle, so a test on
max |lambda| - 1 misses that fold.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact.continuation.multi_impact_branches import continue_multi_impact
from rotorcontact.maps.multi_impact import orbits_from_simulation
from reference_parameters import REF



@pytest.fixture(scope="module")
def m6():
    found = orbits_from_simulation(REF.replace(gamma=0.0818), 6)
    assert found and found[0].impacts == 6
    return found[0]


@pytest.fixture(scope="module")
def up(m6):
    return continue_multi_impact(m6, "gamma", 0.0835, max_points=300)


def test_the_fold_hidden_behind_an_unstable_pair_is_reported(up, power_newton):
    folds = [e for e in up.events if e.kind == "fold"]
    assert len(folds) == 1
    fold = folds[0]
    # the fold is where the branch turns: the largest gamma reached
    assert fold.value >= float(np.max(up.values)) - 1e-9
    assert fold.impacts == 6 and fold.orbits == (up.orbits[0].label,)
    assert fold.to_dict()["impacts"] == 6
    _x, z = power_newton(fold.orbit.params, fold.orbit.states[0], 6)
    assert np.min(np.abs(z - 1.0)) < 1e-5
    # the other multipliers are off the unit circle: max |lambda| - 1 had no sign change there
    assert np.sum(np.abs(np.abs(z) - 1.0) > 1e-3) == 2 and np.max(np.abs(z)) > 1.1


def test_neimark_sacker_has_a_complex_pair_on_the_unit_circle(up, power_newton):
    ns = [e for e in up.events if e.kind == "neimark-sacker"]
    assert len(ns) == 1
    _x, z = power_newton(ns[0].orbit.params, ns[0].orbit.states[0], 6)
    pair = [m for m in z if abs(m.imag) > 1e-3]
    assert len(pair) == 2 and all(abs(abs(m) - 1.0) < 1e-5 for m in pair)
    angle = float(ns[0].detail.rsplit("angle ", 1)[1].split()[0])
    assert angle == pytest.approx(abs(math.atan2(pair[0].imag, pair[0].real)), abs=1e-4)
    assert "loss of stability as gamma increases" in ns[0].detail


def test_period_doubling_has_a_multiplier_minus_one(m6, power_newton):
    down = continue_multi_impact(m6, "gamma", 0.080, max_points=100)
    pds = [e for e in down.events if e.kind == "period-doubling"]
    assert len(pds) == 1 and 0.080 < pds[0].value < 0.0818
    _x, z = power_newton(pds[0].orbit.params, pds[0].orbit.states[0], 6)
    assert np.min(np.abs(z + 1.0)) < 1e-5
    assert not [e for e in down.events if e.kind in ("fold", "neimark-sacker", "branch-point")]


def test_a_branch_that_reaches_its_own_period_doubling_stops_and_says_so():
    from rotorcontact.maps.multi_impact import (
        find_period_doubling,
        period_doubled_orbit,
    )

    pd = find_period_doubling(REF.replace(gamma=0.1), "B1,d", "gamma", lo=0.08, hi=0.09)
    start = period_doubled_orbit(pd, -3e-4)
    branch = continue_multi_impact(start, "gamma", 0.09)
    assert branch.status == "period-doubling" and "returned onto the orbit it doubles from" in branch.message
    ev = branch.events[-1]
    assert ev.kind == "period-doubling" and ev.orbits == ("B1,d", "B1,d/PD") and ev.impacts == 2
    # the doubling of B1,d located independently (bisection on the one-impact multipliers)
    assert ev.value == pytest.approx(pd.value, abs=1e-8)
    # it did not walk back along the other half (the same orbits, points swapped) nor report a fold
    assert np.all(branch.values <= pd.value + 1e-12)
    assert not [e for e in branch.events if e.kind == "fold"]


@pytest.mark.parametrize("label", ["M2-3", "B1,d/PD2"])
def test_the_parent_of_an_own_doubling_is_named_whatever_the_branch_s_label(label):
    # a period-2 orbit found on a grid is labelled M2-<j>, not B1,d/PD: its parent is the one-impact orbit it
    # returns onto, found among the one-impact orbits there; a second doubling's label names it too
    import dataclasses

    from rotorcontact.maps.multi_impact import find_period_doubling, period_doubled_orbit

    pd = find_period_doubling(REF.replace(gamma=0.1), "B1,d", "gamma", lo=0.08, hi=0.09)
    start = dataclasses.replace(period_doubled_orbit(pd, -3e-4), label=label)
    ev = continue_multi_impact(start, "gamma", 0.09).events[-1]
    assert ev.kind == "period-doubling" and ev.orbits == ("B1,d", label)


def test_a_turning_point_with_a_complex_pair_near_one_is_no_neimark_sacker():
    from rotorcontact.continuation.events import multiplier_kind

    # multipliers off the unit circle (a turning point where a complex pair lies near +1)
    z = np.array([0.9967 + 0.0033j, 0.9967 - 0.0033j, 0.1])
    assert multiplier_kind("torus", z) is None and multiplier_kind("plus-one", z) is None
    on = np.array([np.exp(0.5j), np.exp(-0.5j), 0.1])
    assert multiplier_kind("torus", on) == "neimark-sacker"
    assert multiplier_kind("plus-one", np.array([1.0 + 0j, 1.62, 0.05])) == "plus-one"
    assert multiplier_kind("minus-one", np.array([-1.0 + 0j, 0.4, 0.2])) == "period-doubling"
