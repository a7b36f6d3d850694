"""Brute-force orbit diagrams: the impact section against the swept parameter.

Each recorded impact is a dot at (parameter value, section variable), one
colour per direction (up, down), so hysteresis shows where the colours part.
The one-impact orbits can be overlaid, either as continued branches
(`rotorcontact.continuation.branches.OrbitBranches`, with their bifurcations marked) or
as the fixed points computed at each value (`rotorcontact.studies.sweep.one_impact_overlay`):
solid where stable, dashed where unstable, admissible orbits only. A strip
under the diagram shows the regime of each direction at each value (forward rub
and backward whirl have no impacts to plot).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..studies.batch import REGIME_NAMES
from ..errors import ParameterError
from ..model.validation import check_choice, check_float, check_type, quoted
from ..studies.datasets import check_dataset, study_dataset
from .style import check_figure_path, new_axes, save_figure, style_runs

__all__ = ["plot_sweep", "plot_regimes", "save_sweep_figure", "SECTION_LABELS", "REGIME_COLORS"]

SECTION_LABELS = {
    "theta": r"impact angle $\theta$",
    "rdot": r"$\dot r^-$ at impact",
    "thetadot": r"$\dot\theta^-$ at impact",
}
PARAM_LABELS = {
    "gamma": r"$\gamma$", "omega": r"$\omega$", "rho": r"$\rho$", "mu": r"$\mu$", "d": r"$d$",
    "phi": r"$\phi$", "r_ratio": r"$R/c_r$",
}
DIRECTION_COLORS = {"up": "C0", "down": "C3", "independent": "k"}
#: Colours of the overlaid orbits (distinct from the directions' colours).
ORBIT_COLORS = ("C2", "C4", "C5", "C6", "C8", "C9", "C1", "C7")
#: Colour of each regime in the strip.
REGIME_COLORS = {
    "no-contact": "#d9d9d9",
    "periodic-impacting": "#1f77b4",
    "irregular-impacting": "#9467bd",
    "forward-rub": "#d62728",
    "backward-whirl": "#ff7f0e",
    "mixed": "#8c564b",
    "undetermined": "#bcbd22",
    "failed": "#000000",
}


#: The functions whose datasets the figures draw: the sweep, and the fixed points overlaid on it.
MADE_BY = "rotorcontact.studies.sweep.sweep"
OVERLAY_MADE_BY = "rotorcontact.studies.sweep.one_impact_overlay"
#: What an overlay may be, in words.
OVERLAY_KINDS = ("rotorcontact.continuation.branches.OrbitBranches, "
                 "rotorcontact.continuation.multi_impact_families.MultiImpactBranches or the Dataset of "
                 f"{OVERLAY_MADE_BY}")


def _param(ds, *needs: str) -> str:
    """The swept parameter of the sweep ``ds``, once ``ds`` is checked to be a sweep holding ``needs``."""
    check_dataset(ds, ("direction", *needs), MADE_BY, attrs=("swept_parameter",))
    param = str(ds.attrs["swept_parameter"])
    check_dataset(ds, (param,), MADE_BY)
    return param


def _layers(overlay, param: str, variable: str) -> list:
    """The layers of ``overlay`` (None, one layer, or a list or tuple of them), each checked to be one of
    `OVERLAY_KINDS` over the swept parameter ``param``."""
    if overlay is None:
        return []
    import xarray as xr

    from ..continuation.multi_impact_families import MultiImpactBranches
    from ..continuation.results import OrbitBranches

    many = isinstance(overlay, (list, tuple))
    layers = list(overlay) if many else [overlay]
    for i, layer in enumerate(layers):
        name = f"overlay[{i}]" if many else "overlay"
        check_type(name, layer, (OrbitBranches, MultiImpactBranches, xr.Dataset), OVERLAY_KINDS)
        if isinstance(layer, xr.Dataset):
            check_dataset(layer, (param, "orbit", variable, "admissible", "stable"), OVERLAY_MADE_BY, name=name)
        elif layer.param != param:
            raise ParameterError(f"{name} = {quoted(layer)} follows {layer.param!r}; allowed: branches over the "
                                 f"swept parameter {param!r}")
    return layers


def _check_cascades(cascades) -> None:
    if not isinstance(cascades, (list, tuple)):
        raise ParameterError(f"cascades = {quoted(cascades)} is invalid; allowed: a list or tuple of "
                             "rotorcontact.continuation.cascade.Cascade")
    if cascades:
        from ..continuation.cascade import Cascade

        for i, c in enumerate(cascades):
            check_type(f"cascades[{i}]", c, Cascade, "a rotorcontact.continuation.cascade.Cascade")


def _check_sweep(ds, variable, overlay, markersize, cascades) -> tuple[str, list]:
    """The checks of `plot_sweep`; returns the swept parameter and the overlay's layers."""
    check_choice("variable", variable, tuple(SECTION_LABELS))
    param = _param(ds, variable)
    layers = _layers(overlay, param, variable)
    check_float("markersize", markersize, 0.0, low_open=True)
    _check_cascades(cascades)
    return param, layers


