"""Branches of one-impact orbits against a parameter (the paper's Figs. 5, 6b and 7).

* `plot_branch_quantity`: any quantity of the orbits along their branches;
  `plot_rdot` (Fig. 5a, 5b) and `plot_thetadot` (Fig. 5c, 5d) draw rdot- and
  thetadot- of B1,a..d, with a hook to overlay a local estimate.
* `plot_max_multiplier`: max |multiplier| of B1,a..d (Fig. 6b).
* `plot_extrema`: the local extrema of r between impacts, with x_R (Fig. 7),
  marking the NSFH, the grazing point and where the number of extrema changes.

Line styles, everywhere: solid where the orbit is admissible and physically
plausible (thick where also stable, thin where unstable), dotted where it is
admissible but not plausible (r exceeds 1 between impacts, or the impact
does not slip), dashed where it is virtual (rdot- < 0). One colour per
branch letter. Every line carries a ``gid`` ``"<label>:<style>"`` with style
``plausible-stable``, ``plausible-unstable``, ``implausible`` or ``virtual``.
"""

from __future__ import annotations

import math
from typing import Callable, Mapping, Sequence

import numpy as np

from ..continuation.branches import BRANCH_PARAMETERS, LabelBranch, OrbitBranches, orbit_branches, refine_branches
from ..analysis.equilibria import boundary_gamma
from ..errors import ParameterError
from ..maps.impact_map import ORBIT_LABEL
from ..model.params import Parameters
from ..model.validation import (check_bool, check_choice, check_float, check_params, check_type, is_pair, quoted,
                                real_array)
from .equilibria import PARAM_LABELS
from .style import (CLEARANCE_COLOR, MAX_FIGURE_INCHES, check_ax, check_keywords, check_limits, check_names, new_axes,
                    orbit_tex, style_runs)

__all__ = [
    "BRANCH_COLORS",
    "LW_STABLE",
    "LW_UNSTABLE",
    "B1",
    "plot_branch_quantity",
    "plot_rdot",
    "plot_thetadot",
    "plot_max_multiplier",
    "plot_extrema",
    "plot_velocities",
    "compute_branches",
    "EVENT_MARKERS",
    "EVENT_NAMES",
    "point_style",
]

#: Colour of each branch letter.
BRANCH_COLORS = {"a": "C0", "b": "C1", "c": "C2", "d": "C3"}
LW_STABLE = 2.4
LW_UNSTABLE = 1.1
#: The four orbits of the first pair.
B1 = ("B1,a", "B1,b", "B1,c", "B1,d")

_QUANTITIES = {
    "rdot": (r"$\dot r^-$", lambda b: b.rdot),
    "thetadot": (r"$\dot\theta^-$", lambda b: b.thetadot),
    "T": (r"$T$", lambda b: b.T),
    "theta": (r"$\theta$", lambda b: b.theta),
    "max_multiplier": (r"$\max|\lambda_i|$", lambda b: b.max_multiplier),
    "r_max_interior": (r"$r_{\max}$", lambda b: b.r_max_interior),
}

#: Marker of each kind of event along a branch.
EVENT_MARKERS = {"fold": "o", "nsfh": "s", "period-doubling": "^", "neimark-sacker": "D", "grazing": "v",
                 "branch-point": "x", "ac-coalescence": "P", "extrema-change": "*"}
#: Legend text of each kind of event.
EVENT_NAMES = {"fold": "fold", "nsfh": "NSFH", "period-doubling": "period doubling",
               "neimark-sacker": "Neimark–Sacker", "grazing": "grazing", "branch-point": "branch point",
               "ac-coalescence": "a–c coalescence", "extrema-change": "change in number of extrema"}

LocalEstimate = Callable[[str, np.ndarray], "np.ndarray | None"] | Mapping[str, tuple[np.ndarray, np.ndarray]]


def compute_branches(params: Parameters, param: str = "gamma", start: float = -0.6, stop: float = 0.25,
                     **kwargs) -> OrbitBranches:
    """`rotorcontact.continuation.branches.orbit_branches` (a shorthand for the figures); a `ParameterError`
    for a keyword it does not take."""
    check_keywords(kwargs, orbit_branches)
    return orbit_branches(params, param, start, stop, **kwargs)


