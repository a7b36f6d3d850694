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


@pytest.fixture(scope="module")
def rigid():
    m = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
    return drop(m, 3000 * RPM, 0.0, 0.005)


def test_drop_figures_refuse_what_is_not_a_drop(refused, rigid, tmp_path):
    from rotorcontact.plotting.drop import plot_drop, save_drop_figure

    allowed = r"allowed: the DropResult of rotorcontact\.simulation\.drop_run\.drop$"
    refused(rf"^result = None is not an? DropResult object; {allowed}", plot_drop, None)
    refused(rf"^result = 'x' is not an? DropResult object; {allowed}", save_drop_figure, "x", tmp_path / "d.png")
    refused(rf"^result = None is not an? DropResult object; {allowed}", plot_touchdown_forces, None)
    refused(r"^result = DropResult\(.* is a drop with contact = None, not the compliant law; allowed: a drop of a "
            r"machine with contact = 'compliant'$", plot_touchdown_forces, rigid)
    assert not (tmp_path / "d.png").exists()


def test_touchdown_force_counts_are_bounded(refused, rigid):
    import dataclasses

    compliant = dataclasses.replace(rigid, machine=dataclasses.replace(rigid.machine, contact="compliant",
                                                                       contact_stiffness=1e10))
    for bad in (0, 21, 10**12, 2.0, True):
        refused(rf"^episodes = {bad!r} is invalid; allowed: an integer from 1 to 20$", plot_touchdown_forces,
                compliant, episodes=bad)
    for bad in (2, 1001, 10**12, "60"):
        refused(rf"^samples = {bad!r} is invalid; allowed: an integer from 3 to 1000$", plot_touchdown_forces,
                compliant, samples=bad)


def test_rigid_limit_and_dry_whip_check_their_arrays(refused):
    k = np.array([1e9, 1e10])
    diffs = np.array([[1.0], [0.5]])
    refused(r"^stiffness = 'k' is invalid; allowed: a 1-D array of real numbers, finite and > 0$", plot_rigid_limit,
            "k", diffs, ["a"])
    refused(r"^stiffness = \[0, 1\] is invalid", plot_rigid_limit, [0, 1], diffs, ["a"])
    refused(r"^labels = 'a' is invalid; allowed: a list or tuple of legend texts$", plot_rigid_limit, k, diffs, "a")
    refused(r"^differences = .* is invalid; allowed: an array of real numbers of shape \(2, 2\)", plot_rigid_limit,
            k, diffs, ["a", "b"])
    refused(r"^differences = None is invalid", plot_rigid_limit, k, None, ["a"])
    refused(r"^exponent = 'n' is invalid; allowed: a finite number > 0$", plot_rigid_limit, k, diffs, ["a"], "n")
    refused(r"^damping = None is invalid; allowed: a 1-D array of real numbers, finite and > 0$", plot_dry_whip,
            None, [1.0], 42.0)
    refused(r"^whirl_hz = \[1\.0\] is invalid; allowed: a 1-D array of 2 real numbers$", plot_dry_whip, k, [1.0],
            42.0)
    refused(r"^coupled_hz = 'f' is invalid; allowed: a finite number$", plot_dry_whip, k, [1.0, 2.0], "f")
    refused(r"^simulated = 3 is invalid; allowed: None or a pair", plot_dry_whip, k, [1.0, 2.0], 4.0, 3)
    refused(r"^simulated\[1\] = \[1\.0\] is invalid; allowed: a 1-D array of 2 real numbers$", plot_dry_whip, k,
            [1.0, 2.0], 4.0, (k, [1.0]))
