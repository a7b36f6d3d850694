"""Periodic orbits with p >= 2 impacts per period, and the period doubling of B1,d.

The claims: the period-2 orbits are fixed points of the simulator's own P_I^2
and of `simulate`; the period-2 branch is born at the period doubling of B1,d
(its impact states converge to B1,d's and its period to 2T); its multipliers
are those of the map measured by finite differences; brute-force simulation
and branch switching find the same orbit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError, Parameters, simulate
from rotorcontact.maps.impact_map import impact_map, one_impact_orbits
from rotorcontact.continuation.multi_impact_branches import continue_multi_impact, multi_impact_orbits
from rotorcontact.maps.multi_impact import (
    MultiImpactOrbit,
    NewtonFailure,
    find_period_doubling,
    orbits_from_simulation,
    period_doubled_orbit,
    periodic_residual,
    solve_multi_impact,
)
from reference_parameters import REF


GAMMA = 0.083  # between the end of the period-2 branch (grazing) and the period doubling


def _b1d(p: Parameters):
    return next(o for o in one_impact_orbits(p) if o.label == "B1,d")


def _angle(a, b):
    return abs(math.remainder(a - b, 2 * math.pi))


def _state_distance(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    return max(_angle(x[0], y[0]), abs(x[1] - y[1]), abs(x[2] - y[2]))


@pytest.fixture(scope="module")
def pd():
    return find_period_doubling(REF.replace(gamma=0.1), "B1,d", "gamma", lo=0.08, hi=0.09)


@pytest.fixture(scope="module")
def orbit(pd) -> MultiImpactOrbit:
    start = period_doubled_orbit(pd, -1e-4)
    branch = continue_multi_impact(start, "gamma", GAMMA)
    assert branch.status == "terminal" and branch.values[-1] == pytest.approx(GAMMA, abs=1e-12)
    return branch.orbits[-1]


def test_b1d_loses_stability_through_a_multiplier_minus_one(pd):
    assert 0.08 < pd.value < 0.09 and pd.parent == "B1,d"
    assert pd.multiplier == pytest.approx(-1.0, abs=1e-8)
    # stable above, a real multiplier below -1 beneath
    above = _b1d(REF.replace(gamma=pd.value + 1e-4))
    below = _b1d(REF.replace(gamma=pd.value - 1e-4))
    assert above.stable and not below.stable
    assert min(m.real for m in below.multipliers) < -1.0 and pd.unstable_side == -1.0
    # the eigenvector of -1 at the bifurcation
    jac = pd.orbit.jacobian()
    np.testing.assert_allclose(jac @ pd.eigenvector, -pd.eigenvector, atol=1e-7)


def test_period_two_points_are_fixed_points_of_the_impact_map_squared(orbit):
    p = orbit.params
    assert orbit.impacts == 2 and orbit.label == "B1,d/PD"
    x0, x1 = orbit.states
    once = impact_map(p, x0)
    twice = impact_map(p, once.state)
    assert once.status == twice.status == "impact"
    assert _state_distance(once.state, x1) < 1e-10
    assert _state_distance(twice.state, x0) < 1e-10
    assert once.time + twice.time == pytest.approx(orbit.period, abs=1e-10)
    assert [q.dt for q in orbit.points] == pytest.approx([once.time, twice.time], abs=1e-10)
    # the two impacts are distinct: it is not B1,d counted twice
    assert _state_distance(x0, x1) > 0.1


def test_period_two_orbit_is_reproduced_by_simulate(orbit):
    u0, du0 = orbit.initial_condition()
    tr = simulate(orbit.params, u0, du0, orbit.period + 0.5 * orbit.points[0].dt)
    imp = tr.impacts
    assert len(imp) == 2
    x0, x1 = orbit.states
    assert _state_distance((imp.theta[0], imp.rdot[0], imp.thetadot[0]), x1) < 1e-10
    assert _state_distance((imp.theta[1], imp.rdot[1], imp.thetadot[1]), x0) < 1e-10
    assert imp.t[0] == pytest.approx(orbit.points[0].dt, abs=1e-10)
    assert imp.t[1] == pytest.approx(orbit.period, abs=1e-10)


def test_period_two_orbit_is_stable_plausible_and_the_attractor_from_rest(orbit):
    assert orbit.stable and orbit.plausible and orbit.slipping
    assert orbit.r_max_interior is not None and orbit.r_max_interior < 1.0
    found = orbits_from_simulation(orbit.params, 2)
    assert len(found) == 1 and found[0].label == "M2-1"
    # the same orbit, up to the starting impact
    a, b = found[0].states, orbit.states
    shift = min(range(2), key=lambda s: _state_distance(np.roll(b, -s, axis=0)[0], a[0]))
    for x, y in zip(a, np.roll(b, -shift, axis=0)):
        assert _state_distance(x, y) < 1e-9
    assert found[0].period == pytest.approx(orbit.period, abs=1e-10)
    # the high-level search reports it once, under the branch label
    assert [o.label for o in multi_impact_orbits(orbit.params, 2)] == ["B1,d/PD"]


def test_multipliers_are_those_of_the_simulated_map_squared(orbit):
    p = orbit.params
    x0 = orbit.states[0]

    def p2(x):
        y = impact_map(p, impact_map(p, x).state).state
        return np.array([math.remainder(y[0] - x0[0], 2 * math.pi), y[1], y[2]])

    eps = 1e-6
    fd = np.array([(p2(x0 + eps * e) - p2(x0 - eps * e)) / (2 * eps) for e in np.eye(3)]).T
    np.testing.assert_allclose(orbit.jacobian(), fd, atol=1e-6 * np.abs(fd).max())
    ev = np.linalg.eigvals(fd)
    assert sorted(np.abs(ev)) == pytest.approx(sorted(abs(m) for m in orbit.multipliers), abs=1e-5)


def test_the_period_two_branch_meets_b1d_at_the_period_doubling(pd):
    """As gamma -> gamma_PD the two impact states tend to B1,d's like sqrt and the period to 2T."""
    dist, lag = [], []
    offsets = (1e-4, 1e-5, 1e-6)
    for off in offsets:
        o = period_doubled_orbit(pd, -off)
        b = _b1d(o.params)
        d = max(_state_distance(x, b.state) for x in o.states)
        dist.append(d / math.sqrt(off))
        lag.append((2.0 * b.T - o.period) / off)
        # the two impacts straddle B1,d's: their mean is off it only at first order in the offset
        mean = o.states.mean(axis=0)
        assert _state_distance(mean, b.state) < 200.0 * off
    assert max(d * math.sqrt(off) for d, off in zip(dist, offsets)) < 0.2
    assert dist[-1] * math.sqrt(offsets[-1]) < 0.02
    # square-root law of a period doubling, and a period 2T + O(offset)
    assert max(dist) / min(dist) < 1.05
    assert max(lag) / min(lag) < 1.1 and min(lag) > 0.0


