"""Figure of a drop map: regime, onset of backward whirl and peak impulse over speed and friction."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import BoundaryNorm, ListedColormap

from ..studies.datasets import check_dataset, study_dataset
from .style import check_figure_path, save_figure

__all__ = ["plot_drop_map", "save_drop_map_figure"]

_REGIME_COLORS = ("#9ecae1", "#fdd0a2", "#a1d99b", "#de2d26", "#000000")  # failed: black
#: What the figure reads of the dataset of `rotorcontact.studies.drop_map.drop_map`.
NEEDS = ("speed_rpm", "friction", "regime", "backward_whirl_onset_s", "max_normal_impulse_Ns")
NEEDS_ATTRS = ("regimes", "fail_at_s", "t_end_s")
MADE_BY = "rotorcontact.studies.drop_map.drop_map"


def plot_drop_map(ds):
    """Three panels over (speed, friction): the regime after the drop, the onset of backward whirl (s)
    and the peak normal impulse (N s); over speed alone where the map has one friction coefficient.
    Returns (fig, axes).

    Raises
    ------
    ParameterError
        If ``ds`` is not a drop map's dataset (another study's, or not a Dataset).
    """
    ds = study_dataset(ds)
    check_dataset(ds, NEEDS, MADE_BY, attrs=NEEDS_ATTRS)
    regimes = ds.attrs["regimes"].split(",")
    speed = ds["speed_rpm"].values
    mu = ds["friction"].values
    fig, axes = plt.subplots(1, 3, figsize=(14.0, 4.2))
    cmap = ListedColormap(_REGIME_COLORS[: len(regimes)])
    norm = BoundaryNorm(np.arange(len(regimes) + 1) - 0.5, cmap.N)
    panels = [("regime", "regime after the drop"), ("backward_whirl_onset_s", "onset of backward whirl (s)"),
              ("max_normal_impulse_Ns", "peak normal impulse (N s)")]
    for ax, (name, title) in zip(axes, panels):
        values = ds[name].values
        ax.set_xlabel("speed at failure (rpm)")
        if mu.size == 1:  # a single row of cells has no height to draw: the values over speed
            ax.set_title(f"{title}, friction {mu[0]:g}")
            if name == "regime":
                ax.scatter(speed, values[0], c=values[0], cmap=cmap, norm=norm, edgecolors="k", zorder=2)
                ax.set_yticks(range(len(regimes)), regimes)
                ax.set_ylim(-0.5, len(regimes) - 0.5)
            else:
                ax.plot(speed, values[0], "o-")
            continue
        ax.set_title(title)
        ax.set_ylabel("friction coefficient")
        if name == "regime":
            mesh = ax.pcolormesh(speed, mu, values, cmap=cmap, norm=norm, shading="nearest")
            bar = fig.colorbar(mesh, ax=ax, ticks=range(len(regimes)))
            bar.ax.set_yticklabels(regimes)
        else:
            mesh = ax.pcolormesh(speed, mu, np.ma.masked_invalid(values), cmap="viridis", shading="nearest")
            fig.colorbar(mesh, ax=ax)
    fig.suptitle(f"drop map: bearing fails at {ds.attrs['fail_at_s']:g} s, followed to {ds.attrs['t_end_s']:g} s")
    fig.tight_layout()
    return fig, axes


def save_drop_map_figure(ds, path):
    """Draw `plot_drop_map` and save it to ``path``.

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses (before drawing), and
        for a ``ds`` that `plot_drop_map` refuses.
    """
    ds = study_dataset(ds)
    check_figure_path(path)
    fig, _ = plot_drop_map(ds)
    return save_figure(fig, path)
