"""Periodic orbits with p >= 2 impacts per period: fixed points of P_I^p (MODEL.md §5).

Equations
---------
An orbit with p impacts per period visits p points x_0, ..., x_{p-1} of
Sigma = {r = 1}, each x = (theta, rdot-, thetadot-) just before an impact,
with P_I(x_i) = x_{i+1} and P_I(x_{p-1}) = x_0. They are solved together by
Newton's method (multiple shooting on P_I^p - I): the unknowns are the 3p
coordinates, the residual is

    G_i = P_I(x_i) - x_{i+1}     (i = 0 .. p-1, x_p = x_0; angles mod 2 pi)

and its Jacobian is block-cyclic with the analytic 3x3 Jacobians J_i of
`rotorcontact.maps.impact_map.impact_map` on the diagonal and -I beside it. P_I is
the simulator's own impact map (slip-bounded friction law, guaranteed location
of the next impact), so a solution is an orbit of `rotorcontact.simulation.simulator`.

Stability and plausibility
--------------------------
The multipliers are the eigenvalues of the product J_{p-1} ... J_0 (the
Jacobian of P_I^p at x_0), largest modulus first; the orbit is stable when
all lie inside the unit circle. As for one impact, an orbit is *plausible*
when every impact is admissible (rdot- > 0), slips as the law of MODEL.md §5
assumes (v_rel > mu (1 + d) rdot-, so the friction impulse is not capped), and
r < 1 strictly between the impacts: the impact map finds the first crossing
of |U| = 1 with a guarantee, and the interior maxima of r, isolated with
`rotorcontact.maps.impact_map.flight_extrema`, must stay below 1 (a maximum at 1 is
a grazing).

Starting points
---------------
* Brute force (`orbits_from_simulation`): long simulations from a few initial
  states; after a transient the impact sequence is tested for period p
  (`rotorcontact.simulation.motion.detect_period`) and the last p impacts start Newton.
  This finds the stable p-orbits.
* Period doubling (`find_period_doubling`, `period_doubled_orbit`): a
  one-impact orbit B_n,m loses stability through a multiplier -1 at a
  parameter value found by bisection on its multipliers (from
  `rotorcontact.maps.impact_map.one_impact_orbits`). Near it the period-2 orbit is
  x* +- a v, with v the eigenvector of -1; Newton from that guess, slightly
  beyond the bifurcation, gives the period-2 orbit, stable or not.

Labels
------
An orbit on the period-2 branch born at the period doubling of B_n,m is
``"B_n,m/PD"`` (``"B1,d/PD"`` for that of B1,d). Other orbits with p impacts
are ``"M<p>-<j>"`` (``"M2-1"``, ``"M3-1"``, ...), numbered in order of period;
``M`` rather than ``P`` because P1 and P2 name the pseudo-equilibria. The
points of an orbit are listed in the order of the motion, starting from the
impact with the largest rdot- (orbits from `period_doubled_orbit` and along
a continued branch keep the order of the branch: first the image of x* + a v).

Continuation
------------
`continue_multi_impact` follows an orbit in one parameter with the
pseudo-arclength continuation of `rotorcontact.continuation.engine` (folds are
passed), on the unknowns (x_0, ..., x_{p-1}, lambda), and locates the events
of MODEL.md §5 along the branch: a multiplier leaving the unit circle
(classified as fold at +1, period doubling at -1 or Neimark-Sacker for a
complex pair), grazing of an interior maximum of r, and a change of the
slipping condition. The continuation stops at a grazing (P_I is
discontinuous there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np

from ..continuation.engine import (
    ContinuationSettings,
    CorrectionError,
    EventFunction,
    continue_curve,
)
from ..model.angles import wrap_angle
from ..errors import ParameterError
from .impact_map import (
    SLIP_BOUNDED,
    ImpactOrbit,
    flight_extrema,
    impact_map,
    one_impact_orbits,
    post_impact_state,
)
from ..simulation.motion import detect_period
from ..model.params import Parameters, check_range
from ..simulation.simulator import simulate

__all__ = [
    "CONTINUATION_PARAMETERS",
    "ImpactPoint",
    "MultiImpactOrbit",
    "PeriodDoubling",
    "BranchEvent",
    "MultiImpactBranch",
    "NewtonFailure",
    "periodic_residual",
    "solve_multi_impact",
    "orbits_from_simulation",
    "find_period_doubling",
    "period_doubled_orbit",
    "continue_multi_impact",
    "multi_impact_orbits",
]

#: Parameters in which multi-impact orbits can be continued.
CONTINUATION_PARAMETERS = ("gamma", "omega", "rho", "mu", "d")

NEWTON_TOL = 1e-12
MAX_NEWTON = 40
HORIZON = 1000.0
SAME_TOL = 1e-7
PARAMETER_WEIGHT = 100.0
GRAZING_MARGIN = 1e-2
DETECT_TOL = 1e-3
TWO_PI = 2.0 * math.pi


class NewtonFailure(RuntimeError):
    """Newton's method did not converge to an orbit with the requested number of impacts."""


