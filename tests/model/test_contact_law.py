"""The contact law on r = 1 (MODEL.md §4): the normal force, the frictionless tangential
force, the sliding acceleration and its Jacobian, each checked against the formula written
out here or against central finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact.model import contact_law as cl


def random_points(n: int, seed: int = 3):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield dict(
            theta=rng.uniform(-math.pi, math.pi),
            thetadot=rng.uniform(-3.0, 3.0),
            sgn=float(rng.choice([-1.0, 1.0])),
            gamma=rng.uniform(0.0, 1.0),
            omega=rng.uniform(0.1, 2.0),
            rho=rng.uniform(0.0, 1.0),
            mu=rng.uniform(0.0, 1.0),
            phi=rng.uniform(-math.pi, math.pi),
        )


def test_forces_match_the_formulas_of_the_model():
    for x in random_points(200):
        n = (1.0 + x["thetadot"]) ** 2 - x["omega"] ** 2 + x["rho"] * math.cos(x["phi"] - x["theta"])
        f = -(1.0 + x["thetadot"]) * x["gamma"] + x["rho"] * math.sin(x["phi"] - x["theta"])
        assert cl.normal_force(x["theta"], x["thetadot"], x["omega"], x["rho"], x["phi"]) == pytest.approx(n, abs=1e-14)
        assert cl.free_tangential(x["theta"], x["thetadot"], x["gamma"], x["rho"], x["phi"]) == pytest.approx(
            f, abs=1e-14)
        acc = cl.sliding_accel(x["theta"], x["thetadot"], x["sgn"], x["gamma"], x["omega"], x["rho"], x["mu"], x["phi"])
        assert acc == pytest.approx(f - x["mu"] * n * x["sgn"], abs=1e-13)


def test_forces_over_arrays_are_the_pointwise_forces():
    theta = np.linspace(-3.0, 3.0, 7)
    thetadot = np.linspace(-1.0, 1.0, 7)
    n, f = cl.forces_along(theta, thetadot, 0.15, 0.76, 0.43, 0.21)
    assert n.shape == f.shape == (7,)
    for i in range(7):
        assert n[i] == cl.normal_force(theta[i], thetadot[i], 0.76, 0.43, 0.21)
        assert f[i] == cl.free_tangential(theta[i], thetadot[i], 0.15, 0.43, 0.21)


def _fd(fun, x: float, h: float = 1e-6) -> float:
    return (fun(x + h) - fun(x - h)) / (2.0 * h)


def test_gradients_and_sliding_jacobian_against_central_differences():
    for x in random_points(100, seed=5):
        th, td = x["theta"], x["thetadot"]
        g, w, r, m, ph, s = x["gamma"], x["omega"], x["rho"], x["mu"], x["phi"], x["sgn"]
        dn = cl.normal_force_gradient(th, td, r, ph)
        assert dn[0] == pytest.approx(_fd(lambda a: cl.normal_force(a, td, w, r, ph), th), abs=1e-8)
        assert dn[1] == pytest.approx(_fd(lambda a: cl.normal_force(th, a, w, r, ph), td), abs=1e-8)
        df = cl.free_tangential_gradient(th, g, r, ph)
        assert df[0] == pytest.approx(_fd(lambda a: cl.free_tangential(a, td, g, r, ph), th), abs=1e-8)
        assert df[1] == pytest.approx(_fd(lambda a: cl.free_tangential(th, a, g, r, ph), td), abs=1e-8)
        a_th, a_td = cl.sliding_jacobian(th, td, s, g, r, m, ph)
        assert a_th == pytest.approx(_fd(lambda a: cl.sliding_accel(a, td, s, g, w, r, m, ph), th), abs=1e-8)
        assert a_td == pytest.approx(_fd(lambda a: cl.sliding_accel(th, a, s, g, w, r, m, ph), td), abs=1e-8)
        jac = cl.sliding_field_jacobian(th, td, s, g, r, m, ph)
        assert np.array_equal(jac, [[0.0, 1.0], [a_th, a_td]])


def test_accumulation_tail_sums_the_geometric_bounces():
    rd, n, d, mu = 1e-3, 0.7, 0.8, 0.15
    t_tail, p_tail = cl.accumulation_tail(rd, n, d, mu)
    # bounce j starts with radial velocity d^j rd and lasts 2 d^j rd / N; its friction impulse is mu (1 + d) d^j rd
    j = np.arange(1, 2000)
    assert t_tail == pytest.approx(np.sum(2.0 * d**j * rd / n), rel=1e-12)
    assert p_tail == pytest.approx(np.sum(mu * (1.0 + d) * d**j * rd), rel=1e-12)
    assert cl.accumulation_tail(rd, n, 1.0, mu) == (0.0, 0.0)