def point_style(b: LabelBranch, i: int) -> str:
    """How point i of a label's branch is drawn: ``"virtual"`` (rdot < 0), ``"implausible"`` (no orbit of the
    simulator: r > 1 between impacts, or no forward slip), else ``"plausible-stable"`` or
    ``"plausible-unstable"`` (stability unknown counts as unstable)."""
    if not b.admissible[i]:
        return "virtual"
    if not b.plausible[i]:
        return "implausible"
    return "plausible-stable" if b.stable[i] else "plausible-unstable"


_LINE = {
    "virtual": dict(ls="--", lw=LW_UNSTABLE),
    "implausible": dict(ls=":", lw=1.4),
    "plausible-stable": dict(ls="-", lw=LW_STABLE),
    "plausible-unstable": dict(ls="-", lw=LW_UNSTABLE),
}


def _draw_styled(ax, label: str, x: np.ndarray, y: np.ndarray, b: LabelBranch, color: str, sl: slice) -> None:
    """Draw one piece split into runs of constant style; consecutive runs share their end point."""
    idx = np.arange(sl.start, sl.stop)
    if idx.size == 0:
        return
    styles = [point_style(b, i) for i in idx]
    for style, start, stop in style_runs(styles):
        run = idx[start:stop]
        ax.plot(x[run], y[run], color=color, gid=f"{label}:{style}", **_LINE[style])


def _check_labels(branches: OrbitBranches, labels: Sequence[str]) -> list[str]:
    """The orbit labels of ``labels`` that ``branches`` holds: a label that the range does not reach is left
    out (the paper's figures name all four of B1); `_check_options` refused labels of another form."""
    out = [lab for lab in labels if lab in branches.labels]
    return out


_BRANCHES = "the OrbitBranches of rotorcontact.continuation.branches.orbit_branches"


def _check_options(labels, ax, xlim, ylim, local=None, **flags) -> None:
    """The checks of the drawing options the figures of branches share (made before any computation)."""
    check_names("labels", labels)
    for lab in labels:
        if not ORBIT_LABEL.fullmatch(lab):
            raise ParameterError(f"labels = {quoted(labels)} holds {lab!r}, not a one-impact orbit label; allowed: "
                                 "labels 'B<n>,<a|b|c|d>', such as 'B1,d'")
    check_ax(ax)
    check_limits("xlim", xlim)
    check_limits("ylim", ylim)
    if local is not None and not (isinstance(local, Mapping) or callable(local)):
        raise ParameterError(f"local = {quoted(local)} is invalid; allowed: a mapping label -> (x, y), a callable "
                             "local(label, x) or None")
    for name, value in flags.items():
        check_bool(name, value)


def _check_inputs(params, branches) -> None:
    """The checks of the model of the figures that compute their branches when none are given."""
    check_params(params)
    check_type("branches", branches, OrbitBranches, _BRANCHES, optional=True)