class _MapFailure(ValueError):
    """The impact map has no impact from a state (no crossing, stuck on the stator, or failure)."""


# ---------------------------------------------------------------------------
# The equations
# ---------------------------------------------------------------------------


def _chain(params: Parameters, states: np.ndarray, law: str = SLIP_BOUNDED):
    """Images, flight times, Jacobians and sticking flags of P_I at each of the p states."""
    p = states.shape[0]
    images = np.empty((p, 3))
    times = np.empty(p)
    jacs = np.empty((p, 3, 3))
    sticking = np.zeros(p, dtype=bool)
    for i in range(p):
        x = states[i]
        if not x[1] > 0.0:
            raise _MapFailure(f"impact {i} has rdot = {x[1]!r} <= 0 (not an impact)")
        res = impact_map(params, x, horizon=HORIZON, law=law, jacobian=True)
        if res.status != "impact":
            raise _MapFailure(f"no impact after impact {i}: {res.status}")
        images[i] = res.state
        times[i] = res.time
        jacs[i] = res.jacobian
        sticking[i] = res.sticking
    return images, times, jacs, sticking


def periodic_residual(params: Parameters, states, *, law: str = SLIP_BOUNDED) -> tuple[np.ndarray, np.ndarray]:
    """Residual of the p-impact periodic orbit equations and its Jacobian.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    states : array_like, shape (p, 3)
        The points x_i = (theta, rdot-, thetadot-) on Sigma.
    law : {"slip-bounded", "ideal"}
        Impact law of `rotorcontact.maps.impact_map.impact_map`.

    Returns
    -------
    residual : numpy.ndarray, shape (3p,)
        G_i = P_I(x_i) - x_{i+1} (angle differences in (-pi, pi]).
    jacobian : numpy.ndarray, shape (3p, 3p)
        dG / d(x_0, ..., x_{p-1}).

    Raises
    ------
    ValueError
        When the impact map has no next impact from one of the states.
    """
    x = np.asarray(states, dtype=float)
    if x.ndim != 2 or x.shape[1] != 3 or x.shape[0] < 1:
        raise ParameterError(f"states has shape {x.shape}; allowed: (p, 3) with p >= 1")
    p = x.shape[0]
    images, _times, jacs, _st = _chain(params, x, law)
    res = np.empty(3 * p)
    jac = np.zeros((3 * p, 3 * p))
    for i in range(p):
        j = (i + 1) % p
        d = images[i] - x[j]
        d[0] = math.remainder(d[0], TWO_PI)
        res[3 * i : 3 * i + 3] = d
        jac[3 * i : 3 * i + 3, 3 * i : 3 * i + 3] += jacs[i]
        jac[3 * i : 3 * i + 3, 3 * j : 3 * j + 3] -= np.eye(3)
    return res, jac


# ---------------------------------------------------------------------------
# Orbits
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class ImpactPoint:
    """One impact of a periodic orbit.

    Attributes
    ----------
    theta : float
        Impact angle in (-pi, pi].
    rdot, thetadot : float
        Polar velocities just before the impact.
    dt : float
        Time to the next impact.
    """

    theta: float
    rdot: float
    thetadot: float
    dt: float

    def to_dict(self) -> dict[str, float]:
        return {"theta": self.theta, "rdot": self.rdot, "thetadot": self.thetadot, "dt": self.dt}


@dataclass(frozen=True)
class MultiImpactOrbit:
    """A periodic orbit with p impacts per period (a fixed point of P_I^p).

    Attributes
    ----------
    label : str
        ``"B1,d/PD"`` for the period-doubled branch of B1,d, ``"M<p>-<j>"``
        otherwise (module docstring).
    impacts : int
        p, the number of impacts per period (the least period of the points).
    period : float
        Sum of the flight times.
    points : tuple of ImpactPoint
        The impacts in the order of the motion.
    multipliers : tuple of complex
        Eigenvalues of the Jacobian of P_I^p, largest modulus first.
    stable : bool
        All multipliers inside the unit circle.
    plausible : bool
        Every impact admissible and slipping, and r < 1 strictly between impacts.
    admissible : bool
        rdot- > 0 at every impact.
    slipping : bool
        v_rel > mu (1 + d) rdot- at every impact.
    r_max_interior : float or None
        Largest interior local maximum of r over the flights (None where there is none).
    residual : float
        Largest component of the residual of the periodic-orbit equations.
    params : Parameters
        The parameters of the orbit.
    """

    label: str
    impacts: int
    period: float
    points: tuple[ImpactPoint, ...]
    multipliers: tuple[complex, ...]
    stable: bool
    plausible: bool
    admissible: bool
    slipping: bool
    r_max_interior: float | None
    residual: float
    params: Parameters = field(repr=False)

    @property
    def states(self) -> np.ndarray:
        """(p, 3) array of (theta, rdot-, thetadot-)."""
        return np.array([[q.theta, q.rdot, q.thetadot] for q in self.points])

    @property
    def times(self) -> np.ndarray:
        """Flight times to the next impact."""
        return np.array([q.dt for q in self.points])

    def initial_condition(self, index: int = 0) -> tuple[complex, complex]:
        """(U, U') just after impact ``index``: starts `simulate` on the orbit."""
        return post_impact_state(self.params, self.states[index], law=SLIP_BOUNDED)

    def jacobian(self) -> np.ndarray:
        """Jacobian of P_I^p at the first point (the product of the p Jacobians of P_I)."""
        _im, _t, jacs, _s = _chain(self.params, self.states)
        m = np.eye(3)
        for j in jacs:
            m = j @ m
        return m

    def to_dict(self) -> dict[str, Any]:
        """Plain data (the ``orbits --impacts p --json`` contract)."""
        return {
            "label": self.label,
            "impacts": self.impacts,
            "period": self.period,
            "points": [q.to_dict() for q in self.points],
            "multipliers": [[m.real, m.imag] for m in self.multipliers],
            "stable": self.stable,
            "plausible": self.plausible,
        }


