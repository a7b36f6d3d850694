"""The zeros T0,n,a and T0,n,b of F1 against a parameter, and their folds gamma_F,n.

The zeros of F1 do not depend on rdot: each is a curve in the (T, param) plane,
followed here by pseudo-arclength continuation of the regularised F1 of
`rotorcontact.maps.orbit_system` (R1 = 0, one equation in (T, param); same zeros,
no pole at the undamped resonances). Curves are seeded by every zero that
`rotorcontact.maps.impact_map.f1_zeros` finds (with a guarantee) at ``n_seeds``
parameter values. A fold of a curve, where the zeros T0,n,a and T0,n,b of a
pair merge (dR1/dT = 0), is located to ``location_tol`` in the parameter: at
the reference parameters these are gamma_F,1, gamma_F,2, ...
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .engine import (
    ContinuationSettings,
    EventFunction,
    continue_both_ways,
    corrected_crossings,
)
from ..errors import ParameterError
from .results import BranchEvent, BranchResult, check_param_range
from ..maps.impact_map import f1_zeros
from .branches import MAX_SEEDS
from ..maps.orbit_system import OneImpactSystem, regularised_residual
from ..model.params import Parameters, check_range
from ..model.validation import check_int, check_params, settings_or_default

__all__ = ["ZeroFold", "ZeroCurve", "F1ZeroCurves", "f1_zero_curves"]


#: A fold of the zeros of F1 is a `BranchEvent` of kind ``"fold"``: ``value`` the parameter there
#: (gamma_F,n when the parameter is gamma), ``T`` the double zero, ``n`` the pair, ``orbits`` the two
#: zeros that merge (``("T0,n,a", "T0,n,b")``).
ZeroFold = BranchEvent


@dataclass(frozen=True)
class ZeroCurve:
    """One computed curve of zeros of F1.

    Attributes
    ----------
    values, T : numpy.ndarray
        The parameter and the zero along the curve.
    kinds : numpy.ndarray of str
        ``"a"`` (F1 decreasing through 0) or ``"b"`` at each point.
    n : numpy.ndarray of int
        Index of the pair at each point.
    """

    values: np.ndarray = field(repr=False)
    T: np.ndarray = field(repr=False)
    kinds: np.ndarray = field(repr=False)
    n: np.ndarray = field(repr=False)


@dataclass(frozen=True)
class F1ZeroCurves(BranchResult):
    """Zeros of F1 against a parameter.

    Attributes
    ----------
    param : str
    events : tuple of BranchEvent
        The folds, sorted by n, then value.
    start, stop : float
    base : Parameters
    t_max : float
    curves : tuple of ZeroCurve
    """

    start: float
    stop: float
    base: Parameters
    t_max: float
    curves: tuple[ZeroCurve, ...] = field(repr=False)

    @property
    def folds(self) -> tuple[BranchEvent, ...]:
        """The folds (`events`)."""
        return self.events

    def fold_values(self, n: int) -> tuple[float, ...]:
        """Parameter values of the folds of pair n.

        Raises
        ------
        ParameterError
            Unless ``n`` is an integer >= 1 (numpy's too).
        """
        n = check_int("n", n, 1)
        return tuple(f.value for f in self.events if f.n == n)

    def curves_dict(self) -> list[dict[str, list]]:
        """Per curve: the parameter, the zero T, its kind and its pair along the curve."""
        return [{self.param: c.values.tolist(), "T": c.T.tolist(), "kind": c.kinds.tolist(), "n": c.n.tolist()}
                for c in self.curves]


def f1_zero_curves(
    params: Parameters,
    param: str = "gamma",
    start: float = 0.0,
    stop: float = 0.25,
    *,
    t_max: float = 12.0,
    n_seeds: int = 26,
    settings: ContinuationSettings | None = None,
) -> F1ZeroCurves:
    """Follow every zero of F1 with T <= t_max as ``param`` goes from ``start`` to ``stop``.

    Parameters
    ----------
    params : Parameters
        The other parameters.
    param : str
        One of gamma, omega, rho, mu, d (F1 depends only on gamma, omega, mu, d).
    start, stop : float
        The range, start < stop.
    t_max : float
        Largest zero followed.
    n_seeds : int
        Parameter values at which the zeros are found to seed the curves (>= 2).
    settings : ContinuationSettings, optional

    Returns
    -------
    F1ZeroCurves
    """
    system = OneImpactSystem(check_params(params), param)
    start, stop = check_param_range(param, params, start, stop)
    t_max = check_range("t_max", t_max, low=0.0, low_open=True)
    n_seeds = check_int("n_seeds", n_seeds, 2, MAX_SEEDS)
    settings = settings_or_default(settings, ContinuationSettings,
                                   lambda: ContinuationSettings(step=0.01, max_step=0.03, location_tol=1e-10))
    span = stop - start

    def at(v):
        return system.params_at(v)

    def residual(y):
        return np.array([regularised_residual(at(y[1]), float(y[0]), 0.0)[0][0]])

    def slope(y):
        return float(regularised_residual(at(y[1]), float(y[0]), 0.0)[1][0, 0])

    events = [
        EventFunction("lower", lambda y: y[1] - start, terminal=True),
        EventFunction("upper", lambda y: stop - y[1], terminal=True),
        EventFunction("t-max", lambda y: t_max - y[0], terminal=True),
        EventFunction("t-min", lambda y: y[0] - 1e-3, terminal=True),
        EventFunction("fold", slope),
    ]
    seeds = []
    for v in np.linspace(start, stop, int(n_seeds)):
        for z in f1_zeros(at(v), t_max):
            seeds.append([z.T, float(v), False])
    weights = np.array([1.0, 1.0 / span])
    curves: list[ZeroCurve] = []
    folds: list[tuple[float, float]] = []
    for seed in seeds:
        if seed[2]:
            continue
        seed[2] = True
        both = continue_both_ways(residual, seed[:2], events=events, settings=settings, weights=weights,
                                  param_index=1)
        if both is None:
            continue
        pts = both.points
        for r in both.runs:
            folds.extend((float(e.y[1]), float(e.y[0])) for e in r.events if e.name == "fold" and e.continuous)
        _cover(residual, pts, seeds, settings)
        kinds = np.array(["a" if slope(y) < 0 else "b" for y in pts])
        ns = np.array([_pair(at(y[1]), y[0], k, t_max) for y, k in zip(pts, kinds)])
        curves.append(ZeroCurve(values=pts[:, 1].copy(), T=pts[:, 0].copy(), kinds=kinds, n=ns))
    out_folds: list[BranchEvent] = []
    for value, T in sorted(folds):
        if any(abs(f.value - value) <= 1e-8 and abs(f.T - T) <= 1e-6 for f in out_folds):
            continue
        n = _pair(at(value), T, "a", t_max)
        out_folds.append(BranchEvent(kind="fold", value=value, param=param, orbits=(f"T0,{n},a", f"T0,{n},b"),
                                     T=T, n=n))
    out_folds.sort(key=lambda f: (f.n, f.value))
    return F1ZeroCurves(param=param, events=tuple(out_folds), start=start, stop=stop, base=params, t_max=t_max,
                        curves=tuple(curves))


def _pair(p: Parameters, T: float, kind: str, t_max: float) -> int:
    try:
        zeros = f1_zeros(p, max(t_max, T * (1 + 1e-6) + 1e-6))
    except (ParameterError, RuntimeError):
        return 0
    same = [z for z in zeros if z.kind == kind] or list(zeros)
    return min(same, key=lambda z: abs(z.T - T)).n if same else 0


def _cover(residual, pts: np.ndarray, seeds: list, settings) -> None:
    for seed in seeds:
        if seed[2]:
            continue
        for g in corrected_crossings(residual, pts, 1, seed[1], settings=settings):
            if abs(g[0] - seed[0]) <= 1e-6 * (1.0 + seed[0]):
                seed[2] = True
                break