def plot_branch_quantity(
    branches: OrbitBranches,
    quantity: str = "rdot",
    labels: Sequence[str] = B1,
    *,
    ax=None,
    xlim: tuple[float, float] | None = None,
    ylim: tuple[float, float] | None = None,
    local: LocalEstimate | None = None,
    events: bool = True,
    legend: bool = True,
):
    """Draw one orbit quantity of the branches ``labels`` against the parameter.

    Parameters
    ----------
    branches : OrbitBranches
        From `rotorcontact.continuation.branches.orbit_branches`.
    quantity : str
        ``"rdot"``, ``"thetadot"``, ``"T"``, ``"theta"``, ``"max_multiplier"`` or
        ``"r_max_interior"``.
    labels : sequence of str
        Orbits to draw (those absent are skipped).
    ax : matplotlib.axes.Axes, optional
    xlim, ylim : (float, float), optional
    local : callable or mapping, optional
        A local estimate to overlay (dash-dotted, in the orbit's colour, with
        its own legend entry per orbit): either a mapping
        ``label -> (x, y)`` of arrays, or a callable ``local(label, x)``
        returning y at the parameter values x of the branch (or None); y may be nan where the estimate
        does not hold (a gap).
    events : bool
        Mark the events of the drawn orbits (`EVENT_MARKERS`), each kind with a legend entry.
    legend : bool
        Add a legend: the orbits, the line styles, each local estimate and each kind of event marked.

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``branches`` is not an OrbitBranches, ``quantity`` is not one of the quantities, ``labels`` is
        not a list of labels, ``ax`` not an Axes, ``xlim`` or ``ylim`` neither None nor two distinct
        finite numbers, ``local`` neither None, a mapping nor a callable, or ``events`` or ``legend`` not
        True or False.
    """
    check_type("branches", branches, OrbitBranches, _BRANCHES)
    check_choice("quantity", quantity, tuple(_QUANTITIES))
    _check_options(labels, ax, xlim, ylim, local, events=events, legend=legend)
    ylabel, getter = _QUANTITIES[quantity]
    view = xlim or (branches.start, branches.stop)
    branches = refine_branches(branches, (min(view), max(view)), REFINED_POINTS)
    drawn = _check_labels(branches, labels)
    lines = {label: branches.branch(label) for label in drawn}
    # the local estimates are checked before a figure is opened
    estimates = {label: _local_curve(label, b, local) for label, b in lines.items()} if local is not None else {}
    fig, ax = new_axes(ax)
    estimated = []
    for label, b in lines.items():
        color = BRANCH_COLORS.get(label.split(",")[1], "k")
        y = getter(b)
        for sl in b.pieces():
            _draw_styled(ax, label, b.values, y, b, color, sl)
        if estimates.get(label) is not None:
            ax.plot(*estimates[label], color=color, gid=f"{label}:local", **_LOCAL)
            estimated.append(label)
    marked = _mark_events(ax, branches, drawn, quantity, view) if events else []
    level = {"rdot": 0.0, "thetadot": 0.0, "max_multiplier": 1.0, "r_max_interior": 1.0}.get(quantity)
    if level is not None:
        ax.axhline(level, color=CLEARANCE_COLOR, lw=0.8, zorder=0)
    ax.set_xlim(*view)
    if ylim is not None:
        ax.set_ylim(*ylim)
    ax.set_xlabel(PARAM_LABELS.get(branches.param, branches.param))
    ax.set_ylabel(ylabel)
    if legend:
        _legend(ax, drawn, estimated, marked)
    return fig, ax


#: Style of the local estimate of an orbit (in the orbit's colour).
_LOCAL = dict(ls="-.", lw=1.3, alpha=0.75)
#: Points across the view at least, where the branches are drawn (`refine_branches`): the continuation's steps
#: are coarse beside a bifurcation, and a chord there would misdraw the curve and its style.
REFINED_POINTS = 400


def _local_curve(label: str, b: LabelBranch, local) -> tuple[np.ndarray, np.ndarray] | None:
    """The local estimate of ``label`` as (x, y), None where there is none; a `ParameterError` naming
    ``local[label]`` or ``local(label, x)`` unless it gives two equally long 1-d arrays, x finite and y finite
    or nan (a gap where the estimate does not hold)."""
    if isinstance(local, Mapping):
        if label not in local:
            return None
        name, value = f"local[{label!r}]", local[label]
        pair = value if isinstance(value, (tuple, list)) and len(value) == 2 else (None, None)
        x, y = (real_array(v) for v in pair)
    else:
        x = np.sort(b.values[np.isfinite(b.values)])
        name, value = f"local({label!r}, x)", local(label, x)
        if value is None:
            return None
        y = real_array(value)
    # y may hold nan where the estimate does not hold (a gap in its line), not an infinity
    if x is None or y is None or x.ndim != 1 or x.shape != y.shape or not (np.all(np.isfinite(x))
                                                                             and not np.any(np.isinf(y))):
        allowed = "(x, y), two equally long 1-d arrays, x finite and y finite or nan" \
            if isinstance(local, Mapping) else \
            "a 1-d array as long as x (the branch's parameter values), finite or nan, or None"
        raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: {allowed}")
    return x, y


