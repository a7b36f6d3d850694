"""Figure of a drop (MODEL.md §7): where the rotor hits, its spin, and the impulses over time."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..errors import ParameterError
from ..model.validation import check_float, check_int, check_type, is_pair, quoted, real_array
from ..simulation.drop import IMPACT_FIELDS
from ..simulation.drop_run import RPM, DropResult, contact_force_history
from .style import check_figure_path, check_names, draw_clearance, save_figure

__all__ = ["plot_drop", "save_drop_figure", "plot_touchdown_forces", "plot_rigid_limit"]

IMPACT_COL = {name: i for i, name in enumerate(IMPACT_FIELDS)}
#: Most contact episodes `plot_touchdown_forces` draws: one curve and one legend entry each, and ten
#: colours; twenty already fill the figure.
MAX_EPISODES = 20
#: Most samples of each episode's force: each reruns the drop to its time, and a thousand already make a
#: smooth curve of one episode.
MAX_FORCE_SAMPLES = 1000


def _check_result(result) -> DropResult:
    return check_type("result", result, DropResult, "the DropResult of rotorcontact.simulation.drop_run.drop")


def _vector(name: str, value, *, positive: bool = False, size: int | None = None) -> np.ndarray:
    """``value`` as a 1-D array of real numbers (finite and > 0 where ``positive``; ``size`` of them if given)."""
    array = real_array(value)
    ok = array is not None and array.ndim == 1 and array.size > 0 and (size is None or array.size == size)
    if ok and positive:
        ok = bool(np.all(np.isfinite(array) & (array > 0.0)))
    if not ok:
        count = "" if size is None else f"{size} "
        raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: a 1-D array of {count}real numbers"
                             f"{', finite and > 0' if positive else ''}")
    return array


def plot_drop(result: DropResult):
    """Three panels: impact points on the clearance circle (mm, coloured by time), spin (rpm) and normal
    impulse (N s) at each impact against time (s). Returns (fig, axes).

    Raises
    ------
    ParameterError
        If ``result`` is not a DropResult.
    """
    _check_result(result)
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
    """Draw `plot_drop` and save it to ``path``.

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses (before drawing), and
        for a ``result`` that `plot_drop` refuses.
    """
    check_figure_path(path)
    fig, _ = plot_drop(result)
    return save_figure(fig, path)


def plot_touchdown_forces(result: DropResult, episodes: int = 4, samples: int = 60):
    """The compliant normal force (kN) against time (ms) over the first ``episodes`` contact episodes of a
    compliant drop (MODEL.md §8), ``samples`` points each (`contact_force_history`). Returns (fig, ax).

    Raises
    ------
    ParameterError
        If ``result`` is not a DropResult of a machine with the compliant law, ``episodes`` is not an
        integer from 1 to `MAX_EPISODES` or ``samples`` not one from 3 to `MAX_FORCE_SAMPLES`.
    """
    _check_result(result)
    if not result.machine.compliant:
        raise ParameterError(f"result = {quoted(result)} is a drop with contact = {result.machine.contact!r}, "
                             "not the compliant law; allowed: a drop of a machine with contact = 'compliant'")
    episodes = check_int("episodes", episodes, 1, MAX_EPISODES)
    samples = check_int("samples", samples, 3, MAX_FORCE_SAMPLES)
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
    rate K_c^(-1/(n+1)) of MODEL.md §8 drawn through the last point of the first column. Returns (fig, ax).

    Raises
    ------
    ParameterError
        If ``stiffness`` is not a 1-D array of finite numbers > 0, ``labels`` not a list of text,
        ``differences`` not an array of real numbers of one row per stiffness and one column per label, or
        ``exponent`` not a finite number > 0.
    """
    stiffness = _vector("stiffness", stiffness, positive=True)
    labels = check_names("labels", labels, "legend texts")
    table = real_array(differences)
    if table is None or table.shape != (stiffness.size, len(labels)) or not labels:
        raise ParameterError(f"differences = {quoted(differences)} is invalid; allowed: an array of real numbers "
                             f"of shape ({stiffness.size}, {len(labels) or 'at least 1'}), a row per stiffness and a "
                             "column per label")
    exponent = check_float("exponent", exponent, 0.0, low_open=True)
    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    for k, label in enumerate(labels):
        ax.loglog(stiffness, table[:, k], "o-", ms=4, label=label)
    ref = table[-1, 0] * (stiffness / stiffness[-1]) ** (-1.0 / (exponent + 1.0))
    ax.loglog(stiffness, ref, "k--", lw=1, label=f"K_c^(-1/{exponent + 1:g})")
    ax.set_xlabel("contact stiffness K_c (N/m^n)")
    ax.set_ylabel("difference to the rigid law (relative)")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig, ax


def plot_dry_whip(damping, whirl_hz, coupled_hz, simulated=None):
    """The dry whip's whirl frequency |w|/2 pi (Hz) against the stator's support damping c_s (N s/m), with the
    coupled natural frequency it tends to (MODEL.md §8, dry whip); ``simulated`` = (c_s values, frequencies)
    from the simulator as markers (the runs that stayed on the whip). Returns (fig, ax).

    Raises
    ------
    ParameterError
        If ``damping`` is not a 1-D array of finite numbers > 0, ``whirl_hz`` not one of real numbers as
        long, ``coupled_hz`` not a finite number, or ``simulated`` neither None nor a pair of such arrays
        (damping, frequencies) of equal length.
    """
    damping = _vector("damping", damping, positive=True)
    whirl_hz = _vector("whirl_hz", whirl_hz, size=damping.size)
    coupled_hz = check_float("coupled_hz", coupled_hz)
    if simulated is not None:
        if not is_pair(simulated):
            raise ParameterError(f"simulated = {quoted(simulated)} is invalid; allowed: None or a pair "
                                 "(damping values, frequencies)")
        runs = _vector("simulated[0]", simulated[0], positive=True)
        simulated = (runs, _vector("simulated[1]", simulated[1], size=runs.size))
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
