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


SWEEP = r"rotorcontact\.studies\.sweep\.sweep"
BASINS = r"rotorcontact\.studies\.basins\.basins"


def test_sweep_figures_refuse_another_studys_dataset(refused, basins_dataset, tmp_path):
    for draw in (plot_sweep, plot_regimes):
        refused(rf"^ds = None is not an? Dataset object; allowed: a {SWEEP} result or its Dataset$", draw, None)
        refused(rf"^ds = <xarray\.Dataset> .* is not a result of {SWEEP}; allowed: a {SWEEP} result "
                r"or its Dataset \(it needs variables 'direction', .* and attributes 'swept_parameter'; this one lacks "
                r"variable 'direction', attribute 'swept_parameter'\)$", draw, basins_dataset)
    refused(rf"^ds = <xarray\.Dataset> .* is not a result of {SWEEP}", save_sweep_figure, basins_dataset,
            tmp_path / "d.png")
    refused(r"^ds = 3 is not an? Dataset object", save_sweep_figure, 3, tmp_path / "d.png")
    assert not (tmp_path / "d.png").exists()


def test_sweep_figures_check_their_options(refused, diagram, basins_dataset, tmp_path):
    ds, fixed_points = diagram
    for draw in (plot_sweep, plot_regimes):
        refused(r"^ax = 'x' is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$", draw, ds, ax="x")
    refused(r"^variable = 'speed' is invalid; allowed: 'theta', 'rdot', 'thetadot'$", plot_sweep, ds, "speed")
    refused(r"^variable = 'speed' is invalid", save_sweep_figure, ds, tmp_path / "d.png", "speed")
    refused(r"^markersize = 0\.0 is invalid; allowed: a finite number > 0$", plot_sweep, ds, markersize=0)
    refused(r"^overlay = 3 is not an? OrbitBranches or MultiImpactBranches or Dataset object; allowed: "
            r"rotorcontact\.continuation\.branches\.OrbitBranches, ", plot_sweep, ds, overlay=3)
    refused(r"^overlay\[1\] = <xarray\.Dataset> .* is not a result of rotorcontact\.studies\.sweep\."
            r"one_impact_overlay; allowed:", plot_sweep, ds, overlay=[fixed_points, basins_dataset])
    refused(r"^cascades = 3 is invalid; allowed: a list or tuple of rotorcontact\.continuation\.cascade\.Cascade$",
            plot_sweep, ds, cascades=3)
    refused(r"^cascades\[0\] = 'PD' is not an? Cascade object; allowed:", save_sweep_figure, ds, tmp_path / "d.png",
            cascades=["PD"])
    assert not (tmp_path / "d.png").exists()


def test_basins_figure_refuses_another_studys_dataset_and_bad_options(refused, sweep_dataset, basins_dataset,
                                                                      tmp_path):
    refused(rf"^ds = None is not an? Dataset object; allowed: a {BASINS} result or its Dataset$", plot_basins, None)
    refused(rf"^ds = <xarray\.Dataset> .* is not a result of {BASINS}; allowed: a {BASINS} result or its "
            r"Dataset \(it needs variables 'attractor', 'class_name', 'fraction', 'count' and attributes 'gamma', "
            r"'omega', 'rho', 'phi'; this one lacks variable 'attractor', variable 'class_name', variable 'fraction', "
            r"variable 'count', attribute 'gamma'\)$", plot_basins, sweep_dataset)
    refused(rf"^ds = <xarray\.Dataset> .* is not a result of {BASINS}", save_basins_figure, sweep_dataset,
            tmp_path / "b.png")
    assert not (tmp_path / "b.png").exists()
    refused(r"^ax = 'x' is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$", plot_basins,
            basins_dataset, "x")
    refused(r"^legend = 'no' is invalid; allowed: True or False$", plot_basins, basins_dataset, legend="no")
    # the saved figure keeps its size
    path = save_basins_figure(basins_dataset, tmp_path / "b.png")
    assert path.stat().st_size > 0 and not plt.get_fignums()


def test_a_studys_result_draws_as_its_dataset(sweep_result, basins_result, same_drawing):
    import matplotlib.pyplot as plt

    from rotorcontact.plotting.basins import plot_basins
    from rotorcontact.plotting.sweep import plot_regimes, plot_sweep

    for draw, result in ((plot_basins, basins_result), (plot_sweep, sweep_result), (plot_regimes, sweep_result)):
        fig_a, ax_a = draw(result)
        fig_b, ax_b = draw(result.dataset)
        assert same_drawing(ax_a, ax_b)
        plt.close(fig_a)
        plt.close(fig_b)


def test_continued_branches_are_drawn_without_gaps_and_with_their_plausibility():
    """Over gamma in [0.06, 0.1]: B1,d is drawn stable from just past its period doubling (no gap where the
    stability changes), dotted below its grazing (no orbit of the simulator there: r > 1 between impacts),
    and events of several orbits at one value are one mark."""
    from rotorcontact.maps.impact_map import one_impact_orbits
    from rotorcontact.studies.sweep import continued_branches

    values = sweep_values(0.06, 0.1, 3)
    ds = sweep(REF, "gamma", values, mode="independent", n_transient=20, n_record=5, progress=False).dataset
    overlay = continued_branches(REF, "gamma", values)
    (pd,) = [e.value for e in overlay.events if e.type == "period-doubling" and "B1,d" in e.orbits]
    (graze,) = [e.value for e in overlay.events if e.type == "grazing" and "B1,d" in e.orbits]
    fig, ax = plot_sweep(ds, "rdot", overlay=overlay)
    xs = {kind: np.concatenate([ln.get_xdata() for ln in ax.get_lines() if ln.get_gid() == f"branch:B1,d:{kind}"])
          for kind in ("stable", "unstable", "implausible")}
    assert np.any((xs["stable"] > pd) & (xs["stable"] < pd + 1e-3))
    assert np.all(xs["implausible"] <= graze + 1e-9) and np.any(xs["implausible"] < graze - 1e-3)
    (below,) = [o for o in one_impact_orbits(REF.replace(gamma=graze - 2e-3)) if o.label == "B1,d"]
    assert not below.plausible
    drawn = np.sort(np.concatenate(list(xs.values())))
    assert np.max(np.diff(drawn[(drawn > graze) & (drawn < 0.1)])) <= 0.04 / 400 * 1.01
    marks = [(t.get_text().split()[0], round(t.xy[0], 12)) for t in ax.texts]
    assert marks and len(marks) == len(set(marks))  # one mark per kind and value, however many orbits
    plt.close(fig)
