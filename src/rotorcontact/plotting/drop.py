"""Figure of a drop (MODEL.md §7): where the rotor hits, its spin, and the impulses over time."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..simulation.drop import IMPACT_FIELDS
from ..simulation.drop_run import RPM, DropResult, contact_force_history
from .style import draw_clearance, save_figure

__all__ = ["plot_drop", "save_drop_figure", "plot_touchdown_forces", "plot_rigid_limit"]

IMPACT_COL = {name: i for i, name in enumerate(IMPACT_FIELDS)}


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


def plot_touchdown_forces(result: DropResult, episodes: int = 4, samples: int = 60):
    """The compliant normal force (kN) against time (ms) over the first ``episodes`` contact episodes of a
    compliant drop (MODEL.md §8), ``samples`` points each (`contact_force_history`). Returns (fig, ax)."""
    fig, ax = plt.subplots(figsize=(8.0, 4.0))
    rows = result.impacts[:episodes]
    for k, row in enumerate(rows):
        t0 = row[0]
        dur = row[IMPACT_COL["duration_s"]]
        times = t0 + dur * np.linspace(0.0, 1.0, samples)[1:-1]
        forces = contact_force_history(result.machine, result.speed, result.fail_at, times)
        ax.plot(np.concatenate(([t0], times, [t0 + dur])) * 1e3, np.concatenate(([0.0], forces, [0.0])) * 1e-3,
                color=f"C{k % 10}", label=f"{row[IMPACT_COL['normal_velocity_m_per_s']]:.3g} m/s, peak "
                f"{row[IMPACT_COL['max_force_N']] * 1e-3:.3g} kN")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("normal force (kN)")
    ax.set_title(f"first touchdowns, K_c = {result.machine.contact_stiffness:.3g} N/m^{result.machine.exponent:g}, "
                 f"d = {result.machine.restitution:g}")
    if len(rows):
        ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig, ax


def plot_rigid_limit(stiffness, differences, labels, exponent: float = 1.5):
    """Differences to the rigid law (one column per quantity, ``labels``) against K_c on log axes, with the
    rate K_c^(-1/(n+1)) of MODEL.md §8 drawn through the last point of the first column. Returns (fig, ax)."""
    stiffness = np.asarray(stiffness, dtype=float)
    differences = np.asarray(differences, dtype=float)
    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    for k, label in enumerate(labels):
        ax.loglog(stiffness, differences[:, k], "o-", ms=4, label=label)
    ref = differences[-1, 0] * (stiffness / stiffness[-1]) ** (-1.0 / (exponent + 1.0))
    ax.loglog(stiffness, ref, "k--", lw=1, label=f"K_c^(-1/{exponent + 1:g})")
    ax.set_xlabel("contact stiffness K_c (N/m^n)")
    ax.set_ylabel("difference to the rigid law (relative)")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig, ax


def plot_dry_whip(damping, whirl_hz, coupled_hz, simulated=None):
    """The dry whip's whirl frequency |w|/2 pi (Hz) against the stator's support damping c_s (N s/m), with the
    coupled natural frequency it tends to (MODEL.md §8, dry whip); ``simulated`` = (c_s values, frequencies)
    from the simulator as markers (the runs that stayed on the whip). Returns (fig, ax)."""
    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    ax.semilogx(damping, np.abs(whirl_hz), "-", label="steady dry whip (Im G = mu Re G)")
    ax.axhline(coupled_hz, color="k", ls="--", lw=1, label="coupled natural frequency")
    if simulated is not None:
        ax.semilogx(simulated[0], np.abs(simulated[1]), "o", ms=5, mfc="none",
                    label="simulated from it, where it holds (mean whirl)")
    ax.set_xlabel("stator support damping c_s (N s/m)")
    ax.set_ylabel("backward whirl frequency (Hz)")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig, ax
