"""Equilibria against one parameter, in the style of the paper's Fig. 3.

r of the regular equilibrium x_R (r = |k|) and of the pseudo-equilibria x_P
against the parameter: solid where admissible, dashed where virtual, the
boundary equilibrium bifurcation (x_R crossing r = 1) marked.

Pseudo-equilibria lie on the stator, so they are drawn on the line r = 1; their
admissibility (N > 0) is what the line style shows. This is what makes the two
scenarios readable: in a non-smooth fold the x_R curve reaches r = 1 at gamma*
exactly where the partner's line on r = 1 switches from dashed to solid on
the same side; in persistence x_R (solid inside) continues as the partner's
solid line on r = 1 on the other side. Lines are thick where the equilibrium
is stable and thin where it is unstable.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..analysis.equilibria import (PSEUDO_NAMES, EquilibriumBranches, equilibrium_branches, pseudo_equilibria,
                                   regular_equilibrium)
from ..model.params import Parameters
from ..model.validation import check_bool, check_choice, check_params, check_type
from .style import check_ax, check_figure_path, check_keywords, check_limits, new_axes, save_figure

__all__ = ["plot_equilibrium_branches", "plot_equilibria", "save_equilibria_figure", "PARAM_LABELS"]

#: Axis labels of the branch parameters.
PARAM_LABELS = {"gamma": r"$\gamma$", "omega": r"$\omega$", "rho": r"$\rho$", "mu": r"$\mu$", "d": r"$d$"}

COLORS = {"x_R": "C0", "P1": "C3", "P2": "C2"}
LW_STABLE = 2.0
LW_UNSTABLE = 1.0

_PSEUDO_CHOICES = ("partner", "both", "P1", "P2", "none")


def _interval_states(branches: EquilibriumBranches) -> list[dict[str, tuple[bool, bool, bool]]]:
    """(exists, admissible, stable) of each branch at the midpoint of each interval of ``values``.

    Every event is a grid value, so these flags are constant inside each interval.
    """
    out = []
    v = branches.values
    for a, b in zip(v[:-1], v[1:]):
        p = branches.params_at(0.5 * (a + b))
        reg = regular_equilibrium(p)
        row = {"x_R": (reg.exists, reg.admissible, reg.stable)}
        for pe in pseudo_equilibria(p):
            row[pe.name] = (pe.exists, pe.admissible, bool(pe.stable))
        out.append(row)
    return out


def _runs(states: Sequence[tuple[bool, bool, bool]]):
    """Maximal runs [i0, i1] of intervals with the same state."""
    i0 = 0
    for i in range(1, len(states) + 1):
        if i == len(states) or states[i] != states[i0]:
            yield i0, i - 1, states[i0]
            i0 = i


def _check_options(ax, pseudo, ylim, legend) -> None:
    """The checks of the drawing options of `plot_equilibrium_branches` (made by `plot_equilibria` too, before
    its computation)."""
    check_ax(ax)
    check_choice("pseudo", pseudo, _PSEUDO_CHOICES)
    check_limits("ylim", ylim)
    check_bool("legend", legend)


def _which_pseudo(branches: EquilibriumBranches, pseudo: str) -> tuple[str, ...]:
    if pseudo == "none":
        return ()
    if pseudo == "both":
        return PSEUDO_NAMES
    if pseudo == "partner":
        return branches.partners or PSEUDO_NAMES
    return (pseudo,)


def plot_equilibrium_branches(
    branches: EquilibriumBranches,
    ax=None,
    *,
    pseudo: str = "partner",
    ylim: tuple[float, float] | None = None,
    legend: bool = True,
):
    """Draw r of x_R and x_P against the parameter (paper Fig. 3 style).

    Parameters
    ----------
    branches : EquilibriumBranches
        From `rotorcontact.analysis.equilibria.equilibrium_branches`.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; a new figure is made when None.
    pseudo : {"partner", "both", "P1", "P2", "none"}
        Which pseudo-equilibria to draw on r = 1. ``"partner"`` (the paper's
        choice) draws those that meet x_R at a boundary equilibrium in the
        range, or both when there is none. Both lie on r = 1, so where both
        are drawn they overlap (P2 is drawn over P1).
    ylim : (float, float), optional
        Vertical range; by default the range of r of x_R and 1, padded, with
        the top capped at 3 (x_R goes to infinity at the undamped resonance).
    legend : bool
        Add a legend.

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``branches`` is not an EquilibriumBranches, ``ax`` not an Axes, ``pseudo`` not one of its
        choices, ``ylim`` neither None nor two distinct finite numbers, or ``legend`` not True or False.
    """
    check_type("branches", branches, EquilibriumBranches,
               "the EquilibriumBranches of rotorcontact.analysis.equilibria.equilibrium_branches")
    _check_options(ax, pseudo, ylim, legend)
    fig, ax = new_axes(ax)
    names = _which_pseudo(branches, pseudo)
    v = branches.values
    states = _interval_states(branches)
    r = branches.regular_r

    drawn: list[str] = []

    def draw(name: str, ys: np.ndarray | None) -> None:
        for i0, i1, (exists, admissible, stable) in _runs([s[name] for s in states]):
            if not exists:
                continue
            xs = v[i0 : i1 + 2]
            yy = np.ones_like(xs) if ys is None else ys[i0 : i1 + 2]
            ax.plot(
                xs,
                yy,
                color=COLORS[name],
                ls="-" if admissible else "--",
                lw=LW_STABLE if stable else LW_UNSTABLE,
                gid=f"{name}:{'admissible' if admissible else 'virtual'}:{'stable' if stable else 'unstable'}",
            )
            if name not in drawn:
                drawn.append(name)

    draw("x_R", r)
    for name in names:
        draw(name, None)

    for ev in branches.boundary_points:
        ax.plot([ev.value], [1.0], "o", color="k", ms=6, zorder=5)
        ax.annotate("BEB", (ev.value, 1.0), textcoords="offset points", xytext=(4, 6), fontsize=9)
    for ev in branches.select(kind="stability"):
        if ev.branch == "x_R" or ev.branch in names:
            y = 1.0 if ev.branch != "x_R" else float(abs(branches.params_at(ev.value).k))
            ax.plot([ev.value], [y], "s", mfc="none", color=COLORS[ev.branch], ms=6, zorder=5)

    if ylim is None:
        finite = r.compressed()
        finite = finite[np.isfinite(finite)]
        lo = min(1.0, float(finite.min())) if finite.size else 1.0
        hi = min(3.0, max(1.0, float(finite.max()))) if finite.size else 1.0
        pad = max(0.02, 0.08 * (hi - lo))
        ylim = (max(0.0, lo - pad), hi + pad)
    ax.set_ylim(*ylim)
    ax.set_xlim(v[0], v[-1])
    ax.set_xlabel(PARAM_LABELS.get(branches.param, branches.param))
    ax.set_ylabel(r"$r$")
    if legend:
        from matplotlib.lines import Line2D

        handles = [
            Line2D([], [], color=COLORS[name], lw=LW_STABLE, label=r"$x_R$" if name == "x_R" else rf"$x_{{{name}}}$")
            for name in drawn
        ]
        handles += [
            Line2D([], [], color="0.3", ls="-", label="admissible"),
            Line2D([], [], color="0.3", ls="--", label="virtual"),
            Line2D([], [], color="0.3", lw=LW_STABLE, label="stable"),
            Line2D([], [], color="0.3", lw=LW_UNSTABLE, label="unstable"),
        ]
        if branches.boundary_points:
            handles.append(Line2D([], [], color="k", marker="o", ls="none", label="BEB"))
        ax.legend(handles=handles, fontsize=8, loc="best")
    return fig, ax


def plot_equilibria(
    params: Parameters,
    param: str = "gamma",
    start: float = 0.0,
    stop: float = 0.2,
    *,
    n: int = 401,
    ax=None,
    pseudo: str = "partner",
    ylim: tuple[float, float] | None = None,
    legend: bool = True,
):
    """Compute `equilibrium_branches` and draw them with `plot_equilibrium_branches`.

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``params`` is not a Parameters, for the drawing options `plot_equilibrium_branches` refuses
        (checked before the computation), and for the range `equilibrium_branches` refuses.
    """
    check_params(params)
    _check_options(ax, pseudo, ylim, legend)
    branches = equilibrium_branches(params, param, start, stop, n)
    fig, ax = plot_equilibrium_branches(branches, ax, pseudo=pseudo, ylim=ylim, legend=legend)
    p = params
    others = ", ".join(
        f"{name}={getattr(p, name):.4g}" for name in ("gamma", "omega", "rho", "mu", "d") if name != param
    )
    ax.set_title(others, fontsize=9)
    return fig, ax


def save_equilibria_figure(
    params: Parameters, path, param: str = "gamma", start: float = 0.0, stop: float = 0.2, **kwargs
):
    """Draw `plot_equilibria` and save it to ``path`` (.png, .svg or .pdf); returns the path.

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses (before the work), and
        for the arguments `plot_equilibria` refuses.
    """
    check_figure_path(path)
    check_keywords(kwargs, plot_equilibria)
    fig, _ = plot_equilibria(params, param, start, stop, **kwargs)
    return save_figure(fig, path)
