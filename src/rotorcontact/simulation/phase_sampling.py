"""Sample times of a contact phase, and the largest value of a smooth quantity along it.

Used by `rotorcontact.simulation.trajectory.Trajectory.phase_forces` for the largest contact forces and the mean
friction power of each phase.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .peaks import parabola_vertex

__all__ = ["PhaseForces", "phase_times", "phase_grids", "peak_of_samples", "PHASE_DT", "PHASE_DTHETA",
           "PHASE_MAX_STEPS", "PHASE_MAX_PIECES"]

#: Largest step in (dimensionless) time between two sample times of a phase.
PHASE_DT = 0.05
#: Largest turn of theta between two sample times of a phase.
PHASE_DTHETA = math.pi / 16
#: Fewest and most steps between the sample times of a phase (powers of two, so the times are odd in number).
PHASE_MIN_STEPS = 64
PHASE_MAX_STEPS = 2**20
#: Most pieces of `PHASE_MAX_STEPS` steps that `phase_grids` cuts a phase into.
PHASE_MAX_PIECES = 32
#: Times of the resampling about the largest sample in `peak_of_samples`.
REFINE_SAMPLES = 33


@dataclass(frozen=True)
class PhaseForces:
    """Forces of one contact phase, per unit mass (dimensionless).

    Attributes
    ----------
    max_normal : float
        The largest normal force N.
    max_friction : float
        The largest tangential force |F_t|.
    mean_power : float
        The mean friction power |F_t v_rel| over the phase.
    """

    max_normal: float
    max_friction: float
    mean_power: float


def _times(rate: Callable[[np.ndarray], np.ndarray], t_start: float, t_end: float) -> tuple[np.ndarray, float]:
    """`phase_times`, and the steps that the largest rate sampled on them asks for."""
    span = t_end - t_start
    if not span > 0.0:
        return np.array([t_start]), 0.0
    steps = PHASE_MIN_STEPS
    while True:
        t = np.linspace(t_start, t_end, steps + 1)
        needed = span * max(1.0 / PHASE_DT, float(np.max(rate(t))) / PHASE_DTHETA)
        if steps >= needed or steps >= PHASE_MAX_STEPS:
            return t, needed
        steps = min(PHASE_MAX_STEPS, max(2 * steps, 1 << math.ceil(math.log2(needed))))


def phase_times(rate: Callable[[np.ndarray], np.ndarray], t_start: float, t_end: float) -> np.ndarray:
    """Equally spaced times on [t_start, t_end], at most `PHASE_DT` apart and close enough that theta turns at
    most `PHASE_DTHETA` between neighbours, in at most `PHASE_MAX_STEPS` steps.

    Parameters
    ----------
    rate : callable
        |theta'| at an array of times.
    t_start, t_end : float
        The span; a single time where they are equal.

    Returns
    -------
    numpy.ndarray
        ``2**k + 1`` times (``PHASE_MIN_STEPS <= 2**k <= PHASE_MAX_STEPS``): the step count doubles while the
        largest rate sampled asks for more, so at most log2(PHASE_MAX_STEPS / PHASE_MIN_STEPS) + 1 passes.
        Where the bounds ask for more than `PHASE_MAX_STEPS` steps they are not met (see `phase_grids`).
    """
    return _times(rate, t_start, t_end)[0]


def phase_grids(rate: Callable[[np.ndarray], np.ndarray], t_start: float, t_end: float) -> list[np.ndarray]:
    """`phase_times` of consecutive pieces of [t_start, t_end], as many as the bounds ask for.

    A span that needs more than `PHASE_MAX_STEPS` steps is cut into equal pieces, each sampled by
    `phase_times`, so that memory stays bounded; at most `PHASE_MAX_PIECES` of them (a whirl of about a
    million turns), beyond which the pieces' samples are coarser than the bounds.

    Returns
    -------
    list of numpy.ndarray
        The pieces' times in order; each piece's last time is the next one's first.
    """
    t, needed = _times(rate, t_start, t_end)
    pieces = min(PHASE_MAX_PIECES, math.ceil(needed / PHASE_MAX_STEPS))
    if pieces <= 1:
        return [t]
    ends = np.linspace(t_start, t_end, pieces + 1)
    return [phase_times(rate, float(a), float(b)) for a, b in zip(ends[:-1], ends[1:])]


def peak_of_samples(f: Callable[[np.ndarray], np.ndarray], t: np.ndarray, values: np.ndarray) -> float:
    """The largest value of the smooth ``f``, sampled as ``values`` at the increasing times ``t``.

    The two steps about the largest sample are sampled again (`REFINE_SAMPLES` times), and ``f`` is taken at the
    vertex of the parabola through the largest of those and its neighbours; the result is the largest value seen,
    so never below the largest sample.
    """
    k = int(np.argmax(values))
    best = float(values[k])
    if t.size < 2:
        return best
    near = np.linspace(t[max(k - 1, 0)], t[min(k + 1, t.size - 1)], REFINE_SAMPLES)
    v = f(near)
    j = int(np.argmax(v))
    best = max(best, float(v[j]))
    if 0 < j < near.size - 1:
        if v[j - 1] - 2.0 * v[j] + v[j + 1] < 0.0:  # concave
            vertex = parabola_vertex(near[j - 1], v[j - 1], near[j], v[j], near[j + 1], v[j + 1])
            best = max(best, float(f(np.array([vertex]))[0]))
    return best
