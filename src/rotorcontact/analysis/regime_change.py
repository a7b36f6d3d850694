"""Where the motion of a trajectory settled, and how much a running average varies over a window.

`final_regime` finds the regime a trajectory ends in and the time it began:

* ``"contact"``: the run ends in one continuous contact phase (rolling round
  the stator, or sliding onto a pseudo-equilibrium); it began at the start of
  that phase;
* ``"no-contact"``: the run ends in a free flight longer than three times the
  longest interval between its last impacts (and than three whirl periods
  2 pi); it began at the last impact or lift-off;
* ``"periodic"``: impacts that repeat every p <= `MAX_PERIOD_IMPACTS`
  impacts, with no contact, up to the end of the run; it began at the first
  impact from which every impact matches the one p earlier in angle, rdot,
  thetadot and time since it to ``tol`` (as `rotorcontact.simulation.motion.detect_period`
  judges the last impacts);
* ``None``: the run ends in none of these (irregular or quasi-periodic
  impacting, impacts mixed with contact): no settled regime.

`subwindow_rates` and `spread` give the error estimate of a time average: the
window is cut into sub-windows, the average is taken over each, and the
standard error of the mean of those averages is reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..model.validation import check_float, check_type, finite_array, quoted
from ..simulation.motion import MAX_PERIOD_IMPACTS, REPEAT_TOL
from ..simulation.trajectory import Trajectory

__all__ = ["FINAL_REGIMES", "SUBWINDOWS", "FinalRegime", "final_regime", "spread", "subwindow_rates"]

#: Number of sub-windows of the error estimate.
SUBWINDOWS = 8
#: Kinds of final regime.
FINAL_REGIMES = ("contact", "no-contact", "periodic")
#: A final free flight is settled when longer than this many whirl periods 2 pi and impact intervals.
SETTLED_FLIGHTS = 3.0


@dataclass(frozen=True)
class FinalRegime:
    """The regime a trajectory ends in.

    Attributes
    ----------
    kind : str
        One of `FINAL_REGIMES`.
    t_begin : float
        Time at which it began (for ``"periodic"``, the time of an impact).
    impacts_per_period : int
        Impacts per period for ``"periodic"``, else 0.
    """

    kind: str
    t_begin: float
    impacts_per_period: int = 0


def _angle_gap(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * (a - b))))


def _periodic_start(t, theta, rdot, thetadot, tol: float) -> tuple[int, int] | None:
    """(p, first impact index) of the periodic tail of an impact sequence, smallest p first."""
    n = len(t)
    for p in range(1, MAX_PERIOD_IMPACTS + 1):
        need = max(2 * p, 6) + p + 1
        if n < need:
            return None
        dt = t[p:] - t[:-p]
        miss = np.maximum.reduce([
            _angle_gap(theta[p:], theta[:-p]),
            np.abs(rdot[p:] - rdot[:-p]),
            np.abs(thetadot[p:] - thetadot[:-p]),
            np.abs(dt - dt[-1]) / max(1.0, float(dt[-1])),
        ])
        bad = np.flatnonzero(~(miss < tol))
        # miss[j] compares impact j + p with impact j: impacts from `start` on repeat
        start = 0 if bad.size == 0 else int(bad[-1]) + 1
        if n - start >= need:
            return p, start
    return None


def final_regime(traj: Trajectory, tol: float = REPEAT_TOL) -> FinalRegime | None:
    """The regime ``traj`` ends in and when it began (module docstring); None when it ends unsettled.

    Raises
    ------
    ParameterError
        Unless ``traj`` is a `Trajectory` and ``tol`` a finite number > 0.
    """
    check_type("traj", traj, Trajectory, "a Trajectory (rotorcontact.simulate)")
    tol = check_float("tol", tol, 0.0, low_open=True)
    t_stop = float(traj.t_stop)
    contacts = traj.contact_intervals
    imp = traj.impacts
    if contacts and contacts[-1].t_end >= t_stop:
        return FinalRegime("contact", float(contacts[-1].t_start))
    t_last = max(float(imp.t[-1]) if len(imp) else 0.0, float(contacts[-1].t_end) if contacts else 0.0)
    gap = float(np.max(np.diff(imp.t[-MAX_PERIOD_IMPACTS - 1:]))) if len(imp) >= 2 else 0.0
    if t_stop - t_last > SETTLED_FLIGHTS * max(gap, 2.0 * math.pi):
        return FinalRegime("no-contact", t_last)
    t_contact = float(contacts[-1].t_end) if contacts else -math.inf
    later = np.asarray(imp.t) > t_contact
    found = _periodic_start(np.asarray(imp.t)[later], np.asarray(imp.theta)[later], np.asarray(imp.rdot)[later],
                            np.asarray(imp.thetadot)[later], tol)
    if found is None:
        return None
    p, start = found
    return FinalRegime("periodic", float(np.asarray(imp.t)[later][start]), p)


def subwindow_rates(times: np.ndarray, sums: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Average rates of running sums over the sub-windows between ``edges``.

    ``sums[i]`` is the value of the running sums at ``times[i]`` (times
    non-decreasing; at a repeated time the first value is taken); values
    between marks are interpolated linearly. Returns an array
    (len(edges) - 1, n_sums).

    Raises
    ------
    ParameterError
        Unless ``times`` are finite and non-decreasing, ``sums`` finite of shape (len(times), n_sums) and
        ``edges`` at least two finite, increasing times.
    """
    t = finite_array("times", times, "a list of finite, non-decreasing times")
    if np.any(np.diff(t) < 0.0):
        raise ParameterError(f"times = {quoted(times)} is invalid (they decrease); allowed: a list of finite, "
                             "non-decreasing times")
    one_row_per_time = f"finite running sums, an array of shape ({t.size}, n_sums): one row per time"
    s = finite_array("sums", sums, one_row_per_time, ndims=(2,))
    if s.shape[0] != t.size:
        raise ParameterError(f"sums = {quoted(sums)} is invalid (shape {s.shape} for {t.size} times); allowed: "
                             f"{one_row_per_time}")
    e = finite_array("edges", edges, "at least two finite, increasing times")
    if e.size < 2 or not np.all(np.diff(e) > 0.0):
        raise ParameterError(f"edges = {quoted(edges)} is invalid; allowed: at least two finite, increasing times")
    return _subwindow_rates(t, s, e)


