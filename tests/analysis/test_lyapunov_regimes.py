"""Lyapunov exponents that know when the motion changed: final regimes and error estimates."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import Parameters, simulate
from rotorcontact.analysis.lyapunov import lyapunov_spectrum
from rotorcontact.analysis.regime_change import spread, subwindow_rates
from rotorcontact.maps.impact_map import one_impact_orbits
from rotorcontact.simulation.motion import WINDOW as SUMMARY_WINDOW
from reference_parameters import REF

#: Starts near rest spread well beyond rounding, so that their fates are independent draws.
STARTS = [-1e-3, -1e-3j, 2e-3, 2e-3j, -2e-3, 3e-3, 1e-3, 1e-3j, 0j, -2e-3j, 3e-3j, -3e-3]


def _b1d(p: Parameters):
    b1d = next(o for o in one_impact_orbits(p) if o.label == "B1,d")
    expected = sorted([0.0] + [math.log(abs(m)) / b1d.T for m in b1d.multipliers], reverse=True)
    return b1d, np.array(expected)


def test_chaotic_transient_that_ends_in_rolling_is_flagged_with_the_rolling_exponent():
    """At gamma = 0.08 the chaotic set is left for backward whirl; a window holding both is flagged."""
    p = REF.replace(gamma=0.08)
    # which starts leave the chaotic set, and when, is as sensitive to rounding as the motion itself: take
    # the first that starts rolling within 10^4, after 700 at least, and fit the window to it: 500 of chaotic
    # impacts before the rolling, and a run long enough that the rolling fills the part its summary classifies
    for u0 in STARTS:
        rolls = [c.t_start for c in simulate(p, u0, 0j, 1e4).contact_intervals if c.kind == "rolling"]
        if not rolls or rolls[0] < 700.0:
            continue
        t_transient = rolls[0] - 500.0
        t_end = rolls[0] / (1.0 - SUMMARY_WINDOW) + 300.0
        res = lyapunov_spectrum(p, u0, 0j, t_end, t_transient=t_transient)
        last = res.trajectory.contact_intervals[-1] if res.trajectory.contact_intervals else None
        if last is not None and last.kind == "rolling" and last.t_start == rolls[0]:
            break
    else:
        pytest.fail(f"none of {len(STARTS)} starts leaves the chaotic set for rolling between 700 and 10^4")
    assert res.trajectory.summary.regime == "backward-whirl"
    assert res.regime_change and res.final_regime == "contact"
    assert res.regime_start == last.t_start
    # rolling keeps only d theta, which it carries unchanged: exponent 0 exactly, three -inf
    assert res.final_exponents == (0.0, -math.inf, -math.inf, -math.inf)
    assert res.final_errors[0] == 0.0
    # the chaotic impacts before it made the window's average differ from it
    impacts = res.trajectory.impacts.t
    assert np.count_nonzero((impacts > t_transient) & (impacts < last.t_start)) > 100
    data = res.to_dict()
    assert data["regime_change"] is True and data["final_exponents"] == [0.0, None, None, None]
    assert data["regime_start"] == last.t_start


def test_a_run_that_stays_chaotic_has_no_final_regime_and_finite_errors():
    p = REF.replace(gamma=0.08)
    for u0 in STARTS:
        res = lyapunov_spectrum(p, u0, 0j, 1500.0, t_transient=300.0)
        if res.trajectory.summary.motion == "irregular" and res.collapsed == 0:
            break
    else:
        pytest.fail("no start stays on the chaotic set")
    assert not res.regime_change and res.final_regime is None and res.final_exponents is None
    assert all(0.0 < e < 0.05 for e in res.errors)
    assert res.exponents[0] > 3.0 * res.errors[0]


def test_transient_onto_b1d_is_flagged_and_the_final_exponents_are_log_multipliers_over_t():
    """From rest at gamma = 0.1 with no transient discarded: the final regime is B1,d."""
    p = REF.replace(gamma=0.1)
    b1d, expected = _b1d(p)
    res = lyapunov_spectrum(p, 0j, 0j, 1200.0, t_transient=0.0)
    assert res.regime_change and res.final_regime == "periodic"
    # every impact from the start of the final regime is B1,d's fixed point; impacts well before it are not
    imp = res.trajectory.impacts
    dist = np.maximum.reduce([np.abs(np.angle(np.exp(1j * (imp.theta - b1d.theta)))),
                              np.abs(imp.rdot - b1d.rdot), np.abs(imp.thetadot - b1d.thetadot)])
    after = imp.t >= res.regime_start
    assert dist[after].max() < 1e-5
    assert dist[np.flatnonzero(after)[0] - 20] > 1e-6
    final = np.array(res.final_exponents)
    err = np.array(res.final_errors)
    # the flow direction and the real multiplier: exact to the length of the window
    np.testing.assert_allclose(final[:2], expected[:2], atol=1e-6)
    # the complex pair: its sum is exact, the split within it is covered by the error estimate
    assert final[2] + final[3] == pytest.approx(expected[2] + expected[3], abs=1e-6)
    assert np.all(np.abs(final - expected) <= 2.0 * err + 1e-7)
    # the window's own average is spoilt by the transient, and its error estimate says so
    whole = np.array(res.exponents)
    assert abs(whole[0] - expected[0]) > 1e-3 and res.errors[0] > 1e-3


def test_a_settled_run_is_not_flagged_and_its_errors_cover_the_exact_values():
    p = REF.replace(gamma=0.1)
    _b1d_orbit, expected = _b1d(p)
    res = lyapunov_spectrum(p, 0j, 0j, 1200.0, t_transient=300.0)
    assert not res.regime_change and res.final_regime == "periodic" and res.regime_start < res.t_start
    assert np.all(np.abs(np.array(res.exponents) - expected) <= 2.0 * np.array(res.errors) + 1e-7)
    assert res.final_exponents == res.exponents


def test_subwindow_rates_interpolate_the_running_sums():
    times = np.array([0.0, 1.0, 1.0, 3.0, 4.0])
    sums = np.array([[0.0], [2.0], [5.0], [7.0], [7.0]])
    # at the repeated time 1.0 the value before the jump counts: 0 -> 2 over [0, 1], 2 -> 7 over [1, 3]
    rates = subwindow_rates(times, sums, np.array([0.0, 1.0, 2.0, 4.0]))
    np.testing.assert_allclose(rates[:, 0], [2.0, 2.5, 1.25 / 1.0 * 1.0])
    r = np.array([[1.0], [2.0], [3.0], [4.0]])
    assert spread(r)[0] == pytest.approx(np.std([1, 2, 3, 4], ddof=1) / 2.0)
    assert spread(r[:1])[0] == math.inf
