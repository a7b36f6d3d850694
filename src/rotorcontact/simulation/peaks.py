"""The largest value of a smooth function between its samples: successive parabolic interpolation.

A contact phase is sampled where its integrator steps (`general_contact.contact_phase`) or at the nodes of
its quadrature (`rolling.rolling_fixed_phase`); its largest normal force usually falls between two samples.
Where a sample is larger than both of its neighbours, the three bracket a maximum, and a search closes in on
it. The caller runs it as

    search = np.empty(PEAK_SLOTS)  # once, for every search of the caller
    peak_search(search, x1, f1, x2, f2, x3, f3)
    for _ in range(PEAK_STEPS):
        x = peak_next(search)
        if x != x:  # NaN: done
            break
        peak_record(search, x, f(x))
    largest = search[BEST]

Each trial is the vertex of the parabola through three points, the three largest seen (`parabola_vertex`,
`best_three`). Once the vertex moves less than `PEAK_TOL` of the bracket's width, the search probes
`PEAK_PROBE` of the width to either side: a parabola through wide points can settle on a vertex off the
maximum, and the close points then give one on it. It ends once a vertex settles with the points it came from
within four probes of one another, or a vertex leaves the bracket or repeats a point. The largest value seen
is kept, so it is never below the largest sample.

At a phase's start or end the largest sample may be the end itself, with a maximum just inside it that no
sample after it brackets. `peak_search_end` starts the search from the two samples of that last gap: it tries
the gap's middle, then the vertex of the parabola through the three points where it lies inside the gap (else
a probe just inside the larger end), then the vertices of the points nearest that end; a point above both
ends brackets a maximum, which the search then locates as above.

Its functions are compiled and take their arguments unchecked.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["PEAK_STEPS", "PEAK_TOL", "PEAK_PROBE", "PEAK_SLOTS", "BEST", "parabola_vertex", "best_three", "may_exceed",
           "peak_search", "peak_search_end", "peak_next", "peak_record"]

#: Most trials of a search (4 to 6 are usual).
PEAK_STEPS = 16
#: A vertex has settled once it moves less than this fraction of the bracket's width.
PEAK_TOL = 1e-5
#: Then the points probed on either side, as a fraction of the bracket's width.
PEAK_PROBE = 1e-3
#: Slots of a search: the three points (x, f), the bracket, the last vertex, the largest value, the stage
#: (searching, or probing to the left or right of the settled vertex) and that vertex with its value.
_X1, _F1, _X2, _F2, _X3, _F3, _LO, _HI, _BEFORE, BEST, _STAGE, _XC, _FC, _FL, PEAK_SLOTS = range(15)
_SEARCHING, _LEFT, _RIGHT, _DONE, _MIDDLE, _VERTEX = 0.0, 1.0, 2.0, 3.0, 4.0, 5.0


@njit(cache=True)
def parabola_vertex(x1: float, f1: float, x2: float, f2: float, x3: float, f3: float) -> float:
    """Abscissa of the vertex of the parabola through (x1, f1), (x2, f2), (x3, f3); x2 where they are collinear."""
    a = (x2 - x1) * (f2 - f3)
    b = (x2 - x3) * (f2 - f1)
    den = a - b
    if den == 0.0:
        return x2
    return x2 - 0.5 * ((x2 - x1) * a - (x2 - x3) * b) / den


@njit(cache=True)
def best_three(x1: float, f1: float, x2: float, f2: float, x3: float, f3: float, x: float, fx: float):
    """The three points of (x1, f1), (x2, f2), (x3, f3) and (x, fx) with the largest values: the lowest is
    dropped."""
    if fx <= f1 and fx <= f2 and fx <= f3:
        return x1, f1, x2, f2, x3, f3
    if f1 <= f2 and f1 <= f3:
        return x, fx, x2, f2, x3, f3
    if f2 <= f3:
        return x1, f1, x, fx, x3, f3
    return x1, f1, x2, f2, x, fx


@njit(cache=True)
def may_exceed(x1: float, f1: float, x2: float, f2: float, x3: float, f3: float, largest: float) -> bool:
    """Whether a maximum bracketed by the samples f1 <= f2 >= f3 at x1 < x2 < x3 may exceed ``largest``.

    For a parabola, the maximum exceeds f2 by at most r^2 / (4 (r + 1)) times f2's larger drop to a
    neighbour, r >= 1 the ratio of the two gaps (1/8 for equal gaps, 25/24 for r = 5). The margin taken is
    (1 + r^2 / (r + 1)) / 2 times that drop: more than twice the parabola's, for the smooth functions sampled
    finely enough to be near one.
    """
    g1 = x2 - x1
    g3 = x3 - x2
    r = max(g1, g3) / min(g1, g3)
    return f2 + 0.5 * (1.0 + r * r / (r + 1.0)) * (f2 - min(f1, f3)) >= largest


@njit(cache=True)
def peak_search(s: np.ndarray, x1: float, f1: float, x2: float, f2: float, x3: float, f3: float) -> None:
    """Start in ``s`` (`PEAK_SLOTS` floats) a search for the maximum bracketed by x1 < x2 < x3 (f1 < f2 >= f3);
    its largest value is then in ``s[BEST]``."""
    s[_X1], s[_F1], s[_X2], s[_F2], s[_X3], s[_F3] = x1, f1, x2, f2, x3, f3
    s[_LO], s[_HI] = x1, x3
    s[_BEFORE] = x2
    s[BEST] = f2
    s[_STAGE] = _SEARCHING
    s[_XC] = s[_FC] = s[_FL] = 0.0


@njit(cache=True)
def peak_search_end(s: np.ndarray, xa: float, fa: float, xb: float, fb: float) -> None:
    """Start in ``s`` a search for a maximum inside the last gap (xa, xb) of a phase's samples, xa < xb, where
    the one of them at the phase's start or end is the larger (module docstring)."""
    peak_search(s, xa, fa, 0.5 * (xa + xb), max(fa, fb), xb, fb)
    s[_STAGE] = _MIDDLE


