"""The independent reference of the multi-impact tests: Newton's method on P_I^p with finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact.maps.impact_map import impact_map


def _power(params, x, p):
    for _ in range(p):
        res = impact_map(params, x)
        assert res.status == "impact"
        x = np.array(res.state, dtype=float)
    return x


def _fd_jacobian(params, x, p, h=1e-7):
    jac = np.empty((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        a, b = _power(params, x + e, p), _power(params, x - e, p)
        d = a - b
        d[0] = math.remainder(d[0], 2 * math.pi)
        jac[:, j] = d / (2 * h)
    return jac


def _power_newton(params, x, p, tol=1e-11):
    x = np.array(x, dtype=float)
    for _ in range(30):
        g = _power(params, x, p) - x
        g[0] = math.remainder(g[0], 2 * math.pi)
        if np.max(np.abs(g)) < tol:
            return x, np.linalg.eigvals(_fd_jacobian(params, x, p))
        x = x - np.linalg.solve(_fd_jacobian(params, x, p) - np.eye(3), g)
    raise AssertionError("the reference Newton did not converge")


@pytest.fixture(scope="session")
def power_newton():
    """``power_newton(params, x, p) -> (x, multipliers)``: a fixed point of P_I^p by single shooting from x.

    P_I is the simulator's impact map without its Jacobian; the Jacobian of P_I^p
    and the multipliers come from central differences (step 1e-7).
    """
    return _power_newton