def _at_event(b: LabelBranch, e, y: np.ndarray) -> float | None:
    """``y`` of the orbit of branch ``b`` at the event ``e``, interpolated along the branch.

    Of the segments of the branch whose parameter values bracket the event's,
    the one whose impact velocity there is closest to the event's is used (a
    branch can take the same parameter value more than once, around a fold).
    """
    best, out = math.inf, None
    for sl in b.pieces():
        v, r, q = b.values[sl], b.rdot[sl], y[sl]
        for i in range(len(v) - 1):
            lo, hi = sorted((v[i], v[i + 1]))
            if not (lo <= e.value <= hi) or not np.all(np.isfinite([r[i], r[i + 1], q[i], q[i + 1]])):
                continue
            s = 0.5 if hi == lo else (e.value - v[i]) / (v[i + 1] - v[i])
            miss = abs(r[i] + s * (r[i + 1] - r[i]) - e.rdot)
            if miss < best:
                best, out = miss, float(q[i] + s * (q[i + 1] - q[i]))
    return out


def _in_view(value: float, view: tuple[float, float]) -> bool:
    lo, hi = sorted(view)
    return lo <= value <= hi


def _mark_events(ax, branches: OrbitBranches, labels: Sequence[str], quantity: str,
                 view: tuple[float, float]) -> list[str]:
    """Mark the events of the orbits ``labels`` inside the parameter range ``view`` on the curves of
    ``quantity``; return the kinds marked."""
    getter = _QUANTITIES[quantity][1]
    cache: dict[str, LabelBranch] = {}
    marked: list[str] = []
    for e in branches.events:
        orbits = [lab for lab in e.orbits if lab in labels]
        if e.kind not in EVENT_MARKERS or not orbits or not _in_view(e.value, view):
            continue
        if quantity == "rdot":
            y = e.rdot
        elif quantity == "T":
            y = e.T
        else:
            b = cache.setdefault(orbits[0], branches.branch(orbits[0]))
            y = _at_event(b, e, getter(b))
        if y is None or not math.isfinite(y):
            continue
        ax.plot([e.value], [y], EVENT_MARKERS[e.kind], mfc="none", color="k", ms=6, zorder=5,
                gid=f"event:{e.kind}")
        if e.kind not in marked:
            marked.append(e.kind)
    return marked


def _event_handles(kinds: Sequence[str]) -> list:
    from matplotlib.lines import Line2D

    return [Line2D([], [], marker=EVENT_MARKERS[k], mfc="none", color="k", ms=6, ls="none", label=EVENT_NAMES[k])
            for k in EVENT_MARKERS if k in kinds]


def _legend(ax, labels: Sequence[str], estimated: Sequence[str], events: Sequence[str]) -> None:
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=BRANCH_COLORS.get(lab.split(",")[1], "k"), lw=1.6, label=orbit_tex(lab))
               for lab in labels]
    handles += [
        Line2D([], [], color="0.3", lw=LW_STABLE, label="stable"),
        Line2D([], [], color="0.3", lw=LW_UNSTABLE, label="unstable"),
        Line2D([], [], color="0.3", ls=":", lw=1.4, label="not plausible"),
        Line2D([], [], color="0.3", ls="--", lw=LW_UNSTABLE, label="virtual"),
    ]
    handles += [Line2D([], [], color=BRANCH_COLORS.get(lab.split(",")[1], "k"),
                       label=f"local estimate, {orbit_tex(lab)}", **_LOCAL) for lab in estimated]
    handles += _event_handles(events)
    ax.legend(handles=handles, fontsize=7, loc="best", ncol=2 if len(handles) > 10 else 1)


