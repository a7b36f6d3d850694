"""Classification of the long-run motion of a trajectory."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ParameterError
from ..model.angles import angle_difference
from ..model.validation import check_float, check_int, check_type, quoted, real_array

if TYPE_CHECKING:
    from .trajectory import Trajectory

__all__ = ["MotionSummary", "classify", "detect_period", "REGIMES", "REGIME_NAMES", "REGIME_ALIASES", "canonical_regime",
           "regime_code"]

MAX_PERIOD_IMPACTS = 16
REPEAT_TOL = 1e-6
MIN_IRREGULAR = 30
WINDOW = 1.0 / 3.0
#: The contact regimes of a trajectory. The same names are used everywhere a regime is
#: reported: simulations, sweeps, basins, design maps, NetCDF attributes, figures and JSON.
REGIMES = ("no-contact", "periodic-impacting", "irregular-impacting", "forward-rub", "backward-whirl", "mixed")
#: Former names of regimes, accepted on input (`canonical_regime`): ``"rub"`` is ``"forward-rub"``
#: (continuous contact sliding forward) and ``"rolling"`` is ``"backward-whirl"`` (rolling round the stator).
REGIME_ALIASES = {"rub": "forward-rub", "rolling": "backward-whirl"}

#: Codes of the regimes as the compiled batch kernel (`rotorcontact.studies.batch`) stores them: the
#: `REGIMES` in order, then a window with too few impacts to tell (``"undetermined"``; `classify` reports
#: it as motion ``"undetermined"``, regime ``"irregular-impacting"``) and a failed run (``"failed"``;
#: `classify` reports regime None).
NO_CONTACT, PERIODIC, IRREGULAR, RUB, ROLL, MIXED, UNDETERMINED, FAILED_REGIME = range(8)
#: Names of the regime codes.
REGIME_NAMES = (*REGIMES, "undetermined", "failed")


def canonical_regime(name: str) -> str:
    """The current name of a regime or class name: former names (`REGIME_ALIASES`) are translated.

    Any other name (including orbit labels such as ``"B1,d"``) is returned unchanged.

    Parameters
    ----------
    name : str
        A regime name, current or former.

    Returns
    -------
    str
        ``"forward-rub"`` for ``"rub"``, ``"backward-whirl"`` for ``"rolling"``, otherwise ``name``.

    Raises
    ------
    ParameterError
        If ``name`` is not text.
    """
    if not isinstance(name, str):
        raise ParameterError(f"name = {name!r} is invalid; allowed: a regime or class name (text)")
    return REGIME_ALIASES.get(name, name)


def regime_code(summary: "MotionSummary") -> int:
    """The code (index into `REGIME_NAMES`) of a summary's regime, as the batch kernel classifies the same run.

    Parameters
    ----------
    summary : MotionSummary
        A result of `classify`.

    Returns
    -------
    int
        `FAILED_REGIME` for a failed run, `UNDETERMINED` for an undetermined motion, else the index of
        its regime in `REGIMES`.

    Raises
    ------
    ParameterError
        If ``summary`` is not a `MotionSummary`.
    """
    check_type("summary", summary, MotionSummary, "a MotionSummary (classify)")
    if summary.regime is None:
        return FAILED_REGIME
    if summary.motion == "undetermined":
        return UNDETERMINED
    return REGIMES.index(summary.regime)


@dataclass(frozen=True)
class MotionSummary:
    """Long-run motion of a trajectory, judged on the last third of the run.

    Attributes
    ----------
    motion : str
        What the impact sequence does: ``"no-contact"`` (no impact and no
        contact: the rotor settles towards the regular equilibrium),
        ``"periodic-impacting"``, ``"irregular"`` (impacting with no period of
        up to `MAX_PERIOD_IMPACTS` impacts), ``"chatter"`` (impacts accumulate
        and the run stopped there), ``"contact"`` (continuous contact, no
        impacts), ``"undetermined"`` (too few impacts to tell) or ``"failed"``
        (the simulation could not continue; nothing is said about the motion).
    regime : str or None
        The contact regime, one of `REGIMES`: ``"forward-rub"`` is sliding
        forward only (settling onto a pseudo-equilibrium), ``"backward-whirl"``
        ends rolling round the stator, ``"mixed"`` has impacts and contact.
        For a run stopped at chatter it describes the run up to that point.
        None for a failed run.
    n_impacts : int
        Number of impacts in the run.
    impacts_per_period, period : int or None, float or None
        Impacts per period and period of a periodic impacting motion.
    contact_fraction : float or None
        Fraction of the last third of the run spent in contact (None for a failed run).
    """

    motion: str
    regime: str | None
    n_impacts: int
    impacts_per_period: int | None = None
    period: float | None = None
    contact_fraction: float | None = 0.0

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _angle_diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(angle_difference(a, b))


def detect_period(theta, rdot, thetadot, t, *, max_p: int = MAX_PERIOD_IMPACTS, tol: float = REPEAT_TOL):
    """Smallest p such that the last impacts repeat every p impacts.

    The last ``max(2p, 6)`` impacts must each match the impact p earlier in
    angle, rdot and thetadot to ``tol``, and consecutive periods must agree to
    ``tol``. Returns ``(p, period)`` or ``(None, None)``.

    Raises
    ------
    ParameterError
        Unless the four sequences are 1-D arrays of real numbers of one length, ``max_p`` an integer >= 1
        and ``tol`` a number > 0.
    """
    arrays = [real_array(v) for v in (theta, rdot, thetadot, t)]
    if any(a is None for a in arrays) or any(a.ndim != 1 or a.shape != arrays[3].shape for a in arrays):
        raise ParameterError(f"theta, rdot, thetadot, t = {quoted(theta)}, ... are invalid; allowed: four 1-D "
                             "sequences of real numbers of one length (one entry per impact)")
    theta, rdot, thetadot, t = arrays
    max_p = check_int("max_p", max_p, 1)
    tol = check_float("tol", tol, 0.0, low_open=True)
    n = len(t)
    for p in range(1, max_p + 1):
        m = max(2 * p, 6)
        if n < m + p + 1:
            break
        cur = slice(n - m, n)
        prev = slice(n - m - p, n - p)
        if (
            np.all(_angle_diff(theta[cur], theta[prev]) < tol)
            and np.all(np.abs(rdot[cur] - rdot[prev]) < tol)
            and np.all(np.abs(thetadot[cur] - thetadot[prev]) < tol)
        ):
            periods = t[cur] - t[prev]
            if np.ptp(periods) < tol * max(1.0, periods.max()):
                return p, float(t[-1] - t[-1 - p])
    return None, None


def classify(traj: "Trajectory") -> MotionSummary:
    """Classify the long-run motion of ``traj`` (see `MotionSummary`); a `ParameterError` unless it is a
    `rotorcontact.Trajectory`."""
    from .trajectory import Trajectory

    check_type("traj", traj, Trajectory, "a Trajectory (rotorcontact.simulate)")
    imp = traj.impacts
    n = len(imp)
    if traj.status == "failed":
        # the run broke off: what it did up to then says nothing about its long-run regime
        return MotionSummary("failed", None, n, contact_fraction=None)
    t_win = traj.t_stop * (1.0 - WINDOW)
    stopped_at_chatter = traj.status == "chatter"
    late_impacts = int(np.count_nonzero(imp.t >= t_win))
    late = [c for c in traj.contact_intervals if c.t_end > t_win]
    contact_time = sum(min(c.t_end, traj.t_stop) - max(c.t_start, t_win) for c in late)
    fraction = contact_time / max(traj.t_stop - t_win, 1e-300)
    if stopped_at_chatter:
        # contact would follow; the regime describes the run up to the accumulation point
        regime = "mixed" if late else ("irregular-impacting" if late_impacts else "no-contact")
        return MotionSummary("chatter", regime, n, contact_fraction=fraction)
    if late_impacts == 0 and not late:
        return MotionSummary("no-contact", "no-contact", n)
    if late_impacts == 0:
        kinds = {c.kind for c in late}
        if late[-1].kind == "rolling":
            regime = "backward-whirl"
        elif kinds == {"sliding-forward"}:
            regime = "forward-rub"
        else:
            regime = "mixed"
        return MotionSummary("contact", regime, n, contact_fraction=fraction)
    if late:
        return MotionSummary("irregular", "mixed", n, contact_fraction=fraction)
    p, period = detect_period(imp.theta, imp.rdot, imp.thetadot, imp.t)
    if p is not None:
        return MotionSummary("periodic-impacting", "periodic-impacting", n, p, period)
    motion = "irregular" if n >= MIN_IRREGULAR else "undetermined"
    return MotionSummary(motion, "irregular-impacting", n)
