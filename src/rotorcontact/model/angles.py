"""Angles in the package's convention, (-pi, pi]."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..interpreted import call_kernel

__all__ = ["wrap_angle", "angle_difference"]


@njit(cache=True)
def wrap_angle(angle: float) -> float:
    """Return ``angle`` wrapped into (-pi, pi] (usable from Python and from compiled kernels)."""
    y = math.atan2(math.sin(angle), math.cos(angle))
    return math.pi if y <= -math.pi else y


@njit(cache=True)
def _wrap_many(x: np.ndarray) -> np.ndarray:
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = wrap_angle(x[i])
    return out


def angle_difference(a, b):
    """The angle from ``b`` to ``a``, a - b wrapped into (-pi, pi], elementwise.

    Parameters
    ----------
    a, b : float or array_like
        Angles in radians (broadcast together).

    Returns
    -------
    float or numpy.ndarray
        A float for scalar inputs, else an array of the broadcast shape; each
        value is `wrap_angle` of the difference.
    """
    x = np.subtract(a, b, dtype=float)
    if x.ndim == 0:
        return call_kernel(wrap_angle, float(x))
    return call_kernel(_wrap_many, np.ascontiguousarray(x).ravel()).reshape(x.shape)
