"""Figures of the compliant bearing (MODEL.md §8): the force of the first touchdowns, the rigid limit."""

from __future__ import annotations

import numpy as np
import pytest

from rotorcontact import Machine, reference_machine
from rotorcontact.plotting.drop import plot_dry_whip, plot_rigid_limit, plot_touchdown_forces
from rotorcontact.plotting.style import save_figure
from rotorcontact.simulation.drop_run import RPM, drop


def test_touchdown_forces_follow_the_episodes(tmp_path):
    m = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04, "contact": "compliant",
                   "contact_stiffness": 1e10})
    r = drop(m, 12000 * RPM, 0.0, 0.02)
    fig, ax = plot_touchdown_forces(r, episodes=2, samples=40)
    lines = ax.get_lines()
    assert len(lines) == 2
    for line, row in zip(lines, r.impacts):
        t, f = line.get_data()
        # each curve spans its episode, starts and ends at 0 and peaks just below the located maximum
        assert t[0] == pytest.approx(row[0] * 1e3, rel=1e-14) and f[0] == 0.0 and f[-1] == 0.0
        assert t[-1] == pytest.approx((row[0] + row[14]) * 1e3, rel=1e-14)
        assert 0.98 * row[15] * 1e-3 <= f.max() <= row[15] * 1e-3 * (1.0 + 1e-9)
    assert save_figure(fig, tmp_path / "f.png").stat().st_size > 0


def test_rigid_limit_figure_draws_the_rate():
    k = np.array([1e9, 1e10, 1e11])
    diffs = np.array([[1.0, 2.0], [0.4, 0.8], [0.16, 0.32]])
    fig, ax = plot_rigid_limit(k, diffs, ["a", "b"])
    lines = ax.get_lines()
    assert len(lines) == 3
    _x, ref = lines[2].get_data()
    np.testing.assert_allclose(ref, 0.16 * (k / 1e11) ** -0.4, rtol=1e-14)


def test_dry_whip_figure_draws_the_curve_the_coupled_frequency_and_the_runs(tmp_path):
    damping = np.array([50.0, 500.0, 5000.0])
    whirl = np.array([-42.0, -39.0, -30.0])
    fig, ax = plot_dry_whip(damping, whirl, 42.5, (damping[1:], whirl[1:]))
    curve, coupled, runs = ax.get_lines()
    np.testing.assert_array_equal(curve.get_data()[1], -whirl)
    assert list(coupled.get_data()[1]) == [42.5, 42.5]
    np.testing.assert_array_equal(runs.get_data()[0], damping[1:])
    assert save_figure(fig, tmp_path / "w.png").stat().st_size > 0
