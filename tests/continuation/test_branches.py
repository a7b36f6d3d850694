"""Branches of one-impact orbits and their events (MODEL.md §5).

The reference parameters are those of the reference machine (omega =
0.760043..., rho = 3/7, mu = 0.15, d = 0.95, phi = 0.21, R/c_r = 400/7); one
test repeats the two headline numbers at omega = 0.76 exactly. Each event is
checked by a computation that does not use the continuation: the fold by
solving F1 = F1' = 0 with scipy, the NSFH by the closed form of gamma*, the
grazing by the extrema of r along the flight, the period doubling by the
eigenvalues of the simulator's impact-map Jacobian, the coalescence by the
discriminant of the quadratic for rdot.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from rotorcontact import ParameterError, simulate
from rotorcontact.maps import impact_map as im
from rotorcontact.continuation.branches import (
    DEFAULT_RANGES, DEFAULT_SEEDS, EVENT_TYPES, MAX_SEEDS, default_seeds, orbit_branches,
)
from rotorcontact.analysis.equilibria import boundary_gamma
from reference_parameters import REF


@pytest.fixture(scope="module")
def ref_branches():
    return orbit_branches(REF.replace(gamma=0.1), "gamma", -0.6, 0.25)


def angle_diff(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 2.0 * math.pi))


def events(branches, typ, orbit=None):
    return [e for e in branches.events if e.type == typ and (orbit is None or orbit in e.orbits)]


def orbit_with_label(p, label, t_max=12.0):
    found = [o for o in im.one_impact_orbits(p, t_max) if o.label == label]
    assert len(found) == 1, [o.label for o in im.one_impact_orbits(p, t_max)]
    return found[0]


# ---------------------------------------------------------------------------
# every point is a fixed point
# ---------------------------------------------------------------------------


def test_every_branch_point_is_a_fixed_point_of_the_impact_map(ref_branches):
    n_plausible = 0
    for curve in ref_branches.curves:
        for o in curve.orbits:
            # the flight of length T from the reset state ends at the same state (law of MODEL.md §5)
            x1, _, _ = im.impact_map_jacobian(o.params, o.state, o.T, law=im.IDEAL)
            assert angle_diff(x1[0], o.theta) < 1e-10
            assert np.abs(x1[1:] - o.state[1:]).max() < 1e-10
            if o.plausible:
                # and the simulator's own impact map (guaranteed impact location, slip-bounded law)
                res = im.impact_map(o.params, o.state)
                assert res.status == "impact" and abs(res.time - o.T) < 1e-10
                assert angle_diff(res.state[0], o.theta) < 1e-10
                assert np.abs(res.state[1:] - o.state[1:]).max() < 1e-10
                n_plausible += 1
    assert n_plausible > 50


def test_labels_and_values_agree_with_the_guaranteed_zero_search(ref_branches):
    checked = 0
    for curve in ref_branches.curves:
        events_at = {i for i, _ in curve.event_index}
        for i, (v, o) in enumerate(zip(curve.values, curve.orbits)):
            if i in events_at or i % 3:
                continue
            ref = {x.label: x for x in im.one_impact_orbits(o.params, 12.0)}
            assert o.label in ref, (v, o.label, sorted(ref))
            r = ref[o.label]
            assert abs(r.T - o.T) < 1e-9 * (1 + o.T) and abs(r.rdot - o.rdot) < 1e-9 * (1 + abs(o.rdot))
            assert r.admissible == o.admissible and r.plausible == o.plausible
            assert r.interior_extrema == o.interior_extrema
            checked += 1
    assert checked > 200


def test_refined_branches_add_the_orbits_of_the_guaranteed_zero_search(ref_branches):
    """Points put between the continuation's inside a view are the orbits the global search finds at their
    parameter (label, T, rdot, multipliers, stability); the continuation's own points and events stay."""
    from rotorcontact.continuation.branches import refine_branches

    lo, hi, points = 0.05, 0.1, 100
    refined = refine_branches(ref_branches, (lo, hi), points)
    checked = 0
    for old, new in zip(ref_branches.curves, refined.curves):
        kept = {float(v) for v in new.values}
        assert {float(v) for v in old.values} <= kept
        assert [(float(old.values[i]), k) for i, k in old.event_index] == \
            [(float(new.values[i]), k) for i, k in new.event_index]
        inside = [(v, o) for v, o in zip(new.values, new.orbits) if lo <= v <= hi and v not in set(old.values)]
        for v, o in inside[::7]:
            r = {x.label: x for x in im.one_impact_orbits(o.params, 12.0)}[o.label]
            assert abs(r.T - o.T) < 1e-9 * (1 + o.T) and abs(r.rdot - o.rdot) < 1e-9 * (1 + abs(o.rdot))
            if r.multipliers is not None:
                assert max(map(abs, r.multipliers)) == pytest.approx(max(map(abs, o.multipliers)), rel=1e-9)
            assert r.stable == o.stable and r.plausible == o.plausible
            checked += 1
        # inside the view, consecutive points of a monotone stretch are at most (hi - lo) / points apart
        v = new.values
        gaps = np.abs(np.diff(v))[(v[:-1] >= lo) & (v[1:] <= hi)]
        assert gaps.size == 0 or np.mean(gaps <= (hi - lo) / points * (1 + 1e-9)) > 0.95
    assert checked > 20
    # a narrow view gets its points and no others: none is computed outside it
    narrow = refine_branches(ref_branches, (0.087, 0.08701), 10)
    for old, new in zip(ref_branches.curves, narrow.curves):
        added = np.setdiff1d(new.values, old.values)
        assert np.all((added >= 0.087) & (added <= 0.08701))
        assert added.size <= 11 * max(1, np.sum((old.values[:-1] < 0.08701) & (old.values[1:] > 0.087)
                                                | (old.values[:-1] > 0.087) & (old.values[1:] < 0.08701)))
    with pytest.raises(ParameterError, match=r"^view = \(0.1, 0.05\) is invalid"):
        refine_branches(ref_branches, (0.1, 0.05))