def plot_sweep(ds, variable: str = "theta", ax=None, *, overlay=None, markersize: float = 2.0, cascades=()):
    """Draw the impact section of a sweep.

    Parameters
    ----------
    ds : SweepResult or xarray.Dataset
        A sweep (`rotorcontact.studies.sweep.sweep`), or its ``dataset`` (as read back from a file).
    variable : {"theta", "rdot", "thetadot"}
        Section variable.
    ax : matplotlib Axes, optional
    overlay : OrbitBranches, MultiImpactBranches or xarray.Dataset, or a list of them, optional
        Continued branches of one-impact orbits (`rotorcontact.studies.sweep.continued_branches`),
        fixed points (`rotorcontact.studies.sweep.one_impact_overlay`), or continued branches of
        multi-impact orbits (`rotorcontact.continuation.multi_impact_families.multi_impact_branches`):
        every impact of their orbits is drawn, solid where stable, dashed where not.
    markersize : float
    cascades : sequence of Cascade
        Period-doubling cascades (`rotorcontact.continuation.cascade.cascades`) whose doublings are
        marked: the impacts of the orbit that doubles, at each doubling.

    Returns
    -------
    fig, ax

    Raises
    ------
    ParameterError
        If ``ds`` is not a sweep's dataset (another study's, or not a Dataset), ``variable`` is not a
        section variable, ``ax`` is not an Axes, a layer of ``overlay`` is not one of `OVERLAY_KINDS` over
        the swept parameter, ``markersize`` is not a number > 0 or ``cascades`` is not a list of Cascade.
    """
    ds = study_dataset(ds)
    param, layers = _check_sweep(ds, variable, overlay, markersize, cascades)
    fig, ax = new_axes(ax)
    _draw_sweep(ax, ds, param, variable, layers, markersize, cascades)
    return fig, ax


def _draw_sweep(ax, ds, param: str, variable: str, layers: list, markersize: float, cascades) -> None:
    values = ds[param].values
    for d in ds.direction.values:
        d = str(d)
        y = ds[variable].sel(direction=d).values
        x = np.broadcast_to(values[:, None], y.shape)
        ok = np.isfinite(y)
        ax.plot(x[ok], y[ok], ls="none", marker=".", ms=markersize, color=DIRECTION_COLORS.get(d, "k"),
                alpha=0.7, label=f"sweep {d}", gid=f"section:{d}", rasterized=True, zorder=3)
    for ov in layers:
        if hasattr(ov, "depth"):
            _draw_multi_branches(ax, ov, variable)
        elif hasattr(ov, "branch"):
            _draw_branches(ax, ov, variable)
        else:
            _draw_overlay(ax, ov, param, variable)
    _draw_cascades(ax, cascades, variable)
    ax.set_xlabel(PARAM_LABELS.get(param, param))
    ax.set_ylabel(SECTION_LABELS[variable])
    ax.set_xlim(values.min(), values.max()) if values.size > 1 else None
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        leg = ax.legend(loc="best", fontsize="small", markerscale=6)
        leg.set_gid("legend")


