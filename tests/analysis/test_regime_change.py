"""The final regime of a trajectory: bad arguments refused by name."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError, simulate
from rotorcontact.analysis.regime_change import final_regime, spread, subwindow_rates
from reference_parameters import REF


def test_a_run_that_starts_at_x_R_never_touches():
    # x_R = k is the equilibrium of the free flight (MODEL.md §4): inside the clearance, no contact ever
    p = REF.replace(gamma=0.3)
    assert abs(p.k) < 1.0
    traj = simulate(p, p.k, 0.0, 200.0)
    assert len(traj.impacts) == 0 and not traj.contact_intervals
    assert final_regime(traj).kind == "no-contact"


@pytest.mark.parametrize("traj", [None, "x", REF])
def test_a_trajectory_is_required(traj):
    with pytest.raises(ParameterError, match=r"^traj = .* is not a Trajectory object; allowed: a Trajectory"):
        final_regime(traj)


@pytest.mark.parametrize("tol", [0.0, -1.0, math.nan, "1e-6", True])
def test_the_tolerance_is_a_positive_number(tol):
    traj = simulate(REF.replace(gamma=0.3), 0.5, 0.0, 10.0)
    with pytest.raises(ParameterError, match=r"^tol = .* is invalid; allowed: a finite number > 0"):
        final_regime(traj, tol)


@pytest.mark.parametrize("rates", [None, [], 3.0, "x", [[1.0], [2.0, 3.0]], [1, math.nan],
                                   [[1.0, math.nan], [2.0, 1.0]], [math.inf, 1.0], [True, 1.0], np.zeros((2, 2, 2)),
                                   [1j, 2.0]])
def test_spread_takes_finite_rates_one_row_per_sub_window(rates):
    with pytest.raises(ParameterError, match=r"^rates = .* is invalid; allowed: finite real numbers, one row per "
                                             r"sub-window: an array of shape \(k,\) or \(k, n_rates\) with k >= 1$"):
        spread(rates)


def test_spread_of_one_rate_or_of_numpy_values_is_unchanged():
    r = np.array([[1.0, 0.5], [2.0, -0.5], [4.0, 0.25]])
    assert spread(r).tobytes() == spread(r.tolist()).tobytes() == spread(r.astype(np.float32).astype(float)).tobytes()
    assert spread([1.0, 2.0]) == 0.5 and spread(np.array([1, 2])) == 0.5
    assert spread(r[:1]).tolist() == [math.inf, math.inf] and spread([5.0]) == math.inf


TIMES = np.array([0.0, 1.0, 1.0, 3.0, 4.0])
SUMS = np.array([[0.0], [2.0], [5.0], [7.0], [7.0]])
EDGES = np.array([0.0, 1.0, 2.0, 4.0])


@pytest.mark.parametrize("times, sums, edges, match", [
    (None, SUMS, EDGES, r"^times = None is invalid; allowed: a list of finite, non-decreasing times$"),
    ([0.0, math.nan, 1.0, 3.0, 4.0], SUMS, EDGES, r"^times = .* is invalid; allowed: a list of finite"),
    ([0.0, 2.0, 1.0, 3.0, 4.0], SUMS, EDGES, r"^times = .* is invalid \(they decrease\); allowed: "),
    (TIMES, None, EDGES, r"^sums = None is invalid; allowed: finite running sums, an array of shape \(5, n_sums\)"),
    (TIMES, SUMS[:2], EDGES, r"^sums = .* is invalid \(shape \(2, 1\) for 5 times\); allowed: finite running sums"),
    (TIMES, SUMS[:, 0], EDGES, r"^sums = .* is invalid; allowed: finite running sums, an array of shape \(5, n_sums\)"),
    (TIMES, SUMS * math.nan, EDGES, r"^sums = .* is invalid; allowed: "),
    (TIMES, SUMS, None, r"^edges = None is invalid; allowed: at least two finite, increasing times$"),
    (TIMES, SUMS, EDGES[::-1], r"^edges = .* is invalid; allowed: at least two finite, increasing times$"),
    (TIMES, SUMS, [0.0, 1.0, 1.0], r"^edges = .* is invalid; allowed: at least two finite, increasing times$"),
    (TIMES, SUMS, [1.0], r"^edges = .* is invalid; allowed: at least two finite, increasing times$"),
    (TIMES, SUMS, [0.0, math.inf], r"^edges = .* is invalid; allowed: at least two finite, increasing times$"),
])
def test_subwindow_rates_take_matching_finite_times_sums_and_edges(times, sums, edges, match):
    with pytest.raises(ParameterError, match=match):
        subwindow_rates(times, sums, edges)


def test_subwindow_rates_of_lists_and_integers_are_unchanged():
    want = subwindow_rates(TIMES, SUMS, EDGES)
    assert subwindow_rates(TIMES.tolist(), SUMS.tolist(), EDGES.tolist()).tobytes() == want.tobytes()
    assert subwindow_rates([0, 1, 1, 3, 4], [[0], [2], [5], [7], [7]], [0, 1, 2, 4]).tobytes() == want.tobytes()
