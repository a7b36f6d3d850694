"""Period-doubling cascades: the structure of a known cascade and its ends.

The claims: the two-impact orbit M2-1 at the reference parameters starts a
cascade whose doublings, found by branch switching level after level, accumulate
with ratios of successive intervals that approach Feigenbaum's constant
4.669...; each doubling is one (the reference Newton on P_I^p has a multiplier
-1 there); the accumulation estimate lies beyond the last doubling, before the
next interval would; the one-impact cascade of B1,d ends at a grazing after one
doubling (the stable period-2 orbit grazes at gamma ~ 0.08267).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation.cascade import (
    FEIGENBAUM_DELTA,
    cascades,
    cascades_of,
    feigenbaum_ratios,
)
from rotorcontact.continuation.multi_impact_families import MultiImpactBranches
from reference_parameters import REF



@pytest.fixture(scope="module")
def cascade():
    found = cascades(REF.replace(gamma=0.0845), "gamma", 0.0836, 0.0865, impacts=2, depth=4)
    long = [c for c in found if len(c.points) >= 5]
    assert len(long) == 1
    return long[0]


def test_ratios_approach_feigenbaum(cascade):
    v = [e.value for e in cascade.points]
    assert all(a > b for a, b in itertools.pairwise(v))  # the doublings come at decreasing gamma
    assert [e.impacts for e in cascade.points] == [2, 4, 8, 16, 32]
    assert cascade.labels == ("M2-1/PD", "M2-1/PD/PD", "M2-1/PD/PD/PD", "M2-1/PD/PD/PD/PD")
    r = cascade.ratios
    assert len(r) == 3
    assert abs(r[-1] - FEIGENBAUM_DELTA) < 0.1
    assert abs(r[-1] - FEIGENBAUM_DELTA) < abs(r[0] - FEIGENBAUM_DELTA)
    assert cascade.end == "accumulation"
    gap = v[-2] - v[-1]
    assert v[-1] - gap / 2 < cascade.accumulation < v[-1]


def test_deep_in_the_cascade_the_doublings_go_on_at_feigenbaum_s_ratio():
    """Five levels deep the 64-impact orbit's largest multiplier is about 1e11: its doubling is still told (the
    tolerance widens to the eigenvalues' rounding), at Feigenbaum's ratio, and the 64-impact branch is not taken
    for one that passes through its own doubling. A level deeper the multipliers are rounding: the cascade ends
    unresolved, with the same accumulation estimate."""
    found = cascades(REF.replace(gamma=0.0845), "gamma", 0.0836, 0.0865, impacts=2, depth=5)
    (deep,) = [c for c in found if len(c.points) >= 5]
    v = [e.value for e in deep.points]
    assert [e.impacts for e in deep.points] == [2, 4, 8, 16, 32, 64]
    assert all(a > b for a, b in itertools.pairwise(v))
    assert abs(deep.ratios[-1] - FEIGENBAUM_DELTA) < 0.1
    assert deep.end == "accumulation" and v[-1] - (v[-2] - v[-1]) / 2 < deep.accumulation < v[-1]
    deeper = cascades(REF.replace(gamma=0.0845), "gamma", 0.0836, 0.0865, impacts=2, depth=6)
    (c6,) = [c for c in deeper if len(c.points) >= 5]
    assert [e.value for e in c6.points] == v and c6.end == "unresolved"
    assert c6.accumulation == deep.accumulation == c6.end_value


def test_the_first_doublings_have_a_multiplier_minus_one(cascade, power_newton):
    for e in cascade.points[:3]:
        _x, z = power_newton(e.orbit.params, e.orbit.states[0], e.impacts)
        assert np.min(np.abs(z + 1.0)) < 1e-5


def test_one_impact_cascade_ends_at_a_grazing():
    found = cascades(REF, "gamma", 0.08, 0.1, impacts=1, depth=3, t_max=4, n_seeds=4)
    assert len(found) == 1
    c = found[0]
    assert c.labels == ("B1,d/PD",) and c.points[0].orbits == ("B1,d",) and c.points[0].impacts == 1
    assert c.end == "grazing" and c.end_value == pytest.approx(0.08267, abs=1e-4) and c.ratios == ()
    assert c.to_dict()["end"] == {"type": "grazing", "value": c.end_value}


def test_ratios_helper_and_bad_input():
    # a geometric sequence with ratio 4: every delta is 4
    v = [1.0 - sum(4.0 ** -k for k in range(n)) for n in range(6)]
    assert all(d == pytest.approx(4.0, rel=1e-12) for d in feigenbaum_ratios(v))
    assert feigenbaum_ratios([1.0, 2.0]) == ()
    assert feigenbaum_ratios([0.0, 1.0, 1.0]) == (None,)  # a zero interval has no ratio
    assert feigenbaum_ratios([-1e308, 1e308, 1e308 * (1 + 2**-52)])[0] is None  # the interval 2e308 overflows
    assert feigenbaum_ratios([0.0, -1e308, 1e308])[0] is None  # so does this one, the second
    for bad in ([0.0, math.nan, 1.0], "abc", [[0.0, 1.0]], [0.0, True, 1.0], None):
        with pytest.raises(ParameterError, match=r"^values = .* is invalid; allowed: a sequence of finite real"):
            feigenbaum_ratios(bad)
    for bad_family in (None, "x", ()):
        with pytest.raises(ParameterError, match=r"^family = .* is not a MultiImpactBranches object"):
            cascades_of(bad_family)
    empty = MultiImpactBranches(param="gamma", events=(), impacts=2, start=0.0, stop=0.1, base=REF, branches=())
    assert cascades_of(empty) == ()
    for bad_events in ("x", (None,), None):
        with pytest.raises(ParameterError, match=r"^one_impact = .* is invalid; allowed: a tuple of BranchEvent"):
            cascades_of(empty, bad_events)
    with pytest.raises(ParameterError, match="depth"):
        cascades(REF, "gamma", 0.08, 0.1, depth=0)


@pytest.mark.parametrize("grid, match", [
    ("x", r"^grid = 'x' is invalid; allowed: three integers >= 1"),
    ((1, 1), r"^grid = \(1, 1\) is invalid"),
    ((1.5, 1, 1), r"^grid\[0\] = 1.5 is invalid; allowed: an integer from 1 to"),
    ((0, 1, 1), r"^grid\[0\] = 0 is invalid"),
    ((100, 100, 100), r"^grid = \(100, 100, 100\) is invalid; allowed: .* a product of at most"),
])
def test_the_grid_is_checked_for_one_impact_cascades_too(grid, match):
    # p = 1 uses no grid of seeds, but a bad one is still refused (before any computation)
    with pytest.raises(ParameterError, match=match):
        cascades(REF, "gamma", 0.08, 0.1, impacts=1, depth=3, t_max=4, n_seeds=4, grid=grid)


@pytest.mark.parametrize("kw, match", [(dict(t_max=-1.0), r"^t_max = -1.0 is "), (dict(n_seeds=1), r"^n_seeds = 1 is "),
                                       (dict(t_max="x"), r"^t_max = 'x' is ")])
def test_the_one_impact_options_are_checked_for_multi_impact_cascades_too(kw, match):
    # the base gamma lies outside the range: the options are refused before that is found
    with pytest.raises(ParameterError, match=match):
        cascades(REF, "gamma", 0.0, 0.1, impacts=2, **kw)


def test_cascades_take_numpy_scalars():
    a = cascades(REF, "gamma", np.float64(0.08), np.float32(0.1), impacts=np.int64(1), depth=np.int32(3),
                 t_max=np.float64(4.0), n_seeds=np.int64(4), grid=(np.int64(2), 2, np.int32(2)))
    b = cascades(REF, "gamma", 0.08, float(np.float32(0.1)), impacts=1, depth=3, t_max=4, n_seeds=4)
    assert [c.to_dict() for c in a] == [c.to_dict() for c in b] and a
