"""Attractors against a parameter: basin fractions as stacked areas with their confidence band, and the
largest Lyapunov exponent of each attractor beneath."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..studies.datasets import check_dataset, study_dataset
from .style import check_axes, check_figure_path, save_figure

__all__ = ["plot_attractors", "save_attractors_figure"]

#: What the figure reads of the dataset of `rotorcontact.studies.attractors.attractors`.
NEEDS = ("value", "attractor", "count", "exponent", "exponent_error")
NEEDS_ATTRS = ("simulated_per_value", "param")
MADE_BY = "rotorcontact.studies.attractors.attractors"

#: Colours in order of the attractors (a qualitative palette).
COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22",
          "#7f7f7f")


def plot_attractors(ds, axes=None):
    """Draw an attractors dataset (`rotorcontact.studies.attractors.attractors`).

    The upper axes stack the basin fractions of the attractors against the parameter; at each boundary
    between two areas a band shows the confidence interval of the cumulative fraction below it
    (`rotorcontact.studies.attractors.wilson_interval` of the summed counts). The lower axes show each
    attractor's largest Lyapunov exponent where it is reached, with its error bar.

    Parameters
    ----------
    ds : AttractorsResult or xarray.Dataset
        The attractors (`rotorcontact.studies.attractors.attractors`), or their ``dataset``.
    axes : pair of matplotlib Axes, optional
        Where to draw (a new figure otherwise).

    Returns
    -------
    fig, (ax_fraction, ax_exponent)

    Raises
    ------
    ParameterError
        If ``ds`` is not an attractors dataset (another study's, or not a Dataset), or ``axes`` is neither
        None nor two Axes.
    """
    ds = study_dataset(ds)
    import matplotlib.pyplot as plt

    from ..studies.attractors import wilson_interval

    check_dataset(ds, NEEDS, MADE_BY, attrs=NEEDS_ATTRS)
    axes = check_axes(axes, 2, "basin fractions, exponents")
    if axes is None:
        fig, axes = plt.subplots(2, 1, sharex=True, figsize=(8, 6.5), gridspec_kw={"height_ratios": [2, 1]})
    ax_f, ax_l = axes
    fig = ax_f.figure
    x = ds["value"].values
    names = [str(n) for n in ds["attractor"].values]
    count = ds["count"].values
    n_total = int(ds.attrs["simulated_per_value"])
    below = np.zeros(x.size, dtype=np.int64)
    for j, name in enumerate(names):
        color = COLORS[j % len(COLORS)]
        top = below + count[:, j]
        ax_f.fill_between(x, below / n_total, top / n_total, color=color, alpha=0.75, lw=0, label=name)
        if j < len(names) - 1:
            low, high = wilson_interval(top, n_total)
            ax_f.fill_between(x, low, high, color="k", alpha=0.18, lw=0)
        below = top
        on = count[:, j] > 0
        if on.any():
            lam = np.where(on, ds["exponent"].values[:, j], np.nan)
            err = np.where(on, ds["exponent_error"].values[:, j], np.nan)
            ax_l.errorbar(x, lam, yerr=np.where(np.isfinite(err), err, 0.0), color=color, marker=".", ms=4, lw=1,
                          capsize=2, label=name)
    ax_f.set_ylim(0.0, 1.0)
    ax_f.set_xlim(x[0], x[-1]) if x.size > 1 else None
    ax_f.set_ylabel("basin fraction")
    ax_f.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", title="attractor",
                title_fontsize="small")
    ax_l.axhline(0.0, color="0.6", lw=0.8)
    ax_l.set_ylabel("largest Lyapunov exponent")
    unit = ds["value"].attrs.get("units", "1")
    ax_l.set_xlabel(f"{ds.attrs['param']}" + (f" ({unit})" if unit != "1" else ""))
    return fig, (ax_f, ax_l)


def save_attractors_figure(ds, path) -> Path:
    """Write the attractors figure to ``path`` (.png, .svg or .pdf).

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses (before drawing), and
        for a ``ds`` that `plot_attractors` refuses.
    """
    ds = study_dataset(ds)
    check_figure_path(path)
    fig, (ax_f, _ax_l) = plot_attractors(ds)
    band = round(100 * float(ds.attrs.get("confidence", 0.95)))
    ax_f.set_title(f"attractors against {ds.attrs['param']} (grey: {band}% confidence bands)", fontsize="medium")
    return save_figure(fig, path)
