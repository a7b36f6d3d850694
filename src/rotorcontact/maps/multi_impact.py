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
* Grid (`orbits_from_grid`): Newton's method from the iterates of every state
  of a grid on Sigma; this finds unstable orbits too.
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
The continuation of these orbits in one parameter, and the search of every
orbit at given parameters (which follows the period-doubled branches), are in
`rotorcontact.continuation.multi_impact_branches`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np

from ..model.angles import wrap_angle
from ..errors import ParameterError
from .impact_map import (
    SLIP_BOUNDED,
    ImpactOrbit,
    check_orbit_label,
    flight_extrema,
    impact_map,
    one_impact_orbits,
    post_impact_state,
)
from ..simulation.motion import detect_period
from ..model.params import BRANCH_PARAMETERS, MAX_VELOCITY, Parameters, check_finite, check_range
from ..model.validation import (check_bool, check_choice, check_float, check_int, check_length, check_params,
                                check_type, is_pair, quoted, real_array)
from ..simulation.simulator import check_start, simulate

__all__ = [
    "CONTINUATION_PARAMETERS",
    "ImpactPoint",
    "MultiImpactOrbit",
    "PeriodDoubling",
    "NewtonFailure",
    "cycle_jacobian",
    "multipliers_at",
    "periodic_residual",
    "solve_multi_impact",
    "orbits_from_simulation",
    "check_starts",
    "MAX_STARTS",
    "orbits_from_grid",
    "find_period_doubling",
    "period_doubling_at",
    "doubled_orbit_at_amplitude",
    "period_doubled_orbit",
]

#: Parameters in which multi-impact orbits can be continued.
CONTINUATION_PARAMETERS = BRANCH_PARAMETERS

#: Most impacts per period of an orbit: its Newton system has 3 unknowns per impact, and a dense
#: Jacobian of (3 x 4096)^2 doubles is 1.2 GB; 4096 still holds 16 impacts doubled 8 times.
MAX_ORBIT_IMPACTS = 4096
#: Largest amplitude of a period-doubled orbit's entry: the branch is entered near its parent, where the
#: amplitude of the flip is small against the clearance.
MAX_AMPLITUDE = 1.0
#: Most Newton iterations (or first amplitudes) a caller may ask for.
MAX_NEWTON_ITERATIONS = 10_000
#: Most intervals of `find_period_doubling`'s scan: each point finds the orbits of one parameter set.
MAX_SCAN = 10_000
NEWTON_TOL = 1e-12
MAX_NEWTON = 40
HORIZON = 1000.0
SAME_TOL = 1e-7
DETECT_TOL = 1e-3
TWO_PI = 2.0 * math.pi


class NewtonFailure(RuntimeError):
    """Newton's method did not converge to an orbit with the requested number of impacts."""


class _MapFailure(ParameterError):
    """The impact map has no impact from a state (no crossing, stuck on the stator, or failure): for states
    given by a user, a bad input naming them."""


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
            raise _MapFailure(f"states[{i}] = {tuple(map(float, x))} has rdot = {float(x[1])!r} <= 0, not an impact; "
                              "allowed: impact states, rdot > 0")
        res = impact_map(params, x, horizon=HORIZON, law=law, jacobian=True)
        if res.status != "impact":
            raise _MapFailure(f"states[{i}] = {tuple(map(float, x))} has no next impact ({res.status}); allowed: "
                              "the impact states of an impacting motion")
        images[i] = res.state
        times[i] = res.time
        jacs[i] = res.jacobian
        sticking[i] = res.sticking
    return images, times, jacs, sticking


def cycle_jacobian(jacs) -> np.ndarray:
    """J_{p-1} ... J_0: the Jacobian of P_I^p at x_0 from the Jacobians of P_I at the p points."""
    m = np.eye(3)
    for j in jacs:
        m = j @ m
    return m


