"""The angle convention (-pi, pi]."""

from __future__ import annotations

import math

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
