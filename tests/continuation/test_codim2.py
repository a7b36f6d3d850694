"""Two-parameter curves, their intersections and the regions R1-R4 (MODEL.md §4-§5).

The DIB curve is checked against gamma_DIB(omega) = sqrt(rho^2 - (1 - omega^2)^2),
the fold curve against F1 = F1' = 0 (`rotorcontact.maps.impact_map.f1`,
`f1_derivative`), the grazing curve against the interior maximum of r of the
orbit (`flight_extrema` through `one_impact_orbits`), and the regions against
the admissibility of the orbits and of x_R at sample points.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.maps import impact_map as im
from rotorcontact.continuation.branches import orbit_branches
from rotorcontact.continuation.codim2 import classify_plane, codim2_diagram, dib_curve, fold_curve, region
from reference_parameters import REF


def gamma_dib(omega: float, rho: float = REF.rho) -> float:
    return math.sqrt(max(0.0, rho**2 - (1.0 - omega**2) ** 2))


@pytest.fixture(scope="module")
def diagram():
    return codim2_diagram(REF.replace(gamma=0.1), ("gamma", "omega"), ((0.0, 0.5), (0.6, 1.25)))


def test_no_curve_repeats_a_point(diagram):
    # the fold and grazing curves have seeds on the box's edge omega = 0.6
    for name, curve in diagram.curves.items():
        for piece in curve.pieces:
            assert len(piece) > 1 and np.all(np.any(piece[1:] != piece[:-1], axis=1)), name
        listed = curve.to_list()
        assert all(a != b for a, b in zip(listed, listed[1:]) if a is not None), name


def test_dib_curve_is_gamma_dib_of_omega(diagram):
    xy = diagram.curves["dib"].xy()
    xy = xy[np.isfinite(xy[:, 0])]
    assert len(xy) > 20
    for g, w in xy:
        # gamma^2 + (1 - omega^2)^2 = rho^2, i.e. gamma = gamma_DIB(omega) (|k| = 1)
        assert abs(g**2 + (1.0 - w**2) ** 2 - REF.rho ** 2) < 1e-12
        if g > 1e-3:
            assert abs(g - gamma_dib(w)) < 1e-10
    # the whole arc in the box: from omega = sqrt(1 - rho) to sqrt(1 + rho) at gamma = 0, through (rho, 1)
    assert xy[:, 0].max() == pytest.approx(REF.rho, abs=1e-4)
    assert sorted(xy[[0, -1], 1]) == pytest.approx([math.sqrt(1 - REF.rho), math.sqrt(1 + REF.rho)], abs=1e-9)


def test_fold_curve_is_a_double_zero_of_f1(diagram):
    curve = diagram.curves["fold_1"]
    assert len(curve.pieces) == 1
    for T, g, w in curve.pieces[0]:
        p = REF.replace(gamma=g, omega=w)
        assert abs(im.f1(p, T)) < 1e-10 and abs(im.f1_derivative(p, T)) < 1e-8
    # it spans the box in omega and passes the one-parameter fold at the reference omega
    xy = curve.xy()
    assert xy[:, 1].min() == pytest.approx(0.6) and xy[:, 1].max() == pytest.approx(1.25)
    g_ref = np.interp(REF.omega, xy[:, 1], xy[:, 0])
    fold = [e for e in orbit_branches(REF.replace(gamma=0.1), "gamma", 0.15, 0.2, t_max=3.0, n_seeds=3).events
            if e.type == "fold"]
    assert fold and abs(fold[0].value - g_ref) < 1e-5


def test_fold_dib_points_satisfy_both_curve_equations(diagram):
    pts = [p for p in diagram.points if p.type == "fold-dib"]
    assert len(pts) == 2
    for pt in pts:
        g, w = pt.values
        assert abs(g - gamma_dib(w)) < 1e-9
        p = REF.replace(gamma=g, omega=w)
        assert abs(im.f1(p, pt.T)) < 1e-10 and abs(im.f1_derivative(p, pt.T)) < 1e-8
        # the pair n = 1 merges there: it exists just below gamma, not just above
        assert any(z.n == 1 for z in im.f1_zeros(REF.replace(gamma=g - 1e-4, omega=w)))
        assert not any(z.n == 1 for z in im.f1_zeros(REF.replace(gamma=g + 1e-4, omega=w)))


def test_grazing_curve_of_b1d_touches_the_clearance(diagram):
    curve = diagram.curves["grazing_B1d"]
    rows = np.vstack(curve.pieces)
    assert len(rows) > 10
    for T, rdot, tg, g, w in rows[::4]:
        o = next(o for o in im.one_impact_orbits(REF.replace(gamma=g, omega=w)) if o.label == "B1,d")
        assert abs(o.T - T) < 1e-9 and abs(o.rdot - rdot) < 1e-9
        assert abs(o.r_max_interior - 1.0) < 1e-8
    # at the reference omega it is the grazing point of the B1,d branch
    b = orbit_branches(REF.replace(gamma=0.1), "gamma", 0.05, 0.08, t_max=4.0, n_seeds=3)
    graz = [e for e in b.events if e.type == "grazing"]
    xy = curve.xy()
    order = np.argsort(xy[:, 1])
    assert abs(np.interp(REF.omega, xy[order, 1], xy[order, 0]) - graz[0].value) < 1e-5


def test_grazing_dib_point_is_on_both_curves(diagram):
    pts = [p for p in diagram.points if p.type == "grazing-dib"]
    assert pts
    for pt in pts:
        g, w = pt.values
        assert abs(g - gamma_dib(w)) < 1e-9


def test_regions_follow_their_definitions():
    # sample points on either side of the fold and DIB curves at the reference omega
    checks = {}
    for g in (0.03, 0.1, 0.3):
        p = REF.replace(gamma=g)
        orbits = [o for o in im.one_impact_orbits(p) if o.n == 1]
        xr_admissible = abs(p.k) < 1.0
        checks[g] = region(p)
        if not orbits:
            assert checks[g] == ("R3" if xr_admissible else "R2")
        elif not xr_admissible:
            assert checks[g] == "R1"
            assert {o.label for o in orbits if o.admissible} == {"B1,c", "B1,d"}
        else:
            assert checks[g] == "R4" and all(o.admissible for o in orbits)
    assert checks == {0.03: "R1", 0.1: "R4", 0.3: "R3"}
    assert region(REF.replace(gamma=0.3, omega=1.0)) == "R2"


def test_classified_plane_changes_region_on_the_curves(diagram):
    v1, v2, labels = classify_plane(REF.replace(gamma=0.1), ("gamma", "omega"), ((0.0, 0.5), (0.85, 0.95)), (51, 3))
    row = labels[1]  # omega = 0.9
    g_dib = gamma_dib(0.9)
    fold = diagram.curves["fold_1"].xy()
    g_fold = np.interp(0.9, fold[:, 1], fold[:, 0])
    for g, lab in zip(v1, row):
        if g < g_fold - 0.01:
            assert lab == "R1"
        elif g_fold + 0.01 < g < g_dib - 0.01:
            assert lab == "R2"
        elif g > g_dib + 0.01:
            assert lab == "R3"


def test_other_planes_and_json_shape():
    d = dib_curve(REF.replace(gamma=0.1), ("rho", "omega"), ((0.05, 1.0), (0.6, 1.2)))
    for rho, w in d.xy():
        if np.isfinite(rho):
            assert abs(rho**2 - (0.1**2 + (1 - w**2) ** 2)) < 1e-10
    c, pts = fold_curve(REF.replace(gamma=0.1), ("omega", "gamma"), ((0.6, 1.25), (0.0, 0.5)))
    assert c.xy().shape[1] == 2 and all(len(pair) == 2 for pair in c.to_list() if pair is not None)
    assert {tuple(p.to_dict()) for p in pts} == {("type", "omega", "gamma")}


@pytest.mark.parametrize(
    "args",
    [dict(params2=("gamma", "gamma")), dict(params2=("gamma", "phi")), dict(ranges=((0.2, 0.1), (0.6, 1.2))),
     dict(ranges=((0.0, 0.5), (0.6, math.inf))), dict(ranges=((0.0, 0.5), (-1.0, 1.2)))],
)
def test_bad_input_is_rejected(args):
    kw = dict(params2=("gamma", "omega"), ranges=None)
    kw.update(args)
    with pytest.raises(ParameterError):
        codim2_diagram(REF.replace(gamma=0.1), kw["params2"], kw["ranges"])


def test_a_curve_parallel_to_an_axis_is_found_once():
    # F1 does not depend on rho: in the (rho, mu) plane the fold is the line mu = mu_F
    c, _ = fold_curve(REF.replace(gamma=0.1), ("rho", "mu"), ((0.05, 1.0), (0.0, 0.5)))
    assert len(c.pieces) == 1
    xy = c.xy()
    assert xy[:, 0].min() == pytest.approx(0.05) and xy[:, 0].max() == pytest.approx(1.0)
    fold = [e for e in orbit_branches(REF.replace(gamma=0.1), "mu", 0.05, 0.15, t_max=4.0, n_seeds=3).events
            if e.type == "fold"]
    assert fold and np.all(np.abs(xy[:, 1] - fold[0].value) < 1e-8)


@pytest.mark.parametrize("t_max", [math.nan, -1.0, "x", None, 1e9])
def test_region_and_classify_plane_refuse_a_bad_t_max(t_max):
    with pytest.raises(ParameterError, match="^t_max = "):
        region(REF, t_max)
    with pytest.raises(ParameterError, match="^t_max = "):
        classify_plane(REF, ("gamma", "omega"), ((0.05, 0.1), (0.7, 0.8)), shape=(2, 2), t_max=t_max)


@pytest.mark.parametrize("kw", [dict(n_seeds=10**7), dict(n_scan=10**7), dict(n_seeds=0), dict(n_scan=1)])
def test_seed_scans_are_bounded(kw):
    name = next(iter(kw))
    with pytest.raises(ParameterError, match=f"^{name} = .*allowed"):
        codim2_diagram(REF, ("gamma", "omega"), ((0.05, 0.1), (0.7, 0.8)), **kw)


@pytest.mark.parametrize("ranges, match", [
    ([(0.05, 0.1)], r"^ranges = .* allowed: two ranges \(low, high\), one for 'gamma' and one for 'omega'"),
    ([(0.05, 0.1), (0.7, 0.8), (0.1, 0.2)], r"^ranges = .* allowed: two ranges"),
    ("0.05,0.1", r"^ranges = .* allowed: two ranges"),
    ({"gamma": (0.05, 0.1)}, r"^ranges = .* allowed: a range for each of 'gamma' and 'omega' and no other"),
    ({"gamma": (0.05, 0.1), "omega": (0.7, 0.8), "mu": (0, 1)}, r"and no other"),
    ([(0.05, 0.1, 0.2), (0.7, 0.8)], r"^range of gamma = .* allowed: \(low, high\)"),
    ([("0.05", "0.1"), (0.7, 0.8)], r"^range of gamma = '0.05' is text"),
    ([(0.05, 0.1), "ab"], r"^range of omega = 'ab' is invalid"),
    ([(0.05, 0.1), np.array(0.7)], r"^range of omega = .* is invalid"),
    (np.array(0.7), r"^ranges = .* allowed: two ranges"),
])
def test_malformed_ranges_are_refused_by_name(ranges, match):
    with pytest.raises(ParameterError, match=match):
        classify_plane(REF, ("gamma", "omega"), ranges, shape=(2, 2))
    with pytest.raises(ParameterError, match=match):
        codim2_diagram(REF.replace(gamma=0.1), ("gamma", "omega"), ranges)


def test_ranges_given_by_name_or_as_arrays_are_the_ranges_given_in_order():
    box = ((0.05, 0.2), (0.6, 1.1))
    v1, v2, labels = classify_plane(REF, ("gamma", "omega"), box, shape=(4, 3))
    w1, w2, named = classify_plane(REF, ("gamma", "omega"), {"omega": box[1], "gamma": box[0]}, shape=(4, 3))
    assert np.array_equal(v1, w1) and np.array_equal(v2, w2) and (labels == named).all()
    x1, x2, arrays = classify_plane(REF, np.array(["gamma", "omega"]), np.array(box), shape=np.array([4, 3]))
    assert np.array_equal(v1, x1) and np.array_equal(v2, x2) and (labels == arrays).all()


@pytest.mark.parametrize("shape, match", [((3,), "^shape = "), ((2, 2, 2), "^shape = "), (4, "^shape = "),
                                          ((2, 10**6), r"^shape\[1\] = 1000000 is invalid; allowed: an integer from 2 "
                                                       r"to 1000"),
                                          ((1, 3), r"^shape\[0\] = 1 "), (np.array(5), "^shape = ")])
def test_classify_plane_refuses_a_malformed_or_huge_shape(shape, match):
    with pytest.raises(ParameterError, match=match):
        classify_plane(REF, ("gamma", "omega"), ((0.05, 0.1), (0.7, 0.8)), shape=shape)


@pytest.mark.parametrize("param", ["gamma", ("gamma",), ("gamma", "omega", "mu")])
def test_a_plane_is_a_pair_of_parameter_names(param):
    with pytest.raises(ParameterError, match=r"^param = .* allowed: two different parameters, as a pair"):
        codim2_diagram(REF.replace(gamma=0.1), param)


def test_settings_that_are_not_continuation_settings_are_refused():
    p = REF.replace(gamma=0.1)
    box = ((0.05, 0.2), (0.6, 1.1))
    calls = [lambda: codim2_diagram(p, ("gamma", "omega"), box, settings="x"),
             lambda: fold_curve(p, ("gamma", "omega"), box, settings="x"),
             lambda: dib_curve(p, ("gamma", "omega"), box, settings="x"),
             lambda: orbit_branches(p, "gamma", 0.05, 0.2, settings="x")]
    for call in calls:
        with pytest.raises(ParameterError, match=r"^settings = 'x' is not a ContinuationSettings"):
            call()


def test_a_t_max_beyond_what_the_isolation_follows_is_refused_not_a_point_in_no_region():
    from rotorcontact.maps.impact_map import IsolationLimit

    p = REF.replace(gamma=0.0)
    assert region(p, 12.0) is None or region(p, 12.0) in ("R1", "R2", "R3", "R4")
    with pytest.raises(IsolationLimit, match=r"^t_max = 10000.0 is too large at gamma = 0"):
        region(p, 1e4)
    # the undamped resonance has no regular equilibrium: no region, not an error
    assert region(REF.replace(gamma=0.0, omega=1.0)) is None


@pytest.mark.parametrize("kw", [dict(folds=None), dict(folds=1.0), dict(grazing=None), dict(grazing=3)])
def test_the_curves_asked_for_are_lists(kw):
    name = next(iter(kw))
    with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: a list"):
        codim2_diagram(REF.replace(gamma=0.1), ("gamma", "omega"), **kw)


def test_one_fold_and_one_orbit_may_be_given_alone():
    p = REF.replace(gamma=0.1)
    box = ((0.05, 0.2), (0.7, 0.8))
    alone = codim2_diagram(p, ("gamma", "omega"), box, folds=1, grazing="B1,d", n_seeds=3, n_scan=11)
    listed = codim2_diagram(p, ("gamma", "omega"), box, folds=[1], grazing=["B1,d"], n_seeds=3, n_scan=11)
    assert sorted(alone.curves) == sorted(listed.curves) and alone.events == listed.events


def test_the_dib_function_is_that_of_k_and_needs_parameters():
    from rotorcontact import reference_machine
    from rotorcontact.continuation.codim2 import dib_function

    p = REF.replace(gamma=0.3, omega=0.8)
    assert dib_function(p) == pytest.approx((abs(p.k) ** 2 - 1.0) * (p.gamma**2 + (1.0 - p.omega**2) ** 2), rel=1e-12)
    for bad in (None, reference_machine()):
        with pytest.raises(ParameterError, match=r"^p = .* is not a Parameters object"):
            dib_function(bad)


# ---------------------------------------------------------------------------
# bounds and checks of the arguments
# ---------------------------------------------------------------------------

SMALL = dict(n_seeds=1, n_scan=2)
BOX = ((0.05, 0.1), (0.7, 0.8))


def _empty_diagram(curves=None):
    from rotorcontact.continuation.codim2 import Codim2Diagram

    return Codim2Diagram(param=("gamma", "omega"), events=(), ranges=BOX, base=REF, curves=curves or {})


@pytest.mark.parametrize("call", ["fold", "coalescence", "diagram"])
@pytest.mark.parametrize("t_max", [1e300, 2000.0])
def test_t_max_is_bounded_over_the_box(call, t_max):
    from rotorcontact.continuation.codim2 import coalescence_curves
    from rotorcontact.maps.impact_map import f1_zeros

    # the flight grows fastest at the corner gamma = 0.5, omega = 0.6 of the default box (e^{0.25 T}), where
    # 2000 is too long a period, though not at the base parameters
    f1_zeros(REF, 2000.0)
    f = {"fold": fold_curve, "coalescence": coalescence_curves,
         "diagram": lambda p, **kw: codim2_diagram(p, folds=[], grazing=[], **kw)}[call]
    with pytest.raises(ParameterError, match=r"^t_max = .* is too large"):
        f(REF, t_max=t_max, **SMALL)


@pytest.mark.parametrize("n", [10**6, 101, 0, 1.5, None])
def test_the_pair_of_a_fold_or_coalescence_is_bounded(n):
    from rotorcontact.continuation.codim2 import MAX_PAIR, coalescence_curves

    with pytest.raises(ParameterError, match=rf"^n = .* is invalid; allowed: an integer from 1 to {MAX_PAIR}$"):
        fold_curve(REF, ("gamma", "omega"), BOX, n=n, **SMALL)
    with pytest.raises(ParameterError, match=r"^n = .* is invalid"):
        coalescence_curves(REF, ("gamma", "omega"), BOX, n=n, **SMALL)


def test_the_folds_of_a_diagram_are_bounded_as_the_fold_curve():
    with pytest.raises(ParameterError, match=r"^folds = 101 is invalid; allowed: an integer from 1 to 100$"):
        codim2_diagram(REF, ("gamma", "omega"), BOX, folds=[1, 101], **SMALL)


@pytest.mark.parametrize("diagram", [None, REF, "x"])
def test_dib_labels_need_a_diagram(diagram):
    from rotorcontact.continuation.codim2 import dib_labels

    with pytest.raises(ParameterError, match=r"^diagram = .* is not a Codim2Diagram object"):
        dib_labels(diagram, 12.0, lambda p: None)


@pytest.mark.parametrize("beb_kind", [None, "x", 1])
def test_dib_labels_need_a_callable_beb_kind(beb_kind):
    from rotorcontact.continuation.codim2 import dib_labels

    with pytest.raises(ParameterError, match=r"^beb_kind = .* is invalid; allowed: a function of the parameters"):
        dib_labels(_empty_diagram(), 12.0, beb_kind)


def test_dib_labels_refuse_a_bad_t_max_and_a_kind_that_is_not_text():
    from rotorcontact.continuation.codim2 import dib_labels

    for t_max in (1e300, -1.0, "x"):
        with pytest.raises(ParameterError, match=r"^t_max = "):
            dib_labels(_empty_diagram(), t_max, lambda p: None)
    dib = dib_curve(REF.replace(gamma=0.1), ("gamma", "omega"), ((0.0, 0.5), (0.6, 1.25)), n_seeds=2, n_scan=11)
    diagram = _empty_diagram({"dib": dib})
    with pytest.raises(ParameterError, match=r"^beb_kind = .* returning text or None \(it returned 1\)"):
        dib_labels(diagram, 12.0, lambda p: 1)
    labels = dib_labels(diagram, np.float64(12.0), lambda p: "persistence")
    assert labels == dib_labels(diagram, 12.0, lambda p: "persistence")
    assert {t for t, _, _ in labels} <= {"NSFH", "Pers"}


def test_the_curves_take_numpy_scalars():
    kw = dict(n_seeds=np.int64(1), n_scan=np.int32(2), t_max=np.float64(12.0))
    c, _ = fold_curve(REF, ("gamma", "omega"), BOX, n=np.int64(1), **kw)
    d, _ = fold_curve(REF, ("gamma", "omega"), BOX, n=1, n_seeds=1, n_scan=2, t_max=12.0)
    assert c.name == d.name == "fold_1" and c.to_list() == d.to_list()
