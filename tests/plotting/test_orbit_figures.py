"""Figures 4-7 of the paper: what each draws is the computed data, in the documented styles."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import ParameterError  # noqa: E402
from rotorcontact.maps import impact_map as im  # noqa: E402
from rotorcontact.continuation.branches import orbit_branches  # noqa: E402
from rotorcontact.continuation.codim2 import codim2_diagram  # noqa: E402
from rotorcontact.analysis.equilibria import boundary_gamma  # noqa: E402
from rotorcontact.continuation.codim2 import region  # noqa: E402
from rotorcontact.plotting.branches import (  # noqa: E402
    BRANCH_COLORS,
    EVENT_NAMES,
    plot_branch_quantity,
    plot_extrema,
    plot_max_multiplier,
    plot_rdot,
    plot_thetadot,
    plot_velocities,
)
from rotorcontact.plotting.codim2 import OTHER, plot_codim2, region_label_cells  # noqa: E402
from rotorcontact.plotting.f1 import plot_f1, plot_f1_zeros, plot_nsfh_schematic  # noqa: E402
from rotorcontact.plotting.style import orbit_tex, save_figure  # noqa: E402
from rotorcontact.continuation.zero_curves import f1_zero_curves  # noqa: E402
from reference_parameters import REF  # noqa: E402


@pytest.fixture(scope="module")
def branches():
    return orbit_branches(REF, "gamma", 0.0, 0.25, t_max=4.0, n_seeds=6)


def lines(ax, prefix):
    return [ln for ln in ax.get_lines() if (ln.get_gid() or "").startswith(prefix)]


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def test_fig4ab_f1_curve_and_its_zeros():
    p = REF.replace(gamma=0.1)
    fig, ax = plot_f1(p, (0.0, 30.0))
    (curve,) = lines(ax, "F1")
    x, y = curve.get_data()
    assert np.allclose(y, im.f1(p, x), atol=1e-14)
    assert ax.get_ylim() == pytest.approx((-0.25, 0.5)) and ax.get_xlim() == pytest.approx((0.0, 30.0))
    marked = sorted(ln.get_xdata()[0] for ln in lines(ax, "zero:"))
    assert marked == pytest.approx([z.T for z in im.f1_zeros(p, 30.0)])
    fig2, ax2 = plt.subplots()
    out = plot_f1(REF.replace(gamma=0.05), (0.0, 40.0), ax=ax2)
    assert out == (fig2, ax2) and len(lines(ax2, "zero:")) == len(im.f1_zeros(REF.replace(gamma=0.05), 40.0))


def test_fig4c_zeros_against_gamma_with_folds_and_dib():
    zc = f1_zero_curves(REF, "gamma", 0.0, 0.25, t_max=12.0)
    fig, ax = plot_f1_zeros(REF, curves=zc)
    assert {ln.get_gid() for ln in lines(ax, "zeros:")} >= {"zeros:1:a", "zeros:1:b", "zeros:2:a", "zeros:2:b"}
    for ln in lines(ax, "zeros:"):
        x, y = ln.get_data()
        for g, T in zip(x[::7], y[::7]):
            assert np.min(np.abs([z.T - T for z in im.f1_zeros(REF.replace(gamma=g), 12.5)] or [1])) < 1e-6
    folds = {ln.get_gid(): ln.get_xdata()[0] for ln in lines(ax, "fold:")}
    assert set(folds) >= {"fold:1", "fold:2", "fold:3"}
    assert folds["fold:1"] > folds["fold:2"] > folds["fold:3"]
    (dib,) = lines(ax, "gamma_dib")
    assert dib.get_xdata()[0] == pytest.approx(boundary_gamma(REF))
    assert ax.get_ylim() == pytest.approx((0.0, 12.0))


def test_fig4d_schematic_shows_the_boundary_equilibrium_and_small_orbits():
    fig, ax = plot_nsfh_schematic(REF)
    (xb,) = lines(ax, "x_B")
    kb = REF.replace(gamma=boundary_gamma(REF)).k
    assert xb.get_xdata()[0] == pytest.approx(kb.real) and xb.get_ydata()[0] == pytest.approx(kb.imag)
    orbits = lines(ax, "orbit:")
    assert {ln.get_gid() for ln in orbits} == {"orbit:B1,a", "orbit:B1,b"}
    for ln in orbits:
        r = np.hypot(ln.get_xdata(), ln.get_ydata())
        assert r.max() == pytest.approx(1.0, abs=1e-9) and r.min() < 1.0
    texts = legend_texts(ax)
    assert {orbit_tex("B1,a"), orbit_tex("B1,b"), r"$x_R$"} <= set(texts)
    assert any(t.startswith(r"$x_B$") for t in texts)


def _drawn(branches):
    """The branches as drawn over their whole range: refined to `REFINED_POINTS` across it."""
    from rotorcontact.continuation.branches import refine_branches
    from rotorcontact.plotting.branches import REFINED_POINTS

    return refine_branches(branches, (branches.start, branches.stop), REFINED_POINTS)


def test_fig5_rdot_and_thetadot_are_the_branch_data(branches):
    fig, ax = plot_rdot(REF, branches=branches)
    refined = _drawn(branches)
    for label in ("B1,a", "B1,b", "B1,c", "B1,d"):
        b = refined.branch(label)
        drawn = lines(ax, label + ":")
        assert drawn
        xs = np.concatenate([ln.get_xdata() for ln in drawn])
        ys = np.concatenate([ln.get_ydata() for ln in drawn])
        for x, y in zip(xs, ys):
            i = np.nanargmin(np.abs(b.values - x) + np.abs(b.rdot - y))
            assert b.values[i] == x and b.rdot[i] == y
        for ln in drawn:
            style = ln.get_gid().split(":")[1]
            y = ln.get_ydata()[:-1]  # a run ends on the first point of the next one (lines join up)
            if style == "virtual":
                assert ln.get_linestyle() == "--" and np.all(y <= 1e-12)
            elif style.startswith("plausible"):
                assert ln.get_linestyle() == "-" and np.all(y >= -1e-12)
    stable = lines(ax, "B1,d:plausible-stable")
    unstable = lines(ax, "B1,c:plausible-unstable")
    assert stable and unstable and stable[0].get_linewidth() > unstable[0].get_linewidth()
    fig, ax = plot_thetadot(REF, branches=branches, labels=("B1,a", "B1,b"))
    b = refined.branch("B1,b")
    ys = np.concatenate([ln.get_ydata() for ln in lines(ax, "B1,b:")])
    assert set(ys) <= set(b.thetadot[np.isfinite(b.thetadot)])
    assert not lines(ax, "B1,c")


def test_fig5b_local_estimate_hook(branches):
    gs = boundary_gamma(REF)
    # a callable: called with the label and the branch's parameter values
    calls = []

    def local(label, x):
        calls.append(label)
        return (x - gs) * 0.1 if label == "B1,a" else None

    fig, ax = plot_rdot(REF, branches=branches, labels=("B1,a", "B1,b"), xlim=(gs - 0.01, 0.19), local=local)
    assert calls == ["B1,a", "B1,b"]
    (est,) = lines(ax, "B1,a:local")
    assert np.allclose(est.get_ydata(), (est.get_xdata() - gs) * 0.1)
    assert ax.get_xlim() == pytest.approx((gs - 0.01, 0.19))
    # or arrays per label
    fig, ax = plot_rdot(REF, branches=branches, labels=("B1,a",), local={"B1,a": ([0.1, 0.2], [0.0, 1.0])})
    (est,) = lines(ax, "B1,a:local")
    assert list(est.get_xdata()) == [0.1, 0.2]
    with pytest.raises(ParameterError):
        plot_rdot(REF, branches=branches, local=3.0)


@pytest.mark.parametrize("local, name", [
    ({"B1,a": 5}, r"local\['B1,a'\] = 5"),
    ({"B1,a": ([0.0, 1.0], [0.0])}, r"local\['B1,a'\] = "),
    ({"B1,a": ([0.0, float("nan")], [0.0, 1.0])}, r"local\['B1,a'\] = "),
    ({"B1,a": ([0.0, 1.0], [0.0, float("inf")])}, r"local\['B1,a'\] = "),
    (lambda label, x: x[:-1], r"local\('B1,a', x\) = "),
    (lambda label, x: "x", r"local\('B1,a', x\) = 'x'"),
])
def test_a_bad_local_estimate_is_refused_before_a_figure_is_opened(branches, local, name):
    import matplotlib.pyplot as plt

    before = plt.get_fignums()
    with pytest.raises(ParameterError, match=rf"^{name}.* is invalid; allowed: "):
        plot_rdot(REF, branches=branches, labels=("B1,a",), local=local)
    assert plt.get_fignums() == before


def test_a_local_estimate_with_nan_is_drawn_with_a_gap(branches):
    # an estimate that holds on one side only (a square root beyond gamma*): nan elsewhere, a gap in its line
    gs = boundary_gamma(REF)

    def local(label, x):
        return np.where(x >= gs, np.sqrt(np.clip(x - gs, 0.0, None)), np.nan)

    fig, ax = plot_rdot(REF, branches=branches, labels=("B1,a",), xlim=(0.0, 0.2), local=local)
    (est,) = lines(ax, "B1,a:local")
    y = np.asarray(est.get_ydata(), dtype=float)
    assert np.any(np.isnan(y)) and np.all(np.isnan(y) == (np.asarray(est.get_xdata()) < gs))


def test_fig6b_max_multiplier_only_where_admissible(branches):
    fig, ax = plot_max_multiplier(REF, branches=branches)
    assert ax.get_yscale() == "log"
    for label in ("B1,c", "B1,d"):
        b = _drawn(branches).branch(label)
        for ln in lines(ax, label + ":"):
            assert ln.get_gid().split(":")[1] != "virtual" or np.all(np.isnan(ln.get_ydata()))
            y = ln.get_ydata()
            y = y[np.isfinite(y)]
            assert set(y) <= set(b.max_multiplier[np.isfinite(b.max_multiplier)])


def test_fig6b_b1d_is_drawn_stable_from_its_period_doubling_on(branches):
    # B1,d gains stability as gamma increases through its period doubling (one_impact_orbits says so just past
    # it); the figure draws it so there, without a gap, however coarse the continuation's steps
    (pd,) = [e.value for e in branches.events if e.type == "period-doubling" and "B1,d" in e.orbits]
    past = pd + 2e-3
    (orbit,) = [o for o in im.one_impact_orbits(REF.replace(gamma=past)) if o.label == "B1,d"]
    assert orbit.stable
    fig, ax = plot_max_multiplier(REF, branches=branches, xlim=(0.0, 0.2), log=False)
    stable = np.concatenate([ln.get_xdata() for ln in lines(ax, "B1,d:plausible-stable")])
    unstable = np.concatenate([ln.get_xdata() for ln in lines(ax, "B1,d:plausible-unstable")])
    assert np.any((stable > pd) & (stable < pd + 1e-3)) and not np.any(unstable > pd + 1e-3)
    xs = np.sort(np.concatenate([ln.get_xdata() for ln in lines(ax, "B1,d:")]))
    near = xs[(xs > pd - 0.01) & (xs < pd + 0.01)]
    assert np.max(np.diff(near)) <= 0.2 / 400 * 1.01


def test_a_log_axis_of_multipliers_refuses_limits_at_or_below_zero(branches):
    import matplotlib.pyplot as plt

    before = plt.get_fignums()
    with pytest.raises(ParameterError, match=r"^ylim = \(-1, 3\) reaches 0 or below, which a logarithmic axis "):
        plot_max_multiplier(REF, branches=branches, log=True, ylim=(-1, 3))
    assert plt.get_fignums() == before  # refused before drawing
    fig, ax = plot_max_multiplier(REF, branches=branches, log=False, ylim=(-1, 3))
    assert ax.get_ylim() == (-1.0, 3.0)


def test_fig6a_plane_with_curves_regions_and_labels():
    diagram = codim2_diagram(REF, ("gamma", "omega"), ((0.0, 0.5), (0.6, 1.25)), grazing=("B1,d",))
    fig, ax = plot_codim2(REF, diagram=diagram, shape=(21, 21))
    gids = {ln.get_gid() for ln in ax.get_lines()}
    assert {"curve:fold_1", "curve:dib", "curve:grazing_B1d"} <= gids
    (dib,) = lines(ax, "curve:dib")
    g, w = dib.get_data()
    ok = np.isfinite(g)
    assert np.allclose(g[ok] ** 2 + (1 - w[ok] ** 2) ** 2, REF.rho**2, atol=1e-12)
    texts = {t.get_gid(): t.get_text() for t in ax.texts}
    assert {"label:R1", "label:R2", "label:R3", "label:R4"} <= set(texts)
    assert {"NSFH", "NSF", "Pers"} <= set(texts.values())
    assert len(lines(ax, "point:fold-dib")) == 2
    # labels given are drawn as given, none computed
    fig, ax = plot_codim2(REF, diagram=diagram, regions=False, labels=[("NSFH", 0.1, 0.9)])
    assert [(t.get_text(), t.xy) for t in ax.texts] == [("NSFH", (0.1, 0.9))]


def test_fig7_extrema_of_r(branches):
    fig, ax = plot_extrema(REF, branches=branches, labels=("B1,a", "B1,b"), regular=True)
    xr = lines(ax, "x_R:")
    for ln in xr:
        x, y = ln.get_data()
        ok = np.isfinite(y)
        assert np.allclose(y[ok], [abs(REF.replace(gamma=v).k) for v in x[ok]])
        if ln.get_gid() == "x_R:virtual":
            assert np.all(y[ok] > 1.0)
    assert lines(ax, "nsfh")[0].get_xdata()[0] == pytest.approx(boundary_gamma(REF))
    fig, ax = plot_extrema(REF, branches=branches, labels=("B1,c", "B1,d"), regular=False)
    (graz,) = lines(ax, "event:grazing")
    e = [ev for ev in branches.events if ev.type == "grazing" and "B1,d" in ev.orbits][0]
    assert graz.get_xdata()[0] == e.value and graz.get_ydata()[0] == 1.0
    assert lines(ax, "event:extrema-change")
    # the maxima of B1,d reach 1 exactly at the grazing point, from above on the implausible side
    d = branches.branch("B1,d")
    i = int(np.nanargmin(np.abs(d.values - e.value)))
    assert d.r_max_interior[i] == pytest.approx(1.0, abs=1e-6)


def test_figures_accept_an_axes_and_save(tmp_path, branches):
    fig, axes = plt.subplots(1, 2)
    assert plot_branch_quantity(branches, "T", ax=axes[1]) == (fig, axes[1])
    path = save_figure(fig, tmp_path / "t.png")
    assert path.stat().st_size > 0
    with pytest.raises(ParameterError):
        plot_branch_quantity(branches, "nonsense")


def legend_texts(ax):
    legend = ax.get_legend()
    return [] if legend is None else [t.get_text() for t in legend.texts]


def marked_kinds(ax):
    return {ln.get_gid().split(":", 1)[1] for ln in lines(ax, "event:")}


def test_every_kind_of_event_marked_has_a_legend_entry(branches):
    for draw in (plot_rdot, plot_thetadot, plot_max_multiplier):
        fig, ax = draw(REF, branches=branches)
        kinds = marked_kinds(ax)
        assert {"fold", "nsfh"} <= kinds or draw is plot_max_multiplier
        assert kinds, draw
        assert {EVENT_NAMES[k] for k in kinds} <= set(legend_texts(ax)), draw
        # and no entry for a kind that is not marked
        assert not ({EVENT_NAMES[k] for k in set(EVENT_NAMES) - kinds} & set(legend_texts(ax)))
    # only the events inside the view are marked and listed
    fig, ax = plot_rdot(REF, branches=branches, labels=("B1,a", "B1,b"), xlim=(0.1, 0.25))
    assert marked_kinds(ax) == {"fold"} and "NSFH" not in legend_texts(ax)


def test_markers_follow_the_curves_of_every_quantity(branches):
    """On the thetadot panel, the marker of an event sits on the drawn curve of its orbit."""
    fig, ax = plot_thetadot(REF, branches=branches, labels=("B1,d",))
    drawn = lines(ax, "B1,d:")
    assert {"fold", "grazing", "period-doubling"} <= marked_kinds(ax)
    for mark in lines(ax, "event:"):
        gx, gy = mark.get_xdata()[0], mark.get_ydata()[0]
        gaps = []
        for ln in drawn:
            x, y = (np.asarray(v, dtype=float) for v in ln.get_data())
            for i in range(len(x) - 1):
                if min(x[i], x[i + 1]) <= gx <= max(x[i], x[i + 1]):
                    gaps.append(min(abs(gy - y[i]), abs(gy - y[i + 1])) - abs(y[i + 1] - y[i]))
        assert gaps and min(gaps) <= 1e-12, mark.get_gid()  # within the segment's own y-range


def test_each_local_estimate_has_its_own_legend_entry_in_its_orbits_colour(branches):
    gs = boundary_gamma(REF)
    fig, ax = plot_rdot(REF, branches=branches, labels=("B1,a", "B1,b"),
                        local=lambda label, x: (x - gs) * (0.1 if label == "B1,a" else 0.2))
    entries = [t for t in legend_texts(ax) if t.startswith("local estimate")]
    assert entries == [f"local estimate, {orbit_tex('B1,a')}", f"local estimate, {orbit_tex('B1,b')}"]
    for label in ("B1,a", "B1,b"):
        (est,) = lines(ax, f"{label}:local")
        assert est.get_color() == BRANCH_COLORS[label[-1]]


def test_fig7_legend_names_the_marks_and_x_R(branches):
    fig, ax = plot_extrema(REF, branches=branches, labels=("B1,c", "B1,d"), regular=False, xlim=(0.0, 0.2))
    texts = legend_texts(ax)
    assert {"grazing", "change in number of extrema"} <= set(texts)
    assert any(t.startswith("NSFH") for t in texts)
    fig, ax = plot_extrema(REF, branches=branches, labels=("B1,a", "B1,b"), regular=True, xlim=(0.0, 0.2),
                           ylim=(0.96, 1.02))
    assert r"$x_R$" in legend_texts(ax) and orbit_tex("B1,a") in legend_texts(ax)
    assert ax.get_xlim() == pytest.approx((0.0, 0.2)) and ax.get_ylim() == pytest.approx((0.96, 1.02))
    # outside the view: no NSFH line and no entry for it
    fig, ax = plot_extrema(REF, branches=branches, labels=("B1,c", "B1,d"), regular=False, xlim=(0.1, 0.2))
    assert not lines(ax, "nsfh") and not any(t.startswith("NSFH") for t in legend_texts(ax))


def test_region_labels_lie_inside_their_regions_away_from_the_curves():
    diagram = codim2_diagram(REF, ("gamma", "omega"), ((0.0, 0.5), (0.6, 1.25)))
    shape = (31, 31)
    fig, ax = plot_codim2(REF, diagram=diagram, shape=shape)
    (g0, g1), (w0, w1) = diagram.ranges
    cell = max((g1 - g0) / (shape[0] - 1), (w1 - w0) / (shape[1] - 1))
    curves = np.concatenate([ln.get_xydata() for ln in lines(ax, "curve:")])
    curves = curves[np.all(np.isfinite(curves), axis=1)]
    labels = [t for t in ax.texts if (t.get_gid() or "").startswith("label:")]
    names = {t.get_text() for t in labels}
    assert {"R1", "R2", "R3", "R4", OTHER} <= names  # every region of the box, the points fitting none too
    for t in labels:
        x, y = t.get_position()
        name = t.get_text()
        assert region(REF.replace(gamma=x, omega=y)) == (None if name == OTHER else name), (name, x, y)
        # not on a curve: more than a grid cell from each curve, in the plane scaled to the box
        d = np.hypot((curves[:, 0] - x) / (g1 - g0), (curves[:, 1] - y) / (w1 - w0)).min()
        assert d * max(g1 - g0, w1 - w0) > cell, (name, x, y, d)


def _covered(ax, text, line):
    """How many drawn points of ``line`` fall inside the box of ``text`` on the canvas."""
    fig = ax.figure
    fig.canvas.draw()
    box = text.get_window_extent(renderer=fig.canvas.get_renderer())
    xy = line.get_xydata()
    px = ax.transData.transform(xy[np.all(np.isfinite(xy), axis=1)])
    # the segments between the points too, each at 20 points along it
    s = np.linspace(0.0, 1.0, 20)[:, None, None]
    px = (px[:-1] + s * (px[1:] - px[:-1])).reshape(-1, 2)
    inside = (px[:, 0] >= box.x0) & (px[:, 0] <= box.x1) & (px[:, 1] >= box.y0) & (px[:, 1] <= box.y1)
    return int(inside.sum())


def test_the_dib_labels_sit_beside_the_curve_not_on_it():
    diagram = codim2_diagram(REF, ("gamma", "omega"), ((0.0, 0.5), (0.6, 1.25)))
    fig, ax = plot_codim2(REF, diagram=diagram, regions=False)
    (dib,) = lines(ax, "curve:dib")
    labels = [t for t in ax.texts if (t.get_gid() or "").startswith("dib:")]
    assert {t.get_text() for t in labels} >= {"NSFH", "NSF", "Pers"}
    for t in labels:
        assert _covered(ax, t, dib) == 0, t.get_text()
        # and close to the point it names: a few points from it
        assert t.get_anncoords() == "offset points" and np.hypot(*t.get_position()) < 20.0


def test_the_label_of_x_r_in_the_schematic_sits_off_its_path():
    fig, ax = plot_nsfh_schematic(REF)
    (path,) = lines(ax, "x_R-path")
    (label,) = [t for t in ax.texts if t.get_gid() == "label:x_R"]
    assert _covered(ax, label, path) == 0


def test_region_label_cells_pick_the_deepest_cell_of_each_part():
    mask = np.zeros((9, 20), dtype=bool)
    mask[1:8, 1:8] = True  # a 7 x 7 square: its centre
    mask[2:7, 12:19] = True  # a 5 x 7 block: its centre
    mask[0, 9:11] = True  # a sliver along the frame: not labelled
    assert region_label_cells(mask) == [(4, 4), (15, 4)]
    assert region_label_cells(np.zeros((5, 5), dtype=bool)) == []


def test_velocities_figure_clips_to_rdot_max(branches):
    fig, axes = plot_velocities(branches, rdot_max=1.5)
    assert len(axes) == 2 and axes[0].get_ylim()[1] <= 1.5 and axes[1].get_ylim()[0] >= -1.5
    assert "omega=" in axes[0].get_title() and "gamma=" not in axes[0].get_title()
    plt.close(fig)


AX = r"^ax = 'x' is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$"
NOT_PARAMS = r"^params = None is not an? Parameters object; allowed: rotorcontact\.Parameters$"


def test_f1_figures_refuse_bad_input_before_a_figure(refused):
    p = REF.replace(gamma=0.1)
    zc = f1_zero_curves(REF, "gamma", 0.0, 0.25, t_max=4.0, n_seeds=4)
    for draw in (plot_f1, plot_f1_zeros, plot_nsfh_schematic):
        refused(NOT_PARAMS, draw, None)
        refused(AX, draw, p, ax="x")
    refused(r"^n_points = 1000000000000 is invalid; allowed: an integer from 10 to 1000000$", plot_f1, p,
            n_points=10**12)
    refused(r"^n_points = 9 is invalid; allowed: an integer from 10 to 1000000$", plot_f1, p, n_points=9)
    refused(r"^t_range = 30 is invalid; allowed: \(start, stop\), 0 <= start < stop$", plot_f1, p, 30)
    refused(r"^ylim = None is invalid; allowed: \(low, high\), two distinct finite numbers$", plot_f1, p, ylim=None)
    refused(r"^mark_zeros = 'no' is invalid; allowed: True or False$", plot_f1, p, mark_zeros="no")
    for mark in (True, False):
        refused(r"^t_range\[1\] = 1000000000000\.0 is out of range; allowed: \(0, 6000\] \(F1 is evaluated "
                r"accurately up to there at these parameters\)$", plot_f1, p, (0.0, 1e12), mark_zeros=mark)
    refused(r"^curves = 'c' is not an? F1ZeroCurves object; allowed: the F1ZeroCurves of rotorcontact\.continuation\."
            r"zero_curves\.f1_zero_curves or None$", plot_f1_zeros, REF, curves="c")
    refused(r"^t_max = -1\.0 is invalid; allowed: a finite number > 0$", plot_f1_zeros, REF, curves=zc, t_max=-1)
    refused(r"^legend = 'no' is invalid; allowed: True or False$", plot_f1_zeros, REF, curves=zc, legend="no")
    refused(r"^gamma = 'g' is invalid; allowed: a finite number$", plot_nsfh_schematic, REF, gamma="g")
    refused(r"^t_max = 0\.0 is invalid; allowed: a finite number > 0$", plot_nsfh_schematic, REF, t_max=0)
    refused(r"^t_max = 1000000000\.0 is too large", plot_nsfh_schematic, REF, gamma=0.16, t_max=1e9)


def test_branch_figures_refuse_bad_input_before_a_figure(branches, refused):
    allowed = r"allowed: the OrbitBranches of rotorcontact\.continuation\.branches\.orbit_branches"
    refused(rf"^branches = 'b' is not an? OrbitBranches object; {allowed}$", plot_branch_quantity, "b")
    refused(rf"^branches = 'b' is not an? OrbitBranches object; {allowed}$", plot_velocities, "b")
    for draw in (plot_rdot, plot_thetadot, plot_max_multiplier, plot_extrema):
        refused(NOT_PARAMS, draw, None, branches=branches)
        refused(rf"^branches = 'b' is not an? OrbitBranches object; {allowed} or None$", draw, REF, branches="b")
    for draw in (plot_rdot, plot_thetadot, plot_max_multiplier, plot_extrema):
        refused(AX, draw, REF, branches=branches, ax="x")
        refused(r"^labels = 'B1,a' is invalid; allowed: a list or tuple of orbit labels", draw, REF,
                branches=branches, labels="B1,a")
        refused(r"^xlim = \(0, 'a'\) is invalid; allowed: \(low, high\), two distinct finite numbers or None$", draw,
                REF, branches=branches, xlim=(0, "a"))
        refused(r"^ylim = 0\.5 is invalid", draw, REF, branches=branches, ylim=0.5)
    refused(AX, plot_branch_quantity, branches, ax="x")
    refused(r"^quantity = 'nonsense' is invalid; allowed: 'rdot', 'thetadot', 'T', 'theta', 'max_multiplier', "
            r"'r_max_interior'$", plot_branch_quantity, branches, "nonsense")
    refused(r"^local = 3\.0 is invalid; allowed: a mapping label -> \(x, y\), a callable local\(label, x\) or None$",
            plot_rdot, REF, branches=branches, local=3.0)
    refused(r"^events = 'yes' is invalid; allowed: True or False$", plot_branch_quantity, branches, events="yes")
    refused(r"^log = 'yes' is invalid; allowed: True or False$", plot_max_multiplier, REF, branches=branches,
            log="yes")
    refused(r"^regular = 'no' is invalid; allowed: True or False$", plot_extrema, REF, branches=branches,
            regular="no")
    refused(r"^legend = 'no' is invalid; allowed: True or False$", plot_extrema, REF, branches=branches, legend="no")
    refused(r"^rdot_max = -1\.0 is invalid; allowed: a finite number > 0$", plot_velocities, branches, rdot_max=-1)
    refused(r"^figsize = \(1000000\.0, 4\) is invalid; allowed: \(width, height\) in inches, each > 0 and <= 100$",
            plot_velocities, branches, figsize=(1e6, 4))
    refused(r"^labels = 'B1,a' is invalid", plot_velocities, branches, "B1,a")


def test_codim2_figure_refuses_bad_input_before_a_figure(refused):
    diagram = codim2_diagram(REF, ("gamma", "omega"), ((0.0, 0.5), (0.6, 1.25)), folds=())
    refused(NOT_PARAMS, plot_codim2, None, diagram=diagram)
    refused(AX, plot_codim2, REF, ax="x")
    refused(r"^diagram = 'd' is not an? Codim2Diagram object; allowed: the Codim2Diagram of rotorcontact\.continuation"
            r"\.codim2\.codim2_diagram or None$", plot_codim2, REF, diagram="d")
    for bad in ("NSFH", [("NSFH", 0.1)], [("NSFH", 0.1, "y")], [(1, 0.1, 0.9)]):
        refused(r"^labels = .* is invalid; allowed: None or a list of \(text, p1, p2\), p1 and p2 finite numbers$",
                plot_codim2, REF, diagram=diagram, labels=bad)
    refused(r"^regions = 'no' is invalid; allowed: True or False$", plot_codim2, REF, diagram=diagram, regions="no")
    refused(r"^legend = 'no' is invalid; allowed: True or False$", plot_codim2, REF, diagram=diagram, legend="no")
    refused(r"^shape\[0\] = 1000000 is invalid; allowed: an integer from 2 to 1000$", plot_codim2, REF,
            diagram=diagram, shape=(10**6, 3))
    refused(r"^mask = 'abc' is invalid; allowed: a 2-D array of bools$", region_label_cells, "abc")
    refused(r"^mask = \[1, 2\] is invalid", region_label_cells, [1, 2])
    refused(r"^min_depth = -1\.0 is invalid; allowed: a finite number >= 0$", region_label_cells,
            np.ones((3, 3), dtype=bool), -1)


def test_labels_of_another_form_and_unknown_options_are_refused(refused):
    from rotorcontact.plotting.branches import compute_branches, plot_rdot
    from rotorcontact.plotting.equilibria import save_equilibria_figure
    from reference_parameters import REF

    branches = compute_branches(REF, "gamma", 0.05, 0.1, n_seeds=4)
    refused(r"^labels = .* holds 'B9,z', not a one-impact orbit label", plot_rdot, REF, branches=branches,
            labels=["B1,d", "B9,z"])
    refused(r"^foo = 1 is not an option of orbit_branches; allowed: ", compute_branches, REF, foo=1)
    refused(r"^foo = 1 is not an option of plot_equilibria; allowed: ", save_equilibria_figure, REF, "x.png", foo=1)
