"""Angles in the package's convention, (-pi, pi].

`wrap_angle` and `point_angle` are compiled kernels for compiled loops: they take a float or a complex
number unchecked. `angle_difference` is the checked form of `wrap_angle` for Python.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..errors import ParameterError
from ..interpreted import call_kernel

__all__ = ["wrap_angle", "point_angle", "angle_difference"]


@njit(cache=True)
def point_angle(u: complex) -> float:
    """The polar angle of the point u in (-pi, pi] (atan2's -pi, on the negative real axis, is pi)."""
    y = math.atan2(u.imag, u.real)
    return math.pi if y <= -math.pi else y


@njit(cache=True)
def wrap_angle(angle: float) -> float:
    """Return ``angle`` wrapped into (-pi, pi] (usable from Python and from compiled kernels)."""
    return point_angle(complex(math.cos(angle), math.sin(angle)))


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
        Angles in radians (broadcast together); NaN, a missing value as in the sections of a batch, gives
        NaN.

    Returns
    -------
    float or numpy.ndarray
        A float for scalar inputs, else an array of the broadcast shape; each
        value is `wrap_angle` of the difference.

    Raises
    ------
    ParameterError
        Unless ``a`` and ``b`` hold real numbers (not infinite), of shapes that broadcast together.
    """
    from .validation import check_broadcast, quoted, real_array

    arrays = []
    for name, value in (("a", a), ("b", b)):
        array = real_array(value)
        if array is None or np.any(np.isinf(array)):
            raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: finite real numbers (radians), or "
                                 "NaN for a missing value")
        arrays.append(array)
    check_broadcast(a=arrays[0], b=arrays[1])
    x = np.subtract(arrays[0], arrays[1])
    if x.ndim == 0:
        return call_kernel(wrap_angle, float(x))
    return call_kernel(_wrap_many, np.ascontiguousarray(x).ravel()).reshape(x.shape)
