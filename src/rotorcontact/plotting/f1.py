"""F1, its zeros against gamma, and the NSFH in the co-rotating plane (the paper's Fig. 4).

* `plot_f1`: F1(T) on an interval of T, with its zeros T0,n,a / T0,n,b marked
  (Fig. 4a: gamma = 0.1, T in [0, 30]; Fig. 4b: gamma = 0.05, T in [0, 40];
  y-range [-0.25, 0.5]).
* `plot_f1_zeros`: the zeros against the parameter (Fig. 4c: gamma in
  [0, 0.25], T up to 12) with the folds gamma_F,n and gamma_DIB marked.
* `plot_nsfh_schematic`: the non-smooth fold-Hopf bifurcation drawn in the
  co-rotating plane from computed objects (Fig. 4d): near the boundary
  equilibrium x_B, the regular equilibrium x_R and the small impacting orbits
  B1,a and B1,b born there just above gamma*.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.equilibria import boundary_gamma
from ..errors import ParameterError
from ..model.flow import free_flight
from ..maps.impact_map import f1, f1_zeros, one_impact_orbits, period_limit
from ..model.params import Parameters, check_range
from ..model.validation import check_bool, check_float, check_int, check_params, check_type, is_pair, quoted
from ..continuation.zero_curves import F1ZeroCurves, f1_zero_curves
from .equilibria import PARAM_LABELS
from .style import (CLEARANCE_COLOR, MAX_PLOT_POINTS, check_ax, check_limits, new_axes, offset_beside,
                    orbit_tex)

__all__ = ["plot_f1", "plot_f1_zeros", "plot_nsfh_schematic", "PAIR_COLORS"]

#: Colours of the pairs n = 1, 2, 3, ... of zeros of F1.
PAIR_COLORS = ("C0", "C3", "C2", "C4", "C5", "C1")


def _pair_color(n: int) -> str:
    return PAIR_COLORS[(max(n, 1) - 1) % len(PAIR_COLORS)]


def plot_f1(
    params: Parameters,
    t_range: tuple[float, float] = (0.0, 30.0),
    *,
    ax=None,
    ylim: tuple[float, float] = (-0.25, 0.5),
    n_points: int = 4000,
    mark_zeros: bool = True,
):
    """F1(T) = 1 + Re(q a22(T)) on ``t_range`` (paper Fig. 4a, 4b).

    Parameters
    ----------
    params : Parameters
        Model parameters (gamma != 0, or F1 has poles).
    t_range : (float, float)
        Interval of T (0 <= start < stop).
    ax : matplotlib.axes.Axes, optional
    ylim : (float, float)
        Vertical range.
    n_points : int
        Samples of F1, 10 to `rotorcontact.plotting.style.MAX_PLOT_POINTS`.
    mark_zeros : bool
        Mark and label the zeros T0,n,a / T0,n,b (found with a guarantee).

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``params`` is not a Parameters, ``t_range`` not a pair 0 <= start < stop (with a stop where
        F1 is evaluated accurately, `rotorcontact.maps.impact_map.period_limit`), ``ax`` not an Axes,
        ``ylim`` not two distinct finite numbers, ``n_points`` out of its range or ``mark_zeros`` not True
        or False.
    """
    check_params(params)
    if not is_pair(t_range):
        raise ParameterError(f"t_range = {quoted(t_range)} is invalid; allowed: (start, stop), 0 <= start < stop")
    lo = check_range("t_range[0]", t_range[0], low=0.0)
    hi = check_range("t_range[1]", t_range[1], low=lo, low_open=True, high=period_limit(params),
                     why="F1 is evaluated accurately up to there at these parameters")
    check_ax(ax)
    ylim = check_limits("ylim", ylim, optional=False)
    n_points = check_int("n_points", n_points, 10, MAX_PLOT_POINTS)
    check_bool("mark_zeros", mark_zeros)
    t = np.linspace(max(lo, 1e-9 * hi), hi, n_points)
    zeros = f1_zeros(params, hi) if mark_zeros else []
    fig, ax = new_axes(ax)
    ax.axhline(0.0, color=CLEARANCE_COLOR, lw=0.8, zorder=0)
    ax.plot(t, f1(params, t), color="k", lw=1.2, gid="F1")
    if mark_zeros:
        for z in zeros:
            if z.T < lo:
                continue
            ax.plot([z.T], [0.0], "o", ms=4, color=_pair_color(z.n), gid=f"zero:{z.n}:{z.kind}")
            # F1 falls through a zero of kind a and rises through one of kind b: the curve is above the axis
            # left of an a and right of a b, so the label goes below the axis there, outward of the pair
            ax.annotate(
                rf"$T_{{0,{z.n},{z.kind}}}$",
                (z.T, 0.0),
                textcoords="offset points",
                xytext=(-3 if z.kind == "a" else 3, -12),
                ha="right" if z.kind == "a" else "left",
                fontsize=8,
                color=_pair_color(z.n),
            )
    ax.set_xlim(lo, hi)
    ax.set_ylim(*ylim)
    ax.set_xlabel(r"$T$")
    ax.set_ylabel(r"$F_1(T)$")
    ax.set_title(rf"$\gamma = {params.gamma:.4g}$", fontsize=10)
    return fig, ax


def plot_f1_zeros(
    params: Parameters,
    param: str = "gamma",
    start: float = 0.0,
    stop: float = 0.25,
    *,
    t_max: float = 12.0,
    ax=None,
    curves: F1ZeroCurves | None = None,
    legend: bool = True,
):
    """The zeros T0,n,a (solid) and T0,n,b (dashed) of F1 against ``param`` (paper Fig. 4c).

    The folds (gamma_F,n, where the pair n merges) and, for ``param`` gamma, the
    boundary equilibrium gamma_DIB = gamma* are marked with vertical lines.

    Parameters
    ----------
    params : Parameters
    param : str
        Parameter on the horizontal axis.
    start, stop : float
        Its range.
    t_max : float
        Largest T shown.
    ax : matplotlib.axes.Axes, optional
    curves : F1ZeroCurves, optional
        Precomputed `rotorcontact.continuation.zero_curves.f1_zero_curves` (else computed).
    legend : bool

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``params`` is not a Parameters, ``t_max`` not a finite number > 0, ``ax`` not an Axes,
        ``curves`` neither None nor an F1ZeroCurves, or ``legend`` not True or False; and for the range
        `rotorcontact.continuation.zero_curves.f1_zero_curves` refuses.
    """
    check_params(params)
    check_float("t_max", t_max, 0.0, low_open=True)
    check_ax(ax)
    check_type("curves", curves, F1ZeroCurves, "the F1ZeroCurves of rotorcontact.continuation.zero_curves."
               "f1_zero_curves", optional=True)
    check_bool("legend", legend)
    if curves is None:
        curves = f1_zero_curves(params, param, start, stop, t_max=t_max)
    fig, ax = new_axes(ax)
    pairs = set()
    for c in curves.curves:
        key = list(zip(c.n, c.kinds))
        i0 = 0
        for i in range(1, len(key) + 1):
            if i == len(key) or key[i] != key[i0]:
                n, kind = key[i0]
                sl = slice(i0, min(i + 1, len(key)))
                ax.plot(c.values[sl], c.T[sl], color=_pair_color(int(n)), ls="-" if kind == "a" else "--",
                        lw=1.4, gid=f"zeros:{int(n)}:{kind}")
                pairs.add(int(n))
                i0 = i
    ymax = t_max
    for f in curves.folds:
        ax.axvline(f.value, color=_pair_color(f.n), lw=0.8, ls=":", zorder=0)
        ax.annotate(rf"$\gamma_{{F,{f.n}}}$" if curves.param == "gamma" else rf"fold$_{{{f.n}}}$",
                    (f.value, ymax), textcoords="offset points", xytext=(2, -12), fontsize=8,
                    color=_pair_color(f.n))
        ax.plot([f.value], [f.T], "o", ms=4, color=_pair_color(f.n), gid=f"fold:{f.n}")
    if curves.param == "gamma":
        gs = boundary_gamma(curves.base)
        if gs is not None and curves.start <= gs <= curves.stop:
            ax.axvline(gs, color="k", lw=0.9, ls="-.", zorder=0, gid="gamma_dib")
            ax.annotate(r"$\gamma_{DIB}$", (gs, ymax), textcoords="offset points", xytext=(2, -24), fontsize=8)
    ax.set_xlim(curves.start, curves.stop)
    ax.set_ylim(0.0, ymax)
    ax.set_xlabel(PARAM_LABELS.get(curves.param, curves.param))
    ax.set_ylabel(r"$T_{0,n}$")
    if legend:
        from matplotlib.lines import Line2D

        handles = [Line2D([], [], color=_pair_color(n), lw=1.4, label=rf"$n = {n}$") for n in sorted(pairs)]
        handles += [Line2D([], [], color="0.3", ls="-", label=r"$T_{0,n,a}$"),
                    Line2D([], [], color="0.3", ls="--", label=r"$T_{0,n,b}$")]
        ax.legend(handles=handles, fontsize=8, loc="upper right")
    return fig, ax


def plot_nsfh_schematic(params: Parameters, *, gamma: float | None = None, ax=None, t_max: float = 12.0):
    """The NSFH in the co-rotating plane, drawn from computed objects (paper Fig. 4d).

    Just above gamma* the regular equilibrium x_R is inside the clearance and
    two small impacting orbits B1,a and B1,b surround the boundary equilibrium
    x_B (where x_R touched the stator at gamma*). The view is a window around
    x_B, the clearance circle in grey.

    Parameters
    ----------
    params : Parameters
        gamma is replaced (see ``gamma``).
    gamma : float, optional
        Damping at which the orbits are drawn; by default a tenth of the way
        from gamma* to the fold gamma_F,1 (where B1,a/b exist and are small).
        The dotted line is the path of x_R as gamma varies around gamma*; it
        crosses the clearance at x_B.
    ax : matplotlib.axes.Axes, optional
    t_max : float
        Largest period searched for the orbits.

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``params`` is not a Parameters (or has no boundary equilibrium), ``gamma`` is neither None nor
        a finite number, ``ax`` is not an Axes or ``t_max`` is not a finite number > 0 (or too large for
        the search of orbits).
    """
    check_params(params)
    if gamma is not None:
        check_float("gamma", gamma)
    check_ax(ax)
    check_float("t_max", t_max, 0.0, low_open=True)
    gs = boundary_gamma(params)
    if gs is None:
        raise ParameterError("no boundary equilibrium for these parameters (gamma* is not real): no NSFH to draw")
    if gamma is None:
        zc = f1_zero_curves(params, "gamma", gs, gs + 0.5, t_max=t_max, n_seeds=6)
        folds = zc.fold_values(1)
        top = folds[0] if folds else gs + 0.1
        gamma = gs + 0.1 * (top - gs)
    p = params.replace(gamma=gamma)
    pb = params.replace(gamma=gs)
    kb = pb.k
    # the path of x_R as gamma goes through gamma*: it crosses the clearance at x_B
    span = 1.5 * (gamma - gs)
    path = np.array([params.replace(gamma=g).k for g in np.linspace(gs - span, gamma + span, 200)])
    orbits = {o.label: o for o in one_impact_orbits(p, t_max) if o.n == 1}
    fig, ax = new_axes(ax)
    s = np.linspace(0.0, 2.0 * math.pi, 4000)
    ax.plot(np.cos(s), np.sin(s), color=CLEARANCE_COLOR, lw=2.0, zorder=0)
    ax.plot(path.real, path.imag, color="k", lw=0.8, ls=":", gid="x_R-path")
    styles = {"B1,b": ("C1", 1.2, 2), "B1,a": ("C0", 1.8, 3)}
    pts = [kb, p.k]
    for label, (color, lw, z) in styles.items():
        o = orbits.get(label)
        if o is None:
            continue
        u0, du0 = o.initial_condition()
        t = np.linspace(0.0, o.T, 800)
        u, _ = free_flight(p, u0, du0, t)
        ax.plot(u.real, u.imag, color=color, lw=lw, zorder=z, gid=f"orbit:{label}")
        ax.plot([u0.real], [u0.imag], "o", color=color, ms=3, zorder=z)
        pts.extend([u.min().real + 1j * u.min().imag, complex(u.real.max(), u.imag.max()),
                    complex(u.real.min(), u.imag.max()), complex(u.real.max(), u.imag.min())])
    k = p.k
    ax.plot([k.real], [k.imag], "o", color="k", ms=5, zorder=4, gid="x_R")
    x_r_at = (k.real, k.imag)
    ax.plot([kb.real], [kb.imag], "s", mfc="white", color="k", ms=6, zorder=4, gid="x_B")
    ax.annotate(r"$x_B$", (kb.real, kb.imag), textcoords="offset points", xytext=(5, 5), fontsize=9)
    pts = np.array(pts)
    cx, cy = 0.5 * (pts.real.min() + pts.real.max()), 0.5 * (pts.imag.min() + pts.imag.max())
    half = 0.75 * max(pts.real.max() - pts.real.min(), pts.imag.max() - pts.imag.min(), 1e-4)
    ax.set_xlim(cx - half, cx + half)
    ax.set_ylim(cy - half, cy + half)
    ax.set_aspect("equal")
    # x_R's label across the dotted path from it, away from the wall, near which the small orbits lie
    wall = k / abs(k)
    ax.annotate(r"$x_R$", x_r_at, textcoords="offset points", ha="center", va="center", fontsize=9, gid="label:x_R",
                xytext=offset_beside(ax, [np.column_stack([path.real, path.imag])], *x_r_at, distance=11.0,
                                     away_from=(wall.real, wall.imag)))
    ax.set_xlabel(r"$\mathrm{Re}\,U$")
    ax.set_ylabel(r"$\mathrm{Im}\,U$")
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=c, lw=lw, label=orbit_tex(lab)) for lab, (c, lw, _) in styles.items()
               if lab in orbits]
    handles.append(Line2D([], [], color="k", marker="o", ms=5, ls="none", label=r"$x_R$"))
    handles.append(Line2D([], [], color="k", marker="s", mfc="white", ms=6, ls="none",
                          label=r"$x_B$ (boundary equilibrium)"))
    handles.append(Line2D([], [], color="k", lw=0.8, ls=":", label=r"$x_R(\gamma)$"))
    handles.append(Line2D([], [], color=CLEARANCE_COLOR, lw=2, label=r"$|U| = 1$"))
    ax.legend(handles=handles, fontsize=8, loc="best")
    ax.set_title(rf"NSFH: $\gamma = {gamma:.4g} > \gamma^* = {gs:.4g}$", fontsize=10)
    return fig, ax
