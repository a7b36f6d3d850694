"""The angle convention (-pi, pi]."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hypothesis import given, settings
from hypothesis import strategies as st

from rotorcontact.model.angles import wrap_angle


def test_the_ends_of_the_interval():
    assert wrap_angle(math.pi) == math.pi
    assert wrap_angle(-math.pi) == math.pi
    assert wrap_angle(0.0) == 0.0


@settings(derandomize=True, database=None, deadline=None)
@given(st.floats(min_value=-1e4, max_value=1e4, allow_nan=False))
def test_wrapped_angle_is_in_range_and_equivalent(angle):
    w = wrap_angle(angle)
    assert -math.pi < w <= math.pi
    # same direction on the circle
    assert abs(math.cos(w) - math.cos(angle)) < 1e-12 and abs(math.sin(w) - math.sin(angle)) < 1e-12


def test_angle_difference_wraps_elementwise_like_wrap_angle():
    from rotorcontact.model.angles import angle_difference

    rng = np.random.default_rng(2)
    a = rng.uniform(-20, 20, (4, 5))
    b = rng.uniform(-20, 20, (4, 5))
    out = angle_difference(a, b)
    assert out.shape == (4, 5)
    assert np.array_equal(out, [[wrap_angle(x - y) for x, y in zip(ra, rb)] for ra, rb in zip(a, b)])
    assert isinstance(angle_difference(0.5, 0.25), float)
    assert abs(angle_difference(math.pi, -math.pi)) < 1e-15
    assert angle_difference(-math.pi, 0.0) == math.pi
    assert np.array_equal(angle_difference(np.array([3.0, -3.0]), 0.0), [3.0, -3.0])


def test_angle_difference_refuses_what_is_not_an_angle_and_keeps_missing_values():
    from rotorcontact import ParameterError
    from rotorcontact.model.angles import angle_difference

    out = angle_difference([math.nan, 3.0], -3.0)
    assert math.isnan(out[0]) and out[1] == pytest.approx(6.0 - 2.0 * math.pi, abs=1e-15)
    for a, b, name in (("x", 1.0, "a"), (1.0, math.inf, "b"), (True, 1.0, "a"), (1.0, [1.0, "x"], "b"),
                       (1.0 + 1j, 0.0, "a")):
        with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: finite real numbers"):
            angle_difference(a, b)
    with pytest.raises(ParameterError, match=r"^a of shape \(2,\) and b of shape \(3,\) do not match"):
        angle_difference([1.0, 2.0], [1.0, 2.0, 3.0])
