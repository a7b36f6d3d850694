"""The search for the largest value of a smooth function between its samples (`simulation.peaks`)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from rotorcontact.simulation.peaks import (
    BEST, PEAK_SLOTS, PEAK_STEPS, best_three, may_exceed, parabola_vertex, peak_next, peak_record, peak_search,
)


def search(f, x1, x2, x3):
    """The search as the contact phases run it; returns the largest value and the number of trials."""
    state = np.empty(PEAK_SLOTS)
    peak_search(state, x1, f(x1), x2, f(x2), x3, f(x3))
    for trials in range(PEAK_STEPS + 1):
        x = peak_next(state)
        if math.isnan(x) or trials == PEAK_STEPS:
            return state[BEST], trials
        assert x1 <= x <= x3
        peak_record(state, x, f(x))


def test_the_vertex_of_a_parabola():
    rng = np.random.default_rng(0)
    for _ in range(100):
        a, c = rng.uniform(0.1, 10.0), rng.uniform(-1.0, 1.0)
        xs = np.sort(rng.uniform(-2.0, 2.0, 3))
        f = [-a * (x - c) ** 2 + 3.0 for x in xs]
        assert parabola_vertex(xs[0], f[0], xs[1], f[1], xs[2], f[2]) == pytest.approx(c, abs=1e-9)
    assert parabola_vertex(0.0, 1.0, 1.0, 2.0, 2.0, 3.0) == 1.0  # collinear: the middle point


def test_best_three_drops_the_lowest():
    assert best_three(0.0, 1.0, 1.0, 3.0, 2.0, 2.0, 0.5, 2.5) == (0.5, 2.5, 1.0, 3.0, 2.0, 2.0)
    assert best_three(0.0, 1.0, 1.0, 3.0, 2.0, 2.0, 1.5, 0.5) == (0.0, 1.0, 1.0, 3.0, 2.0, 2.0)
    assert best_three(0.0, 2.0, 1.0, 3.0, 2.0, 1.0, 1.5, 2.5) == (0.0, 2.0, 1.0, 3.0, 1.5, 2.5)
    assert best_three(0.0, 2.5, 1.0, 1.0, 2.0, 2.0, 1.5, 3.0) == (0.0, 2.5, 1.5, 3.0, 2.0, 2.0)


def test_may_exceed_bounds_a_parabolas_maximum_twice_over():
    """For a parabola sampled at gaps in any ratio r, the maximum exceeds the largest sample by at most
    r^2 / (4 (r + 1)) of its larger drop; the margin holds twice that."""
    rng = np.random.default_rng(1)
    seen = 0
    for _ in range(4000):
        left, right = np.exp(rng.uniform(-3.0, 3.0, 2))
        x0 = rng.uniform(-left, right)
        f = [-((x - x0) ** 2) for x in (-left, 0.0, right)]
        if f[1] < f[0] or f[1] < f[2]:
            continue
        seen += 1
        assert may_exceed(-left, f[0], 0.0, f[1], right, f[2], 0.0)  # the maximum, 0
        r = max(left, right) / min(left, right)
        excess = -f[1] / (f[1] - min(f[0], f[2]))
        assert excess <= r * r / (4.0 * (r + 1.0)) * (1.0 + 1e-12)
        # the margin is at least twice that bound
        assert may_exceed(-left, f[0], 0.0, f[1], right, f[2], f[1] + 2.0 * r * r / (4.0 * (r + 1.0))
                          * (f[1] - min(f[0], f[2])))
    assert seen > 1000


@pytest.mark.parametrize("seed", range(4))
def test_the_search_finds_the_maximum_between_samples(seed):
    """Smooth forces of a contact phase's shape (a turn's gravity and a second harmonic), sampled at uneven
    steps about their top: the largest value to 1e-13 relative of a bounded scalar optimiser's, in a few
    trials (a vertex through the wide samples alone can settle 1e-4 of the bracket off the maximum)."""
    rng = np.random.default_rng(seed)
    trials = []
    for _ in range(300):
        left, right = rng.uniform(0.02, 0.3, 2)
        x0, amp, phase = rng.uniform(-left, right), rng.uniform(0.0, 20.0), rng.uniform(0.0, 2 * math.pi)

        def f(x):
            return 100.0 * math.cos(x - x0) + amp * math.cos(2.0 * (x - x0) + phase) + 500.0

        if not f(-left) < f(0.0) >= f(right):
            continue
        found, n = search(f, -left, 0.0, right)
        res = minimize_scalar(lambda x: -f(x), bounds=(-left, right), method="bounded", options={"xatol": 1e-14})
        assert f(0.0) <= found <= -res.fun + 1e-12
        assert found == pytest.approx(-res.fun, rel=1e-13)
        trials.append(n)
    assert max(trials) <= PEAK_STEPS and np.mean(trials) < 6