def multipliers_at(params: Parameters, states) -> np.ndarray:
    """Eigenvalues of the Jacobian of P_I^p at the p points ``states`` (not sorted).

    Raises
    ------
    ParameterError
        For ``states`` that are not a (p, 3) array of impact states, or when the impact map has no next
        impact from one of them.
    """
    check_params(params)
    return np.linalg.eigvals(cycle_jacobian(_chain(params, impact_states(states, "states"))[2]))


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
    ParameterError
        For ``states`` that are not a (p, 3) array of impact states, or when the impact map has no next
        impact from one of them.
    """
    x = impact_states(states, "states")
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
        """(U, U') just after impact ``index`` (0 to impacts - 1): starts `simulate` on the orbit."""
        index = check_int("index", index, 0, self.impacts - 1)
        return post_impact_state(self.params, self.states[index], law=SLIP_BOUNDED)

    def jacobian(self) -> np.ndarray:
        """Jacobian of P_I^p at the first point (the product of the p Jacobians of P_I)."""
        return cycle_jacobian(_chain(self.params, self.states)[2])

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
    ev = np.linalg.eigvals(cycle_jacobian(jacs))
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


def impact_states(states, name: str = "guess") -> np.ndarray:
    """``states`` as a (p, 3) array of finite (theta, rdot-, thetadot-) rows, 1 <= p <= `MAX_ORBIT_IMPACTS`,
    each an impact (rdot- > 0) at most `MAX_VELOCITY` fast; a `ParameterError` naming ``name`` otherwise (text,
    bools, ragged lists, other shapes)."""
    x = real_array(states)
    if x is None:
        raise ParameterError(f"{name} = {quoted(states)} is not a (p, 3) array of (theta, rdot, thetadot)")
    if x.ndim != 2 or x.shape[1] != 3 or not 1 <= x.shape[0] <= MAX_ORBIT_IMPACTS:
        raise ParameterError(f"{name} has shape {x.shape}; allowed: (p, 3) with 1 <= p <= {MAX_ORBIT_IMPACTS}")
    if not np.all(np.isfinite(x)):
        raise ParameterError(f"{name} is not finite; allowed: finite (theta, rdot, thetadot) rows")
    # (a `_MapFailure`: within Newton's method an iterate leaving the impacts is a failed step, not bad input)
    for i, row in enumerate(x):
        if not row[1] > 0.0:
            raise _MapFailure(f"{name}[{i}] = {tuple(map(float, row))} has rdot = {float(row[1])!r} <= 0, not an "
                              "impact; allowed: impact states, rdot > 0")
        if not abs(complex(row[1], row[2])) <= MAX_VELOCITY:
            raise _MapFailure(f"{name}[{i}] = {tuple(map(float, row))} is too fast; allowed: |(rdot, thetadot)| <= "
                              f"{MAX_VELOCITY:g}")
    return np.array(x, dtype=float)


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
    check_params(params)
    x = impact_states(guess)
    tol = check_range("tol", tol, low=0.0, low_open=True)
    if label is not None and not (isinstance(label, str) and label):
        raise ParameterError(f"label = {label!r} is invalid; allowed: a non-empty name, or None for M<p>")
    canonical = check_bool("canonical", canonical)
    x = _newton(params, x, tol, check_int("max_iter", max_iter, 1, MAX_NEWTON_ITERATIONS))
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
    check_params(params)
    p = check_int("impacts", impacts, 1, MAX_ORBIT_IMPACTS)
    t_transient = check_range("t_transient", t_transient, low=0.0)
    t_record = check_range("t_record", t_record, low=0.0, low_open=True)
    found: list[MultiImpactOrbit] = []
    starts = check_starts(starts)
    for u0, du0 in _default_starts() if starts is None else starts:
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


#: Default grid of impact states (theta, rdot-, thetadot-) on the section for `orbits_from_grid`.
GRID_SHAPE = (12, 4, 4)
GRID_RDOT = (0.1, 1.5)
GRID_THETADOT = (-3.0, 1.0)
MAX_GRID_POINTS = 20000
#: Shortest flight between two impacts of an orbit found from the grid.
MIN_FLIGHT = 1e-3


#: Most starts of `orbits_from_simulation`: each is a simulation over 1800 time units (a quarter of a
#: second or more), so a thousand take minutes.
MAX_STARTS = 1000


def check_starts(starts) -> list[tuple[complex, complex]] | None:
    """``starts`` as a list of initial states (u0, du0) checked as `rotorcontact.simulate` checks them, at
    most `MAX_STARTS` (none: no simulation); None stays None (the default starts).

    Raises
    ------
    ParameterError
        Naming ``starts``, or ``starts[i]`` for the first state that is not a pair `simulate` takes.
    """
    if starts is None:
        return None
    listed = isinstance(starts, (list, tuple)) or (isinstance(starts, np.ndarray) and starts.ndim >= 1)
    if not listed or len(starts) > MAX_STARTS:
        raise ParameterError(f"starts = {quoted(starts)} is invalid; allowed: a list of at most {MAX_STARTS} initial "
                             "states (u0, du0), or None")
    out = []
    for i, start in enumerate(starts):
        if not is_pair(start):
            raise ParameterError(f"starts[{i}] = {quoted(start)} is invalid; allowed: an initial state (u0, du0), two "
                                 "complex numbers")
        try:
            out.append(check_start(*start))
        except ParameterError as exc:
            raise ParameterError(f"starts[{i}] = {quoted(start)} is invalid; allowed: an initial state (u0, du0) "
                                 f"that rotorcontact.simulate takes ({exc})") from None
    return out


def _check_range_pair(name: str, value) -> tuple[float, float]:
    if not is_pair(value):
        raise ParameterError(f"{name} = {value!r} is invalid; allowed: (low, high), two numbers")
    return check_float(f"{name}[0]", value[0]), check_float(f"{name}[1]", value[1])


def orbits_from_grid(
    params: Parameters,
    impacts: int,
    *,
    shape: Sequence[int] = GRID_SHAPE,
    rdot_range: Sequence[float] = GRID_RDOT,
    thetadot_range: Sequence[float] = GRID_THETADOT,
    max_iter: int = 25,
) -> tuple[MultiImpactOrbit, ...]:
    """Every orbit with ``impacts`` impacts per period that Newton's method finds from a grid on the section.

    The grid is ``shape = (n_theta, n_rdot, n_thetadot)`` states of Sigma:
    theta equally spaced on the circle, rdot- in ``rdot_range`` and
    thetadot- in ``thetadot_range`` (end points included). From each state
    x the guess (x, P_I(x), ..., P_I^{p-1}(x)) starts `solve_multi_impact`;
    states whose iterates leave the impacting motion are skipped. Unstable
    orbits are found as well as stable ones. Distinct orbits are returned,
    sorted by period and labelled ``"M<p>-<j>"``.

    Parameters
    ----------
    params : Parameters
    impacts : int
        p >= 1.
    shape : sequence of 3 int
        Grid points in theta, rdot- and thetadot- (each >= 1, at most
        `MAX_GRID_POINTS` in all).
    rdot_range, thetadot_range : pair of float
        Ranges of rdot- (> 0) and thetadot-.
    max_iter : int
        Newton iterations from each start.

    Returns
    -------
    tuple of MultiImpactOrbit
    """
    check_params(params)
    p = check_int("impacts", impacts, 1, MAX_ORBIT_IMPACTS)
    if not (isinstance(shape, (list, tuple, np.ndarray)) and len(shape) == 3):
        raise ParameterError(f"shape = {shape!r} is invalid; allowed: three integers >= 1")
    n_th, n_r, n_td = (check_int(f"shape[{i}]", n, 1, MAX_GRID_POINTS) for i, n in enumerate(shape))
    if n_th * n_r * n_td > MAX_GRID_POINTS:
        raise ParameterError(f"shape = {tuple(shape)!r} is invalid; allowed: three integers >= 1 with a product "
                             f"of at most {MAX_GRID_POINTS}")
    r_lo, r_hi = _check_range_pair("rdot_range", rdot_range)
    if not 0.0 < r_lo <= r_hi <= MAX_VELOCITY:
        raise ParameterError(f"rdot_range = {tuple(rdot_range)!r} is invalid; allowed: 0 < low <= high <= "
                             f"{MAX_VELOCITY:g}")
    td_lo, td_hi = _check_range_pair("thetadot_range", thetadot_range)
    if not (td_lo <= td_hi and max(abs(td_lo), abs(td_hi)) <= MAX_VELOCITY):
        raise ParameterError(f"thetadot_range = {tuple(thetadot_range)!r} is invalid; allowed: low <= high, both "
                             f"within +-{MAX_VELOCITY:g}")
    max_iter = check_int("max_iter", max_iter, 1, MAX_NEWTON_ITERATIONS)
    found: list[MultiImpactOrbit] = []
    thetas = -math.pi + TWO_PI * (np.arange(n_th) + 0.5) / n_th
    for th in thetas:
        for r in np.linspace(r_lo, r_hi, n_r):
            for td in np.linspace(td_lo, td_hi, n_td):
                guess = _iterates(params, np.array([th, r, td]), p)
                if guess is None:
                    continue
                try:
                    orbit = solve_multi_impact(params, guess, max_iter=max_iter)
                except NewtonFailure:
                    continue
                if not np.min(orbit.times) > MIN_FLIGHT:
                    continue  # an impact at once after an impact (a grazing state), not an orbit
                if not any(_same_orbit(orbit, o) for o in found):
                    found.append(orbit)
    found.sort(key=lambda o: (o.period, o.points[0].theta))
    return tuple(_relabel(o, f"M{p}-{j + 1}") for j, o in enumerate(found))


def _iterates(params: Parameters, x: np.ndarray, p: int) -> np.ndarray | None:
    """(x, P_I(x), ..., P_I^{p-1}(x)), or None where an iterate has no next impact."""
    out = [x]
    for _ in range(p - 1):
        res = impact_map(params, out[-1], horizon=HORIZON, law=SLIP_BOUNDED)
        if res.status != "impact" or not res.state[1] > 0.0:
            return None
        out.append(np.asarray(res.state, dtype=float))
    return np.array(out)


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
    param : str
        The parameter varied (also readable as ``parameter``).
    value : float
        Its value at the period doubling.
    orbit : ImpactOrbit or MultiImpactOrbit
        The orbit that doubles, there (one-impact from `find_period_doubling`,
        any p from `period_doubling_at`).
    eigenvector : numpy.ndarray
        Real unit eigenvector of the multiplier -1 in (theta, rdot-, thetadot-).
    multiplier : float
        The multiplier nearest -1 at ``value``.
    unstable_side : float
        +1 when the orbit is unstable (multiplier below -1) above ``value``, -1
        below, 0.0 where not determined.
    """

    parent: str
    param: str
    value: float
    orbit: Any = field(repr=False)
    eigenvector: np.ndarray = field(repr=False)
    multiplier: float
    unstable_side: float

    @property
    def parameter(self) -> str:
        """`param` (its former name)."""
        return self.param


def _check_parameter(param: str) -> str:
    return check_choice("param", param, CONTINUATION_PARAMETERS)


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
    param: str = "gamma",
    *,
    lo: float,
    hi: float,
    n_scan: int = 24,
    tol: float = 1e-12,
    t_max: float = 12.0,
) -> PeriodDoubling:
    """Locate where a one-impact orbit loses stability through a multiplier -1.

    The interval [lo, hi] of ``param`` is scanned at ``n_scan + 1``
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
    check_params(params)
    label = check_orbit_label("label", label)
    param = _check_parameter(param)
    lo = check_finite("lo", lo)
    hi = check_finite("hi", hi)
    if not lo < hi:
        raise ParameterError(f"lo = {lo!r}, hi = {hi!r} is not an interval; allowed: finite lo < hi")
    n_scan = check_int("n_scan", n_scan, 1, MAX_SCAN)
    tol = check_float("tol", tol, 0.0, low_open=True)

    def measure(v: float) -> float | None:
        try:
            return _flip_measure(_one_impact(params.replace(**{param: v}), label, t_max))
        except ParameterError:
            return None

    grid = np.linspace(lo, hi, n_scan + 1)
    vals = [measure(v) for v in grid]
    bracket = None
    for i in range(len(grid) - 1):
        a, b = vals[i], vals[i + 1]
        if a is not None and b is not None and (a < 0.0) != (b < 0.0):
            bracket = (grid[i], a, grid[i + 1], b)
            break
    if bracket is None:
        raise ParameterError(
            f"no period doubling of {label} found for {param} in [{lo:g}, {hi:g}]; "
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
    p_pd = params.replace(**{param: value})
    orbit = _one_impact(p_pd, label, t_max)
    if orbit is None:
        raise ParameterError(f"{label} does not exist at {param} = {value:g}")
    ev, vec = np.linalg.eig(orbit.jacobian())
    i = int(np.argmin(np.abs(ev + 1.0)))
    if abs(ev[i] + 1.0) > 1e-4:
        raise ParameterError(
            f"{label} loses stability at {param} = {value:.12g} through the multipliers "
            f"{ev[i]:.6g} (not -1: a Neimark-Sacker bifurcation, not a period doubling)"
        )
    v = np.real(vec[:, i])
    v /= np.linalg.norm(v)
    if v[np.argmax(np.abs(v))] < 0:
        v = -v
    return PeriodDoubling(
        parent=label,
        param=param,
        value=float(value),
        orbit=orbit,
        eigenvector=v,
        multiplier=float(np.real(ev[i])),
        unstable_side=unstable_side,
    )


def period_doubling_at(orbit: MultiImpactOrbit, param: str, *, unstable_side: float = 0.0) -> PeriodDoubling:
    """The period doubling at an orbit with p impacts that has a multiplier -1 (located beforehand).

    Parameters
    ----------
    orbit : MultiImpactOrbit
        The orbit at the period doubling (for example the orbit of a located
        ``"period-doubling"`` event of a branch); p = 1 is allowed.
    param : str
        The parameter in which it was located.
    unstable_side : float
        +1 or -1 when known (see `PeriodDoubling`), 0.0 otherwise.

    Raises
    ------
    ParameterError
        When no multiplier is within 1e-4 of -1.
    """
    if not isinstance(orbit, MultiImpactOrbit):
        raise ParameterError(f"orbit = {orbit!r} is not a MultiImpactOrbit")
    param = _check_parameter(param)
    ev, vec = np.linalg.eig(orbit.jacobian())
    i = int(np.argmin(np.abs(ev + 1.0)))
    if abs(ev[i] + 1.0) > 1e-4:
        raise ParameterError(f"{orbit.label} has no multiplier -1 at {param} = {getattr(orbit.params, param):.12g} "
                             f"(nearest {ev[i]:.6g}); allowed: an orbit at a period doubling")
    v = np.real(vec[:, i])
    v /= np.linalg.norm(v)
    if v[np.argmax(np.abs(v))] < 0:
        v = -v
    return PeriodDoubling(parent=orbit.label, param=param, value=float(getattr(orbit.params, param)), orbit=orbit,
                          eigenvector=v, multiplier=float(np.real(ev[i])), unstable_side=float(unstable_side))


def _parent_states(pd: PeriodDoubling) -> np.ndarray:
    """The q points of the orbit that doubles, in the order of the motion (q = 1 for a one-impact orbit)."""
    if isinstance(pd.orbit, MultiImpactOrbit):
        return pd.orbit.states
    return np.asarray(pd.orbit.state, dtype=float)[None, :]


def _doubled_guess(pd: PeriodDoubling, amplitude: float) -> np.ndarray:
    """x_i + a w_i then x_i - a w_i (i < q): w_0 the eigenvector of -1, w_{i+1} = J_i w_i (so w_q = -w_0)."""
    x = _parent_states(pd)
    _im, _t, jacs, _s = _chain(pd.orbit.params, x)
    w = [np.asarray(pd.eigenvector, dtype=float)]
    for j in jacs[:-1]:
        w.append(j @ w[-1])
    w = np.array(w)
    return np.vstack([x + amplitude * w, x - amplitude * w])


def _amplitude_residual(pd: PeriodDoubling, y: np.ndarray, amplitude: float) -> tuple[np.ndarray, np.ndarray]:
    """G(x, lambda) of P_I^{2q} and v . (x_0 - x_q) - 2a, with the Jacobian in (x, lambda)."""
    q2 = (y.shape[0] - 1) // 3
    x = y[:-1].reshape(q2, 3)
    lam = float(y[-1])
    base = pd.orbit.params
    res, jx = periodic_residual(base.replace(**{pd.param: lam}), x)
    h = 1e-7 * max(1.0, abs(lam))
    rp = periodic_residual(base.replace(**{pd.param: lam + h}), x)[0]
    rm = periodic_residual(base.replace(**{pd.param: lam - h}), x)[0]
    diff = x[0] - x[q2 // 2]
    diff[0] = math.remainder(diff[0], TWO_PI)
    v = np.asarray(pd.eigenvector, dtype=float)
    row = np.zeros(3 * q2 + 1)
    row[:3] = v
    row[3 * (q2 // 2) : 3 * (q2 // 2) + 3] = -v
    jac = np.vstack([np.column_stack([jx, (rp - rm) / (2.0 * h)]), row[None, :]])
    return np.append(res, v @ diff - 2.0 * amplitude), jac


def doubled_orbit_at_amplitude(pd: PeriodDoubling, amplitude: float, *, tol: float = NEWTON_TOL,
                               max_iter: int = MAX_NEWTON) -> MultiImpactOrbit:
    """The orbit of the period-doubled branch whose first and (q+1)-th points differ by 2a along v.

    The branch born at a period doubling is parametrised by its amplitude
    a = v . (x_0 - x_q) / 2 (v the eigenvector of -1): Newton's method on
    P_I^{2q}(x) = x together with that condition, with the parameter free,
    is regular at small a whether the doubling is super- or subcritical
    (with the parameter fixed, the Jacobian of P_I^{2q} - I is singular at
    the doubling and Newton drifts onto the orbit that doubles). The
    parameter of the result tells the side on which the branch is born.

    Raises
    ------
    NewtonFailure
        When Newton's method does not converge.
    """
    check_type("pd", pd, PeriodDoubling, "a PeriodDoubling (find_period_doubling, period_doubling_at)")
    a = check_float("amplitude", amplitude, 0.0, MAX_AMPLITUDE, low_open=True)
    tol = check_float("tol", tol, 0.0, low_open=True)
    max_iter = check_int("max_iter", max_iter, 1, MAX_NEWTON_ITERATIONS)
    guess = _doubled_guess(pd, a)
    y = np.append(guess.ravel(), pd.value)
    try:
        res, jac = _amplitude_residual(pd, y, a)
    except (_MapFailure, ParameterError) as exc:
        raise NewtonFailure(f"the impact map failed at the starting point: {exc}") from None
    norm = float(np.max(np.abs(res)))
    for _ in range(max_iter):
        if norm <= tol:
            break
        try:
            dy = np.linalg.solve(jac, -res)
        except np.linalg.LinAlgError:
            raise NewtonFailure("singular Jacobian of the amplitude system") from None
        lam = 1.0
        while lam >= 1.0 / 64.0:
            try:
                r_t, j_t = _amplitude_residual(pd, y + lam * dy, a)
            except (_MapFailure, ParameterError):
                lam *= 0.5
                continue
            n_t = float(np.max(np.abs(r_t)))
            if n_t < norm:
                y, res, jac, norm = y + lam * dy, r_t, j_t, n_t
                break
            lam *= 0.5
        else:
            break
    if not norm <= tol:
        raise NewtonFailure(f"no period-doubled orbit of amplitude {a:g} near {pd.parent} (|G| = {norm:.3g})")
    params = pd.orbit.params.replace(**{pd.param: float(y[-1])})
    x = y[:-1].reshape(-1, 3)
    if _least_period(x) < x.shape[0]:
        raise NewtonFailure(f"amplitude {a:g} converged onto the orbit that doubles")
    drift = np.abs(x - guess)
    drift[:, 0] = np.abs(np.remainder(drift[:, 0] + math.pi, TWO_PI) - math.pi)
    if np.max(drift) > 10.0 * a:
        # the branch leaves the doubling like x* +- a w + O(a^2): far from the guess is another orbit
        raise NewtonFailure(f"amplitude {a:g} converged to an orbit away from {pd.parent}'s doubling")
    return _build_orbit(params, x, f"{pd.parent}/PD")


def period_doubled_orbit(
    pd: PeriodDoubling,
    offset: float,
    *,
    amplitudes: Sequence[float] = (1e-3, 3e-3, 1e-2),
    t_max: float = 12.0,
) -> MultiImpactOrbit:
    """The period-2q orbit born at a period doubling, at ``pd.param = pd.value + offset``.

    The branch is entered at a small amplitude a
    (`doubled_orbit_at_amplitude`), which gives the side on which it is born;
    near the doubling lambda - lambda_PD grows like a^2, so a is rescaled by
    sqrt(offset / (lambda(a) - lambda_PD)) (at most 8 times) until lambda(a)
    is close to the target, and Newton's method with the parameter fixed
    finishes there. Super- and subcritical doublings are handled alike.

    Parameters
    ----------
    pd : PeriodDoubling
        From `find_period_doubling` (a one-impact orbit) or `period_doubling_at`.
    offset : float
        Nonzero distance from the doubling in ``pd.param``.
    amplitudes : sequence of float
        First amplitudes tried, in turn, until one converges.
    t_max : float
        Unused (kept for the former signature).

    Returns
    -------
    MultiImpactOrbit
        Labelled ``"<parent>/PD"``.

    Raises
    ------
    NewtonFailure
        When the branch is born on the other side of the doubling, or when no
        amplitude converges.
    """
    check_type("pd", pd, PeriodDoubling, "a PeriodDoubling (find_period_doubling, period_doubling_at)")
    offset = check_range("offset", offset)
    if not isinstance(amplitudes, (list, tuple, np.ndarray)) or not len(amplitudes):
        raise ParameterError(f"amplitudes = {quoted(amplitudes)} is invalid; allowed: a non-empty list of amplitudes")
    check_length("amplitudes", amplitudes, MAX_NEWTON_ITERATIONS)
    amplitudes = [check_float(f"amplitudes[{i}]", a, 0.0, MAX_AMPLITUDE, low_open=True)
                  for i, a in enumerate(amplitudes)]
    if offset == 0.0:
        raise ParameterError("offset = 0.0 is invalid; allowed: a nonzero offset from the bifurcation")
    target = pd.value + offset
    label = f"{pd.parent}/PD"
    last = "no amplitude tried"
    for a0 in amplitudes:
        try:
            orbit = doubled_orbit_at_amplitude(pd, a0)
        except NewtonFailure as exc:
            last = str(exc)
            continue
        a = a0
        for _ in range(8):
            shift = getattr(orbit.params, pd.param) - pd.value
            if shift == 0.0 or (shift > 0.0) != (offset > 0.0):
                raise NewtonFailure(f"no period-doubled orbit of {pd.parent} at {pd.param} = {target:g}: the branch "
                                    f"is born on the other side of {pd.param} = {pd.value:.12g}")
            if abs(shift - offset) <= 1e-3 * abs(offset):
                break
            a *= math.sqrt(offset / shift)
            try:
                orbit = doubled_orbit_at_amplitude(pd, a)
            except NewtonFailure as exc:
                last = str(exc)
                break
        try:
            return solve_multi_impact(pd.orbit.params.replace(**{pd.param: target}), orbit.states, label=label,
                                      canonical=False)
        except NewtonFailure as exc:
            last = str(exc)
    raise NewtonFailure(f"no period-doubled orbit near {pd.parent} at {pd.param} = {target:g}: {last}")
