"""Figures of brute-force diagrams and basins: what is drawn, and bad input."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import ParameterError  # noqa: E402
from rotorcontact.studies.basins import basins, displacement_grid  # noqa: E402
from rotorcontact.plotting.basins import plot_basins, save_basins_figure  # noqa: E402
from rotorcontact.plotting.sweep import plot_regimes, plot_sweep, save_sweep_figure  # noqa: E402
from rotorcontact.studies.sweep import one_impact_overlay, sweep, sweep_values  # noqa: E402
from reference_parameters import REF  # noqa: E402


@pytest.fixture(scope="module")
def diagram():
    values = sweep_values(0.12, 0.19, 8)
    res = sweep(REF, "gamma", values, mode="both", n_transient=500, n_record=20, progress=False)
    return res.dataset, one_impact_overlay(REF, "gamma", values)


def test_sections_are_drawn_per_direction_with_the_recorded_points(diagram):
    ds, overlay = diagram
    fig, ax = plot_sweep(ds, "rdot", overlay=overlay)
    lines = {line.get_gid(): line for line in ax.get_lines()}
    up = lines["section:up"]
    n_up = int(np.isfinite(ds.rdot.sel(direction="up").values).sum())
    assert len(up.get_xdata()) == n_up and n_up > 0
    assert np.array_equal(np.sort(up.get_ydata()), np.sort(ds.rdot.sel(direction="up").values[
        np.isfinite(ds.rdot.sel(direction="up").values)]))
    # B1,d is overlaid solid where stable; B1,c dashed (unstable)
    assert lines["orbit:B1,d:stable"].get_linestyle() == "-"
    assert lines["orbit:B1,c:unstable"].get_linestyle() == "--"
    plt.close(fig)


def test_regime_strip_and_saved_figure(diagram, tmp_path):
    ds, overlay = diagram
    fig, ax = plot_regimes(ds)
    assert [t.get_text() for t in ax.get_yticklabels()] == ["up", "down"]
    plt.close(fig)
    path = save_sweep_figure(ds, tmp_path / "d.png", "theta", overlay=overlay)
    assert path.stat().st_size > 0
    with pytest.raises(ParameterError, match="variable"):
        plot_sweep(ds, "speed")
    with pytest.raises(ParameterError, match="suffix"):
        save_sweep_figure(ds, tmp_path / "d.gif")


def test_basin_image_legend_holds_the_fractions(tmp_path):
    res = basins(REF.replace(gamma=0.1), displacement_grid((-1, 1, 9), (-1, 1, 9)), progress=False)
    fig, ax = plot_basins(res.dataset)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    for name, frac in res.fractions.items():
        assert f"{name}: {100 * frac:.3g}%" in labels
    assert not any(label.startswith("outside") for label in labels)
    plt.close(fig)
    assert save_basins_figure(res.dataset, tmp_path / "b.svg").stat().st_size > 0


def test_continued_branches_are_overlaid_with_their_bifurcations(diagram):
    pytest.importorskip("rotorcontact.continuation.branches")
    from rotorcontact.studies.sweep import overlay_for

    ds, _ = diagram
    values = ds.gamma.values
    overlay, kind = overlay_for(REF, "gamma", values)
    assert kind == "branches"
    fig, ax = plot_sweep(ds, "rdot", overlay=overlay)
    gids = {line.get_gid() for line in ax.get_lines()}
    assert "branch:B1,d:stable" in gids and "branch:B1,c:unstable" in gids
    folds = [e for e in overlay.events if e.type == "fold" and e.rdot > 0]
    assert folds and "event:fold" in gids  # the fold of B1,c and B1,d near gamma = 0.178
    plt.close(fig)
    # phi cannot be continued: the fixed points at each value are overlaid instead
    _, kind = overlay_for(REF, "phi", [0.1, 0.2])
    assert kind == "fixed-points"
