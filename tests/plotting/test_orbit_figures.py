"""Figures 4-7 of the paper: what each draws is the computed data, in the documented styles."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import ParameterError, Parameters  # noqa: E402
from rotorcontact import impactmap as im  # noqa: E402
from rotorcontact.branches import orbit_branches  # noqa: E402
from rotorcontact.codim2 import codim2_diagram  # noqa: E402
from rotorcontact.equilibria import boundary_gamma  # noqa: E402
from rotorcontact.plotting.branches import (  # noqa: E402
    plot_branch_quantity,
    plot_extrema,
    plot_max_multiplier,
    plot_rdot,
    plot_thetadot,
)
from rotorcontact.plotting.codim2 import plot_codim2  # noqa: E402
from rotorcontact.plotting.f1 import plot_f1, plot_f1_zeros, plot_nsfh_schematic  # noqa: E402
from rotorcontact.plotting.style import save_figure  # noqa: E402
from rotorcontact.zerocurves import f1_zero_curves  # noqa: E402

REF = Parameters.reference()


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


def test_fig5_rdot_and_thetadot_are_the_branch_data(branches):
    fig, ax = plot_rdot(REF, branches=branches)
    for label in ("B1,a", "B1,b", "B1,c", "B1,d"):
        b = branches.branch(label)
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
    b = branches.branch("B1,b")
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


def test_fig6b_max_multiplier_only_where_admissible(branches):
    fig, ax = plot_max_multiplier(REF, branches=branches)
    assert ax.get_yscale() == "log"
    for label in ("B1,c", "B1,d"):
        b = branches.branch(label)
        for ln in lines(ax, label + ":"):
            assert ln.get_gid().split(":")[1] != "virtual" or np.all(np.isnan(ln.get_ydata()))
            y = ln.get_ydata()
            y = y[np.isfinite(y)]
            assert set(y) <= set(b.max_multiplier[np.isfinite(b.max_multiplier)])


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