def _least_period(states: np.ndarray, tol: float = SAME_TOL) -> int:
    """Smallest q dividing p such that the points repeat every q impacts."""
    p = states.shape[0]
    for q in range(1, p):
        if p % q:
            continue
        shifted = np.roll(states, -q, axis=0)
        d = np.abs(shifted - states)
        d[:, 0] = np.abs(np.remainder(shifted[:, 0] - states[:, 0] + math.pi, TWO_PI) - math.pi)
        if np.all(d <= tol * (1.0 + np.abs(states))):
            return q
    return p


def _build_orbit(params: Parameters, states: np.ndarray, label: str) -> MultiImpactOrbit:
    x = np.array(states, dtype=float)
    x[:, 0] = [wrap_angle(t) for t in x[:, 0]]
    res, _jac = periodic_residual(params, x)
    images, times, jacs, sticking = _chain(params, x)
    m = np.eye(3)
    for j in jacs:
        m = j @ m
    ev = np.linalg.eigvals(m)
    ev = ev[np.argsort(-np.abs(ev), kind="stable")]
    admissible = bool(np.all(x[:, 1] > 0.0))
    slipping = bool(
        np.all(params.r_ratio + 1.0 + x[:, 2] > params.mu * (1.0 + params.d) * x[:, 1]) and not np.any(sticking)
    )
    r_max = None
    for i in range(x.shape[0]):
        ext = flight_extrema(params, x[i], float(times[i]), law=SLIP_BOUNDED)
        if ext.r_max is not None:
            r_max = ext.r_max if r_max is None else max(r_max, ext.r_max)
    plausible = admissible and slipping and (r_max is None or r_max < 1.0)
    points = tuple(
        ImpactPoint(theta=float(x[i, 0]), rdot=float(x[i, 1]), thetadot=float(x[i, 2]), dt=float(times[i]))
        for i in range(x.shape[0])
    )
    return MultiImpactOrbit(
        label=label,
        impacts=int(x.shape[0]),
        period=float(np.sum(times)),
        points=points,
        multipliers=tuple(complex(v) for v in ev),
        stable=bool(np.all(np.abs(ev) < 1.0)),
        plausible=bool(plausible),
        admissible=admissible,
        slipping=slipping,
        r_max_interior=r_max,
        residual=float(np.max(np.abs(res))),
        params=params,
    )


def _check_guess(guess) -> np.ndarray:
    try:
        x = np.array(guess, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"guess = {guess!r} is not a (p, 3) array of (theta, rdot, thetadot)") from None
    if x.ndim != 2 or x.shape[1] != 3 or x.shape[0] < 1:
        raise ParameterError(f"guess has shape {x.shape}; allowed: (p, 3) with p >= 1")
    if not np.all(np.isfinite(x)):
        raise ParameterError("guess is not finite; allowed: finite (theta, rdot, thetadot) rows")
    return x


def _newton(params: Parameters, x: np.ndarray, tol: float, max_iter: int) -> np.ndarray:
    p = x.shape[0]
    try:
        res, jac = periodic_residual(params, x)
    except _MapFailure as exc:
        raise NewtonFailure(f"the impact map failed at the starting point: {exc}") from None
    norm = float(np.max(np.abs(res)))
    for _ in range(max_iter):
        if norm <= tol:
            return x
        try:
            dx = np.linalg.solve(jac, -res).reshape(p, 3)
        except np.linalg.LinAlgError:
            raise NewtonFailure("singular Jacobian of P_I^p - I") from None
        lam = 1.0
        while lam >= 1.0 / 64.0:
            trial = x + lam * dx
            try:
                r_t, j_t = periodic_residual(params, trial)
            except _MapFailure:
                lam *= 0.5
                continue
            n_t = float(np.max(np.abs(r_t)))
            if n_t < norm or n_t <= tol:
                x, res, jac, norm = trial, r_t, j_t, n_t
                break
            lam *= 0.5
        else:
            raise NewtonFailure(f"no decrease of the residual (|G| = {norm:.3g})")
    if norm <= tol:
        return x
    raise NewtonFailure(f"no convergence in {max_iter} iterations (|G| = {norm:.3g})")


