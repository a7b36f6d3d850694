"""Fig. 5(b)/(d) with the local estimate overlaid."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import ParameterError  # noqa: E402
from rotorcontact.analysis.equilibria import boundary_gamma  # noqa: E402
from rotorcontact.analysis.local import LinearImpactingSystem, local_analysis  # noqa: E402
from rotorcontact.plotting.local import plot_local_estimate, plot_local_figure  # noqa: E402
from reference_parameters import REF  # noqa: E402


def _line(ax, gid):
    lines = [ln for ln in ax.get_lines() if ln.get_gid() == gid]
    assert len(lines) == 1, gid
    x, y = lines[0].get_data()
    return np.asarray(x, float), np.asarray(y, float)


@pytest.fixture(scope="module")
def rotor():
    return REF


def test_rdot_overlay_like_fig5b(rotor):
    gs = boundary_gamma(rotor)
    an = local_analysis(rotor)
    fig, ax = plot_local_estimate(rotor, "rdot", n=21)
    try:
        for label in ("B1,a", "B1,b"):
            x, adm = _line(ax, f"global:{label}:admissible")
            _, vir = _line(ax, f"global:{label}:virtual")
            xl, yl = _line(ax, f"local:{label}")
            # admissible only above gamma*, virtual below (the NSFH)
            assert np.all(x[np.isfinite(adm)] > gs) and np.any(np.isfinite(adm))
            assert np.all(x[np.isfinite(vir)] < gs + 1e-12 + (x[1] - x[0]))
            # the local estimate is the line through (gamma*, 0) with the local slope
            assert np.allclose(yl, (xl - gs) * an.orbit(label).rdot_slope, rtol=1e-12, atol=1e-15)
            # tangent to the global branch: the gap grows like eps^2 (x4 from eps to 2 eps)
            glob = np.where(np.isfinite(adm), adm, vir)
            i1 = int(np.argmin(np.abs(x - gs - 0.05 * gs)))
            i2 = int(np.argmin(np.abs(x - gs - 0.1 * gs)))
            ratio = abs(glob[i2] - yl[i2]) / abs(glob[i1] - yl[i1])
            assert 3.5 < ratio < 4.5, ratio
        assert ax.get_xlabel() == r"$\gamma$"
    finally:
        plt.close(fig)


def test_thetadot_on_a_given_ax_and_the_two_panel_figure(rotor):
    fig0, ax0 = plt.subplots()
    fig, ax = plot_local_estimate(rotor, "thetadot", ax0, n=11)
    assert fig is fig0 and ax is ax0
    assert "theta" in ax.get_ylabel()
    plt.close(fig)
    fig, axes = plot_local_figure(rotor, n=11)
    try:
        assert len(axes) == 2
        assert axes[0].get_title().startswith("(b)") and axes[1].get_title().startswith("(d)")
        for a in axes:
            assert {ln.get_gid() for ln in a.get_lines()} >= {"local:B1,a", "local:B1,b"}
    finally:
        plt.close(fig)


def test_general_system_overlay():
    s = LinearImpactingSystem.on_boundary(0.18 + 1.9j, 1.7 + 0.3j, 0.7, mu=0.3, d=0.8, sigma=0.8,
                                          alpha1=0.5 - 0.2j, beta1=0.4 + 0.3j, Gamma1=0.1 - 0.2j)
    fig, ax = plot_local_estimate(s, "rdot", labels=("B1,c", "B1,b"), eps_range=(-0.02, 0.02), n=9)
    try:
        x, adm = _line(ax, "global:B1,c:admissible")
        assert np.all(x[np.isfinite(adm)] < 0)  # B1,c lives where the equilibrium is virtual
        assert ax.get_xlabel() == r"$\epsilon$"
    finally:
        plt.close(fig)


def test_bad_input(rotor):
    with pytest.raises(ParameterError, match="quantity"):
        plot_local_estimate(rotor, "theta")
    with pytest.raises(ParameterError, match="no small orbit"):
        plot_local_estimate(rotor, labels=("B1,c",), n=5)
    with pytest.raises(ParameterError, match="empty"):
        plot_local_estimate(rotor, eps_range=(0.01, -0.01))
    with pytest.raises(ParameterError, match="no real gamma"):
        plot_local_estimate(rotor.replace(rho=0.0))


def test_refusals_name_the_argument_before_any_figure(rotor, refused):
    fig, (a, b) = plt.subplots(1, 2)
    allowed = r"allowed: rotorcontact\.Parameters or a rotorcontact\.analysis\.local\.LinearImpactingSystem$"
    for draw in (plot_local_estimate, plot_local_figure):
        refused(rf"^model = None is not an? Parameters or LinearImpactingSystem object; {allowed}", draw, None)
    refused(r"^ax = 'x' is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$", plot_local_estimate,
            rotor, "rdot", "x")
    refused(r"^quantity = 'theta' is invalid; allowed: 'rdot', 'thetadot'$", plot_local_estimate, rotor, "theta")
    refused(r"^axes = 'ab' is not a sequence of Axes; allowed: None or a sequence of 2 matplotlib\.axes\.Axes "
            r"\(rdot, thetadot\)$", plot_local_figure, rotor, "ab")
    refused(r"^axes = .* holds 1 axes; allowed: None or a sequence of 2", plot_local_figure, rotor, [a])
    refused(r"^quantity = 'rdot' is not an option of plot_local_figure; allowed: labels, eps_range, n, t_max$",
            plot_local_figure, rotor, quantity="rdot")
    for draw in (plot_local_estimate, plot_local_figure):
        refused(r"^labels = 'B1,a' is invalid; allowed: a list or tuple of orbit labels", draw, rotor,
                labels="B1,a")
        refused(r"^eps_range = 0\.1 is invalid; allowed: \(low, high\) or None$", draw, rotor, eps_range=0.1)
        refused(r"^n = 2 is invalid; allowed: an integer from 3 to 1000$", draw, rotor, n=2)
        refused(r"^n = 1000000000000 is invalid; allowed: an integer from 3 to 1000$", draw, rotor, n=10**12)
    # the refusals of the analysis come before the figure too
    refused(r"^no small orbit 'B1,c'", plot_local_figure, rotor, labels=("B1,c",), n=5)
    assert not a.lines and not b.lines
    plt.close(fig)