def plot_rdot(
    params: Parameters,
    start: float = -0.6,
    stop: float = 0.25,
    *,
    param: str = "gamma",
    labels: Sequence[str] = B1,
    ax=None,
    branches: OrbitBranches | None = None,
    xlim: tuple[float, float] | None = None,
    ylim: tuple[float, float] | None = None,
    local: LocalEstimate | None = None,
):
    """rdot- of the orbits against the parameter (paper Fig. 5a; with a zoom and ``local``, Fig. 5b).

    Parameters
    ----------
    params : Parameters
    start, stop : float
        The parameter range computed (when ``branches`` is not given).
    param : str
    labels : sequence of str
    ax : matplotlib.axes.Axes, optional
    branches : OrbitBranches, optional
        Precomputed branches.
    xlim, ylim : optional
        The view (for the zoom of Fig. 5b, for example around gamma* .. gamma_F,1 on B1,a and B1,b).
    local : optional
        A local estimate to overlay (see `plot_branch_quantity`).

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``params`` is not a Parameters, ``branches`` neither None nor an OrbitBranches, for the
        options `plot_branch_quantity` refuses (checked before the computation), and for the range
        `rotorcontact.continuation.branches.orbit_branches` refuses.
    """
    _check_inputs(params, branches)
    _check_options(labels, ax, xlim, ylim, local)
    branches = branches or orbit_branches(params, param, start, stop)
    return plot_branch_quantity(branches, "rdot", labels, ax=ax, xlim=xlim, ylim=ylim, local=local)


def plot_thetadot(
    params: Parameters,
    start: float = -0.6,
    stop: float = 0.25,
    *,
    param: str = "gamma",
    labels: Sequence[str] = B1,
    ax=None,
    branches: OrbitBranches | None = None,
    xlim: tuple[float, float] | None = None,
    ylim: tuple[float, float] | None = None,
    local: LocalEstimate | None = None,
):
    """thetadot- of the orbits against the parameter (paper Fig. 5c, 5d). Arguments and errors as `plot_rdot`."""
    _check_inputs(params, branches)
    _check_options(labels, ax, xlim, ylim, local)
    branches = branches or orbit_branches(params, param, start, stop)
    return plot_branch_quantity(branches, "thetadot", labels, ax=ax, xlim=xlim, ylim=ylim, local=local)


def plot_max_multiplier(
    params: Parameters,
    start: float = -0.6,
    stop: float = 0.25,
    *,
    param: str = "gamma",
    labels: Sequence[str] = B1,
    ax=None,
    branches: OrbitBranches | None = None,
    xlim: tuple[float, float] | None = None,
    ylim: tuple[float, float] | None = (0.3, 10.0),
    log: bool = True,
    events: bool = True,
    legend: bool = True,
):
    """max |multiplier| of the admissible orbits against the parameter (paper Fig. 6b).

    Virtual orbits have no multipliers and are not drawn. The unit circle is
    the grey line at 1. The paper's view is ``xlim=(0, 0.2)``,
    ``ylim=(0.5, 3)``, ``log=False``.

    Parameters
    ----------
    params : Parameters
    start, stop : float
        The parameter range computed (when ``branches`` is not given).
    param : str
    labels : sequence of str
    ax : matplotlib.axes.Axes, optional
    branches : OrbitBranches, optional
        Precomputed branches.
    xlim, ylim : (float, float), optional
        The view.
    log : bool
        A logarithmic axis of |multiplier|.
    events : bool
        Mark the events of the drawn orbits (a stability change lies on the line at 1).
    legend : bool

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        As `plot_rdot`, if ``log``, ``events`` or ``legend`` is not True or False, and for a ``ylim`` that
        reaches 0 or below on the logarithmic axis of ``log``.
    """
    _check_inputs(params, branches)
    _check_options(labels, ax, xlim, ylim, log=log, events=events, legend=legend)
    if log and ylim is not None and not min(ylim) > 0.0:
        raise ParameterError(f"ylim = {quoted(ylim)} reaches 0 or below, which a logarithmic axis cannot show; "
                             "allowed: limits > 0, or log=False")
    branches = branches or orbit_branches(params, param, start, stop)
    fig, ax = plot_branch_quantity(branches, "max_multiplier", labels, ax=ax, xlim=xlim, ylim=None, events=events,
                                   legend=legend)
    if log:
        ax.set_yscale("log")
    if ylim is not None:
        ax.set_ylim(*ylim)
    return fig, ax