def test_no_period_two_orbit_on_the_stable_side(pd):
    with pytest.raises(NewtonFailure):
        period_doubled_orbit(pd, 1e-4)


def test_continuation_away_from_the_bifurcation_ends_at_a_grazing(pd):
    start = period_doubled_orbit(pd, -1e-4)
    branch = continue_multi_impact(start, "gamma", 0.07)
    assert branch.status == "grazing"
    assert 0.0825 < branch.values[-1] < GAMMA
    last = branch.orbits[-1]
    assert last.r_max_interior > 0.99
    assert any(e.kind == "grazing" for e in branch.events)
    # each continued point is an orbit
    assert max(o.residual for o in branch.orbits) < 1e-10
    # gamma decreases along the branch; at the grazing the branch turns vertical (square-root
    # singularity of P_I), where the steps only move the impact states
    assert np.all(np.diff(branch.values) < 1e-12) and branch.values[-1] < branch.values[0] - 5e-4


def test_newton_rejects_an_orbit_with_fewer_impacts():
    p = REF.replace(gamma=0.1)
    b = _b1d(p)
    with pytest.raises(NewtonFailure):
        solve_multi_impact(p, [b.state, b.state + [1e-3, 0.0, 0.0]])
    # with one impact per period it is B1,d itself
    one = solve_multi_impact(p, [b.state + [1e-3, 1e-3, 0.0]])
    assert _state_distance(one.states[0], b.state) < 1e-10 and one.period == pytest.approx(b.T, abs=1e-10)


