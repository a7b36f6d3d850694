"""Figures of design maps: regimes against speed (rpm) or over a plane of settings."""

from __future__ import annotations

from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

from ..studies.design_map import OUTCOMES, DesignMap, rpm_to_rad_s
from ..analysis.equilibria import boundary_gamma
from ..errors import ParameterError
from ..model.validation import check_type, quoted
from .style import check_figure_path, new_axes, save_figure

if TYPE_CHECKING:
    import os
    from pathlib import Path

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_speed_regimes", "plot_operating_line", "plot_plane", "plot_speed_recovery", "plot_plane_recovery",
           "plot_design_map", "save_design_map", "REGIME_COLORS"]

#: Colour of each outcome of a design map (`rotorcontact.studies.design_map.OUTCOMES`).
REGIME_COLORS = {"safe": "#4daf4a", "bistable": "#ffbf00", "contact-certain": "#e41a1c"}
_LABELS = {"speed_rpm": "speed (rpm)", "stiffness": "bearing stiffness k (N/m)", "damping": "bearing damping c (N s/m)"}
_KINDS = {1: "a speed map (speed_map)", 2: "a plane map (plane_map)"}


def _check_map(dmap, settings: int | None = None, shock: bool = False) -> DesignMap:
    """``dmap`` if it is a `DesignMap` over ``settings`` settings (any where None), computed with a shock
    where ``shock``; a `ParameterError` naming it otherwise."""
    check_type("dmap", dmap, DesignMap, "a rotorcontact.studies.design_map.DesignMap (speed_map or plane_map)")
    if (settings is not None and len(dmap.axes) != settings) or (shock and dmap.shock is None):
        want = _KINDS[settings] if settings is not None else "a design map"
        want += " computed with a shock" if shock else ""
        raise ParameterError(f"dmap = {quoted(dmap)} is a map over {', '.join(dmap.axes)} "
                             f"{'without' if dmap.shock is None else 'with'} a shock; allowed: {want}")
    return dmap


def _legend(ax) -> None:
    ax.legend(
        handles=[Patch(color=REGIME_COLORS[r], alpha=0.5, label=r) for r in OUTCOMES],
        loc="upper right",
        fontsize=8,
    )


def plot_speed_regimes(dmap: DesignMap, ax: Axes | None = None) -> tuple[Figure, Axes]:
    """Regimes against speed, shaded, with the contact-free whirl amplitude and the clearance (micrometres).

    The forced whirl |k| c_r of each speed is drawn dashed, for comparison.

    Parameters
    ----------
    dmap : DesignMap
        A map over speed alone (`rotorcontact.studies.design_map.speed_map`).
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ParameterError
        If ``dmap`` is not a DesignMap or is a map over two settings (not a speed map, `speed_map`), or
        ``ax`` is neither None nor an Axes (both checked before anything is drawn).
    """
    _check_map(dmap, 1)
    fig, ax = new_axes(ax, figsize=(8, 4))
    speeds = dmap.values[0]
    edges = np.concatenate(([speeds[0]], 0.5 * (speeds[1:] + speeds[:-1]), [speeds[-1]]))
    for pt, a, b in zip(dmap.points, edges[:-1], edges[1:]):
        ax.axvspan(a, b, color=REGIME_COLORS[pt.regime], alpha=0.35, lw=0)
    amp = [next((m.amplitude_um for m in pt.motions if m.name == "x_R"), np.nan) for pt in dmap.points]
    k_abs = [abs(dmap.machine.with_speed(rpm_to_rad_s(s)).parameters().k) for s in speeds]
    ax.plot(speeds, np.array(k_abs) * dmap.machine.clearance * 1e6, "k--", lw=1, label="forced whirl |k| c_r")
    ax.plot(speeds, amp, "k-", lw=2, label="contact-free whirl (admissible)")
    ax.axhline(dmap.machine.clearance * 1e6, color="0.4", lw=1.5, label="clearance")
    ax.set_xlim(speeds[0], speeds[-1])
    ax.set_ylim(0, 2.0 * dmap.machine.clearance * 1e6)
    ax.set_xlabel("speed (rpm)")
    ax.set_ylabel("whirl amplitude (µm)")
    handles, labels = ax.get_legend_handles_labels()
    handles += [Patch(color=REGIME_COLORS[r], alpha=0.5) for r in OUTCOMES]
    labels += list(OUTCOMES)
    ax.legend(handles, labels, fontsize=8, loc="upper left")
    ax.set_title("regimes against speed")
    return fig, ax


