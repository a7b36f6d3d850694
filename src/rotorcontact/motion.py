"""Classification of the long-run motion of a trajectory from its impact sequence."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from .trajectory import Trajectory

__all__ = ["MotionSummary", "classify", "detect_period"]

MAX_PERIOD_IMPACTS = 16
REPEAT_TOL = 1e-6
MIN_IRREGULAR = 30


@dataclass(frozen=True)
class MotionSummary:
    """Long-run motion of a trajectory.

    Attributes
    ----------
    motion : str
        ``"no-contact"`` (no impact in the last third of the run: the rotor
        settles towards the regular equilibrium), ``"periodic-impacting"``,
        ``"irregular"`` (impacting with no period up to `MAX_PERIOD_IMPACTS`
        impacts), ``"chatter"`` (impacts accumulate) or ``"undetermined"``
        (too few impacts to tell).
    n_impacts : int
        Number of impacts in the run.
    impacts_per_period : int or None
        Impacts per period of a periodic impacting motion.
    period : float or None
        Its period in dimensionless time.
    """

    motion: str
    n_impacts: int
    impacts_per_period: int | None = None
    period: float | None = None

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


def _angle_diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * (a - b))))


def detect_period(theta, rdot, thetadot, t, *, max_p: int = MAX_PERIOD_IMPACTS, tol: float = REPEAT_TOL):
    """Smallest p such that the last impacts repeat every p impacts.

    The last ``max(2p, 6)`` impacts must each match the impact p earlier in
    angle, rdot and thetadot to ``tol``, and consecutive periods must agree to
    ``tol``. Returns ``(p, period)`` or ``(None, None)``.
    """
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
    """Classify the long-run motion of ``traj`` (see `MotionSummary`)."""
    imp = traj.impacts
    n = len(imp)
    if traj.status == "chatter":
        return MotionSummary("chatter", n)
    if n == 0 or imp.t[-1] < traj.t_stop * (2.0 / 3.0):
        return MotionSummary("no-contact", n)
    p, period = detect_period(imp.theta, imp.rdot, imp.thetadot, imp.t)
    if p is not None:
        return MotionSummary("periodic-impacting", n, p, period)
    if n >= MIN_IRREGULAR:
        return MotionSummary("irregular", n)
    return MotionSummary("undetermined", n)
