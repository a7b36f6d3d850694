"""The drop map's figure draws every point, over (speed, friction) or, with one friction, over speed."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from rotorcontact import Machine, reference_machine
from rotorcontact.plotting.drop_map import plot_drop_map
from rotorcontact.simulation.drop_run import RPM
from rotorcontact.studies.drop_map import drop_map

M = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
SPEEDS = np.array([3000.0, 9000.0, 15000.0]) * RPM


def test_a_map_with_one_friction_draws_each_speed():
    ds = drop_map(M, SPEEDS, t_end=0.02, progress=False).dataset
    fig, axes = plot_drop_map(ds)
    try:
        regime, onset, impulse = axes
        np.testing.assert_array_equal(regime.collections[0].get_offsets()[:, 0], ds["speed_rpm"].values)
        np.testing.assert_array_equal(regime.collections[0].get_offsets()[:, 1], ds["regime"].values[0])
        x, y = impulse.lines[0].get_data()
        np.testing.assert_array_equal(x, ds["speed_rpm"].values)
        np.testing.assert_array_equal(y, ds["max_normal_impulse_Ns"].values[0])
        assert regime.get_title().endswith(f"friction {M.friction:g}")
    finally:
        plt.close(fig)


def test_a_map_over_two_frictions_draws_a_cell_per_point():
    ds = drop_map(M, SPEEDS, [0.05, 0.3], t_end=0.02, progress=False).dataset
    fig, axes = plot_drop_map(ds)
    try:
        mesh = axes[0].collections[0]
        np.testing.assert_array_equal(np.asarray(mesh.get_array()).reshape(2, 3), ds["regime"].values)
    finally:
        plt.close(fig)


def test_refuses_what_is_not_a_drop_map(refused, basins_dataset, tmp_path):
    from rotorcontact.plotting.drop_map import save_drop_map_figure

    made_by = r"rotorcontact\.studies\.drop_map\.drop_map"
    refused(rf"^ds = None is not an? Dataset object; allowed: a {made_by} result or its Dataset$", plot_drop_map, None)
    refused(rf"^ds = <xarray\.Dataset> .* is not a result of {made_by}; allowed: a {made_by} result or its "
            r"Dataset \(it needs variables 'speed_rpm', 'friction', 'regime', 'backward_whirl_onset_s', "
            r"'max_normal_impulse_Ns' and attributes 'regimes', 'fail_at_s', 't_end_s'; this one lacks variable "
            r"'speed_rpm', variable 'friction', variable 'backward_whirl_onset_s', variable "
            r"'max_normal_impulse_Ns', attribute 'regimes', attribute 'fail_at_s', attribute 't_end_s'\)$",
            plot_drop_map, basins_dataset)
    refused(rf"^ds = <xarray\.Dataset> .* is not a result of {made_by}", save_drop_map_figure, basins_dataset,
            tmp_path / "m.png")
    assert not (tmp_path / "m.png").exists()