def solve_multi_impact(
    params: Parameters,
    guess,
    *,
    label: str | None = None,
    tol: float = NEWTON_TOL,
    max_iter: int = MAX_NEWTON,
    canonical: bool = True,
) -> MultiImpactOrbit:
    """Newton's method for a periodic orbit with p impacts per period.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    guess : array_like, shape (p, 3)
        Approximate impact states (theta, rdot-, thetadot-) in the order of the motion.
    label : str, optional
        Label of the orbit; default ``"M<p>"``.
    tol : float
        Convergence when every component of the residual is below ``tol``.
    max_iter : int
        Largest number of Newton iterations.
    canonical : bool
        Start the listed points at the impact with the largest rdot-.

    Returns
    -------
    MultiImpactOrbit

    Raises
    ------
    NewtonFailure
        When Newton's method fails, or converges to an orbit whose least
        period has fewer impacts than the guess.
    """
    if not isinstance(params, Parameters):
        raise ParameterError(f"params = {params!r} is not a Parameters object")
    x = _check_guess(guess)
    tol = check_range("tol", tol, low=0.0, low_open=True)
    x = _newton(params, x, tol, int(max_iter))
    p = x.shape[0]
    q = _least_period(x)
    if q < p:
        raise NewtonFailure(f"converged to an orbit with {q} impact(s) per period, not {p}")
    if canonical:
        x = np.roll(x, -int(np.argmax(x[:, 1])), axis=0)
    return _build_orbit(params, x, label or f"M{p}")


def _same_orbit(a: MultiImpactOrbit, b: MultiImpactOrbit, tol: float = 1e-6) -> bool:
    if a.impacts != b.impacts:
        return False
    xa, xb = a.states, b.states
    for s in range(a.impacts):
        d = np.abs(np.roll(xb, -s, axis=0) - xa)
        d[:, 0] = np.abs(np.remainder(np.roll(xb, -s, axis=0)[:, 0] - xa[:, 0] + math.pi, TWO_PI) - math.pi)
        if np.all(d <= tol * (1.0 + np.abs(xa))):
            return True
    return False


def _relabel(orbit: MultiImpactOrbit, label: str) -> MultiImpactOrbit:
    return replace(orbit, label=label)


# ---------------------------------------------------------------------------
# Brute force
# ---------------------------------------------------------------------------


def _default_starts() -> tuple[tuple[complex, complex], ...]:
    starts = [(0j, 0j)]
    for j in range(6):
        ang = math.pi * j / 3.0
        starts.append((0.5 * complex(math.cos(ang), math.sin(ang)), 0j))
    for j in range(4):
        ang = math.pi * (j + 0.5) / 2.0
        starts.append((0j, 1.5 * complex(math.cos(ang), math.sin(ang))))
    return tuple(starts)


def orbits_from_simulation(
    params: Parameters,
    impacts: int,
    *,
    starts: Sequence[tuple[complex, complex]] | None = None,
    t_transient: float = 1500.0,
    t_record: float = 300.0,
) -> tuple[MultiImpactOrbit, ...]:
    """Periodic orbits with ``impacts`` impacts per period that attract simulations.

    Each start is simulated for ``t_transient + t_record``; when the impacts
    of the last ``t_record`` repeat with least period ``impacts``
    (`rotorcontact.simulation.motion.detect_period`), the last ``impacts`` impacts
    start `solve_multi_impact`. Distinct orbits are returned, sorted by
    period and labelled ``"M<p>-1"``, ``"M<p>-2"``, ...

    Parameters
    ----------
    params : Parameters
        Model parameters.
    impacts : int
        p >= 1.
    starts : sequence of (u0, du0), optional
        Initial states; default: rest, six points at r = 0.5 at rest, and
        four velocity kicks from the centre.
    t_transient, t_record : float
        Lengths of the transient and of the recorded window.

    Returns
    -------
    tuple of MultiImpactOrbit
    """
    if not isinstance(params, Parameters):
        raise ParameterError(f"params = {params!r} is not a Parameters object")
    p = _check_impacts(impacts, low=1)
    t_transient = check_range("t_transient", t_transient, low=0.0)
    t_record = check_range("t_record", t_record, low=0.0, low_open=True)
    found: list[MultiImpactOrbit] = []
    for u0, du0 in starts if starts is not None else _default_starts():
        traj = simulate(params, u0, du0, t_transient + t_record)
        imp = traj.impacts
        if len(imp) == 0:
            continue
        late = imp.t >= t_transient
        if np.count_nonzero(late) < 2 * p + 6:
            continue
        if any(c.t_end > t_transient for c in traj.contact_intervals):
            continue
        # a loose test: the candidate only starts Newton, which decides
        q, _period = detect_period(
            imp.theta[late], imp.rdot[late], imp.thetadot[late], imp.t[late], tol=DETECT_TOL
        )
        if q != p:
            continue
        guess = np.column_stack([imp.theta[-p:], imp.rdot[-p:], imp.thetadot[-p:]])
        try:
            orbit = solve_multi_impact(params, guess)
        except NewtonFailure:
            continue
        if not any(_same_orbit(orbit, o) for o in found):
            found.append(orbit)
    found.sort(key=lambda o: (o.period, o.points[0].theta))
    return tuple(_relabel(o, f"M{p}-{j + 1}") for j, o in enumerate(found))


