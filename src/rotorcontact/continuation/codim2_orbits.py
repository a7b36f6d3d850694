"""Two-parameter curves of orbits with p >= 1 impacts per period: period doubling, Neimark-Sacker, fold, grazing.

Each curve is a solution curve, in the unknowns (x_0, ..., x_{p-1}, p1, p2),
of the periodic-orbit equations G(x) = 0 of `rotorcontact.maps.multi_impact`
(x_i the impact states, G_i = P_I(x_i) - x_{i+1}) and one more equation:

* ``period-doubling``: det(M + I) = 0, M the Jacobian of P_I^p;
* ``neimark-sacker``: the bialternate product prod_{i<j}(z_i z_j - 1) = 0 of
  the multipliers z of M (a complex pair on the unit circle); the curve ends
  where that pair turns real, at a 1:2 (z = -1, -1) or 1:1 (z = 1, 1) strong
  resonance (`rotorcontact.continuation.events.unit_pair_discriminant`), beyond
  which the product vanishes for a real pair with product 1, no bifurcation;
* ``fold``: det(M - I) = 0.

Grazing curves (`grazing_curve_of`) use the orbit equations with the flight
times as unknowns, which stay smooth through the grazing.

These are the test functions of the one-parameter branches
(`rotorcontact.continuation.events`). The seed is found on the branch of the
orbit in p1 (`rotorcontact.continuation.multi_impact_branches.continue_multi_impact`,
towards each end of the p1 range in turn): the first event of the kind. The curve is then continued both ways by
pseudo-arclength (`rotorcontact.continuation.engine.continue_both_ways`) inside
the box, with a Jacobian by central differences.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ..errors import ParameterError
from ..maps.impact_map import (
    SLIP_BOUNDED,
    _check_t_max,
    flight_extrema,
    impact_map_jacobian,
    one_impact_orbits,
    post_impact_state,
)
from ..maps.multi_impact import (
    MultiImpactOrbit,
    NewtonFailure,
    _MapFailure,
    multipliers_at,
    periodic_residual,
    solve_multi_impact,
)
from ..model.flow import propagate
from ..model.params import Parameters
from ..model.validation import check_choice, check_params, check_type, quoted, settings_or_default
from ..simulation.motion import MAX_PERIOD_IMPACTS
from .codim2 import Codim2Curve, _check_scan, _Plane, coalescence_curves
from .engine import (
    ContinuationSettings,
    CorrectionError,
    EventFunction,
    continue_both_ways,
    correct_fixed,
)
from .events import bialternate_product, det_minus_identity, det_plus_identity, unit_pair_discriminant
from .multi_impact_branches import check_orbit, continue_multi_impact
from .multi_impact_families import seed_orbits

__all__ = ["CURVE_KINDS", "CURVE_SPECS", "MAX_SPECS", "extra_curves", "grazing_curve_of", "orbit_by_label",
           "orbit_curve"]

#: The ``--curves`` specifications: a kind of `CURVE_KINDS` by its short name, or the coalescences.
CURVE_SPECS = ("coalescence", "pd:<orbit>", "ns:<orbit>", "fold:<orbit>", "grazing:<orbit>")

#: The kinds of two-parameter curves of an orbit, and the short names of the curves.
CURVE_KINDS = {"period-doubling": "pd", "neimark-sacker": "ns", "fold": "fold"}

_TESTS = {"period-doubling": det_plus_identity, "neimark-sacker": bialternate_product, "fold": det_minus_identity}

#: Most specifications of `extra_curves`: each asks for a continuation of a curve (a minute or more for
#: an orbit of many impacts); the command line's ``--curves`` takes fewer.
MAX_SPECS = 40


def _check_name(name) -> str | None:
    return check_type("name", name, str, "the name of the curve (text)", optional=True)


#: The orbit labels of `orbit_by_label`.
LABEL_FORMS = f"B<n>,<m> (B1,d) or M<p>-<j> (M2-1) with p from 1 to {MAX_PERIOD_IMPACTS}"


def _label_kind(label) -> tuple[str, int] | None:
    """``("M", p)`` for a label ``"M<p>-<j>"``, ``("B", 1)`` for ``"B<n>,<m>"``, None for anything else
    (`LABEL_FORMS`)."""
    if isinstance(label, str):
        m = re.fullmatch(r"M(\d+)-(\d+)", label)
        if m and 1 <= int(m.group(1)) <= MAX_PERIOD_IMPACTS:
            return "M", int(m.group(1))
        if re.fullmatch(r"B\d+,[abcd]", label):
            return "B", 1
    return None


def _settings() -> ContinuationSettings:
    return ContinuationSettings(step=0.01, min_step=1e-9, max_step=0.04, max_points=600, location_tol=1e-10,
                                residual_tol=1e-9)


def _seed(orbit: MultiImpactOrbit, kind: str, plane: _Plane) -> np.ndarray | None:
    """A point of the curve on the branch of ``orbit`` in p1 at the base p2: the first event of ``kind``."""
    p1 = plane.params[0]
    for end in plane.ranges[0][::-1]:
        branch = continue_multi_impact(orbit, p1, end, max_points=4000)
        ev = next((e for e in branch.events if e.kind == kind and e.orbit is not None), None)
        if ev is not None:
            return np.concatenate([ev.orbit.states.ravel(), [ev.value, getattr(orbit.params, plane.params[1])]])
    return None


def orbit_curve(
    orbit: MultiImpactOrbit,
    kind: str,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    *,
    name: str | None = None,
    settings: ContinuationSettings | None = None,
) -> Codim2Curve:
    """The two-parameter curve of ``kind`` of an orbit with p impacts per period (module docstring).

    Parameters
    ----------
    orbit : MultiImpactOrbit
        The orbit at the base parameters (p = 1 for a one-impact orbit).
    kind : str
        One of `CURVE_KINDS`.
    param : (str, str)
        The plane; the seed is looked for along p1.
    ranges : ((float, float), (float, float)), optional
        The box; `rotorcontact.continuation.codim2.DEFAULT_RANGES` when omitted.
    name : str, optional
        Name of the curve; default ``"<short kind>_<label>"`` with the comma of the label dropped
        (``"pd_B1d"``, ``"ns_M6-1"``).
    settings : ContinuationSettings, optional

    Returns
    -------
    Codim2Curve
        Of kind ``kind`` (``"orbit-fold"`` for a fold, apart from the folds
        of F1 of `rotorcontact.continuation.codim2`). With no piece when no
        seed is found along p1. The unknowns of a piece
        are (x_0 .. x_{p-1}, p1, p2).

    Raises
    ------
    ParameterError
        Unless ``orbit`` is a `MultiImpactOrbit`, ``kind`` one of `CURVE_KINDS`, ``param`` and ``ranges`` a
        plane and its box, ``name`` text or None and ``settings`` a `ContinuationSettings` or None.
    """
    check_orbit(orbit)
    kind = check_choice("kind", kind, tuple(CURVE_KINDS))
    _check_name(name)
    plane = _Plane(orbit.params, param, ranges)
    name = name or f"{CURVE_KINDS[kind]}_{orbit.label.replace(',', '')}"
    curve_kind = "orbit-fold" if kind == "fold" else kind
    settings = settings_or_default(settings, ContinuationSettings, _settings)
    p = orbit.impacts
    seed = _seed(orbit, kind, plane)
    if seed is None:
        return Codim2Curve(name=name, kind=curve_kind, params=plane.params, pieces=(), ends=("no seed along " +
                                                                                       plane.params[0],))
    y0 = seed

    def residual(y):
        params = plane.at(y[-2], y[-1])
        x = y[: 3 * p].reshape(p, 3)
        try:
            g = periodic_residual(params, x)[0]
            extra = [_TESTS[kind](multipliers_at(params, x))]
        except _MapFailure as exc:
            raise ParameterError(f"the impact map failed: {exc}") from None
        return np.concatenate([g, extra])

    events = []
    if kind == "neimark-sacker":

        def resonance(y):
            try:
                return -unit_pair_discriminant(multipliers_at(plane.at(y[-2], y[-1]), y[: 3 * p].reshape(p, 3)))
            except (_MapFailure, ParameterError):
                return None

        # the bialternate product also vanishes where a real pair has product 1 (a neutral saddle, no
        # bifurcation): the curve ends where its pair leaves the unit circle, at a 1:2 (-1, -1) or 1:1 resonance
        # (the event is >= 0 on the curve, as every terminal event inside its domain)
        events.append(EventFunction("strong-resonance", resonance, terminal=True))
    return _continued(residual, y0, plane, name, curve_kind, p, events, settings)


def _continued(residual, y0: np.ndarray, plane: _Plane, name: str, kind: str, p: int,
               events: list[EventFunction], settings: ContinuationSettings) -> Codim2Curve:
    """The seed corrected onto the curve (p2 held) and continued both ways inside the box.

    Besides the box and ``events``, the curve ends where an impact velocity reaches 0 (the orbit turns virtual).
    """
    weights = np.ones_like(y0)
    weights[-2] = 1.0 / plane.span(0)
    weights[-1] = 1.0 / plane.span(1)
    try:
        y0 = correct_fixed(residual, y0, len(y0) - 1, settings=settings)
    except CorrectionError:
        return Codim2Curve(name=name, kind=kind, params=plane.params, pieces=(),
                           ends=("the seed could not be corrected onto the curve",))
    events = plane.box_events() + [
        EventFunction("impact", lambda y: float(np.min(y[1: 3 * p: 3])), terminal=True)] + events
    both = continue_both_ways(residual, y0, events=events, settings=settings, weights=weights, param_index=-1,
                              correct_start=False)
    if both is None:
        return Codim2Curve(name=name, kind=kind, params=plane.params, pieces=(), ends=("no continuation",))
    return Codim2Curve(name=name, kind=kind, params=plane.params, pieces=(both.points,), ends=both.messages)


def _flight(params: Parameters, x: np.ndarray, t: float) -> tuple[complex, complex]:
    """(U, U') at time t after the impact at the pre-impact state x (exact free flight, MODEL.md §3)."""
    u0, du0 = post_impact_state(params, x, law=SLIP_BOUNDED)
    k = params.k
    v, dv = propagate(u0 - k, du0, t, params.gamma, params.omega)
    return k + v, dv


def _formal_residual(params: Parameters, x: np.ndarray, times: np.ndarray) -> np.ndarray:
    """The orbit equations with the flight times as unknowns: P(x_i; T_i) - x_{i+1} and |U(T_i)|^2 - 1.

    P(x; T) is the state after a flight of length T with no search for an earlier
    crossing (`rotorcontact.maps.impact_map.impact_map_jacobian`), so the equations
    stay smooth where an interior maximum of r passes 1.
    """
    p = x.shape[0]
    out = np.empty(4 * p)
    for i in range(p):
        x1 = impact_map_jacobian(params, x[i], float(times[i]))[0]
        d = x1 - x[(i + 1) % p]
        d[0] = math.remainder(d[0], 2.0 * math.pi)
        out[3 * i: 3 * i + 3] = d
        u, _du = _flight(params, x[i], float(times[i]))
        out[3 * p + i] = abs(u) ** 2 - 1.0
    return out


def grazing_curve_of(orbit: MultiImpactOrbit, param: Sequence[str] = ("gamma", "omega"), ranges=None, *,
                     name: str | None = None, settings: ContinuationSettings | None = None) -> Codim2Curve:
    """Where an interior maximum of r of an orbit with p impacts per period touches the clearance.

    Unknowns (x_0 .. x_{p-1}, T_0 .. T_{p-1}, t_g, p1, p2): the orbit equations with
    the flight times as unknowns (`_formal_residual`: no impact search, so they
    are smooth through the grazing, where the simulator's impact map jumps to the
    earlier impact), and |U(t_g)|^2 = 1, Re(conj(U) U')(t_g) = 0 on the flight
    after impact i (the one whose interior maximum grazes). The seed is the end of
    the orbit's branch in p1 at a grazing
    (`rotorcontact.continuation.multi_impact_branches.continue_multi_impact`),
    corrected onto the grazing. The curve ends at the box, where t_g leaves
    (0, T_i), or where an impact velocity reaches 0.

    Returns
    -------
    Codim2Curve
        ``"grazing_<label>"`` (comma dropped) of kind ``"grazing"``; no piece when
        the branch in p1 ends at no grazing.

    Raises
    ------
    ParameterError
        Unless ``orbit`` is a `MultiImpactOrbit`, ``param`` and ``ranges`` a plane and its box, ``name``
        text or None and ``settings`` a `ContinuationSettings` or None.
    """
    check_orbit(orbit)
    _check_name(name)
    plane = _Plane(orbit.params, param, ranges)
    name = name or f"grazing_{orbit.label.replace(',', '')}"
    settings = settings_or_default(settings, ContinuationSettings, _settings)
    p = orbit.impacts
    seed = None
    for end in plane.ranges[0][::-1]:
        branch = continue_multi_impact(orbit, plane.params[0], end, max_points=4000)
        if branch.status == "grazing" and branch.orbits:
            last = branch.orbits[-1]
            best = None
            for i in range(p):
                ext = flight_extrema(last.params, last.states[i], float(last.times[i]), law=SLIP_BOUNDED)
                for t, r, is_max in zip(ext.times, ext.radii, ext.maxima):
                    if is_max and (best is None or r > best[0]):
                        best = (float(r), i, float(t))
            if best is not None:
                seed = (np.concatenate([last.states.ravel(), last.times, [best[2], branch.values[-1],
                                        getattr(orbit.params, plane.params[1])]]), best[1])
                break
    if seed is None:
        return Codim2Curve(name=name, kind="grazing", params=plane.params, pieces=(),
                           ends=(f"the branch in {plane.params[0]} ends at no grazing",))
    y0, flight = seed

    def residual(y):
        params = plane.at(y[-2], y[-1])
        x = y[: 3 * p].reshape(p, 3)
        times = y[3 * p: 4 * p]
        try:
            u, du = _flight(params, x[flight], float(y[4 * p]))
            return np.concatenate([_formal_residual(params, x, times),
                                   [abs(u) ** 2 - 1.0, (u.conjugate() * du).real]])
        except (ValueError, ZeroDivisionError) as exc:
            raise ParameterError(f"the flight failed: {exc}") from None

    events = [
        EventFunction("t-g-low", lambda y: y[4 * p], terminal=True),
        EventFunction("t-g-high", lambda y: y[3 * p + flight] - y[4 * p], terminal=True),
    ]
    return _continued(residual, y0, plane, name, "grazing", p, events, settings)


def orbit_by_label(params: Parameters, label: str, t_max: float = 12.0) -> MultiImpactOrbit:
    """The orbit ``label`` at ``params``: a one-impact orbit ``"B<n>,<m>"`` (as an orbit of one impact) or
    ``"M<p>-<j>"`` of `rotorcontact.continuation.multi_impact_families.seed_orbits`.

    Raises
    ------
    ParameterError
        Unless ``params`` is a `Parameters`, ``label`` such a label and ``t_max`` a period within the
        limit of the flight; when there is no such orbit there (naming those found).
    """
    check_params(params)
    kind = _label_kind(label)
    if kind is None:
        raise ParameterError(f"label = {quoted(label)} is invalid; allowed: {LABEL_FORMS}")
    family, p = kind
    t_max = _check_t_max(params, t_max)
    if family == "M":
        found = seed_orbits(params, p)
        hit = [o for o in found if o.label == label]
        if not hit:
            raise ParameterError(f"label = {label!r} is not found here; allowed: an orbit found here: "
                                 f"{', '.join(o.label for o in found) or 'none'}")
        return hit[0]
    orbits = [o for o in one_impact_orbits(params, t_max) if o.admissible]
    hit = [o for o in orbits if o.label == label]
    if not hit:
        raise ParameterError(f"label = {label!r} is not an admissible orbit here; allowed: an orbit found here: "
                             f"{', '.join(o.label for o in orbits) or 'none'}")
    try:
        return solve_multi_impact(params, [hit[0].state], label=label)
    except NewtonFailure as exc:
        raise ParameterError(f"label = {label!r} is not an orbit of the simulator's impact map here ({exc}); "
                             "allowed: an orbit of the simulator") from None


def extra_curves(params: Parameters, param: Sequence[str], ranges, specs: Sequence[str], *, t_max: float = 12.0,
                 n_seeds: int = 7, n_scan: int = 41) -> dict[str, Codim2Curve]:
    """The curves of the ``codim2 --curves`` specifications (`CURVE_SPECS`), by name.

    ``"coalescence"``: the a-c and b-d coalescence curves of the pair 1
    (`rotorcontact.continuation.codim2.coalescence_curve`); ``"pd:<orbit>"``,
    ``"ns:<orbit>"``, ``"fold:<orbit>"``: `orbit_curve` of the orbit
    (`orbit_by_label`) at the base parameters; ``"grazing:<orbit>"``:
    `grazing_curve_of` it, named ``"grazing_<label>_p<impacts>"`` (apart from
    the one-impact grazing curves of ``--grazing``). A specification given twice is computed once.

    Raises
    ------
    ParameterError
        Before any curve is computed: unless ``params`` is a `Parameters`, ``param`` and ``ranges`` a plane
        and its box, ``specs`` a list of at most `MAX_SPECS` specifications of `CURVE_SPECS`, ``t_max`` a
        period within the limit of the flight over the box and ``n_seeds``, ``n_scan`` as in
        `rotorcontact.continuation.codim2.fold_curve`; then as `orbit_by_label` for an orbit that is not there.
    """
    check_params(params)
    plane = _Plane(params, param, ranges)
    if not isinstance(specs, (list, tuple)) or len(specs) > MAX_SPECS:
        raise ParameterError(f"specs = {quoted(specs)} is invalid; allowed: a list of at most {MAX_SPECS} of "
                             f"{', '.join(CURVE_SPECS)}")
    short = {v: k for k, v in CURVE_KINDS.items()}
    for i, spec in enumerate(specs):
        kind, _, label = spec.partition(":") if isinstance(spec, str) else ("", "", "")
        if spec != "coalescence" and (kind not in (*short, "grazing") or _label_kind(label) is None):
            raise ParameterError(f"specs[{i}] = {quoted(spec)} is invalid; allowed: {', '.join(CURVE_SPECS)}, "
                                 f"<orbit> {LABEL_FORMS}")
    t_max = plane.check_t_max(t_max)
    n_seeds, n_scan = _check_scan(n_seeds, n_scan)
    out: dict[str, Codim2Curve] = {}
    for spec in dict.fromkeys(specs):
        if spec == "coalescence":
            for c in coalescence_curves(params, param, ranges, t_max=t_max, n_seeds=n_seeds, n_scan=n_scan):
                out[c.name] = c
            continue
        kind, _, label = spec.partition(":")
        orbit = orbit_by_label(params, label, t_max)
        c = grazing_curve_of(orbit, param, ranges) if kind == "grazing" else orbit_curve(orbit, short[kind], param,
                                                                                         ranges)
        if kind == "grazing":
            c = replace(c, name=f"grazing_{label.replace(',', '')}_p{orbit.impacts}")
        out[c.name] = c
    return out