def _subwindow_rates(times: np.ndarray, sums: np.ndarray, edges: np.ndarray) -> np.ndarray:
    times = np.asarray(times, dtype=float)
    sums = np.asarray(sums, dtype=float)
    uniq, first = np.unique(times, return_index=True)
    at = np.column_stack([np.interp(edges, uniq, sums[first, j]) for j in range(sums.shape[1])])
    return np.diff(at, axis=0) / np.diff(edges)[:, None]


def spread(rates: np.ndarray) -> np.ndarray:
    """Standard error of the mean of sub-window rates (``inf`` with fewer than two sub-windows).

    ``rates`` holds one row per sub-window: an array (k, n_rates), or (k,) for a single rate.

    Raises
    ------
    ParameterError
        Unless ``rates`` are finite real numbers in an array of shape (k,) or (k, n_rates), k >= 1.
    """
    return _spread(finite_array("rates", rates, "finite real numbers, one row per sub-window: an array of shape "
                                "(k,) or (k, n_rates) with k >= 1", ndims=(1, 2)))


def _spread(rates: np.ndarray) -> np.ndarray:
    rates = np.asarray(rates, dtype=float)
    k = rates.shape[0]
    if k < 2:
        return np.full(rates.shape[1:], math.inf)
    return np.std(rates, axis=0, ddof=1) / math.sqrt(k)