# ---------------------------------------------------------------------------
# Period doubling of a one-impact orbit
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class PeriodDoubling:
    """A one-impact orbit losing stability through a multiplier -1.

    Attributes
    ----------
    parent : str
        Label of the one-impact orbit (``"B1,d"``).
    parameter : str
        The parameter varied.
    value : float
        Its value at the period doubling.
    orbit : ImpactOrbit
        The one-impact orbit there.
    eigenvector : numpy.ndarray
        Real unit eigenvector of the multiplier -1 in (theta, rdot-, thetadot-).
    multiplier : float
        The multiplier nearest -1 at ``value``.
    unstable_side : float
        +1 when the orbit is unstable (multiplier below -1) above ``value``, -1 below.
    """

    parent: str
    parameter: str
    value: float
    orbit: ImpactOrbit = field(repr=False)
    eigenvector: np.ndarray = field(repr=False)
    multiplier: float
    unstable_side: float


def _check_parameter(parameter: str) -> str:
    if parameter not in CONTINUATION_PARAMETERS:
        raise ParameterError(
            f"parameter = {parameter!r} is invalid; allowed: {', '.join(CONTINUATION_PARAMETERS)}"
        )
    return parameter


def _check_impacts(impacts, low: int = 2) -> int:
    if isinstance(impacts, bool) or not isinstance(impacts, (int, np.integer)) or impacts < low:
        raise ParameterError(f"impacts = {impacts!r} is invalid; allowed: an integer >= {low}")
    return int(impacts)


def _one_impact(params: Parameters, label: str, t_max: float) -> ImpactOrbit | None:
    for o in one_impact_orbits(params, t_max):
        if o.label == label and o.admissible and o.multipliers is not None:
            return o
    return None


def _flip_measure(orbit: ImpactOrbit | None) -> float | None:
    """max |lambda| - 1 over the multipliers with Re(lambda) < 0 (None where there is none).

    It changes sign where a multiplier crosses the unit circle in the left
    half-plane: at -1 (a period doubling) or as a complex pair.
    """
    if orbit is None:
        return None
    neg = [abs(m) for m in orbit.multipliers if m.real < 0.0]
    if not neg:
        return None
    return max(neg) - 1.0


def _has_real_flip(orbit: ImpactOrbit | None) -> bool:
    """True when a real multiplier lies below -1."""
    if orbit is None:
        return False
    return any(abs(m.imag) <= 1e-12 * (1.0 + abs(m)) and m.real < -1.0 for m in orbit.multipliers)


def find_period_doubling(
    params: Parameters,
    label: str = "B1,d",
    parameter: str = "gamma",
    *,
    lo: float,
    hi: float,
    n_scan: int = 24,
    tol: float = 1e-12,
    t_max: float = 12.0,
) -> PeriodDoubling:
    """Locate where a one-impact orbit loses stability through a multiplier -1.

    The interval [lo, hi] of ``parameter`` is scanned at ``n_scan + 1``
    points for a sign change of max |lambda| - 1 over the multipliers of the
    orbit ``label`` in the left half-plane; the change is then bisected to
    ``tol``. It is a period doubling when the multiplier on the unit circle
    there is real (-1); the eigenvector of the multiplier nearest -1 is taken
    at the located value.

    Raises
    ------
    ParameterError
        When no such change is found in [lo, hi], or when the change found is
        a complex pair crossing the unit circle (a Neimark-Sacker bifurcation).
    """
    if not isinstance(params, Parameters):
        raise ParameterError(f"params = {params!r} is not a Parameters object")
    parameter = _check_parameter(parameter)
    lo = float(lo)
    hi = float(hi)
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ParameterError(f"lo = {lo!r}, hi = {hi!r} is not an interval; allowed: finite lo < hi")

    def measure(v: float) -> float | None:
        try:
            return _flip_measure(_one_impact(params.replace(**{parameter: v}), label, t_max))
        except ParameterError:
            return None

    grid = np.linspace(lo, hi, int(n_scan) + 1)
    vals = [measure(v) for v in grid]
    bracket = None
    for i in range(len(grid) - 1):
        a, b = vals[i], vals[i + 1]
        if a is not None and b is not None and (a < 0.0) != (b < 0.0):
            bracket = (grid[i], a, grid[i + 1], b)
            break
    if bracket is None:
        raise ParameterError(
            f"no period doubling of {label} found for {parameter} in [{lo:g}, {hi:g}]; "
            "allowed: an interval where its multiplier crosses -1"
        )
    a, fa, b, fb = bracket
    unstable_side = 1.0 if fb > 0.0 else -1.0
    for _ in range(200):
        if abs(b - a) <= tol * (1.0 + abs(a)):
            break
        m = 0.5 * (a + b)
        fm = measure(m)
        if fm is None:
            break
        if (fm < 0.0) == (fa < 0.0):
            a, fa = m, fm
        else:
            b, fb = m, fm
    value = 0.5 * (a + b)
    p_pd = params.replace(**{parameter: value})
    orbit = _one_impact(p_pd, label, t_max)
    if orbit is None:
        raise ParameterError(f"{label} does not exist at {parameter} = {value:g}")
    ev, vec = np.linalg.eig(orbit.jacobian())
    i = int(np.argmin(np.abs(ev + 1.0)))
    if abs(ev[i] + 1.0) > 1e-4:
        raise ParameterError(
            f"{label} loses stability at {parameter} = {value:.12g} through the multipliers "
            f"{ev[i]:.6g} (not -1: a Neimark-Sacker bifurcation, not a period doubling)"
        )
    v = np.real(vec[:, i])
    v /= np.linalg.norm(v)
    if v[np.argmax(np.abs(v))] < 0:
        v = -v
    return PeriodDoubling(
        parent=label,
        parameter=parameter,
        value=float(value),
        orbit=orbit,
        eigenvector=v,
        multiplier=float(np.real(ev[i])),
        unstable_side=unstable_side,
    )