@njit(cache=True)
def _restart(s: np.ndarray, x1: float, f1: float, x2: float, f2: float, x3: float, f3: float) -> None:
    """Go on as a search bracketed by x1 < x2 < x3 (f2 above both), keeping the largest value seen."""
    best = s[BEST]
    peak_search(s, x1, f1, x2, f2, x3, f3)
    s[BEST] = max(best, f2)


@njit(cache=True)
def peak_next(s: np.ndarray) -> float:
    """The next abscissa to evaluate, or NaN where the search is done."""
    stage = s[_STAGE]
    if stage == _MIDDLE:
        return s[_X2]
    if stage == _VERTEX:
        return s[_XC]
    probe = PEAK_PROBE * (s[_HI] - s[_LO])
    if stage == _LEFT:
        return max(s[_LO], s[_XC] - probe)
    if stage == _RIGHT:
        return min(s[_HI], s[_XC] + probe)
    if stage == _DONE:
        return math.nan
    x = parabola_vertex(s[_X1], s[_F1], s[_X2], s[_F2], s[_X3], s[_F3])
    if not s[_LO] < x < s[_HI] or x == s[_X1] or x == s[_X2] or x == s[_X3]:
        return math.nan
    return x


@njit(cache=True)
def peak_record(s: np.ndarray, x: float, fx: float) -> None:
    """Record the value ``fx`` at the abscissa ``x`` that `peak_next` gave."""
    s[BEST] = max(s[BEST], fx)
    stage = s[_STAGE]
    if stage == _MIDDLE:
        x1, f1, x3, f3 = s[_X1], s[_F1], s[_X3], s[_F3]
        if fx > f1 and fx > f3:
            _restart(s, x1, f1, x, fx, x3, f3)
            return
        v = parabola_vertex(x1, f1, x, fx, x3, f3)
        concave = (fx - f1) * (x3 - x) > (f3 - fx) * (x - x1)  # the slope falls from the left half to the right
        s[_X2], s[_F2] = x, fx
        if concave and x1 < v < x3 and v != x:
            s[_XC] = v
        else:
            # a vertex past the larger end, within the parabola's error of it: a probe just inside that end
            probe = PEAK_PROBE * (x3 - x1)
            s[_XC] = x3 - probe if f3 >= f1 else x1 + probe
        s[_STAGE] = _VERTEX
        return
    if stage == _VERTEX:
        x1, f1, xm, fm, x3, f3 = s[_X1], s[_F1], s[_X2], s[_F2], s[_X3], s[_F3]
        if fx > max(f1, fm, f3):
            if x < xm:
                _restart(s, x1, f1, x, fx, xm, fm)
            else:
                _restart(s, xm, fm, x, fx, x3, f3)
            return
        # not above the points yet: the next vertex, of the three points nearest the end that is the larger
        if f3 >= f1:
            xa, fa, xb, fb, xc, fc = (x, fx, xm, fm, x3, f3) if x < xm else (xm, fm, x, fx, x3, f3)
        else:
            xa, fa, xb, fb, xc, fc = (x1, f1, x, fx, xm, fm) if x < xm else (x1, f1, xm, fm, x, fx)
        v = parabola_vertex(xa, fa, xb, fb, xc, fc)
        if (fb - fa) * (xc - xb) > (fc - fb) * (xb - xa) and xa < v < xc and v != xb and \
                abs(v - x) > PEAK_TOL * (s[_HI] - s[_LO]):
            s[_X1], s[_F1], s[_X2], s[_F2], s[_X3], s[_F3] = xa, fa, xb, fb, xc, fc
            s[_XC] = v
        else:
            s[_STAGE] = _DONE
        return
    if stage == _LEFT:
        s[_FL] = fx
        s[_STAGE] = _RIGHT
        return
    if stage == _RIGHT:
        probe = PEAK_PROBE * (s[_HI] - s[_LO])
        s[_X1], s[_F1] = max(s[_LO], s[_XC] - probe), s[_FL]
        s[_X2], s[_F2] = s[_XC], s[_FC]
        s[_X3], s[_F3] = x, fx
        s[_STAGE] = _SEARCHING
        return
    width = s[_HI] - s[_LO]
    if abs(x - s[_BEFORE]) >= PEAK_TOL * width:
        s[_BEFORE] = x
        s[_X1], s[_F1], s[_X2], s[_F2], s[_X3], s[_F3] = best_three(s[_X1], s[_F1], s[_X2], s[_F2], s[_X3],
                                                                    s[_F3], x, fx)
        return
    spread = max(s[_X1], s[_X2], s[_X3], x) - min(s[_X1], s[_X2], s[_X3], x)
    if spread <= 4.0 * PEAK_PROBE * width:
        s[_STAGE] = _DONE
        return
    # settled on points far apart: probe either side of the vertex
    s[_XC], s[_FC] = x, fx
    s[_BEFORE] = x
    s[_STAGE] = _LEFT
