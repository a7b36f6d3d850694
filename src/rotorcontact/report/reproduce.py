"""The paper's results in one call: Figures 2 to 7, the report's numbers, and an HTML page.

Every number is computed here from the model; the paper's stated values (a
data file, `paper_values`) are only shown beside ours for comparison.
"""

from __future__ import annotations

import base64
import html
import math
import re
import sys
import time
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Callable

import matplotlib.pyplot as plt
from matplotlib.figure import Figure
import numpy as np

from .. import __version__
from ..continuation.branches import orbit_branches
from ..continuation.codim2 import codim2_diagram
from ..analysis.equilibria import boundary_gamma, classify_beb_analytic
from ..errors import ParameterError
from ..maps.impact_map import one_impact_orbits
from ..analysis.local import local_analysis
from ..model.params import Parameters, reference_machine
from ..model.validation import check_bool, check_params, check_path
from ..plotting.branches import plot_extrema, plot_max_multiplier, plot_rdot, plot_thetadot
from ..plotting.codim2 import plot_codim2
from ..plotting.equilibria import plot_equilibria
from ..plotting.f1 import plot_f1, plot_f1_zeros, plot_nsfh_schematic
from ..plotting.trajectory import plot_corotating, plot_inertial, plot_radius
from ..simulation.simulator import simulate

__all__ = ["paper_values", "paper_parameters", "Quantity", "Reproduction", "reproduce", "PAPER_VIEWS"]

STABILITY_TYPES = ("branch-point", "period-doubling", "neimark-sacker")

#: The ranges of the paper's panels, (gamma range, y range); None where the y range is fitted to the data.
PAPER_VIEWS: dict[str, tuple[tuple[float, float], tuple[float, float] | None]] = {
    "fig5b": ((0.0, 0.2), None),
    "fig5d": ((0.0, 0.2), None),
    "fig6b": ((0.0, 0.2), (0.5, 3.0)),
    "fig7a": ((0.0, 0.2), (0.96, 1.02)),
    "fig7b": ((0.0, 0.2), (-0.2, 1.4)),
}
#: The gamma range of the branches computed, and of the wide views.
WIDE = (-0.6, 0.25)


def paper_values() -> dict[str, Any]:
    """The paper's stated parameters and values (a data file of the package), as text at their precision."""
    text = resources.files("rotorcontact").joinpath("data", "paper.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def paper_parameters() -> Parameters:
    """The parameters of the paper's figures: the reference machine with the paper's rounded omega."""
    stated = paper_values()["parameters"]
    return reference_machine().parameters().replace(**{k: float(v) for k, v in stated.items()})


@dataclass(frozen=True)
class Quantity:
    """One row of the report's table.

    Attributes
    ----------
    key : str
        Its key in report.json (dotted for nested values).
    label : str
        What it is.
    ours : float or str or None
        Our value.
    paper : str or None
        The paper's stated value, as written (None where none is on file).
    agrees : bool or None
        Whether ours rounds to the paper's value at the paper's precision.
    note : str
        For example "not stated in the paper".
    """

    key: str
    label: str
    ours: float | str | None
    paper: str | None = None
    agrees: bool | None = None
    note: str = ""


def _agrees(ours: Any, paper: str | None) -> bool | None:
    """Ours agrees when it lies within half a unit of the paper's last stated digit."""
    if paper is None or not isinstance(ours, (int, float)):
        return None
    text = paper.strip()
    if "/" in text:
        num, den = text.split("/")
        return abs(ours - float(num) / float(den)) <= 1e-12 * max(1.0, abs(ours))
    decimals = len(text.split(".")[1]) if "." in text else 0
    return abs(ours - float(text)) <= 0.5 * 10.0 ** (-decimals) * (1 + 1e-9)


@dataclass
class Reproduction:
    """Everything ``reproduce`` computed.

    Attributes
    ----------
    params : Parameters
        The parameters of the run.
    paper : bool
        True when they are the paper's (so the paper column is filled).
    report : dict
        The content of report.json.
    quantities : list of Quantity
        The table of the HTML report.
    figures : list of (name, caption, png path, svg path)
    timings : dict
        Seconds per stage.
    """

    params: Parameters
    paper: bool
    report: dict[str, Any] = field(default_factory=dict)
    quantities: list[Quantity] = field(default_factory=list)
    figures: list[tuple[str, str, Path, Path]] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)


