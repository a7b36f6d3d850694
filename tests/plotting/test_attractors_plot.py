"""The attractors figure: stacked basin fractions with confidence bands, and exponents beneath."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest

from rotorcontact.plotting.attractors import plot_attractors, save_attractors_figure
from rotorcontact.studies.attractors import attractors
from reference_parameters import REF


def test_stacked_areas_bands_and_exponents(tmp_path):
    res = attractors(REF, "gamma", [0.08, 0.12, 0.16], "plane:7", t_lyapunov=100.0,
                     progress=False)
    ds = res.dataset
    fig, (ax_f, ax_l) = plot_attractors(ds)
    n = len(res.attractors)
    # one area per attractor and one band per boundary between two areas
    areas = ax_f.collections
    assert len(areas) == n + (n - 1)
    # the top of the last area is 1 at every value: the fractions stack to the whole grid
    xy = areas[-1].get_paths()[0].vertices
    for v in ds["value"].values:
        assert np.isclose(xy[np.isclose(xy[:, 0], v), 1].max(), 1.0)
    assert [t.get_text() for t in ax_f.get_legend().get_texts()] == list(res.names)
    # the exponent lines are the exponents where the attractor is reached
    lines = [ln for ln in ax_l.get_lines() if ln.get_marker() == "."]
    assert len(lines) == n
    for ln, att in zip(lines, res.attractors):
        y = np.asarray(ln.get_ydata(), dtype=float)
        np.testing.assert_array_equal(np.isfinite(y), att.present)
        np.testing.assert_allclose(y[att.present], att.exponent[att.present])
    matplotlib.pyplot.close(fig)
    assert save_attractors_figure(ds, tmp_path / "a.png").stat().st_size > 0


@pytest.fixture(scope="module")
def small_result():
    return attractors(REF, "gamma", [0.12], "plane:3", t_lyapunov=20.0, progress=False)


@pytest.fixture(scope="module")
def small(small_result):
    return small_result.dataset


def test_refuses_what_is_not_an_attractors_dataset(refused, small, sweep_dataset, basins_dataset, tmp_path):
    refused(r"^ds = None is not an? Dataset object; allowed: a rotorcontact\.studies\.attractors\."
            r"attractors result or its Dataset$", plot_attractors, None)
    refused(r"^ds = .* is not an? Dataset object", plot_attractors, small["count"])
    for other in (sweep_dataset, basins_dataset):
        refused(r"^ds = <xarray\.Dataset> .* is not a result of rotorcontact\.studies\.attractors\.attractors; "
                r"allowed: a rotorcontact\.studies\.attractors\.attractors result or its Dataset \(it needs "
                r"variables 'value', 'attractor', .*; this one lacks ", plot_attractors, other)
        refused(r"^ds = <xarray\.Dataset> .* is not a result of rotorcontact\.studies\.attractors\.attractors",
                save_attractors_figure, other, tmp_path / "a.png")
    assert not (tmp_path / "a.png").exists()


def test_refuses_axes_that_are_not_two(refused, small):
    fig, grid = plt.subplots(1, 3)
    refused(r"^axes = 'ab' is not a sequence of Axes; allowed: None or a sequence of 2 matplotlib\.axes\.Axes "
            r"\(basin fractions, exponents\)$", plot_attractors, small, "ab")
    refused(r"^axes = .* holds 3 axes; allowed: None or a sequence of 2", plot_attractors, small, grid)
    assert plot_attractors(small, grid[:2])[0] is fig
    plt.close(fig)


def test_the_result_draws_as_its_dataset(small_result, same_drawing):
    import matplotlib.pyplot as plt

    from rotorcontact.plotting.attractors import plot_attractors

    fig_a, axes_a = plot_attractors(small_result)
    fig_b, axes_b = plot_attractors(small_result.dataset)
    assert all(same_drawing(ax_a, ax_b) for ax_a, ax_b in zip(axes_a, axes_b))
    plt.close(fig_a)
    plt.close(fig_b)
