"""Figure of a drop (MODEL.md §7): where the rotor hits, its spin, and the impulses over time."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..simulation.drop_run import RPM, DropResult
from .style import draw_clearance, save_figure

__all__ = ["plot_drop", "save_drop_figure"]


def plot_drop(result: DropResult):
    """Three panels: impact points on the clearance circle (mm, coloured by time), spin (rpm) and normal
    impulse (N s) at each impact against time (s). Returns (fig, axes)."""
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 4.2))
    ax0, ax1, ax2 = axes
    cr_mm = result.machine.clearance * 1e3
    draw_clearance(ax0, cr_mm)
    t = result.column("t_s")
    if t.size:
        pts = ax0.scatter(result.column("x_m") * 1e3, result.column("y_m") * 1e3, c=t, s=10, cmap="viridis")
        fig.colorbar(pts, ax=ax0, label="time (s)")
        spins = np.concatenate(([result.speed], result.column("spin_after"))) / RPM
        ax1.step(np.concatenate(([0.0], t)), spins, where="post", color="C0", label="rotor")
        if result.machine.has_race:
            ax1.plot(t, result.column("race_after") / RPM, "o", ms=2, color="C1", label="race (after impacts)")
        ax1.legend(loc="best")
        ax2.semilogy(t, result.column("normal_impulse_Ns"), ".", ms=3, color="C3")
    ax0.set_xlabel("x (mm)")
    ax0.set_ylabel("y (mm)")
    ax0.set_title("impact points")
    ax1.set_xlabel("time (s)")
    ax1.set_ylabel("spin (rpm)")
    ax1.set_title(f"spin; bearing fails at {result.fail_at:g} s")
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("normal impulse (N s)")
    ax2.set_title(f"{len(t)} impacts, {result.status}")
    fig.tight_layout()
    return fig, axes


def save_drop_figure(result: DropResult, path):
    """Draw `plot_drop` and save it to ``path``."""
    fig, _ = plot_drop(result)
    return save_figure(fig, path)