def test_residual_and_bad_input():
    p = REF.replace(gamma=0.1)
    b = _b1d(p)
    res, jac = periodic_residual(p, [b.state, b.state])
    assert np.max(np.abs(res)) < 1e-10 and jac.shape == (6, 6)
    with pytest.raises(ParameterError):
        periodic_residual(p, [1.0, 2.0])
    with pytest.raises(ParameterError):
        multi_impact_orbits(p, 1)
    with pytest.raises(ParameterError):
        orbits_from_simulation(p, 0)
    with pytest.raises(ParameterError):
        find_period_doubling(p, "B1,d", "phase", lo=0.08, hi=0.09)
    with pytest.raises(ParameterError):
        find_period_doubling(p, "B1,d", "gamma", lo=0.09, hi=0.08)
    with pytest.raises(ParameterError):
        # B1,d is stable throughout: no period doubling there
        find_period_doubling(p, "B1,d", "gamma", lo=0.09, hi=0.1, n_scan=4)
    with pytest.raises(ParameterError):
        solve_multi_impact(p, [[0.0, float("nan"), 0.0]])
    # a guess that is not an impact, or too fast, is bad input (not a failure of Newton's method)
    with pytest.raises(ParameterError, match=r"^guess\[0\] = \(0.0, -1.0, 0.0\) has rdot = -1.0 <= 0, not an "
                                             r"impact; allowed: impact states, rdot > 0$"):
        solve_multi_impact(p, [(0.0, -1.0, 0.0), (0.0, -1.0, 0.0)])
    with pytest.raises(ParameterError, match=r"^guess\[1\] = \(0.0, 1e\+300, 0.0\) is too fast; allowed: "):
        solve_multi_impact(p, [b.state, (0.0, 1e300, 0.0)])


def test_orbits_of_more_impacts_than_the_bound_are_refused_before_any_allocation():
    from rotorcontact.continuation.cascade import cascades
    from rotorcontact.continuation.multi_impact_families import multi_impact_branches
    from rotorcontact.maps.multi_impact import MAX_ORBIT_IMPACTS, orbits_from_grid

    p = REF.replace(gamma=0.1)
    match = rf"^impacts = 1000000 is invalid; allowed: an integer from \d to {MAX_ORBIT_IMPACTS}$"
    for call in (lambda: orbits_from_simulation(p, 10**6), lambda: orbits_from_grid(p, 10**6),
                 lambda: multi_impact_orbits(p, 10**6), lambda: multi_impact_branches(p, 10**6),
                 lambda: cascades(p, "gamma", 0.0, 0.2, impacts=10**6)):
        with pytest.raises(ParameterError, match=match):
            call()


@pytest.mark.parametrize("kwargs, match", [(dict(lo="0"), r"^lo = '0' is text"), (dict(hi=None), r"^hi = None"),
                                           (dict(tol=-1.0), r"^tol = -1.0 is invalid; allowed: a finite number > 0$"),
                                           (dict(n_scan=10**9), r"^n_scan = 1000000000 is invalid; allowed: an integer "
                                                                r"from 1 to 10000$"),
                                           (dict(label="B9,z"), r"^label = 'B9,z' is not a one-impact orbit label; "
                                                                r"allowed: 'B<n>,<a\|b\|c\|d>'"),
                                           (dict(label=None), r"^label = None is not a one-impact orbit label")])
def test_find_period_doubling_refuses_bad_intervals_and_scans(kwargs, match):
    args = dict(label="B1,d", param="gamma", lo=0.0, hi=0.2)
    args.update(kwargs)
    with pytest.raises(ParameterError, match=match):
        find_period_doubling(REF, **args)


def test_the_impact_bound_holds_for_the_doubled_orbits_too():
    from rotorcontact.continuation.cascade import cascades
    from rotorcontact.continuation.multi_impact_families import multi_impact_branches
    from rotorcontact.maps.multi_impact import MAX_ORBIT_IMPACTS

    p = REF.replace(gamma=0.1)
    with pytest.raises(ParameterError, match=rf"^impacts = 4096 doubled depth = 1 times makes orbits of 8192 impacts; "
                                             rf"allowed: impacts \* 2\^depth <= {MAX_ORBIT_IMPACTS}$"):
        cascades(p, "gamma", 0.0, 0.2, impacts=4096, depth=1)
    with pytest.raises(ParameterError, match=r"^impacts = 16 doubled doublings = 9|^doublings = 9"):
        multi_impact_branches(p, 16, doublings=9)
    with pytest.raises(ParameterError, match=r"^impacts = 2048 doubled doublings = 2 times makes orbits of 8192"):
        multi_impact_branches(p, 2048, doublings=2)