def plot_operating_line(dmap: DesignMap, ax: Axes | None = None) -> tuple[Figure, Axes]:
    """The speed run-up as a curve in the (gamma, omega) plane, over the boundary-equilibrium curve.

    Each point of the map is marked in the colour of its regime, and the machine's own operating point
    with a star.

    Parameters
    ----------
    dmap : DesignMap
        A design map (`rotorcontact.studies.design_map.speed_map` or
        `rotorcontact.studies.design_map.plane_map`), with or without a shock.
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ParameterError
        If ``dmap`` is not a DesignMap or ``ax`` is neither None nor an Axes (both checked before anything is drawn).
    """
    _check_map(dmap)
    fig, ax = new_axes(ax, figsize=(5, 4))
    p0 = dmap.machine.parameters()
    omegas = np.linspace(1e-3, 1.5, 600)
    g_star = [boundary_gamma(p0.replace(omega=w)) for w in omegas]
    g_star = np.array([np.nan if g is None else g for g in g_star])
    ax.plot(g_star, omegas, "k-", lw=1.5, label="γ* (x_R on the stator)")
    gam = np.array([pt.gamma for pt in dmap.points])
    om = np.array([pt.omega for pt in dmap.points])
    ax.plot(gam, om, "-", color="0.5", lw=1, zorder=1)
    for regime in OUTCOMES:
        sel = np.array([pt.regime == regime for pt in dmap.points])
        if sel.any():
            ax.plot(gam[sel], om[sel], "o", ms=3, color=REGIME_COLORS[regime], label=regime, zorder=2)
    ref = dmap.machine.parameters()
    rpm = dmap.machine.speed * 60 / (2 * np.pi)
    ax.plot([ref.gamma], [ref.omega], "k*", ms=10, label=f"operating point ({rpm:.0f} rpm)")
    ax.set_xlabel("γ = c / (m Ω)")
    ax.set_ylabel("ω = √(k / m) / Ω")
    ax.set_xlim(0, max(0.5, 1.1 * np.nanmax(gam)))
    ax.set_ylim(0, max(1.5, 1.1 * np.nanmax(om)))
    ax.legend(fontsize=7)
    ax.set_title("operating line")
    return fig, ax


def plot_plane(dmap: DesignMap, ax: Axes | None = None) -> tuple[Figure, Axes]:
    """Regimes over a plane of two settings, with the machine's own setting marked.

    Parameters
    ----------
    dmap : DesignMap
        A map over two settings (`rotorcontact.studies.design_map.plane_map`).
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ParameterError
        If ``dmap`` is not a DesignMap or is a map over one setting (not a plane map, `plane_map`), or
        ``ax`` is neither None nor an Axes (both checked before anything is drawn).
    """
    _check_map(dmap, 2)
    fig, ax = new_axes(ax, figsize=(6, 4.5))
    a, b = dmap.values
    codes = dmap.regime_codes().T
    cmap = ListedColormap([REGIME_COLORS[r] for r in OUTCOMES])
    ax.pcolormesh(a, b, codes, cmap=cmap, vmin=-0.5, vmax=len(OUTCOMES) - 0.5, shading="nearest", alpha=0.75)
    m = dmap.machine
    own = {"speed_rpm": m.speed * 60 / (2 * np.pi), "stiffness": m.stiffness, "damping": m.damping}
    ax.plot([own[dmap.axes[0]]], [own[dmap.axes[1]]], "k*", ms=12, label="machine setting")
    ax.set_xlabel(_LABELS[dmap.axes[0]])
    ax.set_ylabel(_LABELS[dmap.axes[1]])
    _legend(ax)
    ax.set_title("regimes")
    return fig, ax


def _recovery(dmap: DesignMap) -> np.ndarray:
    """Recovery probability of each point in percent (NaN where it was not computed), shaped like the grid."""
    return np.array([np.nan if pt.recovery_probability is None else 100.0 * pt.recovery_probability
                     for pt in dmap.points]).reshape(dmap.shape)


def _shock_text(dmap: DesignMap) -> str:
    return f"recovery after a {1e3 * dmap.shock:.3g} mm/s shock (%)"


def plot_speed_recovery(dmap: DesignMap, ax: Axes | None = None) -> tuple[Figure, Axes]:
    """Recovery probabilities of the bistable speeds (%), as points against speed.

    With ``ax`` (for example a twin of the axes of `plot_speed_regimes`) they are drawn there.
    Speeds whose probability was not computed are left blank.

    Parameters
    ----------
    dmap : DesignMap
        A map over speed alone computed with a shock (`rotorcontact.studies.design_map.speed_map` with
        ``shock``).
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ParameterError
        If ``dmap`` is not a DesignMap, is a map over two settings or was computed without a shock (not a
        speed map computed with a shock), or ``ax`` is neither None nor an Axes (both checked before anything is drawn).
    """
    _check_map(dmap, 1, shock=True)
    fig, ax = new_axes(ax, figsize=(8, 4))
    ax.plot(dmap.values[0], _recovery(dmap), "o", color="#377eb8", ms=4, gid="recovery", label="recovery (%)")
    ax.set_ylim(-5, 105)
    ax.set_ylabel(_shock_text(dmap), color="#377eb8")
    return fig, ax