def test_branches_pass_through_the_smooth_fold(ref_branches):
    # one computed curve holds B1,a and B1,b, joined at the fold gamma_F,1 (and B1,c, B1,d)
    curve = next(c for c in ref_branches.curves if {"B1,a", "B1,b", "B1,c", "B1,d"} <= set(c.labels))
    labels = curve.labels
    folds = [i for i, kind in curve.event_index if kind == "fold"]
    assert len(folds) == 2
    # a multiplier +1 at the fold is the fold: no second event point beside it
    assert not [k for _, k in curve.event_index if k == "plus-one"]
    events = {i for i, _ in curve.event_index}
    for i in folds:
        # the nearest regular points on either side, whatever events sit next to the fold
        before = max(j for j in range(i) if j not in events)
        after = min(j for j in range(i + 1, len(labels)) if j not in events)
        assert {labels[before], labels[after]} in ({"B1,a", "B1,b"}, {"B1,c", "B1,d"})
        # the parameter turns back at the fold: it is the largest value nearby
        window = curve.values[max(0, i - 6): i + 7]
        assert curve.values[i] >= window.max() - 1e-14
        assert window.min() < curve.values[i] - 1e-4


# ---------------------------------------------------------------------------
# multipliers and stability
# ---------------------------------------------------------------------------


def fd_jacobian(p, x, h):
    def central(step):
        jac = np.empty((3, 3))
        for j in range(3):
            e = np.zeros(3)
            e[j] = step
            plus = im.impact_map(p, x + e)
            minus = im.impact_map(p, x - e)
            assert plus.status == minus.status == "impact"
            diff = plus.state - minus.state
            diff[0] = math.remainder(diff[0], 2.0 * math.pi)
            jac[:, j] = diff / (2.0 * step)
        return jac

    return (4.0 * central(h / 2.0) - central(h)) / 3.0