def plot_extrema(
    params: Parameters,
    start: float = -0.6,
    stop: float = 0.25,
    *,
    param: str = "gamma",
    labels: Sequence[str] = ("B1,a", "B1,b"),
    regular: bool = True,
    ax=None,
    branches: OrbitBranches | None = None,
    xlim: tuple[float, float] | None = None,
    ylim: tuple[float, float] | None = None,
    legend: bool = True,
):
    """Local extrema of r between impacts against the parameter (paper Fig. 7).

    For each orbit, each interior local maximum (and minimum) of r is drawn
    as a line while the number of extrema stays the same; x_R (r = |k|) is
    drawn when ``regular``. A dash-dotted vertical line marks the NSFH
    (gamma*), triangles the grazing points (r_max = 1) and dotted vertical
    lines the points where the number of interior extrema changes, each kind
    with a legend entry. Fig. 7a: ``labels=("B1,a", "B1,b")``,
    ``regular=True``; Fig. 7b: ``labels=("B1,c", "B1,d")``, ``regular=False``.
    The paper's views are ``xlim=(0, 0.2)`` with ``ylim=(0.96, 1.02)`` (7a)
    and ``ylim=(-0.2, 1.4)`` (7b).

    Parameters
    ----------
    params : Parameters
    start, stop : float
        The parameter range computed (when ``branches`` is not given).
    param : str
    labels : sequence of str
        Orbits to draw.
    regular : bool
        Draw x_R.
    ax : matplotlib.axes.Axes, optional
    branches : OrbitBranches, optional
        Precomputed branches.
    xlim, ylim : (float, float), optional
        The view.
    legend : bool

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        As `plot_rdot`, and if ``regular`` or ``legend`` is not True or False.
    """
    _check_inputs(params, branches)
    _check_options(labels, ax, xlim, ylim, regular=regular, legend=legend)
    branches = branches or orbit_branches(params, param, start, stop)
    view = xlim or (branches.start, branches.stop)
    branches = refine_branches(branches, (min(view), max(view)), REFINED_POINTS)
    fig, ax = new_axes(ax)
    drawn = _check_labels(branches, labels)
    for label in drawn:
        b = branches.branch(label)
        color = BRANCH_COLORS.get(label.split(",")[1], "k")
        for sl in b.pieces():
            idx = np.arange(sl.start, sl.stop)
            keys = [(len(b.extrema[i][0]), point_style(b, i)) for i in idx]
            # a change of style alone: the runs share their end point (no gap); a change of the number of
            # extrema: the curves of extrema themselves change there
            for (count, style), start, stop in style_runs(keys, lambda key, following: key[0] == following[0]):
                run = idx[start:stop]
                for j in range(count):
                    x = b.values[run]
                    y = np.array([b.extrema[m][0][j] for m in run])
                    is_max = bool(b.extrema[run[0]][1][j])
                    kw = dict(ls=_LINE[style]["ls"], lw=1.8 if is_max else 0.9)
                    ax.plot(x, y, color=color, gid=f"{label}:{style}:{'max' if is_max else 'min'}", **kw)
    if regular:
        v = np.linspace(*view, 801)
        rk = np.array([_radius_of_x_R(branches.params_at(x)) for x in v])
        adm = rk < 1.0
        for mask, ls, tag in ((adm, "-", "admissible"), (~adm, "--", "virtual")):
            y = np.where(mask, rk, np.nan)
            ax.plot(v, y, color="k", ls=ls, lw=1.2, gid=f"x_R:{tag}")
    ax.axhline(1.0, color=CLEARANCE_COLOR, lw=1.0, zorder=0)
    marks = {}  # legend entries of the marks drawn, by kind
    if branches.param == "gamma":
        gs = boundary_gamma(branches.base)
        if gs is not None and branches.start <= gs <= branches.stop and _in_view(gs, view):
            ax.axvline(gs, **_EXTREMA_MARKS["nsfh"], zorder=0, gid="nsfh")
            marks["nsfh"] = True
    for e in branches.events:
        if not any(lab in drawn for lab in e.orbits) or not _in_view(e.value, view):
            continue
        if e.kind == "grazing":
            ax.plot([e.value], [1.0], **_EXTREMA_MARKS["grazing"], zorder=5, gid="event:grazing")
            marks["grazing"] = True
        elif e.kind == "extrema-change":
            ax.axvline(e.value, **_EXTREMA_MARKS["extrema-change"], zorder=0, gid="event:extrema-change")
            marks["extrema-change"] = True
    ax.set_xlim(*view)
    if ylim is not None:
        ax.set_ylim(*ylim)
    ax.set_xlabel(PARAM_LABELS.get(branches.param, branches.param))
    ax.set_ylabel(r"local extrema of $r$")
    if legend:
        from matplotlib.lines import Line2D

        handles = [Line2D([], [], color=BRANCH_COLORS.get(lab.split(",")[1], "k"), lw=1.6, label=orbit_tex(lab))
                   for lab in drawn]
        if regular:
            handles.append(Line2D([], [], color="k", lw=1.2, label=r"$x_R$"))
        handles += [
            Line2D([], [], color="0.3", lw=1.8, label="maximum"),
            Line2D([], [], color="0.3", lw=0.9, label="minimum"),
            Line2D([], [], color="0.3", ls="--", lw=LW_UNSTABLE, label="virtual"),
            Line2D([], [], color="0.3", ls=":", lw=1.4, label="not plausible"),
        ]
        handles += [Line2D([], [], **_EXTREMA_MARKS[kind], label=_EXTREMA_NAMES[kind])
                    for kind in _EXTREMA_MARKS if kind in marks]
        ax.legend(handles=handles, fontsize=7, loc="best")
    return fig, ax


