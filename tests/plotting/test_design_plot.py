"""Figures of design maps refuse what is not the map they draw, before making a figure."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import reference_machine  # noqa: E402
from rotorcontact.plotting.design import (  # noqa: E402
    plot_design_map,
    plot_operating_line,
    plot_plane,
    plot_plane_recovery,
    plot_speed_recovery,
    plot_speed_regimes,
    save_design_map,
)
from rotorcontact.studies.design_map import DesignMap  # noqa: E402

WITH_AX = (plot_speed_regimes, plot_operating_line, plot_plane, plot_speed_recovery, plot_plane_recovery)


@pytest.fixture(scope="module")
def speed():
    """A map over speed with a shock (no points: the checks come before any drawing)."""
    return DesignMap(reference_machine(), ("speed_rpm",), (np.array([1800.0, 2200.0]),), (), shock=5e-3)


@pytest.fixture(scope="module")
def plane():
    return DesignMap(reference_machine(), ("stiffness", "damping"), (np.array([9e5, 1e6]), np.array([50.0])), (),
                     shock=5e-3)


def test_every_figure_refuses_what_is_not_a_design_map(refused, tmp_path):
    for draw in (*WITH_AX, plot_design_map):
        refused(r"^dmap = None is not an? DesignMap object; allowed: a rotorcontact\.studies\.design_map\.DesignMap "
                r"\(speed_map or plane_map\)$", draw, None)
    refused(r"^dmap = 'map' is not an? DesignMap object", save_design_map, "map", tmp_path / "m.png")
    assert not (tmp_path / "m.png").exists()


def test_each_figure_refuses_the_other_kind_of_map(refused, speed, plane):
    import dataclasses

    refused(r"^dmap = DesignMap\(.* is a map over stiffness, damping with a shock; allowed: a speed map "
            r"\(speed_map\)$", plot_speed_regimes, plane)
    refused(r"^dmap = DesignMap\(.* is a map over speed_rpm with a shock; allowed: a plane map \(plane_map\)$",
            plot_plane, speed)
    refused(r"^dmap = DesignMap\(.* is a map over stiffness, damping with a shock; allowed: a speed map "
            r"\(speed_map\) computed with a shock$", plot_speed_recovery, plane)
    refused(r"^dmap = DesignMap\(.* is a map over speed_rpm without a shock; allowed: a speed map \(speed_map\) "
            r"computed with a shock$", plot_speed_recovery, dataclasses.replace(speed, shock=None))
    refused(r"^dmap = DesignMap\(.* is a map over stiffness, damping without a shock; allowed: a plane map "
            r"\(plane_map\) computed with a shock$", plot_plane_recovery, dataclasses.replace(plane, shock=None))


def test_figures_refuse_an_ax_that_is_not_one(refused, speed, plane):
    fig = plt.figure()
    for draw, dmap in zip(WITH_AX, (speed, speed, plane, speed, plane)):
        refused(r"^ax = 'x' is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$", draw, dmap, "x")
        refused(r"^ax = <Figure .* is not an? Axes object", draw, dmap, fig)
    plt.close(fig)
