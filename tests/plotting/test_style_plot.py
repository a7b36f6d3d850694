"""The checks the figures share: axes, views, labels and figure files."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import ParameterError  # noqa: E402
from rotorcontact.plotting.style import (  # noqa: E402
    MAX_PLOT_POINTS,
    check_axes,
    check_figure_path,
    check_limits,
    check_names,
    draw_clearance,
    new_axes,
    orbit_tex,
    save_figure,
)


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def test_new_axes_refuses_what_is_not_an_axes_before_making_a_figure(refused):
    fig, ax = plt.subplots()
    assert new_axes(ax) == (fig, ax)
    for bad in ("x", fig, [ax], 1):
        refused(r"^ax = .* is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$", new_axes, bad)


def test_check_axes_takes_lists_tuples_and_arrays_of_the_right_count():
    fig, grid = plt.subplots(2, 2)
    assert check_axes(None, 3, "a, b, c") is None
    assert check_axes(grid, 4, "four") == list(grid.ravel())
    assert check_axes(tuple(grid[0]), 2, "two") == list(grid[0])
    with pytest.raises(ParameterError, match=r"^axes = .* holds 3 axes; allowed: None or a sequence of 2 "
                                             r"matplotlib\.axes\.Axes \(left, right\)$"):
        check_axes(list(grid.ravel()[:3]), 2, "left, right")
    with pytest.raises(ParameterError, match=r"^axes = 'ab' is not a sequence of Axes; allowed: None or"):
        check_axes("ab", 2, "left, right")
    with pytest.raises(ParameterError, match=r"^axes = .* holds an object that is not an Axes; allowed:"):
        check_axes([grid[0, 0], "x"], 2, "left, right")


def test_views_labels_and_paths():
    assert check_limits("xlim", None) is None
    assert check_limits("xlim", np.array([1, 0])) == (1.0, 0.0)
    for bad in ((0, 0), (0, np.nan), "ab", (0, 1, 2), (True, 2), 3.0):
        with pytest.raises(ParameterError, match=r"^xlim = .* is invalid; allowed: \(low, high\), two distinct"):
            check_limits("xlim", bad)
    with pytest.raises(ParameterError, match=r"^ylim = None is invalid; .* finite numbers$"):
        check_limits("ylim", None, optional=False)
    assert check_names("labels", ["B1,a"]) == ("B1,a",)
    for bad in ("B1,a", ["B1,a", 3], None):
        with pytest.raises(ParameterError, match=r"^labels = .* is invalid; allowed: a list or tuple of"):
            check_names("labels", bad)
    with pytest.raises(ParameterError, match=r"^path = 'f\.gif' has an unsupported suffix; allowed: \.png"):
        check_figure_path("f.gif")


def test_shared_drawing_helpers_refuse_bad_input(tmp_path):
    fig, ax = plt.subplots()
    with pytest.raises(ParameterError, match=r"^ax = None is not an? Axes object; allowed: a matplotlib\.axes\.Axes$"):
        draw_clearance(None)
    with pytest.raises(ParameterError, match=r"^radius = -1\.0 is invalid; allowed: a finite number > 0$"):
        draw_clearance(ax, -1)
    with pytest.raises(ParameterError, match=r"^label = 3 is not a str object; allowed: an orbit label"):
        orbit_tex(3)
    with pytest.raises(ParameterError, match=r"^fig = 'x' is not an? Figure object; allowed: a matplotlib\.figure"):
        save_figure("x", tmp_path / "f.png")
    assert not (tmp_path / "f.png").exists()


def test_the_bound_on_points_is_a_million():
    assert MAX_PLOT_POINTS == 1_000_000


def test_a_figure_left_open_by_a_refused_call_is_reported(refused):
    def leaky():
        plt.figure()
        raise ParameterError("x = 1 is invalid")

    with pytest.raises(AssertionError, match="left a figure open"):
        refused(r"^x = 1", leaky)
    assert not plt.get_fignums()


def test_importing_the_figures_leaves_the_users_backend_alone():
    # a researcher's interactive backend (here pdf, chosen before the import) is kept: plt.show() must work
    import subprocess
    import sys

    code = ("import matplotlib; matplotlib.use('pdf'); import rotorcontact.plotting.sweep, "
            "rotorcontact.plotting.branches; print(matplotlib.get_backend())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "pdf"


def test_style_runs_split_a_line_by_style_and_join_the_runs_where_asked():
    from rotorcontact.plotting.style import style_runs

    keys = ["a", "a", "b", None, None, "a"]
    assert style_runs(keys) == [("a", 0, 3), ("b", 2, 4), (None, 3, 6), ("a", 5, 6)]
    assert style_runs(keys, lambda key, following: following is not None) == \
        [("a", 0, 3), ("b", 2, 3), (None, 3, 6), ("a", 5, 6)]
    assert style_runs([]) == [] and style_runs(["x"]) == [("x", 0, 1)]