def plot_plane_recovery(dmap: DesignMap, ax: Axes | None = None) -> tuple[Figure, Axes]:
    """Recovery probabilities (%) of the bistable settings of a plane; blank elsewhere.

    A colour bar is added beside ``ax``.

    Parameters
    ----------
    dmap : DesignMap
        A map over two settings computed with a shock (`rotorcontact.studies.design_map.plane_map` with
        ``shock``).
    ax : matplotlib.axes.Axes, optional
        Where to draw; without it a figure of its own is made.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The figure drawn in (that of ``ax`` where given).
    ax : matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ParameterError
        If ``dmap`` is not a DesignMap, is a map over one setting or was computed without a shock (not a
        plane map computed with a shock), or ``ax`` is neither None nor an Axes (both checked before anything is drawn).
    """
    _check_map(dmap, 2, shock=True)
    fig, ax = new_axes(ax, figsize=(6, 4.5))
    a, b = dmap.values
    mesh = ax.pcolormesh(a, b, _recovery(dmap).T, cmap="viridis", vmin=0.0, vmax=100.0, shading="nearest")
    mesh.set_gid("recovery")
    fig.colorbar(mesh, ax=ax, label=_shock_text(dmap))
    ax.set_xlabel(_LABELS[dmap.axes[0]])
    ax.set_ylabel(_LABELS[dmap.axes[1]])
    ax.set_title("recovery of the bistable settings")
    return fig, ax


def plot_design_map(dmap: DesignMap) -> tuple[Figure, np.ndarray | Axes]:
    """The figure written by ``design-map``: regimes and operating line for speed maps, the plane otherwise.

    With recovery probabilities (``--shock``) they are drawn too: on a second axis against speed,
    or as a second panel beside the plane.

    Parameters
    ----------
    dmap : DesignMap
        A design map (`rotorcontact.studies.design_map.speed_map` or
        `rotorcontact.studies.design_map.plane_map`), with or without a shock.

    Returns
    -------
    fig : matplotlib.figure.Figure
        A new figure.
    axes : numpy.ndarray of matplotlib.axes.Axes, or matplotlib.axes.Axes
        The panels: an array of two (`plot_speed_regimes` and `plot_operating_line` for a speed map,
        `plot_plane` and `plot_plane_recovery` for a plane map with a shock), or the single Axes of
        `plot_plane` for a plane map without a shock. The second axis of the recovery against speed is
        a twin of ``axes[0]``, not among them.

    Raises
    ------
    ParameterError
        If ``dmap`` is not a DesignMap.
    """
    _check_map(dmap)
    if len(dmap.axes) == 1:
        fig, axes = plt.subplots(1, 2, figsize=(13, 4.5), gridspec_kw={"width_ratios": [1.7, 1]})
        plot_speed_regimes(dmap, axes[0])
        plot_operating_line(dmap, axes[1])
        if dmap.shock is not None:
            plot_speed_recovery(dmap, axes[0].twinx())
    elif dmap.shock is not None:
        fig, axes = plt.subplots(1, 2, figsize=(13, 5))
        plot_plane(dmap, axes[0])
        plot_plane_recovery(dmap, axes[1])
    else:
        fig, axes = plt.subplots(1, 1, figsize=(7, 5))
        plot_plane(dmap, axes)
    fig.tight_layout()
    return fig, axes


def save_design_map(dmap: DesignMap, path: str | os.PathLike[str]) -> Path:
    """Draw `plot_design_map` and save it.

    The figure is saved by `rotorcontact.plotting.style.save_figure` (150 dpi, format from the suffix)
    and closed.

    Parameters
    ----------
    dmap : DesignMap
        A design map (`rotorcontact.studies.design_map.speed_map` or
        `rotorcontact.studies.design_map.plane_map`), with or without a shock.
    path : str or os.PathLike
        The file to write: a ``.png``, ``.svg`` or ``.pdf`` file in a folder that exists.

    Returns
    -------
    pathlib.Path
        ``path``, as written.

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses (before drawing): not
        text or os.PathLike, empty or holding a NUL character, another suffix than ``.png``, ``.svg`` or
        ``.pdf``, or in a folder that does not exist; and for a ``dmap`` that `plot_design_map` refuses
        (not a DesignMap).
    """
    check_figure_path(path)
    fig, _ = plot_design_map(dmap)
    return save_figure(fig, path)
