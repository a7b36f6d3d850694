"""The Fig. 3-style figure of equilibria against a parameter."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import ParameterError  # noqa: E402
from rotorcontact.analysis.equilibria import boundary_gamma, equilibrium_branches  # noqa: E402
from rotorcontact.plotting.equilibria import (  # noqa: E402
    plot_equilibria,
    plot_equilibrium_branches,
    save_equilibria_figure,
)
from reference_parameters import REF


def _lines(ax, branch):
    """Lines of one branch, keyed by their (admissibility, stability) tag."""
    out = []
    for line in ax.get_lines():
        gid = line.get_gid()
        if gid and gid.split(":")[0] == branch:
            _, adm, stab = gid.split(":")
            out.append((adm, stab, line))
    return out


@pytest.fixture
def fold_params():
    return REF.replace(omega=0.76)


def test_nonsmooth_fold_figure_like_fig3a(fold_params):
    """Fig. 3a: x_R dashed (virtual) below gamma*, solid above; x_P1 on r = 1 likewise; BEB marked."""
    fig, ax = plot_equilibria(fold_params, "gamma", 0.0, 0.2)
    gs = boundary_gamma(fold_params)
    reg = _lines(ax, "x_R")
    assert {(a, s) for a, s, _ in reg} == {("virtual", "stable"), ("admissible", "stable")}
    for adm, _, line in reg:
        x, y = line.get_data()
        assert np.allclose(y, [abs(fold_params.replace(gamma=g).k) for g in x], rtol=1e-13)
        assert line.get_linestyle() == ("-" if adm == "admissible" else "--")
        if adm == "virtual":
            assert x.min() == pytest.approx(0.0) and x.max() == pytest.approx(gs, abs=1e-12)
            assert np.all(y >= 1 - 1e-12)
        else:
            assert x.min() == pytest.approx(gs, abs=1e-12) and x.max() == pytest.approx(0.2)
            assert np.all(y <= 1 + 1e-12)
    p1 = _lines(ax, "P1")
    assert {(a, s) for a, s, _ in p1} == {("virtual", "unstable"), ("admissible", "unstable")}
    for adm, _, line in p1:
        x, y = line.get_data()
        assert np.all(y == 1.0)
        assert (x.max() <= gs + 1e-12) if adm == "virtual" else (x.min() >= gs - 1e-12)
    assert not _lines(ax, "P2")  # the paper's Fig. 3a shows only the partner
    markers = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    assert len(markers) == 1
    assert markers[0].get_xdata()[0] == pytest.approx(gs, abs=1e-12) and markers[0].get_ydata()[0] == 1.0
    assert ax.get_xlabel() == r"$\gamma$"
    plt.close(fig)


def test_persistence_figure_like_fig3b():
    """Fig. 3b: at omega = 1, x_P2 admissible below gamma* = rho, x_R admissible above."""
    p = REF.replace(omega=1.0)
    fig, ax = plot_equilibria(p, "gamma", 0.0, 0.8)
    p2 = _lines(ax, "P2")
    admissible = [line for adm, _, line in p2 if adm == "admissible"]
    assert len(admissible) == 1
    assert admissible[0].get_xdata().max() == pytest.approx(p.rho, abs=1e-12)
    reg = [line for adm, _, line in _lines(ax, "x_R") if adm == "admissible"]
    assert len(reg) == 1 and reg[0].get_xdata().min() == pytest.approx(p.rho, abs=1e-12)
    assert not _lines(ax, "P1")
    plt.close(fig)


def test_draws_into_given_axes_and_can_show_both_pseudo_equilibria(fold_params):
    fig, axes = plt.subplots(1, 2)
    branches = equilibrium_branches(fold_params, "omega", 0.5, 1.3, 101)
    f, ax = plot_equilibrium_branches(branches, axes[1], pseudo="both")
    assert f is fig and ax is axes[1]
    assert _lines(ax, "P1") and _lines(ax, "P2")
    assert not axes[0].get_lines()
    # two BEBs in omega: the partner choice draws both partners
    _, ax2 = plot_equilibrium_branches(branches, axes[0])
    assert {"P1", "P2"} == {gid.split(":")[0] for gid in (ln.get_gid() for ln in ax2.get_lines()) if gid} - {"x_R"}
    plt.close(fig)


def test_bad_choices_raise(fold_params, tmp_path):
    branches = equilibrium_branches(fold_params, "gamma", 0.0, 0.2, 21)
    with pytest.raises(ParameterError, match="pseudo"):
        plot_equilibrium_branches(branches, pseudo="P3")
    with pytest.raises(ParameterError, match="suffix"):
        save_equilibria_figure(fold_params, tmp_path / "fig.txt")
    with pytest.raises(ParameterError):
        plot_equilibrium_branches("not branches")


def test_save_writes_a_png(fold_params, tmp_path):
    path = save_equilibria_figure(fold_params, tmp_path / "fig3a.png", "gamma", 0.0, 0.2, n=51)
    assert path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_refusals_name_the_argument_before_any_figure_or_computation(fold_params, refused, tmp_path, monkeypatch):
    import rotorcontact.plotting.equilibria as module

    branches = equilibrium_branches(fold_params, "gamma", 0.0, 0.2, 11)
    refused(r"^branches = 'x' is not an? EquilibriumBranches object; allowed: the EquilibriumBranches of "
            r"rotorcontact\.analysis\.equilibria\.equilibrium_branches$", plot_equilibrium_branches, "x")
    refused(r"^pseudo = 'P3' is invalid; allowed: 'partner', 'both', 'P1', 'P2', 'none'$",
            plot_equilibrium_branches, branches, pseudo="P3")

    def no_computation(*args, **kwargs):
        raise AssertionError("computed before the options were checked")

    monkeypatch.setattr(module, "equilibrium_branches", no_computation)
    for draw, first in ((plot_equilibrium_branches, branches), (plot_equilibria, fold_params)):
        refused(r"^ax = 'x' is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$", draw, first, ax="x")
        refused(r"^ylim = \(1, 1\) is invalid; allowed: \(low, high\), two distinct finite numbers or None$", draw,
                first, ylim=(1, 1))
        refused(r"^ylim = 'ab' is invalid", draw, first, ylim="ab")
        refused(r"^legend = 'no' is invalid; allowed: True or False$", draw, first, legend="no")
    refused(r"^pseudo = 3 is invalid", plot_equilibria, fold_params, pseudo=3)
    refused(r"^params = 'p' is not an? Parameters object; allowed: rotorcontact\.Parameters$", save_equilibria_figure,
            "p", tmp_path / "e.png")
    refused(r"^path = '.*e\.txt' has an unsupported suffix; allowed: \.png, \.svg, \.pdf$", save_equilibria_figure,
            fold_params, tmp_path / "e.txt")
