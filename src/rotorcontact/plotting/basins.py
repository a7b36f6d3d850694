"""Basins of attraction as a categorical image with the fraction of each class."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..model.validation import check_bool
from ..simulation.motion import canonical_regime
from ..studies.datasets import check_dataset, study_dataset
from .style import check_figure_path, draw_clearance, new_axes, save_figure

__all__ = ["plot_basins", "save_basins_figure", "CLASS_COLORS"]

#: Colours of the classes that are not named orbits.
CLASS_COLORS = {
    "outside": "#ffffff",
    "no-contact": "#c7e9c0",
    "one-impact": "#6baed6",
    "multi-impact": "#9467bd",
    "forward-rub": "#d62728",
    "backward-whirl": "#ff7f0e",
    "mixed": "#8c564b",
    "irregular": "#17becf",
    "undetermined": "#bcbd22",
    "failed": "#000000",
}
ORBIT_COLORS = ("#08519c", "#3182bd", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#1b9e77", "#7570b3")
AXIS_LABELS = {
    "x": r"Re $U(0)$",
    "y": r"Im $U(0)$",
    "amplitude": r"kick amplitude $|U'(0)|$",
    "direction": r"kick direction $\beta$ from the radial (rad)",
}
#: What the figure reads of the dataset of `rotorcontact.studies.basins.basins`.
NEEDS = ("attractor", "class_name", "fraction", "count")
NEEDS_ATTRS = ("gamma", "omega", "rho", "phi")
MADE_BY = "rotorcontact.studies.basins.basins"


def _colors(names) -> list[str]:
    out = []
    j = 0
    for name in names:
        if name in CLASS_COLORS:
            out.append(CLASS_COLORS[name])
        else:
            out.append(ORBIT_COLORS[j % len(ORBIT_COLORS)])
            j += 1
    return out


def plot_basins(ds, ax=None, *, legend: bool = True):
    """Draw the attractor reached from each grid point.

    Parameters
    ----------
    ds : BasinResult or xarray.Dataset
        Basins (`rotorcontact.studies.basins.basins`), or their ``dataset`` (as read back from a file).
    ax : matplotlib Axes, optional
    legend : bool
        Add a legend with the fraction of each class that occurs.

    Returns
    -------
    fig, ax

    Raises
    ------
    ParameterError
        If ``ds`` is not a basins dataset (another study's, or not a Dataset), ``ax`` is not an Axes or
        ``legend`` is not True or False.
    """
    ds = study_dataset(ds)
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    check_dataset(ds, NEEDS, MADE_BY, attrs=NEEDS_ATTRS)
    check_bool("legend", legend)
    fig, ax = new_axes(ax)
    # files written before the regimes were renamed hold "rub" and "rolling"
    names = [canonical_regime(str(n)) for n in ds["class_name"].values]
    codes = ds["attractor"].values
    row_dim, col_dim = ds["attractor"].dims
    x = ds[col_dim].values
    y = ds[row_dim].values

    def edges(v):
        if v.size == 1:
            return np.array([v[0] - 0.5, v[0] + 0.5])
        mid = 0.5 * (v[1:] + v[:-1])
        return np.concatenate(([v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]))

    cmap = ListedColormap(_colors(names))
    ax.pcolormesh(edges(x), edges(y), codes, cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5, rasterized=True)
    if ds.attrs.get("grid_kind") == "displacement":
        draw_clearance(ax)
        k = complex(ds.attrs["rho"] * np.exp(1j * ds.attrs["phi"])) / complex(ds.attrs["omega"] ** 2 - 1.0,
                                                                              ds.attrs["gamma"])
        if abs(k) < 1:
            ax.plot([k.real], [k.imag], marker="x", color="k", ms=6, ls="none", label="x_R")
    ax.set_xlabel(AXIS_LABELS.get(col_dim, col_dim))
    ax.set_ylabel(AXIS_LABELS.get(row_dim, row_dim))
    if legend:
        frac = ds["fraction"].values
        count = ds["count"].values
        handles = [
            Patch(facecolor=_colors(names)[i], edgecolor="0.5", label=f"{names[i]}: {100 * frac[i]:.3g}%")
            for i in range(len(names))
            if count[i] > 0 and names[i] != "outside"
        ]
        leg = ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small",
                        title="attractor (fraction)", title_fontsize="small")
        leg.set_gid("legend")
    return fig, ax


def save_basins_figure(ds, path) -> Any:
    """Write the basin image to ``path`` (.png, .svg or .pdf).

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses (before drawing), and
        for a ``ds`` that `plot_basins` refuses.
    """
    ds = study_dataset(ds)
    check_figure_path(path)
    fig, ax = plot_basins(ds)
    fig.set_size_inches(7.5, 5.5)
    a = ds.attrs
    ax.set_title(f"basins at gamma = {a['gamma']:.6g}, omega = {a['omega']:.6g}", fontsize="medium")
    return save_figure(fig, path)