def _draw_overlay(ax, overlay, param: str, variable: str) -> None:
    x = overlay[param].values
    for j, label in enumerate(overlay.orbit.values):
        label = str(label)
        y = overlay[variable].values[:, j]
        adm = overlay["admissible"].values[:, j].astype(bool) & np.isfinite(y)
        stable = overlay["stable"].values[:, j].astype(bool)
        first = True
        for want, ls in ((True, "-"), (False, "--")):
            sel = adm & (stable == want)
            if not sel.any():
                continue
            yy = np.where(sel, y, np.nan)
            ax.plot(x, yy, ls=ls, lw=0.9, color=ORBIT_COLORS[j % len(ORBIT_COLORS)], zorder=2,
                    gid=f"orbit:{label}:{'stable' if want else 'unstable'}",
                    label=f"{label} (fixed points)" if first else None)
            first = False


#: Bifurcations marked on a diagram with continued branches.
MARKED_EVENTS = {"fold": "fold", "period-doubling": "PD", "neimark-sacker": "NS", "grazing": "graze",
                 "branch-point": "BP", "nsfh": "NSFH"}


#: Name and line style of a continued one-impact orbit on a sweep, by its points' style
#: (`rotorcontact.plotting.branches.point_style`; virtual points are not drawn).
_BRANCH_STYLES = {"plausible-stable": ("stable", "-"), "plausible-unstable": ("unstable", "--"),
                  "implausible": ("implausible", ":")}


def _draw_branches(ax, branches, variable: str) -> None:
    from ..continuation.branches import refine_branches
    from .branches import REFINED_POINTS, point_style

    lo, hi = branches.start, branches.stop
    # beside a bifurcation the continuation's steps are coarse: refined, the runs of each kind meet there
    branches = refine_branches(branches, (lo, hi), REFINED_POINTS)
    for j, label in enumerate(branches.labels):
        b = branches.branch(label)
        y = getattr(b, variable)
        color = ORBIT_COLORS[j % len(ORBIT_COLORS)]
        first = True
        for sl in b.pieces():
            idx = np.arange(sl.start, sl.stop)
            styles = [point_style(b, i) for i in idx]
            # a run of one style ends on the first point of the next (no gap), not on a virtual one
            for style, start, stop in style_runs(styles, lambda key, following: following != "virtual"):
                if style == "virtual":
                    continue
                kind, ls = _BRANCH_STYLES[style]
                run = idx[start:stop]
                ax.plot(b.values[run], y[run], ls=ls, lw=0.9, color=color, zorder=2,
                        gid=f"branch:{label}:{kind}", label=f"{label} (continued)" if first else None)
                first = False
    # events at one value (the NSFH of B1,a and B1,b) get one mark, naming every orbit
    marks: dict[tuple[str, float], list[str]] = {}
    for e in branches.events:
        if e.type in MARKED_EVENTS and e.rdot > 0 and lo <= e.value <= hi:
            marks.setdefault((e.type, round(e.value, 12)), []).extend(e.orbits)
    for (kind, value), orbits in marks.items():
        ax.axvline(value, color="0.5", lw=0.6, ls=":", zorder=1, gid=f"event:{kind}")
        ax.annotate(f"{MARKED_EVENTS[kind]} {', '.join(dict.fromkeys(orbits))}", (value, 1.0),
                    xycoords=("data", "axes fraction"), rotation=90, va="top", ha="right", fontsize="x-small",
                    color="0.35", bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.8), zorder=3)


def _draw_multi_branches(ax, family, variable: str) -> None:
    """Every impact of the orbits along each continued multi-impact branch (solid stable, dashed unstable)."""
    for j, b in enumerate(family.branches):
        if not b.orbits:
            continue
        label = b.orbits[0].label
        color = ORBIT_COLORS[(j + 3) % len(ORBIT_COLORS)]
        y = np.array([[getattr(q, variable) for q in o.points] for o in b.orbits])
        stable = np.array([o.stable for o in b.orbits])
        first = True
        for want, ls in ((True, "-"), (False, "--")):
            if not np.any(stable == want):
                continue
            yy = np.where((stable == want)[:, None], y, np.nan)
            ax.plot(b.values, yy, ls=ls, lw=0.8, color=color, zorder=2,
                    gid=f"multi:{label}:{'stable' if want else 'unstable'}")
            if first:
                ax.plot([], [], ls=ls, lw=0.8, color=color, label=f"{label} (continued)")
                first = False


