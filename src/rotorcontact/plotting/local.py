"""The local estimate at the boundary equilibrium overlaid on the global branches (Fig. 5(b), 5(d)).

rdot- (Fig. 5(b)) or thetadot- (Fig. 5(d)) of the small orbits B1,a and B1,b
against the bifurcation parameter near the boundary equilibrium: the global fixed
points (solid where admissible, dashed where virtual) and the first-order local
estimate eps * slope (dotted) of `rotorcontact.analysis.local`, which is tangent to them
at the boundary equilibrium. For the rotor the parameter is gamma (eps = gamma -
gamma*); for a general `LinearImpactingSystem` it is eps.

Lines carry a ``gid``: ``"global:<label>:admissible"``, ``"global:<label>:virtual"``
and ``"local:<label>"``.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..analysis.equilibria import boundary_gamma
from ..errors import ParameterError
from ..analysis.local import MAX_EPSILONS, LinearImpactingSystem, global_fixed_points, local_analysis
from ..model.params import Parameters, check_range
from ..model.validation import check_choice, check_int, check_type, is_pair, quoted
from .style import check_ax, check_axes, check_names, new_axes

__all__ = ["plot_local_estimate", "plot_local_figure"]

QUANTITIES = {"rdot": r"$\dot r^-$", "thetadot": r"$\dot\theta^-$"}
COLORS = {"a": "C0", "b": "C1", "c": "C2", "d": "C3"}


#: The options of `plot_local_estimate` that `plot_local_figure` passes on, and their defaults.
FIGURE_OPTIONS = ("labels", "eps_range", "n", "t_max")
SMALL_ORBITS = ("B1,a", "B1,b")
N_VALUES = 121
T_MAX = 12.0


def _check_local(model, quantity, labels=SMALL_ORBITS, eps_range=None, n=N_VALUES, t_max=T_MAX):
    """The checks of the arguments of `plot_local_estimate`; returns the labels, the offset and grid of eps,
    and the small orbits of the local analysis by label."""
    check_type("model", model, (Parameters, LinearImpactingSystem),
               "rotorcontact.Parameters or a rotorcontact.analysis.local.LinearImpactingSystem")
    check_choice("quantity", quantity, tuple(QUANTITIES))
    labels = check_names("labels", labels)
    if eps_range is not None and not is_pair(eps_range):
        raise ParameterError(f"eps_range = {quoted(eps_range)} is invalid; allowed: (low, high) or None")
    n = check_int("n", n, 3, MAX_EPSILONS)
    offset, eps = _grid(model, eps_range, n)
    local = {o.label: o for o in local_analysis(model, t_max).orbits}
    for lab in labels:
        if lab not in local:
            raise ParameterError(f"no small orbit {lab!r} at the boundary equilibrium; allowed: "
                                 f"{', '.join(local) or 'none'}")
    return labels, offset, eps, local


def _grid(model, eps_range, n):
    offset = 0.0
    if isinstance(model, Parameters):
        gs = boundary_gamma(model)
        if gs is None:
            raise ParameterError("no real gamma* for these parameters; allowed: rho > 0 and rho >= |1 - omega^2|")
        offset = gs
        if eps_range is None:
            eps_range = (-0.5 * gs, 0.5 * gs)
    elif eps_range is None:
        eps_range = (-0.05, 0.05)
    lo = check_range("eps_range[0]", eps_range[0])
    hi = check_range("eps_range[1]", eps_range[1])
    if not lo < hi:
        raise ParameterError(f"eps_range = {eps_range!r} is empty; allowed: eps_range[0] < eps_range[1]")
    eps = np.linspace(lo, hi, int(n))
    return offset, eps


def plot_local_estimate(
    model: Parameters | LinearImpactingSystem,
    quantity: str = "rdot",
    ax=None,
    *,
    labels: Sequence[str] = SMALL_ORBITS,
    eps_range: tuple[float, float] | None = None,
    n: int = N_VALUES,
    t_max: float = T_MAX,
):
    """Global branches of ``quantity`` with the local first-order estimate overlaid.

    Parameters
    ----------
    model : Parameters or LinearImpactingSystem
        The rotor (x-axis gamma, global orbits from `rotorcontact.maps.impact_map.one_impact_orbits`)
        or a general system (x-axis eps, global orbits from
        `LinearImpactingSystem.fixed_points`).
    quantity : {"rdot", "thetadot"}
        Fig. 5(b) (rdot-) or Fig. 5(d) (thetadot-).
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; a new figure if None.
    labels : sequence of str
        Orbits to draw (the small orbits; default B1,a and B1,b).
    eps_range : (float, float), optional
        Range of eps = parameter - its boundary value; default +-gamma*/2 for the
        rotor, +-0.05 for a general system.
    n : int
        Number of parameter values for the global branches, 3 to
        `rotorcontact.analysis.local.MAX_EPSILONS`.
    t_max : float
        End of the period search.

    Returns
    -------
    fig, ax

    Raises
    ------
    ParameterError
        If ``model`` is neither a Parameters nor a LinearImpactingSystem, ``quantity`` is not one of
        `QUANTITIES`, ``ax`` is not an Axes, ``labels`` is not a list of the small orbits' labels,
        ``eps_range`` is not an increasing pair of finite numbers, ``n`` is out of its range or ``t_max``
        is not a finite number > 0; and for a rotor without a real gamma*.
    """
    check_ax(ax)
    labels, offset, eps, local = _check_local(model, quantity, labels, eps_range, n, t_max)
    values = {lab: np.full(eps.shape, np.nan) for lab in labels}
    admissible = {lab: np.zeros(eps.shape, dtype=bool) for lab in labels}
    for i, e in enumerate(eps):
        orbits = {o.label: o for o in global_fixed_points(model, float(e), t_max)}
        for lab in labels:
            o = orbits.get(lab)
            if o is not None:
                values[lab][i] = getattr(o, quantity)
                admissible[lab][i] = o.admissible
    fig, ax = new_axes(ax)
    x = offset + eps
    for lab in labels:
        color = COLORS.get(local[lab].branch, "k")
        y = values[lab]
        adm = np.where(admissible[lab], y, np.nan)
        # virtual: keep the end points next to admissible ones so that the two styles join
        vir_mask = ~admissible[lab] | np.r_[~admissible[lab][1:], False] | np.r_[False, ~admissible[lab][:-1]]
        vir = np.where(vir_mask, y, np.nan)
        ax.plot(x, adm, color=color, lw=2.0, ls="-", gid=f"global:{lab}:admissible",
                label=f"{lab} (global)")
        ax.plot(x, vir, color=color, lw=1.2, ls="--", gid=f"global:{lab}:virtual")
        slope = getattr(local[lab], f"{quantity}_slope")
        if slope is not None:
            ax.plot(x, eps * slope, color="k", lw=1.0, ls=":", gid=f"local:{lab}",
                    label=f"{lab} local estimate")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.axvline(offset, color="0.6", lw=0.8, ls="-.")
    ax.set_xlabel(r"$\gamma$" if isinstance(model, Parameters) else r"$\epsilon$")
    ax.set_ylabel(QUANTITIES[quantity])
    ax.legend(fontsize="small")
    return fig, ax


def plot_local_figure(
    model: Parameters | LinearImpactingSystem,
    axes=None,
    **kwargs,
):
    """Fig. 5(b) and 5(d) side by side: rdot- and thetadot- with the local estimate.

    Parameters
    ----------
    model : Parameters or LinearImpactingSystem
    axes : sequence of two matplotlib.axes.Axes, optional
    **kwargs
        Passed to `plot_local_estimate`: `FIGURE_OPTIONS`.

    Returns
    -------
    fig, axes

    Raises
    ------
    ParameterError
        If ``axes`` is neither None nor two Axes, for an option that is not one of `FIGURE_OPTIONS`, and
        for the arguments `plot_local_estimate` refuses (all before drawing).
    """
    flat = check_axes(axes, 2, "rdot, thetadot")
    for key, value in kwargs.items():
        if key not in FIGURE_OPTIONS:
            raise ParameterError(f"{key} = {quoted(value)} is not an option of plot_local_figure; allowed: "
                                 f"{', '.join(FIGURE_OPTIONS)}")
    _check_local(model, "rdot", **kwargs)
    if flat is None:
        fig, axes = new_axes(None, ncols=2, figsize=(10.0, 4.0))
        flat = list(axes)
    fig = flat[0].figure
    plot_local_estimate(model, "rdot", flat[0], **kwargs)
    plot_local_estimate(model, "thetadot", flat[1], **kwargs)
    flat[0].set_title(r"(b) $\dot r^-$ of the small orbits")
    flat[1].set_title(r"(d) $\dot\theta^-$ of the small orbits")
    return fig, axes