class _Stages:
    """Runs named stages, timing each and reporting progress on stderr."""

    def __init__(self, progress: bool, total: int):
        self.progress = progress
        self.total = total
        self.done = 0
        self.timings: dict[str, float] = {}

    def run(self, name: str, func: Callable[[], Any]) -> Any:
        if self.progress:
            print(f"[{self.done + 1}/{self.total}] {name} ...", file=sys.stderr, flush=True)
        t0 = time.perf_counter()
        out = func()
        self.timings[name] = time.perf_counter() - t0
        self.done += 1
        if self.progress:
            print(f"[{self.done}/{self.total}] {name}: {self.timings[name]:.2f} s", file=sys.stderr, flush=True)
        return out


def _panel(ax, draw: Callable[[], Any], title: str) -> None:
    """Draw one panel; where it does not exist at these parameters, say so on the panel instead."""
    try:
        draw()
    except ParameterError as exc:
        ax.clear()
        ax.text(0.5, 0.5, f"not defined at these parameters:\n{exc}", ha="center", va="center",
                transform=ax.transAxes, wrap=True, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    ax.set_title(title)


def _save(rep: Reproduction, out: Path, fig: Figure, name: str, caption: str) -> Figure:
    """Write ``fig`` as PNG and SVG, record it in ``rep`` and close it; return it (for inspection)."""
    png, svg = out / f"{name}.png", out / f"{name}.svg"
    fig.savefig(png, dpi=130, bbox_inches="tight")
    fig.savefig(svg, bbox_inches="tight")
    plt.close(fig)
    rep.figures.append((name, caption, png, svg))
    return fig


def _fig2(p: Parameters, rep: Reproduction, out: Path) -> Figure:
    """Three orbits in the inertial frame, the co-rotating frame and r(t)."""
    fig, axes = plt.subplots(3, 3, figsize=(12, 11), gridspec_kw={"width_ratios": [1, 1, 1.5]})
    cases = [(r"(a) $x_R$", 0.3, None), (r"(b) $B_{1,d}$", 0.065, "B1,d"), (r"(c) $B_{1,a}$", 0.1, "B1,a")]
    for row, (title, gamma, label) in zip(axes, cases):
        q = p.replace(gamma=gamma)

        def trajectory(q=q, label=label, gamma=gamma):
            if label is None:
                if abs(q.k) >= 1.0:
                    raise ParameterError(f"x_R is virtual at gamma = {gamma} (|k| = {abs(q.k):.4g} >= 1)")
                return simulate(q, q.k, 0j, 2.0 * math.pi)
            orbit = next((o for o in one_impact_orbits(q) if o.label == label and o.admissible), None)
            if orbit is None:
                raise ParameterError(f"{label} does not exist (admissible) at gamma = {gamma}")
            u0, du0 = orbit.initial_condition()
            return simulate(q, u0, du0, 0.999 * orbit.T)

        try:
            traj = trajectory()
            # the small orbit B1,a is drawn again in a zoomed inset, as in the paper
            draws = [lambda ax: plot_inertial(traj, ax),
                     lambda ax, small=label == "B1,a": plot_corotating(traj, ax, inset=small),
                     lambda ax: plot_radius(traj, ax)]
        except ParameterError as exc:
            message = exc

            def fail(ax, message=message):
                raise ParameterError(str(message))

            draws = [fail, fail, fail]
        titles = [f"{title}, γ = {gamma}: inertial frame", "co-rotating frame", "r(t)"]
        for ax, draw, t in zip(row, draws, titles):
            _panel(ax, lambda ax=ax, draw=draw: draw(ax), t)
    fig.tight_layout()
    where = ("(b) the orbit B1,d near grazing at γ = 0.065; (c) the small orbit B1,a near the non-smooth "
             "fold–Hopf bifurcation at γ = 0.1" if rep.paper else
             "(b) the orbit B1,d at γ = 0.065; (c) the orbit B1,a at γ = 0.1 (the paper's values of γ, where at its "
             "parameters B1,d is near grazing and B1,a near the non-smooth fold–Hopf bifurcation)")
    caption = (
        f"Fig. 2. (a) The regular equilibrium x_R at γ = 0.3; {where}. Each in the inertial frame Z, the "
        "co-rotating frame U (clearance circle in grey; in (c) with an inset zoomed on the small orbit) and as "
        "r(t) over one period."
    )
    return _save(rep, out, fig, "fig2_orbits", caption)


def _beb_words(params: Parameters) -> str:
    """The boundary equilibrium bifurcation at ``params``, in the words of Fig. 3's caption."""
    kind = classify_beb_analytic(params)
    if kind == "nonsmooth-fold":
        return "a non-smooth fold with x_P1"
    if kind == "persistence":
        return "persistence of x_P2 into x_R"
    return "a degenerate boundary equilibrium bifurcation (at a border of the ω-ranges)"


def _fig3(p: Parameters, rep: Reproduction, out: Path) -> Figure:
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    _panel(axes[0], lambda: plot_equilibria(p, "gamma", 0.0, 0.2, ax=axes[0]), f"(a) ω = {p.omega:g}")
    _panel(axes[1], lambda: plot_equilibria(p.replace(omega=1.0), "gamma", 0.0, 0.8, ax=axes[1]), "(b) ω = 1")
    fig.tight_layout()
    caption = (
        "Fig. 3. r of the regular equilibrium x_R and of its partner pseudo-equilibrium against γ, solid "
        f"where admissible and dashed where virtual, with the boundary equilibrium bifurcation marked: (a) "
        f"{_beb_words(p)} at ω = {p.omega:g}; (b) {_beb_words(p.replace(omega=1.0))} at ω = 1."
    )
    return _save(rep, out, fig, "fig3_equilibria", caption)


def _fig4(p: Parameters, rep: Reproduction, out: Path, g_dib: float | None) -> Figure:
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    _panel(axes[0, 0], lambda: plot_f1(p.replace(gamma=0.1), (0.0, 30.0), ax=axes[0, 0]), r"(a) $F_1(T)$, γ = 0.1")
    _panel(axes[0, 1], lambda: plot_f1(p.replace(gamma=0.05), (0.0, 40.0), ax=axes[0, 1]),
           r"(b) $F_1(T)$, γ = 0.05")
    _panel(axes[1, 0], lambda: plot_f1_zeros(p, "gamma", 0.0, 0.25, t_max=12.0, ax=axes[1, 0]),
           r"(c) zeros of $F_1$ against γ")
    _panel(axes[1, 1], lambda: plot_nsfh_schematic(p, gamma=None if g_dib is None else g_dib + 0.02, ax=axes[1, 1]),
           "(d) the non-smooth fold–Hopf bifurcation (co-rotating plane)")
    fig.tight_layout()
    caption = (
        "Fig. 4. The function F_1(T) whose zeros are the periods of one-impact orbits: (a) on [0, 30] at γ = "
        "0.1 and (b) on [0, 40] at γ = 0.05; (c) its zeros T_0,n,a and T_0,n,b against γ with the smooth "
        f"folds {'γ_F,1..3' if rep.paper else 'γ_F found there'} and γ_DIB marked; (d) a sketch of the small "
        "orbits born at the boundary equilibrium."
    )
    return _save(rep, out, fig, "fig4_f1", caption)


def _local_overlay(p: Parameters) -> Callable[[str, np.ndarray], np.ndarray | None] | None:
    """First-order estimate of rdot or thetadot of B1,a/B1,b near gamma* (MODEL.md §6)."""
    try:
        analysis = local_analysis(p)
    except ParameterError:
        return None
    g_star = boundary_gamma(p)
    orbits = {o.label: o for o in analysis.orbits}

    def estimate(label: str, gammas: np.ndarray, quantity: str = "rdot"):
        o = orbits.get(label)
        if o is None or o.rdot_slope is None:
            return None
        slope = o.rdot_slope if quantity == "rdot" else o.thetadot_slope
        return (np.asarray(gammas) - g_star) * slope

    return estimate


def _autoscale_y(ax, margin: float = 0.08, select: Callable[[str], bool] | None = None) -> None:
    """Fit the y-range to the lines inside the current x-range.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    margin : float
        Space added above and below, as a fraction of the span.
    select : callable, optional
        Only the lines whose gid it accepts count (all lines when None).
    """
    lo, hi = ax.get_xlim()
    ys = []
    for line in ax.get_lines():
        if select is not None and not select(line.get_gid() or ""):
            continue
        x, y = (np.asarray(v, dtype=float) for v in line.get_data())
        if x.shape != y.shape or x.size < 2:
            continue
        sel = (x >= lo) & (x <= hi) & np.isfinite(y)
        ys.append(y[sel])
    y = np.concatenate(ys) if ys else np.array([])
    if y.size:
        span = max(y.max() - y.min(), 1e-12)
        ax.set_ylim(y.min() - margin * span, y.max() + margin * span)


def _plausible(gid: str) -> bool:
    """The lines of orbits that are admissible and physically plausible (gid ``"<label>:plausible-..."``)."""
    return ":plausible-" in gid


def _fig5(p: Parameters, rep: Reproduction, out: Path, branches) -> Figure:
    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    (zoom_b, _), (zoom_d, _) = PAPER_VIEWS["fig5b"], PAPER_VIEWS["fig5d"]
    # the local estimate, about gamma*, where gamma* exists and lies in the zoomed views (MODEL.md §6)
    g_star = boundary_gamma(p)
    in_view = g_star is not None and all(lo <= g_star <= hi for lo, hi in (zoom_b, zoom_d))
    estimate = _local_overlay(p) if in_view else None
    local_r = None if estimate is None else (lambda lab, g: estimate(lab, g, "rdot"))
    local_t = None if estimate is None else (lambda lab, g: estimate(lab, g, "thetadot"))
    # the wide views: fitted to the plausible orbits (the virtual ends run to |rdot| = rdot_max), with room
    # around them for the virtual and implausible parts nearby
    _panel(axes[0, 0], lambda: (plot_rdot(p, branches=branches, ax=axes[0, 0]),
                                _autoscale_y(axes[0, 0], 0.5, _plausible)),
           r"(a) $\dot r^-$ of $B_{1,a}$–$B_{1,d}$")
    with_estimate = "" if estimate is None else " with the local estimate"
    _panel(axes[0, 1], lambda: (plot_rdot(p, branches=branches, ax=axes[0, 1], labels=("B1,a", "B1,b"),
                                          xlim=zoom_b, local=local_r), _autoscale_y(axes[0, 1])),
           r"(b) $B_{1,a}$ and $B_{1,b}$" + with_estimate)
    _panel(axes[1, 0], lambda: (plot_thetadot(p, branches=branches, ax=axes[1, 0]),
                                _autoscale_y(axes[1, 0], 0.5, _plausible)),
           r"(c) $\dot\theta^-$ of $B_{1,a}$–$B_{1,d}$")
    _panel(axes[1, 1], lambda: (plot_thetadot(p, branches=branches, ax=axes[1, 1], labels=("B1,a", "B1,b"),
                                              xlim=zoom_d, local=local_t), _autoscale_y(axes[1, 1])),
           r"(d) $\dot\theta^-$ of $B_{1,a}$ and $B_{1,b}$" + with_estimate)
    fig.tight_layout()
    caption = (
        "Fig. 5. Impact velocities of the one-impact orbits B1,a to B1,d against γ (solid: admissible and "
        "plausible, thick where stable; dotted: not plausible; dashed: virtual; markers: the events along the"
        " branches): (a) ṙ⁻ and (c) θ̇⁻ over the whole range including negative γ; (b), (d) B1,a and B1,b for"
        " γ from 0 to 0.2"
        + ("." if estimate is None else ", through the non-smooth fold–Hopf point γ* and the fold γ_F,1, with the"
           " first-order local estimate of MODEL.md §6 of each overlaid.")
    )
    return _save(rep, out, fig, "fig5_branches", caption)


def _fig6(p: Parameters, rep: Reproduction, out: Path, branches, diagram) -> Figure:
    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    (xlim, ylim) = PAPER_VIEWS["fig6b"]
    _panel(axes[0, 0], lambda: plot_codim2(p, ("gamma", "omega"), ax=axes[0, 0], diagram=diagram),
           "(a) the (γ, ω) plane")
    _panel(axes[0, 1], lambda: plot_max_multiplier(p, branches=branches, ax=axes[0, 1], xlim=xlim, ylim=ylim,
                                                    log=False, legend=False),
           r"(b) largest |multiplier| of $B_{1,a}$–$B_{1,d}$")
    _panel(axes[1, 0], lambda: plot_max_multiplier(p, branches=branches, ax=axes[1, 0], xlim=WIDE),
           "(c) the same over the whole range (log scale)")
    # one legend for (b) and (c), in the fourth slot: (c) shows every kind of line and event that (b) does
    axes[1, 1].axis("off")
    wide = axes[1, 0].get_legend()
    if wide is not None:
        axes[1, 1].legend(handles=wide.legend_handles, labels=[t.get_text() for t in wide.texts], loc="center",
                          fontsize=10, title="(b) and (c)")
        wide.remove()
    fig.tight_layout()
    caption = (
        "Fig. 6. (a) The (γ, ω) plane: the first smooth-fold curve γ_F,1(ω) and the curve γ_DIB(ω) = √(ρ² − "
        "(1 − ω²)²), with the regions R1–R4 (grey, \"other\": points fitting none of them) and the labels NSFH,"
        " NSF and Pers; (b) the largest modulus of the multipliers of B1,a..d against γ from 0 to 0.2 (stable"
        " below 1), with the events along the branches marked; (c) the same over the whole range computed, "
        "including negative γ, on a log scale."
    )
    return _save(rep, out, fig, "fig6_codim2", caption)


def _fig7(p: Parameters, rep: Reproduction, out: Path, branches) -> Figure:
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    (xa, ya), (xb, yb) = PAPER_VIEWS["fig7a"], PAPER_VIEWS["fig7b"]
    _panel(axes[0], lambda: plot_extrema(p, branches=branches, ax=axes[0], labels=("B1,a", "B1,b"), regular=True,
                                         xlim=xa, ylim=ya),
           r"(a) $B_{1,a}$, $B_{1,b}$ and $x_R$")
    _panel(axes[1], lambda: plot_extrema(p, branches=branches, ax=axes[1], labels=("B1,c", "B1,d"), regular=False,
                                         xlim=xb, ylim=yb),
           r"(b) $B_{1,c}$ and $B_{1,d}$")
    fig.tight_layout()
    caption = (
        "Fig. 7. Local extrema of r(t) between impacts against γ from 0 to 0.2: (a) for B1,a, B1,b and x_R, "
        "(b) for B1,c and B1,d, with the non-smooth fold–Hopf point, the grazing of B1,d and the change in "
        "the number of extrema marked."
    )
    return _save(rep, out, fig, "fig7_extrema", caption)


def _first(events, type_: str, orbit: str | None = None, sign: int = 0):
    for e in sorted(events, key=lambda e: e.value):
        if e.kind == type_ and (orbit is None or orbit in e.orbits) and (sign == 0 or sign * e.value > 0):
            return e
    return None


def _fold_values(events) -> list[float | None]:
    """gamma_F,n for n = 1, 2, 3: the smooth fold where B_n,a meets B_n,b."""
    out = []
    for n in (1, 2, 3):
        e = next((e for e in events if e.kind == "fold" and {f"B{n},a", f"B{n},b"} <= set(e.orbits)), None)
        out.append(None if e is None else e.value)
    return out


def reproduce(out: str | Path, params: Parameters | None = None, *, progress: bool = True) -> Reproduction:
    """Compute everything behind the paper's Figures 2 to 7 and write the report to ``out``.

    Writes each figure as PNG and SVG, ``report.json`` and a self-contained
    ``report.html``. report.json holds our values and, under ``"paper"``, the
    paper's stated values keyed by the report's own keys (dotted for nested
    values, an index for lists, e.g. ``"codim2_fold_dib.omega"``,
    ``"gamma_F.0"``), as the paper writes them. With ``params`` other than the
    paper's, ``"paper"`` is empty and so is the paper column of the table.

    Parameters
    ----------
    out : path
        Output folder (created).
    params : Parameters, optional
        Parameters of the run; default `paper_parameters`.
    progress : bool
        Report each stage on stderr.

    Returns
    -------
    Reproduction
    """
    paper = paper_parameters()
    p = paper if params is None else check_params(params)
    is_paper = p == paper
    progress = check_bool("progress", progress)
    out = check_path("out", out)
    if out.exists() and not out.is_dir():
        raise ParameterError(f"out = {str(out)!r} is a file; allowed: a folder, new or existing")
    out.mkdir(parents=True, exist_ok=True)
    rep = Reproduction(p, is_paper)
    stages = _Stages(progress, 8)
    machine = reference_machine().parameters()

    g_star = stages.run("equilibria", lambda: boundary_gamma(p))
    g_pers = boundary_gamma(p.replace(omega=1.0))
    branches = stages.run("branches", lambda: orbit_branches(p, "gamma", *WIDE))
    def two_parameter():
        try:
            return codim2_diagram(p, ("gamma", "omega"), None, folds=(1,), grazing=())
        except ParameterError:
            return None

    diagram = stages.run("two-parameter diagram", two_parameter)
    events = branches.events
    folds = _fold_values(events)
    # the paper's bifurcations of B1,d lie at positive damping; gamma < 0 mirrors some of them
    nsfh = _first(events, "nsfh", sign=1)
    graze = _first(events, "grazing", "B1,d", sign=1)
    stab = next((e for e in sorted(events, key=lambda e: e.value)
                 if e.kind in STABILITY_TYPES and "B1,d" in e.orbits and e.value > 0), None)
    extrema = _first(events, "extrema-change", "B1,d", sign=1)
    coalesce = _first(events, "ac-coalescence", sign=-1)
    # of the points where gamma_F,1(omega) = gamma_DIB(omega), the one nearest the run's omega
    fold_dibs = [] if diagram is None else [pt for pt in diagram.points if pt.type == "fold-dib"]
    fold_dib = min(fold_dibs, key=lambda pt: abs(pt.values[1] - p.omega), default=None)

    stages.run("figure 2", lambda: _fig2(p, rep, out))
    stages.run("figure 3", lambda: _fig3(p, rep, out))
    stages.run("figure 4", lambda: _fig4(p, rep, out, None if nsfh is None else nsfh.value))
    stages.run("figure 5", lambda: _fig5(p, rep, out, branches))
    stages.run("figures 6 and 7", lambda: (_fig6(p, rep, out, branches, diagram), _fig7(p, rep, out, branches)))

    rep.timings = stages.timings
    rep.report = {
        "nondimensional": {"gamma": machine.gamma, "omega": machine.omega, "rho": machine.rho},
        "parameters": p.as_dict(),
        "gamma_star": g_star,
        "gamma_F": folds,
        "gamma_DIB": None if nsfh is None else nsfh.value,
        "B1d_grazing": None if graze is None else graze.value,
        "B1d_stability": {"gamma": None if stab is None else stab.value, "type": None if stab is None else stab.kind},
        "B1d_extrema_change": None if extrema is None else extrema.value,
        "ac_coalescence": None if coalesce is None else coalesce.value,
        "codim2_fold_dib": {
            "gamma": None if fold_dib is None else fold_dib.values[0],
            "omega": None if fold_dib is None else fold_dib.values[1],
        },
        "persistence_gamma_star": g_pers,
        "paper": dict(paper_values()["values"]) if is_paper else {},
        "timings": rep.timings,
        "version": __version__,
    }
    rep.quantities = _quantities(rep.report, rep.report["paper"])
    t0 = time.perf_counter()
    _write_json(rep, out)
    _write_html(rep, out)
    rep.timings["report"] = time.perf_counter() - t0
    rep.report["timings"] = rep.timings
    _write_json(rep, out)
    return rep


_ROWS = [
    ("nondimensional.gamma", "γ = c/(mΩ) of the reference machine", ""),
    ("nondimensional.omega", "ω = √(k/(mΩ²)) of the reference machine", ""),
    ("nondimensional.rho", "ρ = e_c/c_r of the reference machine", ""),
    ("gamma_star", "γ*: boundary equilibrium (x_R on the stator)", ""),
    ("gamma_F.0", "γ_F,1: first smooth fold (B1,a meets B1,b)", ""),
    ("gamma_F.1", "γ_F,2: second smooth fold", ""),
    ("gamma_F.2", "γ_F,3: third smooth fold", ""),
    ("gamma_DIB", "γ_DIB: non-smooth fold–Hopf (ṙ of B1,a/b reaches 0)", ""),
    ("B1d_grazing", "γ where B1,d grazes (interior maximum of r reaches 1)", ""),
    ("B1d_stability.gamma", "γ where B1,d changes stability", ""),
    ("B1d_stability.type", "how B1,d changes stability", "not stated in the paper"),
    ("B1d_extrema_change", "γ where the number of interior extrema of r on B1,d changes", ""),
    ("ac_coalescence", "γ < 0 where B1,a meets B1,c", ""),
    ("codim2_fold_dib.gamma", "γ where γ_F,1(ω) = γ_DIB(ω)", ""),
    ("codim2_fold_dib.omega", "ω where γ_F,1(ω) = γ_DIB(ω)", ""),
    ("persistence_gamma_star", "γ* at ω = 1 (persistence; equals ρ)", ""),
]


def _lookup(report: dict[str, Any], key: str) -> Any:
    value: Any = report
    for part in key.split("."):
        value = value[int(part)] if isinstance(value, list) else value.get(part)
        if value is None:
            return None
    return value


def _quantities(report: dict[str, Any], stated: dict[str, str]) -> list[Quantity]:
    rows = []
    for key, label, note in _ROWS:
        ours = _lookup(report, key)
        paper = stated.get(key)
        if paper is None and not note and stated:
            note = "no value from the paper on file"
        rows.append(Quantity(key, label, ours, paper, _agrees(ours, paper), note))
    return rows


def _jsonable(obj: Any) -> Any:
    from ..io.json import jsonable

    return jsonable(obj)


def _write_json(rep: Reproduction, out: Path) -> None:
    import json

    (out / "report.json").write_text(json.dumps(_jsonable(rep.report), indent=2, allow_nan=False) + "\n",
                                     encoding="utf-8")


def _fmt(value: Any) -> str:
    if value is None:
        return "—"
    if isinstance(value, float):
        return f"{value:.6g}"
    return html.escape(str(value))


# subscripts as the plain-text labels write them: x_R, x_P1, γ_F,1, γ_F,1..3, T_0,n,a, e_c, F_1(T), and the
# orbit labels B1,a, B1,a..d, B1,a/b
_SUBSCRIPT = re.compile(r"(?<=[A-Za-z\u0370-\u03ff])_([A-Za-z0-9]+(?:(?:,|\.\.)[A-Za-z0-9]+)*)")
_ORBIT = re.compile(r"\bB([1-9][0-9]*,[a-d](?:(?:\.\.|/)[a-d])?)(?![A-Za-z0-9])")


def _html_text(text: str) -> str:
    """Plain text with its math labels as HTML: ``x_R`` gives x<sub>R</sub>, ``B1,a`` gives B<sub>1,a</sub>."""
    out = html.escape(text)
    out = _SUBSCRIPT.sub(r"<sub>\1</sub>", out)
    return _ORBIT.sub(r"B<sub>\1</sub>", out)


def _write_html(rep: Reproduction, out: Path) -> None:
    """One self-contained page: figures inlined as base64 PNG, the table, parameters and version."""
    rows = []
    for q in rep.quantities:
        agree = {True: "yes", False: "no", None: "—"}[q.agrees]
        cls = {True: "agree", False: "disagree", None: ""}[q.agrees]
        rows.append(
            f"<tr class='{cls}'><td>{_html_text(q.label)}</td><td><code>{html.escape(q.key)}</code></td>"
            f"<td>{_fmt(q.paper)}</td><td>{_fmt(q.ours)}</td><td>{agree}</td><td>{_html_text(q.note)}</td></tr>"
        )
    figs = []
    for name, caption, png, svg in rep.figures:
        data = base64.b64encode(png.read_bytes()).decode("ascii")
        figs.append(
            f"<figure id='{name}'><img alt='{html.escape(name)}' src='data:image/png;base64,{data}'>"
            f"<figcaption>{_html_text(caption)} <a href='{svg.name}'>SVG</a></figcaption></figure>"
        )
    stated = rep.report.get("paper", {})
    params = "".join(
        f"<tr><td>{html.escape(k)}</td><td>{_fmt(stated.get(f'parameters.{k}'))}</td><td>{v:.12g}</td></tr>"
        for k, v in rep.params.as_dict().items()
    )
    timings = "".join(f"<tr><td>{html.escape(k)}</td><td>{v:.2f} s</td></tr>" for k, v in rep.timings.items())
    source = "the paper's parameters" if rep.paper else "parameters other than the paper's (paper column left empty)"
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>rotorcontact: reproduction of Mora et al. (2015)</title>
<style>
body {{ font-family: sans-serif; max-width: 1100px; margin: 2em auto; color: #222; }}
table {{ border-collapse: collapse; margin: 1em 0; }}
td, th {{ border: 1px solid #bbb; padding: 0.3em 0.6em; text-align: left; }}
tr.agree td:nth-child(5) {{ color: #1a7f37; font-weight: bold; }}
tr.disagree td:nth-child(5) {{ color: #b00020; font-weight: bold; }}
figure {{ margin: 2em 0; }} img {{ max-width: 100%; }}
figcaption {{ font-size: 0.95em; color: #333; }}
</style></head><body>
<h1>Reproduction of Mora, Budd, Glendinning &amp; Keogh, Proc. R. Soc. A (2015)</h1>
<p>Computed from scratch by rotorcontact {html.escape(__version__)} at {source}.</p>
<h2>Results</h2>
<table id="results"><thead><tr><th>quantity</th><th>key</th><th>paper</th><th>rotorcontact</th>
<th>agrees at the paper's precision</th><th>note</th></tr></thead><tbody>
{''.join(rows)}
</tbody></table>
<h2>Figures</h2>
{''.join(figs)}
<h2>Parameters</h2>
<table id="parameters"><thead><tr><th>parameter</th><th>paper</th><th>rotorcontact</th></tr></thead>
<tbody>{params}</tbody></table>
<h2>Timings</h2>
<table id="timings"><tbody>{timings}</tbody></table>
<p>Software: rotorcontact {html.escape(__version__)}.</p>
</body></html>
"""
    (out / "report.html").write_text(page, encoding="utf-8")