def _draw_cascades(ax, cascades, variable: str) -> None:
    """The doublings of each cascade: a marker at every impact of the orbit that doubles there."""
    first = True
    for c in cascades:
        for e in c.points:
            if e.orbit is None:
                continue
            y = [getattr(q, variable) for q in e.orbit.points]
            ax.plot([e.value] * len(y), y, ls="none", marker="D", ms=4, mfc="none", mec="k", zorder=5,
                    gid=f"cascade:{e.orbits[0]}")
            if first:
                # the legend scales markers up for the sweep's dots: a smaller proxy for this one
                ax.plot([], [], ls="none", marker="D", ms=1, mfc="none", mec="k", label="period doubling (cascade)")
                first = False


def plot_regimes(ds, ax=None):
    """The regime of each direction at each value, as coloured strips. Returns (fig, ax).

    Raises
    ------
    ParameterError
        If ``ds`` is not a sweep's dataset (another study's, or not a Dataset) or ``ax`` is not an Axes.
    """
    ds = study_dataset(ds)
    param = _param(ds, "regime")
    fig, ax = new_axes(ax)
    _draw_regimes(ax, ds, param)
    return fig, ax


def _draw_regimes(ax, ds, param: str) -> None:
    values = ds[param].values
    dirs = [str(d) for d in ds.direction.values]
    codes = ds["regime"].values
    if values.size > 1:
        edges = np.concatenate(([values[0] - 0.5 * (values[1] - values[0])], 0.5 * (values[1:] + values[:-1]),
                                [values[-1] + 0.5 * (values[-1] - values[-2])]))
    else:
        edges = np.array([values[0] - 0.5, values[0] + 0.5])
    from matplotlib.colors import ListedColormap

    cmap = ListedColormap([REGIME_COLORS[name] for name in REGIME_NAMES])
    ax.pcolormesh(edges, np.arange(len(dirs) + 1), codes, cmap=cmap, vmin=-0.5, vmax=len(REGIME_NAMES) - 0.5)
    ax.set_yticks(np.arange(len(dirs)) + 0.5, dirs)
    ax.set_xlabel(PARAM_LABELS.get(param, param))
    present = sorted({int(c) for c in np.unique(codes)})
    from matplotlib.patches import Patch

    ax.legend(handles=[Patch(color=REGIME_COLORS[REGIME_NAMES[c]], label=REGIME_NAMES[c]) for c in present],
              loc="upper center", bbox_to_anchor=(0.5, -0.6), ncol=min(4, len(present)), fontsize="small",
              frameon=False)


def save_sweep_figure(ds, path, variable: str = "theta", *, overlay=None, cascades=()) -> Any:
    """Write the diagram (section and regime strip) to ``path`` (.png, .svg or .pdf).

    Raises
    ------
    ParameterError
        For a ``path`` that `rotorcontact.plotting.style.check_figure_path` refuses, and for the arguments
        `plot_sweep` and `plot_regimes` refuse (all before drawing).
    """
    ds = study_dataset(ds)
    import matplotlib.pyplot as plt

    check_figure_path(path)
    param, layers = _check_sweep(ds, variable, overlay, 2.0, cascades)
    _param(ds, "regime")
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7.5, 6.0), sharex=True,
                                  gridspec_kw=dict(height_ratios=(6, 1), hspace=0.08))
    _draw_sweep(ax, ds, param, variable, layers, 2.0, cascades)
    ax.set_xlabel("")
    _draw_regimes(ax2, ds, param)
    p = ds.attrs
    ax.set_title(
        f"brute-force diagram, {p.get('n_transient')} transient + {p.get('n_record')} recorded events per value",
        fontsize="medium",
    )
    return save_figure(fig, path)
