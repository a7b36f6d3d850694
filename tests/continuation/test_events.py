"""Arguments of the test functions and event typing of `rotorcontact.continuation.events`.

Each function refuses what is not its input by name (`ParameterError`), rather than failing deep inside
or returning a value for nonsense (an empty product of multipliers is 1); numpy scalars are numbers.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation import events
from rotorcontact.continuation.engine import LocatedEvent
from rotorcontact.continuation.events import (
    BranchAnalyser,
    at_turning_point,
    bialternate_product,
    branch_event_functions,
    classify_event,
    det_minus_identity,
    det_plus_identity,
    multiplier_kind,
    report_events,
    rotation_angle,
    turning_points,
)
from rotorcontact.maps.orbit_system import OneImpactSystem
from reference_parameters import REF


@pytest.fixture(scope="module")
def system():
    return OneImpactSystem(REF.replace(gamma=0.1), "gamma")


@pytest.fixture(scope="module")
def analyser(system):
    return BranchAnalyser(system)


def located(name="fold", y=(2.0, 0.5, 0.1)):
    y = np.array(y)
    return LocatedEvent(name=name, index=0, y=y, parameter=float(y[2]), value=0.0, before=-1.0, after=1.0,
                        y_before=y, y_after=y, bracket=0.0, converged=True, continuous=True)


@pytest.mark.parametrize("z", ["x", [], [1.0, "a"], [[1.0, 2.0]], None, [True, 0.5]])
def test_the_determinants_refuse_what_is_not_a_list_of_multipliers(z):
    for test in (det_minus_identity, det_plus_identity, bialternate_product):
        with pytest.raises(ParameterError, match=r"^z = .* is invalid; allowed: the multipliers"):
            test(z)


def test_the_bialternate_product_needs_a_pair():
    with pytest.raises(ParameterError, match=r"^z = \[1.0\] is invalid; allowed: .* at least 2"):
        bialternate_product([1.0])
    z = np.array([np.exp(0.5j), np.exp(-0.5j), np.float64(0.1)])
    assert bialternate_product(z) == pytest.approx(0.0, abs=1e-12)
    assert det_minus_identity([np.float32(3.0), 2]) == pytest.approx(2.0)
    assert det_plus_identity((np.int64(-1), 0.5j)) == 0.0


@pytest.mark.parametrize("z", [[], [0.5, 2.0], "x"])
def test_rotation_angle_needs_a_complex_multiplier(z):
    with pytest.raises(ParameterError, match=r"^z = .* is invalid; allowed: "):
        rotation_angle(z)


@pytest.mark.parametrize("kw, match", [
    (dict(name="plus_one"), r"^name = 'plus_one' is invalid; allowed: 'plus-one', 'minus-one', 'torus'$"),
    (dict(name=None), r"^name = None is invalid"),
    (dict(z="x"), r"^z = 'x' is invalid"),
    (dict(tol=-1.0), r"^tol = -1.0 is invalid; allowed: a finite number > 0"),
    (dict(tol=math.nan), r"^tol = nan is invalid"),
])
def test_multiplier_kind_refuses_a_misspelt_test_or_bad_multipliers(kw, match):
    args = dict(name="plus-one", z=[1.0, 0.5], tol=1e-6)
    args.update(kw)
    with pytest.raises(ParameterError, match=match):
        multiplier_kind(args["name"], args["z"], args["tol"])


def test_multipliers_beside_a_large_one_are_typed_within_their_rounding():
    # eigenvalues of an orthogonally similar matrix with multipliers 1e11, -1, 0.3 (the large one's row coupled
    # to the others, as the expanding direction of a long orbit's map): numpy gives -1 to within
    # EIGENVALUE_ROUNDING eps 1e11 (the bound multiplier_kind takes), not to 1e-6
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(200):
        q, _r = np.linalg.qr(rng.standard_normal((3, 3)))
        upper = np.zeros((3, 3))
        upper[0, 1:] = rng.standard_normal(2) * 1e10
        m = q @ (np.diag([1e11, -1.0, 0.3]) + upper) @ q.T
        z = np.linalg.eigvals(m)
        worst = max(worst, float(np.min(np.abs(z + 1.0))))
        assert events.multiplier_kind("minus-one", z) == "period-doubling"
    assert worst > 1e-6  # beyond the plain tolerance: the widening is needed
    assert events.multiplier_kind("minus-one", [1e11, -1.0 + 5e-3, 0.3]) is None
    assert events.multiplier_kind("plus-one", [1e11, 1.0 + 1e-4, 0.3]) == "plus-one"
    assert events.multipliers_resolved([7e11, 0.5]) and not events.multipliers_resolved([1e13, -1.0])
    assert events.multiplier_kind("minus-one", [1e13, -1.0, 0.3]) is None  # not resolved: not typed


def test_the_unit_pair_discriminant_changes_sign_where_the_pair_leaves_the_unit_circle():
    for theta in (0.3, 2.0, 3.1):
        z = [np.exp(1j * theta), np.exp(-1j * theta), 0.2]
        assert events.unit_pair_discriminant(z) == pytest.approx(4.0 * math.cos(theta) ** 2 - 4.0, abs=1e-14)
    for x in (-3.0, -1.2, 2.5):  # a real pair with product 1: positive
        assert events.unit_pair_discriminant([0.2, x, 1.0 / x]) == pytest.approx((x - 1.0 / x) ** 2, rel=1e-14)
    assert abs(events.unit_pair_discriminant([-1.0, -1.0, 0.4])) < 1e-15
    with pytest.raises(ParameterError, match="at least 2"):
        events.unit_pair_discriminant([0.5])


def test_multiplier_kind_takes_numpy_scalars():
    assert multiplier_kind("minus-one", [np.float64(-1.0), 0.3], np.float32(1e-6)) == "period-doubling"
    assert multiplier_kind("torus", [np.exp(0.5j), np.exp(-0.5j), 0.1], np.float64(1e-6)) == "neimark-sacker"


def test_turning_points_refuse_what_is_not_a_list_of_located_events():
    for raw in (1, "x", [None], None):
        with pytest.raises(ParameterError, match=r"^raw = .* is invalid; allowed: a list of LocatedEvent"):
            turning_points(raw)
    assert len(turning_points((located(), located("grazing")))) == 1


def test_at_turning_point_refuses_what_is_not_a_point():
    with pytest.raises(ParameterError, match=r"^y = 'x' is invalid; allowed: a point \(T, rdot, lambda\)"):
        at_turning_point("x", [])
    with pytest.raises(ParameterError, match=r"^turning = 1 is invalid; allowed: a list of points"):
        at_turning_point([1.0, 0.5, 0.1], 1)
    with pytest.raises(ParameterError, match=r"^turning\[1\] = \[1.0\] is invalid"):
        at_turning_point([1.0, 0.5, 0.1], [[1.0, 0.5, 0.1], [1.0]])
    y = np.array([np.float64(1.0), 0.5, np.float32(0.25)])
    assert at_turning_point(y, (np.array([1.0, 0.5, 0.25]),)) and not at_turning_point(y, [])


def test_classify_and_report_refuse_the_wrong_objects(system, analyser):
    e = located()
    for args, match in (((None, analyser, system), r"^e = None is not a LocatedEvent"),
                        ((e, None, system), r"^an = None is not a BranchAnalyser"),
                        ((e, analyser, "gamma"), r"^system = 'gamma' is not an OneImpactSystem")):
        with pytest.raises(ParameterError, match=match):
            classify_event(*args)
    for args, match in (((e, analyser, system), r"^raw = .* is invalid; allowed: a list of LocatedEvent"),
                        (([e], "x", system), r"^an = 'x' is not a BranchAnalyser"),
                        (([e], analyser, None), r"^system = None is not an OneImpactSystem")):
        with pytest.raises(ParameterError, match=match):
            report_events(*args)
    assert classify_event(e, analyser, system) == ("fold", "")


@pytest.mark.parametrize("args, match", [
    ((None, False), r"^system = None is not an OneImpactSystem"),
    (("x", False), r"^system = 'x' is not an OneImpactSystem"),
    (("system", "x"), r"^virtual = 'x' is invalid; allowed: True or False"),
])
def test_branch_analyser_checks_its_system_and_flag(system, args, match):
    sys_arg = system if args[0] == "system" else args[0]
    with pytest.raises(ParameterError, match=match):
        BranchAnalyser(sys_arg, virtual=args[1])
    assert BranchAnalyser(system, virtual=np.bool_(True)).virtual is True


@pytest.mark.parametrize("kw, match", [
    (dict(an=None), r"^an = None is not a BranchAnalyser"),
    (dict(start=0.2, stop=0.1), r"^stop = 0.1 is invalid; allowed: a number > start = 0.2"),
    (dict(t_min="x"), r"^t_min = 'x' is invalid; allowed: a finite number > 0"),
    (dict(t_max=-1.0), r"^t_max = -1.0 is invalid; allowed: a finite number > 0.02"),
    (dict(rdot_max=math.nan), r"^rdot_max = nan is invalid"),
    (dict(start=math.inf), r"^start = inf is not finite"),
])
def test_branch_event_functions_check_the_box(analyser, kw, match):
    args = dict(an=analyser, start=0.0, stop=0.2, t_min=0.02, t_max=12.0, rdot_max=5.0)
    args.update(kw)
    with pytest.raises(ParameterError, match=match):
        branch_event_functions(**args)


def test_branch_event_functions_take_numpy_scalars(analyser):
    funcs = branch_event_functions(analyser, np.float64(0.0), np.float32(0.25), np.float64(0.02), np.int64(12),
                                   np.float32(5.0))
    by_name = {f.name: f for f in funcs}
    y = np.array([3.0, 1.0, 0.1])
    assert by_name["upper"].function(y) == pytest.approx(0.15) and by_name["t-max"].function(y) == 9.0


def test_the_multiplier_tests_are_an_abstract_base():
    assert "MultiplierTests" not in events.__all__
    with pytest.raises(TypeError):
        events.MultiplierTests()