def test_impact_states_are_checked_by_every_function_that_takes_them():
    from rotorcontact.maps.multi_impact import MAX_ORBIT_IMPACTS, multipliers_at

    p = REF.replace(gamma=0.1)
    b = _b1d(p)
    z = multipliers_at(p, np.array([b.state]))
    assert np.allclose(np.sort_complex(z), np.sort_complex(np.asarray(b.multipliers)), atol=1e-9)
    for call, name in ((lambda s: multipliers_at(p, s), "states"), (lambda s: periodic_residual(p, s), "states"),
                       (lambda s: solve_multi_impact(p, s), "guess")):
        for bad in ([], "x", [[0.0, 0.5, True]], [[0.0, 0.5]], [[0.0, 0.5, 0.1], [0.0, 0.5]], None):
            with pytest.raises(ParameterError, match=rf"^{name} "):
                call(bad)
        # more rows than an orbit may have: refused before the (3p, 3p) Jacobian is allocated
        with pytest.raises(ParameterError, match=rf"^{name} has shape \({MAX_ORBIT_IMPACTS + 1}, 3\); allowed: "):
            call(np.tile(b.state, (MAX_ORBIT_IMPACTS + 1, 1)))
    # a state that is not an impact, or has no next impact, is named by its row
    with pytest.raises(ParameterError, match=r"^states\[1\] = .* has rdot = -0.5 <= 0, not an impact; allowed: "):
        multipliers_at(p, [b.state, [0.0, -0.5, 0.0]])
    with pytest.raises(ParameterError, match=r"^params = "):
        multipliers_at(None, [b.state])



def test_searches_and_doublings_check_their_options(pd, orbit):
    from rotorcontact.maps.multi_impact import doubled_orbit_at_amplitude, orbits_from_grid

    p = REF.replace(gamma=0.1)
    for kw, name in ((dict(shape=(1.5, 1, 1)), r"shape\[0\]"), (dict(shape=(True, 1, 1)), r"shape\[0\]"),
                     (dict(shape="abc"), "shape"), (dict(rdot_range=None), "rdot_range"),
                     (dict(rdot_range=(0.1,)), "rdot_range"), (dict(rdot_range=(0.1, 1e300)), "rdot_range"),
                     (dict(thetadot_range=("a", 1.0)), r"thetadot_range\[0\]"), (dict(max_iter=10**9), "max_iter")):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            orbits_from_grid(p, 2, **kw)
    for starts, name in (("x", "starts"), ([1], r"starts\[0\]"), ([(0.1,)], r"starts\[0\]"),
                         ([(0.1, "x")], r"starts\[0\] = \(0.1, 'x'\) is invalid; allowed: .* \(du0"),
                         ([(2.0, 0.0)], r"starts\[0\] = \(2.0, 0.0\) is invalid; allowed: .* \(u0")):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            orbits_from_simulation(p, 2, starts=starts)
    assert orbits_from_simulation(p, 2, starts=[]) == ()  # no starts: no simulation, as multi_impact_orbits uses
    assert orbit.initial_condition(np.int64(1)) == orbit.initial_condition(1)
    for bad in (2, -1, None, True, 0.5):
        with pytest.raises(ParameterError, match=r"^index = .* is invalid; allowed: an integer from 0 to 1$"):
            orbit.initial_condition(bad)
    for call, name in ((lambda: doubled_orbit_at_amplitude(None, 1e-3), "pd"),
                       (lambda: doubled_orbit_at_amplitude(pd, 1e300), "amplitude"),
                       (lambda: doubled_orbit_at_amplitude(pd, 1e-3, tol=0.0), "tol"),
                       (lambda: doubled_orbit_at_amplitude(pd, 1e-3, max_iter=1.5), "max_iter"),
                       (lambda: period_doubled_orbit(orbit, 0.01), "pd"),
                       (lambda: period_doubled_orbit(pd, 0.01, amplitudes=0.001), "amplitudes"),
                       (lambda: period_doubled_orbit(pd, 0.01, amplitudes=[]), "amplitudes"),
                       (lambda: period_doubled_orbit(pd, 0.01, amplitudes=["x"]), r"amplitudes\[0\]"),
                       (lambda: solve_multi_impact(p, orbit.states, label=1), "label"),
                       (lambda: solve_multi_impact(p, orbit.states, canonical="x"), "canonical")):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            call()
