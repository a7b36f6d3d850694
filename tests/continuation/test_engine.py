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