def period_doubled_orbit(
    pd: PeriodDoubling,
    offset: float,
    *,
    amplitudes: Sequence[float] = (1e-3, 3e-3, 1e-2, 3e-2, 1e-1),
    t_max: float = 12.0,
) -> MultiImpactOrbit:
    """The period-2 orbit born at a period doubling, at ``parameter = pd.value + offset``.

    Newton on P_I^2 starts from x* + a v, x* - a v (x* the one-impact orbit at
    the new parameter value, v the eigenvector of -1), for each amplitude a
    in turn, until it converges to an orbit with two distinct impacts.

    Returns
    -------
    MultiImpactOrbit
        Labelled ``"<parent>/PD"``.

    Raises
    ------
    NewtonFailure
        When no amplitude gives a period-2 orbit (for example on the side of
        the bifurcation where the branch does not exist).
    """
    offset = check_range("offset", offset)
    if offset == 0.0:
        raise ParameterError("offset = 0.0 is invalid; allowed: a nonzero offset from the bifurcation")
    params = pd.orbit.params.replace(**{pd.parameter: pd.value + offset})
    parent = _one_impact(params, pd.parent, t_max)
    if parent is None:
        raise NewtonFailure(f"{pd.parent} does not exist at {pd.parameter} = {pd.value + offset:g}")
    x_star = parent.state
    v = pd.eigenvector
    last = "no amplitude tried"
    for a in amplitudes:
        guess = np.array([x_star + a * v, x_star - a * v])
        try:
            return solve_multi_impact(params, guess, label=f"{pd.parent}/PD", canonical=False)
        except NewtonFailure as exc:
            last = str(exc)
    raise NewtonFailure(f"no period-2 orbit near {pd.parent} at {pd.parameter} = {pd.value + offset:g}: {last}")


# ---------------------------------------------------------------------------
# Continuation
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class BranchEvent:
    """An event located along a branch of multi-impact orbits.

    Attributes
    ----------
    kind : str
        ``"fold"``, ``"period-doubling"``, ``"neimark-sacker"`` (a multiplier
        leaves or enters the unit circle at +1, -1, or as a complex pair),
        ``"grazing"`` (an interior maximum of r reaches 1) or ``"slip"``
        (the slipping condition changes).
    value : float
        The parameter there.
    orbit : MultiImpactOrbit or None
        The orbit at the event (None where it could not be built).
    """

    kind: str
    value: float
    orbit: MultiImpactOrbit | None = field(repr=False)


@dataclass(frozen=True)
class MultiImpactBranch:
    """A continued branch of orbits with p impacts per period.

    Attributes
    ----------
    parameter : str
        The continuation parameter.
    values : numpy.ndarray
        Its values along the branch.
    orbits : tuple of MultiImpactOrbit
        The orbits at those values.
    events : tuple of BranchEvent
        Located events, in order.
    status, message : str
        How the continuation ended: the statuses of
        `rotorcontact.continuation.engine.ContinuationResult`, or ``"grazing"`` when
        the steps failed with an interior maximum of r within
        `GRAZING_MARGIN` of 1.
    """

    parameter: str
    values: np.ndarray = field(repr=False)
    orbits: tuple[MultiImpactOrbit, ...] = field(repr=False)
    events: tuple[BranchEvent, ...]
    status: str
    message: str


