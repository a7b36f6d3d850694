"""Pseudo-arclength continuation on curves known in closed form.

Each test states a property of the method on an analytic curve: the unit
circle x^2 + lambda^2 = 1 (two folds in lambda, a closed loop), the fold of
x^2 + lambda = 0, a helix-like curve in R^3, and curves with no solution
nearby (the continuation must stop, never loop).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation.engine import (
    ContinuationSettings,
    CorrectionError,
    EventFunction,
    continue_both_ways,
    continue_curve,
    correct_fixed,
    corrected_crossings,
    null_vector,
    numerical_jacobian,
)


def circle(y):
    return np.array([y[0] ** 2 + y[1] ** 2 - 1.0])


def circle_jac(y):
    return np.array([[2.0 * y[0], 2.0 * y[1]]])


def parabola(y):  # x^2 + lambda = 0: a fold at lambda = 0
    return np.array([y[0] ** 2 + y[1]])


def test_circle_is_followed_through_both_folds_and_closes():
    res = continue_curve(circle, [1.0, 0.0], jacobian=circle_jac, direction=1.0)
    assert res.status == "closed"
    pts = res.points
    assert np.max(np.abs(np.hypot(pts[:, 0], pts[:, 1]) - 1.0)) < 1e-12
    # it goes all the way round: through lambda = 1 and lambda = -1 (the two folds in lambda)
    assert pts[:, 1].max() > 1.0 - 1e-3 and pts[:, 1].min() < -1.0 + 1e-3
    angles = np.unwrap(np.arctan2(pts[:, 1], pts[:, 0]))
    assert np.all(np.diff(angles) > 0)  # always the same way round
    assert angles[-1] - angles[0] == pytest.approx(2.0 * math.pi, abs=1e-12)
    # unit tangents, orthogonal to the gradient
    grads = 2.0 * pts
    assert np.max(np.abs(np.sum(res.tangents * grads, axis=1))) < 1e-10
    assert np.allclose(np.linalg.norm(res.tangents, axis=1), 1.0)


def test_numerical_jacobian_gives_the_same_curve():
    a = continue_curve(circle, [1.0, 0.0], jacobian=circle_jac)
    b = continue_curve(circle, [1.0, 0.0])
    assert a.status == b.status == "closed"
    assert np.max(np.abs(np.hypot(b.points[:, 0], b.points[:, 1]) - 1.0)) < 1e-12


def test_folds_of_the_circle_are_located_to_1e_10_in_lambda():
    # x changes sign exactly where lambda turns (lambda = +-1)
    ev = EventFunction("x = 0", lambda y: y[0])
    res = continue_curve(circle, [1.0, 0.0], events=[ev], settings=ContinuationSettings(max_step=0.2))
    found = sorted(e.parameter for e in res.events)
    assert len(found) == 2
    assert found[0] == pytest.approx(-1.0, abs=1e-10) and found[1] == pytest.approx(1.0, abs=1e-10)
    for e in res.events:
        assert e.converged and e.continuous
        assert abs(e.y[0]) < 1e-8  # the fold point itself (lambda = +-sqrt(1 - x^2) is flat there)


def test_parabola_passes_its_fold_and_the_event_is_there():
    # from (x, lambda) = (-1, -1) with lambda increasing: up to the fold at lambda = 0, then back down
    ev = EventFunction("fold", lambda y: y[0])
    stop = EventFunction("x = 2", lambda y: 2.0 - y[0], terminal=True)
    res = continue_curve(parabola, [-1.0, -1.0], direction=1.0, events=[ev, stop],
                         settings=ContinuationSettings(max_step=0.2))
    assert res.status == "terminal"
    lam = res.points[:, 1]
    top = int(np.argmax(lam))
    assert np.all(np.diff(lam[: top + 1]) > 0) and np.all(np.diff(lam[top:]) < 0)
    assert np.max(np.abs(res.points[:, 0] ** 2 + lam)) < 1e-12
    folds = [e for e in res.events if e.name == "fold"]
    assert len(folds) == 1 and abs(folds[0].parameter) < 1e-10
    # the terminal event ends the curve exactly at x = 2, lambda = -4
    assert res.points[-1] == pytest.approx([2.0, -4.0], abs=1e-10)
    assert res.events[-1].terminal and res.events[-1].name == "x = 2"


def test_events_are_located_with_recorrection_on_the_curve():
    # lambda crossing 0.5 on the unit circle: the located point is on the circle, at lambda = 0.5
    ev = EventFunction("lambda = 0.5", lambda y: y[1] - 0.5)
    res = continue_curve(circle, [1.0, 0.0], events=[ev], settings=ContinuationSettings(max_step=0.3))
    assert len(res.events) == 2
    for e in res.events:
        assert e.parameter == pytest.approx(0.5, abs=1e-10)
        assert abs(e.y[0] ** 2 + e.y[1] ** 2 - 1.0) < 1e-12
        assert abs(abs(e.y[0]) - math.sqrt(0.75)) < 1e-9


@pytest.mark.parametrize("direction, ends_at_start", [(-1.0, True), (1.0, False)])
@pytest.mark.parametrize("side", [0.0, 1.0])
def test_a_start_a_rounding_error_off_a_terminal_bound_counts_as_on_it(direction, ends_at_start, side):
    """lambda >= 0.3 as a terminal bound, the start a rounding error below or above it (a seed on a bound after
    its correction): heading down the curve ends at its start; heading up it runs on to the other side of the
    bound."""
    bound = 0.3
    start = np.nextafter(bound, side)
    lower = EventFunction("lower", lambda y: y[1] - bound, terminal=True)
    res = continue_curve(circle, [math.sqrt(1.0 - start**2), start], events=[lower], direction=direction,
                         correct_start=False, settings=ContinuationSettings(max_step=0.2))
    assert res.status == "terminal"
    assert res.points[:, 1].min() >= min(start, bound)  # never beyond the start and the bound
    if ends_at_start:
        assert len(res.points) == 2 and res.points[-1, 1] == pytest.approx(bound, abs=1e-15)
    else:  # round through lambda = 1 and down to the bound on the other side of the circle
        assert res.points[:, 1].max() > 1.0 - 1e-3
        assert res.points[-1, 0] < 0.0 and res.points[-1, 1] == pytest.approx(bound, abs=1e-10)


@pytest.mark.parametrize("scale", [1e-13, 1.0, 1e13])
def test_a_start_outside_a_terminal_bound_by_more_than_rounding_is_not_taken_as_on_it(scale):
    """The rounding allowed is in the event's own scale: scale (lambda - 0.3) from lambda = 0.3 - 1e-9 is a
    sign change to locate, whatever the scale, and one ulp below the bound is on it, whatever the scale."""
    bound = 0.3
    lower = EventFunction("lower", lambda y: scale * (y[1] - bound), terminal=True)
    settings = ContinuationSettings(max_step=0.2)
    start = bound - 1e-9
    res = continue_curve(circle, [math.sqrt(1.0 - start**2), start], events=[lower], direction=1.0,
                         correct_start=False, settings=settings)
    assert res.status == "terminal" and len(res.events) == 1
    assert res.points[-1, 1] == pytest.approx(bound, abs=1e-12) and res.points[:, 1].max() < bound + 1e-12
    start = np.nextafter(bound, 0.0)
    res = continue_curve(circle, [math.sqrt(1.0 - start**2), start], events=[lower], direction=-1.0,
                         correct_start=False, settings=settings)
    assert res.status == "terminal" and len(res.points) == 2


def test_discrete_event_is_located_by_bisection():
    ev = EventFunction("x > 0.3", lambda y: int(y[0] > 0.3), kind="discrete")
    res = continue_curve(circle, [1.0, 0.0], events=[ev])
    assert len(res.events) == 2
    for e in res.events:
        assert abs(e.y[0] - 0.3) < 1e-8
        assert e.bracket <= 1e-10


def test_a_sign_change_through_a_pole_is_flagged():
    ev = EventFunction("1/x", lambda y: 1.0 / y[0] if y[0] != 0 else None)
    res = continue_curve(circle, [1.0, 0.0], events=[ev], settings=ContinuationSettings(max_step=0.2))
    assert res.events and all(not e.continuous for e in res.events)


def test_a_curve_in_three_dimensions():
    # the sphere x^2 + y^2 + lambda^2 = 2 cut by the plane x = lambda: the ellipse 2 lambda^2 + y^2 = 2
    def f(y):
        return np.array([y[0] ** 2 + y[1] ** 2 + y[2] ** 2 - 2.0, y[0] - y[2]])

    res = continue_curve(f, [0.0, math.sqrt(2.0), 0.0], weights=[1.0, 2.0, 1.0])
    assert res.status == "closed"
    assert np.max(np.abs(np.array([f(p) for p in res.points]))) < 1e-12
    assert res.points[:, 2].max() == pytest.approx(1.0, abs=1e-3)
    assert res.points[:, 2].min() == pytest.approx(-1.0, abs=1e-3)


def test_the_continuation_always_ends():
    # a residual that exists only for lambda < 0.5: the steps shrink at the edge and the run stops
    def f(y):
        if y[1] > 0.5:
            raise ParameterError("out of the domain")
        return np.array([y[0] - y[1]])

    res = continue_curve(f, [0.0, 0.0], settings=ContinuationSettings(min_step=1e-6))
    assert res.status == "step-failure"
    assert 0.5 - 1e-5 < res.points[-1, 1] <= 0.5
    res = continue_curve(f, [0.0, 0.0], direction=-1.0, settings=ContinuationSettings(max_points=7))
    assert res.status == "max-points" and len(res.points) == 8


def test_correct_fixed_holds_one_component():
    y = correct_fixed(circle, [0.9, 0.3], 1)
    assert y[1] == 0.3 and y[0] == pytest.approx(math.sqrt(1 - 0.09), abs=1e-14)
    with pytest.raises(CorrectionError):
        correct_fixed(circle, [0.9, 1.5], 1)  # no x with x^2 = 1 - 2.25


def test_null_vector_and_numerical_jacobian():
    j = numerical_jacobian(circle, np.array([0.6, 0.8]))
    assert j == pytest.approx(circle_jac([0.6, 0.8]), abs=1e-8)
    v = null_vector(j, np.array([-1.0, 0.0]))
    assert v == pytest.approx([-0.8, 0.6], abs=1e-8)


@pytest.mark.parametrize(
    "kw",
    [dict(step=0.0), dict(min_step=-1.0), dict(max_points=0), dict(grow=1.0), dict(step=1.0, max_step=0.1),
     dict(max_newton=2.5), dict(location_tol=math.nan)],
)
def test_bad_settings_are_rejected(kw):
    with pytest.raises(ParameterError):
        ContinuationSettings(**kw)


def test_bad_start_is_rejected():
    with pytest.raises(ParameterError):
        continue_curve(circle, [math.nan, 0.0])
    with pytest.raises(ParameterError):
        continue_curve(circle, [1.0, 0.0], weights=[1.0, -1.0])
    with pytest.raises(ParameterError):
        EventFunction("e", lambda y: 0.0, kind="smooth")


def test_both_ways_stops_after_a_closed_loop_and_joins_two_runs():
    loop = continue_both_ways(circle, [1.0, 0.0], jacobian=circle_jac)
    assert len(loop.runs) == 1 and loop.runs[0].status == "closed"
    events = [EventFunction("lower", lambda y: y[1] + 0.5, terminal=True),
              EventFunction("upper", lambda y: 0.5 - y[1], terminal=True)]
    both = continue_both_ways(parabola, [0.5, -0.25], events=events)
    assert len(both.runs) == 2 and both.messages == tuple(r.message for r in both.runs)
    assert len(both.points) == len(both.runs[0].points) + len(both.runs[1].points) - 1
    assert both.points[0] == pytest.approx(both.runs[1].points[-1])
    assert both.points[-1] == pytest.approx(both.runs[0].points[-1])
    hits = list(corrected_crossings(parabola, both.points, 1, -0.16))
    assert sorted(h[0] for h in hits) == pytest.approx([-0.4, 0.4], abs=1e-12)


# ---------------------------------------------------------------------------
# bad arguments are refused by name; numpy scalars are numbers
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["step", "min_step", "max_step", "newton_tol", "residual_tol", "max_angle",
                                  "max_drift", "location_tol", "fd_step"])
def test_settings_refuse_a_bool_for_a_length_or_tolerance(name):
    with pytest.raises(ParameterError, match=rf"^{name} = True is invalid; allowed: a finite number > 0"):
        ContinuationSettings(**{name: True})


@pytest.mark.parametrize("name, bound", [("max_points", "MAX_POINTS"), ("max_newton", "MAX_NEWTON"),
                                         ("max_location_iterations", "MAX_LOCATION_ITERATIONS")])
def test_settings_bound_their_counts(name, bound):
    from rotorcontact.continuation import engine

    high = getattr(engine, bound)
    assert ContinuationSettings(**{name: high}) == ContinuationSettings(**{name: high})
    with pytest.raises(ParameterError, match=rf"^{name} = 1000000000000 is invalid; allowed: an integer from 1 to "
                                             rf"{high}$"):
        ContinuationSettings(**{name: 10**12})


@pytest.mark.parametrize("grow", [math.inf, 1e12, None, "x", True, 1.0])
def test_settings_bound_the_growth_of_the_step(grow):
    with pytest.raises(ParameterError, match=r"^grow = .* is invalid; allowed: a finite number > 1 and <= 10"):
        ContinuationSettings(grow=grow)


def test_settings_name_the_bad_field_rather_than_step():
    with pytest.raises(ParameterError, match=r"^min_step = True is invalid"):
        ContinuationSettings(min_step=True)


def test_settings_take_numpy_scalars():
    s = ContinuationSettings(step=np.float32(0.01), max_step=np.float64(0.2), grow=np.float32(2.0),
                             max_points=np.int64(300), max_newton=np.int32(8), location_tol=np.float16(1e-3))
    assert s.step == pytest.approx(0.01) and type(s.step) is float and type(s.max_points) is int
    assert s.max_points == 300 and s.max_newton == 8 and s.grow == 2.0
    assert ContinuationSettings() == ContinuationSettings(step=0.02)  # the defaults are valid
    res = continue_curve(circle, [1.0, 0.0], settings=s)
    assert res.status == "closed"


def _short(**kw):
    return continue_curve(circle, [1.0, 0.0], **{"settings": ContinuationSettings(max_points=3), **kw})


@pytest.mark.parametrize("kw, match", [
    (dict(direction=None), r"^direction = None is invalid; allowed: a finite number other than 0"),
    (dict(direction=[math.nan, 1.0]), r"^direction = \[nan, 1.0\] is invalid"),
    (dict(direction=0.0), r"^direction = 0.0 is invalid"),
    (dict(direction=[0, 0]), r"^direction = \[0, 0\] is invalid"),
    (dict(direction=[1.0, 0.0, 0.0]), r"^direction = .* a vector of 2 finite numbers"),
    (dict(direction="up"), r"^direction = 'up' is invalid"),
    (dict(events="x"), r"^events = 'x' is invalid; allowed: a list of EventFunction"),
    (dict(events=[lambda y: y[0]]), r"^events = .* is invalid; allowed: a list of EventFunction"),
    (dict(weights="ab"), r"^weights = 'ab' is invalid"),
    (dict(param_index=None), r"^param_index = None is invalid; allowed: an integer from -2 to 1$"),
    (dict(param_index=1.5), r"^param_index = 1.5 is invalid"),
    (dict(param_index=2), r"^param_index = 2 is invalid"),
    (dict(correct_start="no"), r"^correct_start = 'no' is invalid; allowed: True or False"),
    (dict(jacobian="x"), r"^jacobian = 'x' is invalid; allowed: a function"),
])
def test_continue_curve_refuses_bad_arguments_by_name(kw, match):
    with pytest.raises(ParameterError, match=match):
        _short(**kw)


@pytest.mark.parametrize("y0", ["ab", [1.0], [[1.0, 0.0]], [1.0, True], None, [1.0, "0"]])
def test_continue_curve_refuses_a_start_that_is_not_a_vector(y0):
    with pytest.raises(ParameterError, match=r"^y0 = .* is invalid; allowed: a vector of at least 2 finite numbers"):
        continue_curve(circle, y0)
    with pytest.raises(ParameterError, match=r"^y0 = "):
        continue_both_ways(circle, y0)


@pytest.mark.parametrize("residual", [1, None, "circle"])
def test_the_residual_must_be_callable(residual):
    for call in (lambda: continue_curve(residual, [1.0, 0.0]), lambda: continue_both_ways(residual, [1.0, 0.0]),
                 lambda: correct_fixed(residual, [1.0, 0.0], 1), lambda: numerical_jacobian(residual, [1.0, 0.0]),
                 lambda: corrected_crossings(residual, np.array([[1.0, 0.0], [0.0, 1.0]]), 1, 0.5)):
        with pytest.raises(ParameterError, match=r"^residual = .* is invalid; allowed: a function"):
            call()


def test_a_residual_or_jacobian_of_the_wrong_shape_is_refused_by_name():
    def two(y):
        return np.array([y[0] ** 2 + y[1] ** 2 - 1.0, 0.0])

    for kw in ({}, dict(correct_start=False)):
        with pytest.raises(ParameterError, match=r"^residual = .* returning an array of shape \(1,\) \(it returned "
                                                 r"shape \(2,\)\)"):
            continue_curve(two, [1.0, 0.0], **kw)
    with pytest.raises(ParameterError, match=r"^jacobian = .* returning an array of shape \(1, 2\)"):
        continue_curve(circle, [1.0, 0.0], jacobian=lambda y: np.zeros(2))
    with pytest.raises(ParameterError, match=r"^residual = .* returning a vector"):
        numerical_jacobian(lambda y: 1.0, [1.0, 0.0])


def test_correct_fixed_refuses_bad_arguments_by_name():
    with pytest.raises(ParameterError, match=r"^index = None is invalid; allowed: an integer from -2 to 1$"):
        correct_fixed(circle, [0.9, 0.3], None)
    with pytest.raises(ParameterError, match=r"^index = 2 is invalid"):
        correct_fixed(circle, [0.9, 0.3], 2)
    with pytest.raises(ParameterError, match=r"^y = 'ab' is invalid"):
        correct_fixed(circle, "ab", 1)
    y = correct_fixed(circle, np.array([0.9, 0.3]), np.int64(-1))
    assert y[1] == 0.3 and y[0] == pytest.approx(math.sqrt(1 - 0.09), abs=1e-14)


@pytest.mark.parametrize("rel_step", [0, 0.0, math.nan, -1.0, 2.0, True, "x", None])
def test_numerical_jacobian_refuses_a_step_that_gives_no_difference(rel_step):
    with pytest.raises(ParameterError, match=r"^rel_step = .* is invalid; allowed: a finite number > 0 and <= 1"):
        numerical_jacobian(circle, [0.6, 0.8], rel_step)


def test_numerical_jacobian_and_null_vector_take_numpy_scalars_and_refuse_other_input():
    j = numerical_jacobian(circle, [np.float64(0.6), np.float32(0.8)], np.float32(1e-6))
    assert j == pytest.approx(circle_jac([0.6, 0.8]), abs=1e-5)
    with pytest.raises(ParameterError, match=r"^y = \[0.6, nan\] is invalid"):
        numerical_jacobian(circle, [0.6, math.nan])
    for bad in ("x", np.zeros((2, 2)), [[1.0, math.nan]], np.zeros(3)):
        with pytest.raises(ParameterError, match=r"^jac = .* is invalid; allowed: an n x \(n \+ 1\) matrix"):
            null_vector(bad)
    with pytest.raises(ParameterError, match=r"^reference = .* a vector of 2 finite numbers"):
        null_vector(j, np.array([1.0, 0.0, 0.0]))


def test_corrected_crossings_refuses_bad_arguments_when_called():
    pts = np.array([[1.0, 0.0], [0.0, 1.0]])
    for kw, match in ((dict(value=math.nan), r"^value = nan is invalid; allowed: a finite number"),
                      (dict(value="x"), r"^value = 'x' is invalid"),
                      (dict(index=None), r"^index = None is invalid"),
                      (dict(index=5), r"^index = 5 is invalid"),
                      (dict(points="ab"), r"^points = 'ab' is invalid; allowed: an \(m, n \+ 1\) array"),
                      (dict(points=np.zeros(3)), r"^points = .* is invalid")):
        args = dict(points=pts, index=1, value=0.5)
        args.update(kw)
        with pytest.raises(ParameterError, match=match):
            corrected_crossings(circle, args["points"], args["index"], args["value"])  # not iterated
    hits = list(corrected_crossings(circle, pts, np.int64(-1), np.float64(0.5)))
    assert len(hits) == 1 and hits[0] == pytest.approx([math.sqrt(0.75), 0.5], abs=1e-12)


@pytest.mark.parametrize("kw, match", [
    (dict(name=None), r"^name = None is not a str object"),
    (dict(function=None), r"^function = None is invalid; allowed: a function"),
    (dict(terminal="x"), r"^terminal = 'x' is invalid; allowed: True or False"),
    (dict(kind=None), r"^kind = None is invalid; allowed: 'continuous', 'discrete'"),
])
def test_event_functions_are_checked(kw, match):
    args = dict(name="e", function=lambda y: y[0])
    args.update(kw)
    with pytest.raises(ParameterError, match=match):
        EventFunction(**args)
    assert EventFunction("e", abs, terminal=np.bool_(True)).terminal is True


def test_continue_curve_takes_numpy_scalars():
    ev = EventFunction("lambda = 0.5", lambda y: y[1] - 0.5)
    a = continue_curve(circle, [1.0, 0.0], events=(ev,), direction=np.float64(-2.0), param_index=np.int64(1),
                       weights=np.array([1.0, 1.0]), correct_start=np.bool_(True))
    b = continue_curve(circle, [1.0, 0.0], events=[ev], direction=-1.0, param_index=1)
    assert a.status == b.status == "closed" and np.array_equal(a.points, b.points)
    assert a.points[1, 1] < 0  # the direction's sign: the last component decreases first
