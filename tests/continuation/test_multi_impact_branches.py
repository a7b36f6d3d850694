"""Arguments of `rotorcontact.continuation.multi_impact_branches`: the search for all orbits of p impacts
(its starts, flags, window and grid) and the continuation of one orbit refuse bad input by name, before any
simulation or continuation; numpy scalars are numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation.multi_impact_branches import continue_multi_impact, multi_impact_orbits
from rotorcontact.maps.impact_map import one_impact_orbits
from rotorcontact.maps.multi_impact import solve_multi_impact
from reference_parameters import REF

P0 = REF.replace(gamma=0.1)


@pytest.fixture(scope="module")
def b1d():
    o = next(o for o in one_impact_orbits(P0) if o.label == "B1,d")
    return solve_multi_impact(P0, [o.state], label="B1,d")


@pytest.mark.parametrize("starts, match", [
    ("x", r"^starts = 'x' is invalid; allowed: a list of at most 1000 initial states"),
    (3, r"^starts = 3 is invalid"),
    ([(0j, 0j)] * 1001, r"^starts = .* is invalid; allowed: a list of at most 1000"),
    ([1], r"^starts\[0\] = 1 is invalid; allowed: an initial state \(u0, du0\)"),
    ([(0.1,)], r"^starts\[0\] = \(0.1,\) is invalid"),
    ([(0j, 0j), "ab"], r"^starts\[1\] = 'ab' is invalid"),
    ([(2.0, 0.0)], r"^starts\[0\] = \(2.0, 0.0\) is invalid; allowed: .* \(u0 = .* outside the clearance"),
    ([(0.1, "x")], r"^starts\[0\] = \(0.1, 'x'\) is invalid; allowed: .* \(du0 = 'x' is text"),
    ([(math.nan, 0.0)], r"^starts\[0\] = \(nan, 0.0\) is invalid"),
])
def test_the_starts_are_refused_by_their_index(starts, match):
    with pytest.raises(ParameterError, match=match):
        multi_impact_orbits(P0, 2, starts=starts, period_doubling=False)


@pytest.mark.parametrize("kw, match", [
    (dict(period_doubling=None), r"^period_doubling = None is invalid; allowed: True or False"),
    (dict(period_doubling="x"), r"^period_doubling = 'x' is invalid"),
    (dict(period_doubling=2), r"^period_doubling = 2 is invalid"),
    (dict(scan_width=1e300), r"^scan_width = 1e\+300 is invalid; allowed: a finite number > 0 and <= 1"),
    (dict(scan_width=0.0), r"^scan_width = 0.0 is invalid"),
    (dict(grid=(1.5, 1, 1)), r"^grid\[0\] = 1.5 is invalid; allowed: an integer from 1 to 20000"),
    (dict(grid=(0, 1, 1)), r"^grid\[0\] = 0 is invalid"),
    (dict(grid="x"), r"^grid = 'x' is invalid; allowed: three integers >= 1"),
    (dict(grid=(1, 1)), r"^grid = \(1, 1\) is invalid"),
    (dict(grid=(200, 200, 1)), r"^grid = \(200, 200, 1\) is invalid; allowed: .* a product of at most 20000"),
    (dict(t_max=-1.0), r"^t_max = -1.0 is "),
])
def test_every_option_of_the_search_is_checked(kw, match):
    # three impacts and no starts: no option is used unless the grid is given, and none may be wrong
    with pytest.raises(ParameterError, match=match):
        multi_impact_orbits(P0, 3, starts=[], **kw)


def test_the_search_takes_numpy_scalars():
    kw = dict(starts=[(np.complex128(0.1j), np.float64(0.0))], period_doubling=np.bool_(False),
              scan_width=np.float32(0.05), t_max=np.float64(12.0), grid=(np.int64(1), np.int32(1), 1))
    a = multi_impact_orbits(P0, np.int64(3), **kw)
    b = multi_impact_orbits(P0, 3, starts=[(0.1j, 0.0)], period_doubling=False, grid=(1, 1, 1))
    assert [o.label for o in a] == [o.label for o in b]


@pytest.mark.parametrize("kw, match", [
    (dict(stop=1e300), r"^stop = 1e\+300 is invalid; allowed: a value that gamma may take"),
    (dict(param="d", stop=1.5), r"^stop = 1.5 is invalid; allowed: a value that d may take"),
    (dict(step=1e300), r"^step = 1e\+300 is invalid; allowed: a finite number >= 1e-09 and <= 1"),
    (dict(max_step=1e300), r"^max_step = 1e\+300 is invalid"),
    (dict(step=True), r"^step = True is invalid"),
    (dict(max_points=10**12), r"^max_points = 1000000000000 is invalid; allowed: an integer from 1 to 1000000"),
])
def test_the_continuation_of_an_orbit_is_bounded(b1d, kw, match):
    args = dict(param="gamma", stop=0.1001, max_points=2)
    args.update(kw)
    with pytest.raises(ParameterError, match=match):
        continue_multi_impact(b1d, **args)


def test_the_continuation_of_an_orbit_takes_numpy_scalars(b1d):
    a = continue_multi_impact(b1d, "gamma", np.float64(0.1001), step=np.float32(1e-3), max_step=np.float64(0.02),
                              max_points=np.int64(5))
    b = continue_multi_impact(b1d, "gamma", 0.1001, step=float(np.float32(1e-3)), max_step=0.02, max_points=5)
    assert a.status == b.status and np.array_equal(a.values, b.values)