class _System:
    """(x_0 .. x_{p-1}, lambda) -> G as a continuation problem."""

    def __init__(self, base: Parameters, parameter: str, p: int, fd_step: float = 1e-7):
        self.base = base
        self.parameter = parameter
        self.p = p
        self.fd_step = fd_step

    def params_at(self, value: float) -> Parameters:
        return self.base.replace(**{self.parameter: float(value)})

    def residual(self, y: np.ndarray) -> np.ndarray:
        return periodic_residual(self.params_at(y[-1]), y[:-1].reshape(self.p, 3))[0]

    def jacobian(self, y: np.ndarray) -> np.ndarray:
        lam = float(y[-1])
        x = y[:-1].reshape(self.p, 3)
        _res, jx = periodic_residual(self.params_at(lam), x)
        h = self.fd_step * max(1.0, abs(lam))
        rp = periodic_residual(self.params_at(lam + h), x)[0]
        rm = periodic_residual(self.params_at(lam - h), x)[0]
        return np.column_stack([jx, (rp - rm) / (2.0 * h)])

    def orbit(self, y: np.ndarray, label: str) -> MultiImpactOrbit:
        params = self.params_at(y[-1])
        x = y[:-1].reshape(self.p, 3).copy()
        try:
            x = _newton(params, x, NEWTON_TOL, 8)
        except NewtonFailure:
            pass
        return _build_orbit(params, x, label)

    def max_multiplier(self, y: np.ndarray) -> float | None:
        try:
            _im, _t, jacs, _s = _chain(self.params_at(y[-1]), y[:-1].reshape(self.p, 3))
        except (_MapFailure, ParameterError):
            return None
        m = np.eye(3)
        for j in jacs:
            m = j @ m
        return float(np.max(np.abs(np.linalg.eigvals(m)))) - 1.0

    def grazing(self, y: np.ndarray) -> float | None:
        params = self.params_at(y[-1])
        x = y[:-1].reshape(self.p, 3)
        try:
            _im, times, _j, _s = _chain(params, x)
            r_max = None
            for i in range(self.p):
                ext = flight_extrema(params, x[i], float(times[i]), law=SLIP_BOUNDED)
                if ext.r_max is not None:
                    r_max = ext.r_max if r_max is None else max(r_max, ext.r_max)
        except (_MapFailure, ParameterError, RuntimeError):
            return None
        return None if r_max is None else 1.0 - r_max

    def slipping(self, y: np.ndarray) -> int | None:
        params = self.params_at(y[-1])
        x = y[:-1].reshape(self.p, 3)
        return int(np.all(params.r_ratio + 1.0 + x[:, 2] > params.mu * (1.0 + params.d) * x[:, 1]))


def _classify_stability_event(orbit: MultiImpactOrbit) -> str:
    m = min(orbit.multipliers, key=lambda z: abs(abs(z) - 1.0))
    if abs(m.imag) > 1e-6 * (1.0 + abs(m)):
        return "neimark-sacker"
    return "fold" if m.real > 0.0 else "period-doubling"


def continue_multi_impact(
    orbit: MultiImpactOrbit,
    parameter: str,
    stop: float,
    *,
    step: float = 1e-3,
    max_step: float = 0.02,
    max_points: int = 2000,
) -> MultiImpactBranch:
    """Follow a multi-impact orbit in one parameter up to ``stop``.

    Pseudo-arclength continuation (`rotorcontact.continuation.engine.continue_curve`)
    of (x_0, ..., x_{p-1}, lambda), starting in the direction of ``stop``.
    It ends at ``stop`` (a terminal event), at a grazing (terminal: P_I
    is discontinuous there), or when the step fails (for example where the
    branch returns onto a one-impact orbit at a period doubling).

    Parameters
    ----------
    orbit : MultiImpactOrbit
        Starting orbit.
    parameter : str
        One of `CONTINUATION_PARAMETERS`.
    stop : float
        The parameter value to reach.
    step, max_step : float
        First and largest step of the (scaled) arclength.
    max_points : int
        Largest number of steps.

    Returns
    -------
    MultiImpactBranch
    """
    if not isinstance(orbit, MultiImpactOrbit):
        raise ParameterError(f"orbit = {orbit!r} is not a MultiImpactOrbit")
    parameter = _check_parameter(parameter)
    stop = check_range("stop", stop)
    step = check_range("step", step, low=0.0, low_open=True)
    max_step = max(check_range("max_step", max_step, low=0.0, low_open=True), step)
    p = orbit.impacts
    base = orbit.params
    start = float(getattr(base, parameter))
    if stop == start:
        return MultiImpactBranch(parameter, np.array([start]), (orbit,), (), "terminal", "already at stop")
    system = _System(base, parameter, p)
    y0 = np.append(orbit.states.ravel(), start)
    direction = 1.0 if stop > start else -1.0
    events = [
        EventFunction("stop", lambda y: direction * (stop - y[-1]), terminal=True),
        EventFunction("stability", system.max_multiplier),
        EventFunction("grazing", system.grazing, terminal=True),
        EventFunction("slip", system.slipping, kind="discrete"),
    ]
    settings = ContinuationSettings(
        step=min(step, max_step),
        min_step=1e-9,
        max_step=max_step,
        max_points=int(max_points),
        residual_tol=1e-10,
        location_tol=1e-10,
    )
    # unknowns of order one; the parameter weighted up so that steps move it
    weights = np.ones(3 * p + 1)
    weights[-1] = PARAMETER_WEIGHT
    result = continue_curve(
        system.residual,
        y0,
        jacobian=system.jacobian,
        direction=direction,
        events=events,
        settings=settings,
        weights=weights,
        param_index=-1,
        correct_start=False,
    )
    orbits = []
    values = []
    for y in result.points:
        try:
            orbits.append(system.orbit(y, orbit.label))
            values.append(float(y[-1]))
        except (_MapFailure, ParameterError):
            break
    located = []
    for ev in result.events:
        if ev.name == "stop":
            continue
        try:
            o = system.orbit(ev.y, orbit.label)
        except (_MapFailure, ParameterError):
            o = None
        kind = ev.name
        if ev.name == "stability":
            kind = _classify_stability_event(o) if o is not None else "stability"
        located.append(BranchEvent(kind=kind, value=float(ev.parameter), orbit=o))
    status, message = result.status, result.message
    if status == "step-failure" and orbits:
        # the map is continuous but not smooth at a grazing (square-root singularity): steps
        # fail as an interior maximum of r approaches 1
        last = orbits[-1]
        if last.r_max_interior is not None and 1.0 - last.r_max_interior < GRAZING_MARGIN:
            located.append(BranchEvent(kind="grazing", value=values[-1], orbit=last))
            status = "grazing"
            message = (
                f"the branch approaches a grazing at {parameter} = {values[-1]:.10g} "
                f"(interior maximum r = {last.r_max_interior:.6g}); {message}"
            )
    return MultiImpactBranch(
        parameter=parameter,
        values=np.array(values),
        orbits=tuple(orbits),
        events=tuple(located),
        status=status,
        message=message,
    )