def test_multipliers_match_finite_differences(ref_branches):
    checked = 0
    for label in ("B1,a", "B1,b", "B1,c", "B1,d"):
        b = ref_branches.branch(label)
        idx = [i for i in range(len(b.values)) if b.plausible[i] and 0.08 < b.values[i] < 0.17]
        for i in idx[:: max(1, len(idx) // 3)]:
            p = REF.replace(gamma=float(b.values[i]))
            x = np.array([b.theta[i], b.rdot[i], b.thetadot[i]])
            fd = fd_jacobian(p, x, 1e-5 * max(1e-2, b.rdot[i]))
            _, jac, _ = im.impact_map_jacobian(p, x, float(b.T[i]), law=im.IDEAL)
            assert np.abs(jac - fd).max() <= 1e-6 * max(1.0, np.abs(fd).max())
            ev = np.sort_complex(np.linalg.eigvals(fd))
            assert np.abs(ev - np.sort_complex(np.linalg.eigvals(jac))).max() < 1e-6
            assert b.max_multiplier[i] == pytest.approx(np.abs(ev).max(), abs=1e-6)
            assert b.stable[i] == bool(np.all(np.abs(ev) < 1.0))
            checked += 1
    assert checked >= 8


def test_a_stable_branch_point_is_the_attractor_of_a_long_simulation(ref_branches):
    b = ref_branches.branch("B1,d")
    i = min((i for i in range(len(b.values)) if b.stable[i] is True and b.plausible[i]),
            key=lambda i: abs(b.values[i] - 0.13))
    p = REF.replace(gamma=float(b.values[i]))
    x = np.array([b.theta[i], b.rdot[i], b.thetadot[i]])
    u0, du0 = im.post_impact_state(p, x)
    traj = simulate(p, 0.97 * u0, du0 + 0.05, 800.0)
    imp = traj.impacts
    assert len(imp) > 50
    assert np.allclose(np.diff(imp.t[-5:]), b.T[i], atol=1e-8)
    assert angle_diff(imp.theta[-1], x[0]) < 1e-8
    assert abs(imp.rdot[-1] - x[1]) < 1e-8 and abs(imp.thetadot[-1] - x[2]) < 1e-8


# ---------------------------------------------------------------------------
# events, each checked independently
# ---------------------------------------------------------------------------


def test_headline_values_at_the_reference(ref_branches):
    # MODEL.md §5: gamma_F,1 ~ 0.178 and the NSFH at gamma* ~ 0.072 (two decimals)
    folds = events(ref_branches, "fold", "B1,a")
    assert len(folds) == 1 and abs(folds[0].value - 0.178) < 5e-3
    nsfh = [e for e in events(ref_branches, "nsfh", "B1,a") if e.value > 0]
    assert len(nsfh) == 1 and abs(nsfh[0].value - 0.072) < 5e-3


def test_headline_values_at_omega_exactly_076():
    b = orbit_branches(REF.replace(gamma=0.1, omega=0.76), "gamma", 0.05, 0.2, t_max=4.0)
    fold = events(b, "fold", "B1,a")
    nsfh = events(b, "nsfh", "B1,b")
    assert len(fold) == 1 and abs(fold[0].value - 0.178) < 5e-3
    assert len(nsfh) == 1 and abs(nsfh[0].value - 0.072) < 5e-3
    assert abs(nsfh[0].value - boundary_gamma(REF.replace(gamma=0.1, omega=0.76))) < 1e-8


def test_event_types_are_the_documented_ones(ref_branches):
    assert {e.type for e in ref_branches.events} <= set(EVENT_TYPES)
    assert all(e.accuracy <= 1e-8 for e in ref_branches.events)


def test_folds_are_double_zeros_of_f1(ref_branches):
    folds = events(ref_branches, "fold")
    assert len(folds) >= 4
    for e in folds:
        def eqs(z):
            p = REF.replace(gamma=z[1])
            return [im.f1(p, z[0]), im.f1_derivative(p, z[0])]

        sol = fsolve(eqs, [e.T + 1e-3, e.value + 1e-4], xtol=1e-12)
        assert np.abs(eqs(sol)).max() < 1e-12
        assert abs(sol[1] - e.value) < 1e-8
        assert abs(sol[0] - e.T) < 1e-6 * (1 + e.T)
        assert len(e.orbits) == 2


def test_nsfh_is_at_the_boundary_equilibrium(ref_branches):
    gs = boundary_gamma(REF.replace(gamma=0.1))
    nsfh = events(ref_branches, "nsfh")
    positive = [e for e in nsfh if e.value > 0]
    assert {lab for e in positive for lab in e.orbits} == {"B1,a", "B1,b"}
    for e in nsfh:
        assert abs(abs(e.value) - gs) < 1e-8  # |k| = 1 at +-gamma*
        assert abs(e.rdot) < 1e-12


def test_grazing_of_b1d_has_its_interior_maximum_on_the_clearance(ref_branches):
    graz = events(ref_branches, "grazing", "B1,d")
    assert len(graz) == 1
    e = graz[0]
    o = orbit_with_label(REF.replace(gamma=e.value), "B1,d")
    ext = im.flight_extrema(o.params, o.state, o.T)
    assert abs(ext.r_max - 1.0) < 1e-8
    # below it the orbit crosses the clearance, above it stays inside
    assert orbit_with_label(REF.replace(gamma=e.value - 1e-4), "B1,d").plausible is False
    assert orbit_with_label(REF.replace(gamma=e.value + 1e-4), "B1,d").plausible is True


def test_period_doubling_has_a_multiplier_at_minus_one(ref_branches):
    pd = events(ref_branches, "period-doubling", "B1,d")
    pd = [e for e in pd if e.value > 0]
    assert len(pd) == 1
    o = orbit_with_label(REF.replace(gamma=pd[0].value), "B1,d")
    res = im.impact_map(o.params, o.state, jacobian=True)
    ev = np.linalg.eigvals(res.jacobian)
    assert np.min(np.abs(ev + 1.0)) < 1e-6
    # stable above, unstable below
    assert orbit_with_label(REF.replace(gamma=pd[0].value + 1e-4), "B1,d").stable is True
    assert orbit_with_label(REF.replace(gamma=pd[0].value - 1e-4), "B1,d").stable is False


def test_extrema_change_is_where_the_count_changes(ref_branches):
    changes = events(ref_branches, "extrema-change", "B1,d")
    assert len(changes) == 1
    v = changes[0].value
    below = orbit_with_label(REF.replace(gamma=v - 1e-6), "B1,d").interior_extrema
    above = orbit_with_label(REF.replace(gamma=v + 1e-6), "B1,d").interior_extrema
    assert below != above


def test_ac_coalescence_is_a_double_root_at_negative_gamma(ref_branches):
    ac = events(ref_branches, "ac-coalescence")
    assert len(ac) == 1 and ac[0].value < 0 and set(ac[0].orbits) == {"B1,a", "B1,c"}
    p = REF.replace(gamma=ac[0].value)
    zero = min(im.f1_zeros(p, 12.0), key=lambda z: abs(z.T - ac[0].T))
    q = (1 + p.d) * complex(1, p.mu)
    a12 = im.a_matrix(p, zero.T)[0, 1]
    disc, _ = im.rdot_roots(p, zero.T)
    assert abs(disc) < 1e-8 * (q * a12).real ** 2
    # real roots on one side, none on the other
    assert len(im.rdot_roots(REF.replace(gamma=ac[0].value + 1e-4), zero.T)[1]) == 2
    assert im.one_impact_orbits(REF.replace(gamma=ac[0].value - 1e-3), 1.0) == ()


def test_nsfh_against_omega_is_where_k_has_modulus_one():
    gamma, rho = 0.1, REF.rho
    b = orbit_branches(REF.replace(gamma=gamma), "omega", 0.7, 0.9, t_max=4.0, n_seeds=5)
    nsfh = events(b, "nsfh")
    omega_star = math.sqrt(1.0 - math.sqrt(rho**2 - gamma**2))
    assert nsfh and all(abs(e.value - omega_star) < 1e-8 for e in nsfh)
    assert b.param == "omega" and set(b.to_dict()["branches"]["B1,a"]) == {"omega", "T", "rdot", "thetadot", "stable"}


# ---------------------------------------------------------------------------
# results and input checking
# ---------------------------------------------------------------------------


def test_to_dict_has_no_nan_and_aligned_arrays(ref_branches):
    import json

    data = ref_branches.to_dict()
    text = json.dumps(data, allow_nan=False)
    assert json.loads(text)["param"] == "gamma"
    for label, arrays in data["branches"].items():
        n = len(arrays["gamma"])
        assert all(len(v) == n for v in arrays.values())
        for g, s, r in zip(arrays["gamma"], arrays["stable"], arrays["rdot"]):
            assert (g is None) == (r is None)
            if r is not None and r < 0:
                assert s is None  # virtual orbits have no stability


@pytest.mark.parametrize(
    "kw",
    [dict(param="phi"), dict(start=0.2, stop=0.1), dict(t_max=-1.0), dict(n_seeds=1), dict(rdot_max=0.0),
     dict(param="d", start=0.5, stop=1.5), dict(events_on_virtual="yes")],
)
def test_bad_input_is_rejected(kw):
    args = dict(param="gamma", start=0.0, stop=0.2)
    args.update(kw)
    with pytest.raises(ParameterError):
        orbit_branches(REF.replace(gamma=0.1), **args)


# ---------------------------------------------------------------------------
# the seeds keep their spacing when the range widens
# ---------------------------------------------------------------------------


def test_the_default_seeds_keep_the_spacing_of_the_default_range():
    lo, hi = DEFAULT_RANGES["gamma"]
    assert default_seeds("gamma", lo, hi) == DEFAULT_SEEDS
    assert default_seeds("gamma", 0.0, 0.01) == DEFAULT_SEEDS
    n = default_seeds("gamma", -5.0, 0.2)
    assert (0.2 + 5.0) / (n - 1) <= (hi - lo) / (DEFAULT_SEEDS - 1) < (0.2 + 5.0) / (n - 2)
    assert default_seeds("d", 0.0, 1e6) == MAX_SEEDS


def test_widening_the_range_loses_no_branch_or_event(ref_branches):
    """A curve confined between two seed values is not seen: with 41 seeds over [-5, 0.2] the B3 fold and
    period doubling near gamma = 0.03 and 0.01 were lost. The default seeds keep their spacing instead."""
    wide = orbit_branches(REF.replace(gamma=0.1), "gamma", -5.0, 0.2)

    def inner(b):
        return sorted((e.type, e.orbits, round(e.value, 7)) for e in b.events if -0.55 <= e.value <= 0.15)

    ref = inner(ref_branches)
    assert any(t == "fold" and 0.0 < v < 0.05 and any(o.startswith("B3") for o in orbits) for t, orbits, v in ref)
    assert inner(wide) == ref


def test_a_range_that_starts_at_the_undamped_resonance_keeps_to_its_box():
    """At gamma = 0 the b-branches pass the resonance point, where no point can be corrected onto the curve:
    a curve leaving the range there ends at its last point inside, rather than running on past the bound."""
    at_zero = orbit_branches(REF.replace(gamma=0.1), "gamma", 0.0, 0.2, t_max=5.0)
    wider = orbit_branches(REF.replace(gamma=0.1), "gamma", -0.05, 0.2, t_max=5.0)
    tol = 1e-10  # the location tolerance of a curve's end on its bound
    assert all(-tol <= o.params.gamma <= 0.2 + tol for c in at_zero.curves for o in c.orbits)
    assert all(-tol <= e.value <= 0.2 + tol for e in at_zero.events)

    def inner(b):
        return sorted((e.type, e.orbits, round(e.value, 7)) for e in b.events if 0.01 <= e.value <= 0.19)

    assert inner(at_zero) == inner(wider) and inner(wider)


def test_seeds_on_the_bounds_keep_their_curves_in_the_box():
    """gamma from 0.1 (a seed value, put a rounding error off the bound by its correction): the curves heading
    below it end there, rather than run on to gamma = -0.5 with their events."""
    box = orbit_branches(REF, "gamma", 0.1, 0.12, t_max=4.0)
    tol = 1e-10
    assert box.curves and all(0.1 - tol <= o.params.gamma <= 0.12 + tol for c in box.curves for o in c.orbits)
    assert all(0.1 - tol <= e.value <= 0.12 + tol for e in box.events)


@pytest.mark.parametrize("args, match", [
    ((None, 0.0, 0.1), r"^param = None is invalid; allowed: 'gamma', 'omega', 'rho', 'mu', 'd'$"),
    (("x", 0.0, 0.1), r"^param = 'x' is invalid"),
    (("gamma", 0.1, 0.0), r"^stop = 0.0 is invalid; allowed: a number > start = 0.1"),
    (("gamma", 0.1, 0.1), r"^stop = 0.1 is invalid"),
    (("gamma", math.nan, 0.1), r"^start = nan is not finite"),
    (("gamma", 0.0, "1"), r"^stop = '1' is text"),
])
def test_default_seeds_refuse_an_unknown_parameter_or_an_empty_range(args, match):
    with pytest.raises(ParameterError, match=match):
        default_seeds(*args)


def test_default_seeds_take_numpy_scalars():
    assert default_seeds("gamma", np.float32(-5.0), np.float64(0.2)) == default_seeds("gamma", -5.0, 0.2)
    assert default_seeds("d", np.int64(0), np.int64(1)) == default_seeds("d", 0.0, 1.0)
