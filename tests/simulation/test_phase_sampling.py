"""Sample times of a contact phase and the largest value along it (`phase_sampling`), and the largest forces and
mean friction power of the simulator's contact phases (`Trajectory.phase_forces`) against dense samples and
adaptive quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rotorcontact import ParameterError, simulate
from rotorcontact.simulation.phase_sampling import (
    PHASE_DT,
    PHASE_DTHETA,
    PHASE_MAX_PIECES,
    PHASE_MAX_STEPS,
    PHASE_MIN_STEPS,
    peak_of_samples,
    phase_grids,
    phase_times,
)
from reference_parameters import REF


def _is_power_of_two(k: int) -> bool:
    return k > 0 and k & (k - 1) == 0


@pytest.mark.parametrize("rate", [0.0, 1.0, 58.0, 1e3])
def test_phase_times_are_fine_enough_for_a_constant_rate(rate):
    t = phase_times(lambda x: np.full(x.shape, rate), 2.0, 40.0)
    steps = t.size - 1
    assert _is_power_of_two(steps) and steps >= PHASE_MIN_STEPS
    h = np.diff(t)
    assert t[0] == 2.0 and t[-1] == 40.0 and np.all(h > 0)
    assert h.max() <= PHASE_DT * (1 + 1e-12) and h.max() * rate <= PHASE_DTHETA * (1 + 1e-12)
    assert steps == PHASE_MIN_STEPS or h.max() * 2 > min(PHASE_DT, PHASE_DTHETA / rate if rate else math.inf)


def test_phase_times_follow_a_rate_that_rises_between_the_first_samples():
    def rate(x):  # a narrow peak between the samples of the first pass, seen only by a finer one
        return 1.0 + 100.0 * np.exp(-(((x - 5.078125) / 0.03) ** 2))

    assert rate(np.linspace(0.0, 10.0, PHASE_MIN_STEPS + 1)).max() < 2.0
    t = phase_times(rate, 0.0, 10.0)
    assert np.diff(t).max() * rate(t).max() <= PHASE_DTHETA * (1 + 1e-12)
    assert np.diff(t).max() * 101.0 <= PHASE_DTHETA * 1.01


def test_phase_times_are_bounded_and_a_point_for_an_empty_span():
    t = phase_times(lambda x: np.full(x.shape, 1e12), 0.0, 1.0)
    assert t.size == PHASE_MAX_STEPS + 1
    assert phase_times(lambda x: np.ones_like(x), 3.0, 3.0).tolist() == [3.0]


@pytest.mark.parametrize("rate, pieces", [(1.0, 1), (1e3, 5), (1e12, PHASE_MAX_PIECES)])
def test_phase_grids_cut_a_long_span_into_pieces(rate, pieces):
    grids = phase_grids(lambda x: np.full(x.shape, rate), 0.0, 1e3)
    assert len(grids) == pieces
    assert grids[0][0] == 0.0 and grids[-1][-1] == 1e3
    assert all(a[-1] == b[0] for a, b in zip(grids, grids[1:]))
    assert all(t.size - 1 <= PHASE_MAX_STEPS and _is_power_of_two(t.size - 1) for t in grids)
    if pieces < PHASE_MAX_PIECES:
        assert max(np.diff(t).max() for t in grids) * rate <= PHASE_DTHETA * (1 + 1e-12)


@pytest.mark.parametrize("centre", [0.123456789, 0.5, 0.987654321])
def test_peak_of_samples_finds_a_peak_between_samples(centre):
    def f(x):
        return 2.0 - (x - centre) ** 2 + 0.1 * (x - centre) ** 3

    t = np.linspace(0.0, 1.0, 17)
    v = f(t)
    peak = peak_of_samples(f, t, v)
    assert peak >= v.max()
    # the vertex misses the peak by O(h^2) in time (h = 1/256 after the resampling), the value by O(h^4) (1.6e-13)
    assert peak == pytest.approx(2.0, abs=1e-12)


def test_peak_of_samples_at_an_end_and_of_one_sample():
    t = np.linspace(0.0, 1.0, 9)
    v = np.exp(t)
    peak = peak_of_samples(np.exp, t, v)
    assert peak >= v[-1] and peak == pytest.approx(math.e, rel=1e-15)
    assert peak_of_samples(np.exp, t[:1], v[:1]) == v[0]


@pytest.fixture(scope="module")
def whirl():
    """The low-damping rub: a sliding-forward phase ending in rolling at theta' = -58, over 3000 turns."""
    return simulate(REF.replace(gamma=0.05, d=0.95), 0.5, 0.8 + 0.3j, 400.0)


def test_phase_forces_against_dense_samples_and_quadrature(whirl):
    p = whirl.params
    kinds = [c.kind for c in whirl.contact_intervals]
    assert kinds == ["sliding-forward", "rolling"]
    for c in whirl.contact_intervals:
        f = whirl.phase_forces(c.t_start, c.t_end, c.kind)
        # strictly inside the phase, where contact_forces gives its own law; the ends are a step beyond the
        # first and last samples
        t = np.linspace(c.t_start, c.t_end, 400_001)[1:-1]
        n, ft = whirl.contact_forces(t)
        for got, v in ((f.max_normal, n), (f.max_friction, np.abs(ft))):
            assert v.max() * (1 - 1e-12) <= got <= v.max() + 2.0 * np.abs(np.diff(v)).max()
        if c.kind == "sliding-forward":
            assert f.max_friction == pytest.approx(p.mu * f.max_normal, rel=1e-12)
            power = quad(lambda x: whirl.friction_power(np.array([x]))[0], c.t_start, c.t_end, epsabs=0.0,
                         epsrel=1e-11, limit=500)[0] / (c.t_end - c.t_start)
            assert f.mean_power == pytest.approx(power, rel=1e-9)
        else:  # rolling: no slip
            assert abs(f.mean_power) <= 1e-10 * f.max_friction * (1.0 + abs(p.r_ratio))


def test_phase_forces_of_a_short_span_late_in_the_run(whirl):
    """The mean power of a span of 1e-9 at t = 37 (steps of about 2e-11, rounded in t to 7e-15) is the power there."""
    c = whirl.contact_intervals[0]
    t0 = 37.0
    assert c.kind == "sliding-forward" and c.t_start < t0 < c.t_end
    f = whirl.phase_forces(t0, t0 + 1e-9, c.kind)
    assert f.mean_power == pytest.approx(whirl.friction_power(np.array([t0]))[0], rel=1e-7)
    assert whirl.phase_forces(t0, t0, c.kind).mean_power == whirl.friction_power(np.array([t0]))[0]


@pytest.mark.parametrize("args, name", [
    ((37.0, 38.0, "sliding"), "kind"), ((-1.0, 38.0, "rolling"), "t_start"), ((38.0, 37.0, "rolling"), "t_end"),
    ((37.0, 401.0, "rolling"), "t_end"), ((math.nan, 38.0, "rolling"), "t_start"),
])
def test_phase_forces_refuses_bad_input(whirl, args, name):
    with pytest.raises(ParameterError, match=f"^{name} = "):
        whirl.phase_forces(*args)