def plot_velocities(branches: OrbitBranches, labels: Sequence[str] = B1, *, rdot_max: float | None = None,
                    figsize: tuple[float, float] = (7, 8)):
    """rdot- (top) and thetadot- (bottom) of the orbits ``labels`` against the parameter, on a shared axis.

    Parameters
    ----------
    branches : OrbitBranches
    labels : sequence of str
        Orbits to draw.
    rdot_max : float, optional
        Both vertical axes are clipped to [-rdot_max, rdot_max] (the range followed).
    figsize : (float, float)

    Returns
    -------
    (fig, axes)
        The figure, titled with the other parameters, and its two axes.

    Raises
    ------
    ParameterError
        If ``branches`` is not an OrbitBranches, ``labels`` not a list of labels, ``rdot_max`` neither None
        nor a finite number > 0, or ``figsize`` not two finite numbers > 0 and at most
        `rotorcontact.plotting.style.MAX_FIGURE_INCHES`.
    """
    import matplotlib.pyplot as plt

    check_type("branches", branches, OrbitBranches, _BRANCHES)
    check_names("labels", labels)
    if rdot_max is not None:
        check_float("rdot_max", rdot_max, 0.0, low_open=True)
    size = real_array(figsize) if is_pair(figsize) else None
    if size is None or size.shape != (2,) or not np.all((size > 0.0) & (size <= MAX_FIGURE_INCHES)):
        raise ParameterError(f"figsize = {quoted(figsize)} is invalid; allowed: (width, height) in inches, each "
                             f"> 0 and <= {MAX_FIGURE_INCHES:g}")
    fig, axes = plt.subplots(2, 1, figsize=figsize, sharex=True)
    plot_branch_quantity(branches, "rdot", labels, ax=axes[0])
    plot_branch_quantity(branches, "thetadot", labels, ax=axes[1], legend=False)
    if rdot_max is not None:
        for ax in axes:
            ax.set_ylim(max(ax.get_ylim()[0], -rdot_max), min(ax.get_ylim()[1], rdot_max))
    axes[0].set_title(
        ", ".join(f"{n}={getattr(branches.base, n):.4g}" for n in BRANCH_PARAMETERS if n != branches.param),
        fontsize=9,
    )
    return fig, axes


def _radius_of_x_R(p: Parameters) -> float:
    """|k|, NaN at the undamped resonance (gamma = 0, omega = 1) where x_R does not exist."""
    try:
        return abs(p.k)
    except ZeroDivisionError:
        return math.nan


#: How `plot_extrema` marks the NSFH (a vertical line at gamma*), the grazing points
#: (a triangle on r = 1) and the changes in the number of extrema (a vertical line).
_EXTREMA_MARKS = {
    "nsfh": dict(color="k", lw=0.8, ls="-."),
    "grazing": dict(marker="v", color="k", ms=6, ls="none"),
    "extrema-change": dict(color="0.4", lw=0.9, ls=":"),
}
_EXTREMA_NAMES = {"nsfh": r"NSFH ($\gamma^*$)", "grazing": "grazing", "extrema-change": "change in number of extrema"}
