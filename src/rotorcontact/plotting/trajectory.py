"""Figures of a single trajectory: inertial frame, co-rotating frame and r(t) (paper Fig. 2 style)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np

from ..model.validation import check_bool, check_float, check_int, check_type
from ..simulation.trajectory import Trajectory
from .style import MAX_PLOT_POINTS, check_ax, check_axes, check_figure_path, draw_clearance, new_axes, save_figure

if TYPE_CHECKING:
    import os
    from collections.abc import Sequence
    from pathlib import Path

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_inertial", "plot_corotating", "shade_contact", "plot_radius", "plot_trajectory",
           "save_trajectory_figure", "MAX_CONTACT_SAMPLES", "CONTACT_COLORS"]

#: Most plot times added along the contact phases of a trajectory figure, all phases together (beyond the
#: ``n`` uniform times), so that fast whirl in contact is followed without unbounded memory.
MAX_CONTACT_SAMPLES = 20000


def _check_trajectory(traj, t_from, n) -> None:
    """The checks every trajectory figure makes of its trajectory, ``t_from`` and ``n``."""
    check_type("traj", traj, Trajectory, "a rotorcontact.Trajectory (rotorcontact.simulate)")
    if t_from is not None:
        check_float("t_from", t_from)
    check_int("n", n, 2, MAX_PLOT_POINTS)


def _times(traj: Trajectory, t_from: float | None, n: int) -> np.ndarray:
    """Plot times: uniform, every impact, and contact phases fine enough to follow fast whirl."""
    t0 = 0.0 if t_from is None else max(0.0, min(t_from, traj.t_stop))
    parts = [np.linspace(t0, traj.t_stop, n)]
    imp = traj.impacts.t
    parts.append(imp[imp >= t0])
    budget = MAX_CONTACT_SAMPLES
    for c, row in zip(traj.contact_intervals, traj.contacts):
        a, b = max(c.t_start, t0), min(c.t_end, traj.t_stop)
        if b <= a or budget <= 0:
            continue
        rate = np.abs(traj.path[int(row[3]) : int(row[4]) + 1, 2]).max() + 1.0
        m = int(min(budget, max(2, rate * (b - a) / 0.05)))
        parts.append(np.linspace(a, b, m))
        budget -= m
    return np.unique(np.concatenate(parts))


def plot_inertial(traj: Trajectory, ax: Axes | None = None, *, t_from: float | None = None,
                  n: int = 4000) -> tuple[Figure, Axes]:
    """Rotor centre Z = U e^{it} in the inertial frame, with the clearance circle.

    Parameters
    ----------
    traj : Trajectory
        The motion to draw (`rotorcontact.simulate`).
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.
    t_from : float, optional
        Draw from this time on (dimensionless, clipped to [0, ``traj.t_stop``]); default: from the start.
    n : int
        Number of uniform plot times, 2 to `rotorcontact.plotting.style.MAX_PLOT_POINTS` (impacts and
        contact phases are added).

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ParameterError
        If ``traj`` is not a Trajectory, ``ax`` neither None nor an Axes, ``t_from`` neither None nor a
        finite number, or ``n`` not an integer from 2 to `rotorcontact.plotting.style.MAX_PLOT_POINTS`
        (all checked before anything is drawn).
    """
    _check_trajectory(traj, t_from, n)
    fig, ax = new_axes(ax)
    t = _times(traj, t_from, n)
    z = traj.Z(t)
    ax.plot(z.real, z.imag, lw=0.8)
    draw_clearance(ax)
    ax.set_xlabel("Re Z")
    ax.set_ylabel("Im Z")
    ax.set_title("inertial frame")
    return fig, ax


def _draw_corotating(ax, u: np.ndarray, impacts: np.ndarray, k: complex, lw: float = 0.8) -> None:
    ax.plot(u.real, u.imag, lw=lw, color="C0", gid="orbit", label="orbit")
    if impacts.size:
        ax.plot(impacts.real, impacts.imag, "o", ms=3, color="C3", gid="impacts", label="impacts")
    ax.plot([k.real], [k.imag], "k+", ms=8, gid="x_R", label=r"$x_R$")
    draw_clearance(ax)


def plot_corotating(traj: Trajectory, ax: Axes | None = None, *, t_from: float | None = None, n: int = 4000,
                    inset: bool = False, legend: bool = True) -> tuple[Figure, Axes]:
    """Rotor centre U in the co-rotating frame, impacts marked, clearance circle in grey.

    Parameters
    ----------
    traj : Trajectory
        The motion to draw (`rotorcontact.simulate`).
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.
    t_from : float, optional
        Draw from this time on (dimensionless, clipped to [0, ``traj.t_stop``]); default: from the start.
    n : int
        Number of uniform plot times, 2 to `rotorcontact.plotting.style.MAX_PLOT_POINTS` (impacts and
        contact phases are added).
    inset : bool
        Add an inset zoomed on the orbit (for a small orbit near the
        clearance, such as B1,a near the NSFH), its frame marked on the main
        axes and its magnification written in it. The inset is the child axes
        with label ``"zoom"``.
    legend : bool
        A legend of the orbit, the impacts and x_R.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The main axes drawn on (the inset, if any, is its child).

    Raises
    ------
    ParameterError
        If ``traj`` is not a Trajectory, ``ax`` neither None nor an Axes, ``t_from`` neither None nor a
        finite number, ``n`` not an integer from 2 to `rotorcontact.plotting.style.MAX_PLOT_POINTS`, or
        ``inset`` or ``legend`` not True or False (all checked before anything is drawn).
    """
    _check_trajectory(traj, t_from, n)
    check_bool("inset", inset)
    check_bool("legend", legend)
    fig, ax = new_axes(ax)
    t = _times(traj, t_from, n)
    u = traj.U(t)
    imp = traj.impacts
    hits = imp.point[imp.t >= t[0]]
    k = traj.params.k
    _draw_corotating(ax, u, hits, k)
    ax.set_xlabel(r"$\mathrm{Re}\,U$")
    ax.set_ylabel(r"$\mathrm{Im}\,U$")
    ax.set_title("co-rotating frame")
    if inset:
        zoom = ax.inset_axes([0.25, 0.25, 0.5, 0.5], label="zoom")
        _draw_corotating(zoom, u, hits, k, lw=1.2)
        x, y = np.concatenate([u.real, hits.real]), np.concatenate([u.imag, hits.imag])
        cx, cy = 0.5 * (x.min() + x.max()), 0.5 * (y.min() + y.max())
        half = 0.6 * max(x.max() - x.min(), y.max() - y.min(), 1e-9)
        zoom.set_xlim(cx - half, cx + half)
        zoom.set_ylim(cy - half, cy + half)
        zoom.set_xticks([])
        zoom.set_yticks([])
        lo, hi = ax.get_xlim()
        zoom.text(0.04, 0.96, f"×{(hi - lo) / (2.0 * half):.0f}", transform=zoom.transAxes, ha="left", va="top",
                  fontsize=7, gid="zoom-factor")
        ax.indicate_inset_zoom(zoom, edgecolor="0.3")
    if legend:
        ax.legend(loc="upper right", fontsize=7, framealpha=0.85)
    return fig, ax


#: Colour of each kind of contact phase in `shade_contact`.
CONTACT_COLORS = {"sliding-forward": "tab:orange", "rolling": "tab:red", "sliding-backward": "tab:purple"}


def shade_contact(traj: Trajectory, ax: Axes, t_from: float = 0.0) -> None:
    """Shade the contact phases of ``traj`` on a time axis, one colour per kind.

    The colours are `CONTACT_COLORS`; a legend of the kinds shaded is added where there is any.

    Parameters
    ----------
    traj : Trajectory
        The motion to draw (`rotorcontact.simulate`).
    ax : matplotlib.axes.Axes
        The axes to shade, with the (dimensionless) time along x.
    t_from : float
        Shade from this time on: phases that end before it are left out, one that spans it is cut there.

    Returns
    -------
    None

    Raises
    ------
    ParameterError
        If ``traj`` is not a Trajectory, ``ax`` not an Axes (None included) or ``t_from`` not a finite
        number.
    """
    check_type("traj", traj, Trajectory, "a rotorcontact.Trajectory (rotorcontact.simulate)")
    check_ax(ax, optional=False)
    t_from = check_float("t_from", t_from)
    seen = set()
    for c in traj.contact_intervals:
        if c.t_end < t_from:
            continue
        label = None if c.kind in seen else c.kind
        seen.add(c.kind)
        ax.axvspan(max(c.t_start, t_from), c.t_end, color=CONTACT_COLORS[c.kind], alpha=0.25, lw=0, label=label)
    if seen:
        ax.legend(loc="lower right", fontsize=8)


def plot_radius(traj: Trajectory, ax: Axes | None = None, *, t_from: float | None = None,
                n: int = 4000) -> tuple[Figure, Axes]:
    """r(t) = |U(t)|, with the clearance r = 1 and the contact phases shaded.

    The contact phases are shaded by `shade_contact`.

    Parameters
    ----------
    traj : Trajectory
        The motion to draw (`rotorcontact.simulate`).
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.
    t_from : float, optional
        Draw from this time on (dimensionless, clipped to [0, ``traj.t_stop``]); default: from the start.
    n : int
        Number of uniform plot times, 2 to `rotorcontact.plotting.style.MAX_PLOT_POINTS` (impacts and
        contact phases are added).

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ParameterError
        If ``traj`` is not a Trajectory, ``ax`` neither None nor an Axes, ``t_from`` neither None nor a
        finite number, or ``n`` not an integer from 2 to `rotorcontact.plotting.style.MAX_PLOT_POINTS`
        (all checked before anything is drawn).
    """
    _check_trajectory(traj, t_from, n)
    fig, ax = new_axes(ax)
    t = _times(traj, t_from, n)
    ax.plot(t, traj.r(t), lw=0.8)
    ax.axhline(1.0, color="0.6", lw=1.5, zorder=0)
    shade_contact(traj, ax, t[0])
    ax.set_xlabel("t (dimensionless)")
    ax.set_ylabel("r")
    ax.set_title("radius")
    return fig, ax


def plot_trajectory(traj: Trajectory, axes: Sequence[Axes] | np.ndarray | None = None, *,
                    t_from: float | None = None, n: int = 4000) -> tuple[Figure, np.ndarray | list[Axes]]:
    """Three panels: inertial frame, co-rotating frame and r(t).

    The panels are drawn by `plot_inertial`, `plot_corotating` and `plot_radius`.

    Parameters
    ----------
    traj : Trajectory
        The motion to draw (`rotorcontact.simulate`).
    axes : sequence of three matplotlib.axes.Axes, optional
        Where to draw the three panels: a list, a tuple or a numpy array of three Axes (of any shape, read
        in C order). Without it a figure of its own is made, with the parameters and the motion in its
        title.
    t_from : float, optional
        Draw from this time on (dimensionless, clipped to [0, ``traj.t_stop``]); default: from the start.
    n : int
        Number of uniform plot times, 2 to `rotorcontact.plotting.style.MAX_PLOT_POINTS` (impacts and
        contact phases are added).

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``axes[0]`` where ``axes`` are given).
    axes : numpy.ndarray or list of matplotlib.axes.Axes
        The three panels: the numpy array of `matplotlib.pyplot.subplots` for a figure of its own, else
        the given Axes as a list.

    Raises
    ------
    ParameterError
        If ``traj`` is not a Trajectory, ``axes`` neither None nor a list, tuple or numpy array of exactly
        three Axes, ``t_from`` neither None nor a finite number, or ``n`` not an integer from 2 to
        `rotorcontact.plotting.style.MAX_PLOT_POINTS` (all checked before anything is drawn).
    """
    _check_trajectory(traj, t_from, n)
    axes = check_axes(axes, 3, "inertial, co-rotating, radius")
    own = axes is None
    if own:
        fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), gridspec_kw={"width_ratios": [1, 1, 1.6]})
    else:
        fig = axes[0].figure
    plot_inertial(traj, axes[0], t_from=t_from, n=n)
    plot_corotating(traj, axes[1], t_from=t_from, n=n)
    plot_radius(traj, axes[2], t_from=t_from, n=n)
    if own:
        p = traj.params
        fig.suptitle(
            f"gamma={p.gamma:.4g}, omega={p.omega:.4g}, rho={p.rho:.4g}, mu={p.mu:.4g}, d={p.d:.4g}  "
            f"({traj.summary.regime or traj.summary.motion})",
            fontsize=10,
        )
        fig.tight_layout()
    return fig, axes


def save_trajectory_figure(traj: Trajectory, path: str | os.PathLike[str], **kwargs) -> Path:
    """Draw `plot_trajectory` and save it to ``path``.

    The figure is saved by `rotorcontact.plotting.style.save_figure` (150 dpi, format from the suffix)
    and closed.

    Parameters
    ----------
    traj : Trajectory
        The motion to draw (`rotorcontact.simulate`).
    path : str or os.PathLike
        The file to write: a ``.png``, ``.svg`` or ``.pdf`` file in a folder that exists.
    **kwargs
        Passed on to `plot_trajectory`: ``axes``, ``t_from`` and ``n``.

    Returns
    -------
    pathlib.Path
        ``path``, as written.

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses (before drawing): not
        text or os.PathLike, empty or holding a NUL character, another suffix than ``.png``, ``.svg`` or
        ``.pdf``, or in a folder that does not exist; and for the arguments `plot_trajectory` refuses.
    TypeError
        For a keyword argument that `plot_trajectory` does not take.
    """
    check_figure_path(path)
    fig, _ = plot_trajectory(traj, **kwargs)
    return save_figure(fig, path)