# ---------------------------------------------------------------------------
# All orbits at given parameters
# ---------------------------------------------------------------------------


def multi_impact_orbits(
    params: Parameters,
    impacts: int,
    *,
    starts: Sequence[tuple[complex, complex]] | None = None,
    period_doubling: bool = True,
    scan_width: float = 0.05,
    t_max: float = 12.0,
) -> tuple[MultiImpactOrbit, ...]:
    """Periodic orbits with ``impacts`` (>= 2) impacts per period at given parameters.

    Two sources are combined:

    * the stable orbits found by `orbits_from_simulation`;
    * for ``impacts == 2`` and ``period_doubling``: for each admissible
      one-impact orbit with a real multiplier below -1, the period doubling
      where that multiplier passes -1 is located in gamma within
      ``scan_width`` of the given gamma (`find_period_doubling`), and the
      period-2 orbit born there is continued to the given gamma
      (`continue_multi_impact`); it is labelled ``"B<n>,<m>/PD"``.

    Orbits found by both are reported once, with the branch label.

    Returns
    -------
    tuple of MultiImpactOrbit
        Branch-switched orbits first, then the others by period.
    """
    if not isinstance(params, Parameters):
        raise ParameterError(f"params = {params!r} is not a Parameters object")
    p = _check_impacts(impacts, low=2)
    scan_width = check_range("scan_width", scan_width, low=0.0, low_open=True)
    out: list[MultiImpactOrbit] = []
    if p == 2 and period_doubling:
        for parent in one_impact_orbits(params, t_max):
            if not (parent.admissible and _has_real_flip(parent)):
                continue
            orbit = _pd_branch_orbit(params, parent, scan_width, t_max)
            if orbit is not None and not any(_same_orbit(orbit, o) for o in out):
                out.append(orbit)
    brute = orbits_from_simulation(params, p, starts=starts)
    n = 0
    for o in brute:
        if any(_same_orbit(o, b) for b in out):
            continue
        n += 1
        out.append(_relabel(o, f"M{p}-{n}"))
    return tuple(out)


def _pd_branch_orbit(params: Parameters, parent: ImpactOrbit, width: float, t_max: float) -> MultiImpactOrbit | None:
    """The period-2 orbit of the period-doubled branch of ``parent`` at ``params``, if it reaches them."""
    g = params.gamma
    for lo, hi in ((g, g + width), (g - width, g)):
        try:
            pd = find_period_doubling(params, parent.label, "gamma", lo=lo, hi=hi, t_max=t_max)
        except ParameterError:
            continue
        # the branch is born on one side of the bifurcation; the orbit at params lies on the side of g
        side = 1.0 if g > pd.value else -1.0
        offset = side * min(1e-4, 0.5 * abs(g - pd.value))
        try:
            start = period_doubled_orbit(pd, offset, t_max=t_max)
        except (NewtonFailure, ParameterError):
            continue
        try:
            branch = continue_multi_impact(start, "gamma", g)
        except (CorrectionError, ParameterError):
            continue
        if branch.orbits and abs(branch.values[-1] - g) <= 1e-9 * (1.0 + abs(g)):
            last = branch.orbits[-1]
            try:
                return solve_multi_impact(params, last.states, label=last.label)
            except NewtonFailure:
                return None
    return None
