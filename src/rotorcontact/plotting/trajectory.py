"""Figures of a single trajectory: inertial frame, co-rotating frame and r(t) (paper Fig. 2 style)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..trajectory import Trajectory
from .style import draw_clearance, new_axes, save_figure


def _times(traj: Trajectory, t_from: float | None, n: int) -> np.ndarray:
    t0 = 0.0 if t_from is None else max(0.0, min(t_from, traj.t_stop))
    t = np.linspace(t0, traj.t_stop, n)
    imp = traj.impacts.t
    return np.unique(np.concatenate((t, imp[imp >= t0])))


def plot_inertial(traj: Trajectory, ax=None, *, t_from: float | None = None, n: int = 4000):
    """Rotor centre Z = U e^{it} in the inertial frame, with the clearance circle."""
    fig, ax = new_axes(ax)
    t = _times(traj, t_from, n)
    z = traj.Z(t)
    ax.plot(z.real, z.imag, lw=0.8)
    draw_clearance(ax)
    ax.set_xlabel("Re Z")
    ax.set_ylabel("Im Z")
    ax.set_title("inertial frame")
    return fig, ax


def plot_corotating(traj: Trajectory, ax=None, *, t_from: float | None = None, n: int = 4000):
    """Rotor centre U in the co-rotating frame, impacts marked, clearance circle in grey."""
    fig, ax = new_axes(ax)
    t = _times(traj, t_from, n)
    u = traj.U(t)
    ax.plot(u.real, u.imag, lw=0.8)
    imp = traj.impacts
    sel = imp.t >= t[0]
    ax.plot(imp.point.real[sel], imp.point.imag[sel], "o", ms=3, color="C3", label="impacts")
    k = traj.params.k
    ax.plot([k.real], [k.imag], "k+", ms=8, label="x_R")
    draw_clearance(ax)
    ax.set_xlabel("Re U")
    ax.set_ylabel("Im U")
    ax.set_title("co-rotating frame")
    return fig, ax


def plot_radius(traj: Trajectory, ax=None, *, t_from: float | None = None, n: int = 4000):
    """r(t) = |U(t)|, with the clearance r = 1."""
    fig, ax = new_axes(ax)
    t = _times(traj, t_from, n)
    ax.plot(t, traj.r(t), lw=0.8)
    ax.axhline(1.0, color="0.6", lw=1.5, zorder=0)
    ax.set_xlabel("t (dimensionless)")
    ax.set_ylabel("r")
    ax.set_title("radius")
    return fig, ax


def plot_trajectory(traj: Trajectory, *, t_from: float | None = None, n: int = 4000):
    """Three panels: inertial frame, co-rotating frame and r(t). Returns (fig, axes)."""
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2), gridspec_kw={"width_ratios": [1, 1, 1.6]})
    plot_inertial(traj, axes[0], t_from=t_from, n=n)
    plot_corotating(traj, axes[1], t_from=t_from, n=n)
    plot_radius(traj, axes[2], t_from=t_from, n=n)
    p = traj.params
    fig.suptitle(
        f"gamma={p.gamma:.4g}, omega={p.omega:.4g}, rho={p.rho:.4g}, mu={p.mu:.4g}, d={p.d:.4g}  "
        f"({traj.summary.motion})",
        fontsize=10,
    )
    fig.tight_layout()
    return fig, axes


def save_trajectory_figure(traj: Trajectory, path, **kwargs):
    """Draw `plot_trajectory` and save it to ``path``."""
    fig, _ = plot_trajectory(traj, **kwargs)
    return save_figure(fig, path)
