"""Angles in the package's convention, (-pi, pi]."""

from __future__ import annotations

import math

from numba import njit

__all__ = ["wrap_angle"]


@njit(cache=True)
def wrap_angle(angle: float) -> float:
    """Return ``angle`` wrapped into (-pi, pi] (usable from Python and from compiled kernels)."""
    y = math.atan2(math.sin(angle), math.cos(angle))
    return math.pi if y <= -math.pi else y
