"""Exact free flight (MODEL.md §3) against an mpmath evaluation of the closed form
U(t) = k + c+ e^{l+ t} + c- e^{l- t}, and against solve_ivp in the inertial frame."""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorcontact import ParameterError, Parameters, free_flight, to_inertial
from rotorcontact.model.flow import equilibrium_point
from reference_parameters import REF, REF_VALUES


TIMES = [0.0, 1e-9, 0.013, 0.3, 1.0, 2.7, 6.4, 13.0, 31.7, 50.0]

FLOWS = [
    # (label, parameters, u0, du0)
    ("reference-gamma0.1", dict(REF_VALUES, gamma=0.1), 0.0, 0.0),
    ("undamped", dict(REF_VALUES, gamma=0.0), 0.3 - 0.4j, 1.1 + 0.2j),
    ("negative-damping", dict(REF_VALUES, gamma=-0.05), 0.1j, -0.3 + 0.2j),
    ("stiff", dict(REF_VALUES, gamma=0.4, omega=2.7, rho=1.3, phi=-2.0), -0.5 + 0.5j, 2.0 - 1.0j),
    ("soft", dict(REF_VALUES, gamma=0.05, omega=0.06, rho=0.01, phi=3.0), 0.9, 0.0),
    ("overdamped", dict(REF_VALUES, gamma=2.0), 0.2 + 0.1j, -1.0 + 0.5j),
    ("strongly-overdamped", dict(REF_VALUES, gamma=3.0, omega=0.3, rho=1.7, phi=1.0), 0.7j, 3.0),
    ("near-critical-below", dict(REF_VALUES, gamma=2 * 0.76 * (1 - 1e-9), omega=0.76), 0.4, 0.3j),
    ("near-critical-above", dict(REF_VALUES, gamma=2 * 0.76 * (1 + 1e-9), omega=0.76), 0.4, 0.3j),
    ("near-critical-1e-5", dict(REF_VALUES, gamma=2 * 0.76 * (1 + 1e-5), omega=0.76), -0.4, 0.3 + 1j),
]


def _reference_values(ref, p, u0, du0, times):
    critical = 0.25 * p.gamma**2 - p.omega**2 == 0.0
    cls = ref.MPFlightCritical if critical else ref.MPFlight
    fl = cls(p.gamma, p.omega, p.rho, p.phi, u0, du0)
    return fl, [fl.state(t) for t in times]


@pytest.mark.parametrize("label,kw,u0,du0", FLOWS, ids=[f[0] for f in FLOWS])
def test_free_flight_matches_mpmath_closed_form(ref, label, kw, u0, du0):
    p = Parameters(**kw)
    times = np.array(TIMES)
    u, du = free_flight(p, u0, du0, times)
    fl, exact = _reference_values(ref, p, u0, du0, TIMES)
    with mp.workdps(ref.DPS):
        k = complex(fl.k)
        # error scale: size of the motion (rounding of the inputs is relative to it)
        scale = 1.0 + abs(k) + abs(u0 - k) + abs(du0)
        for j, t in enumerate(TIMES):
            ue, due = exact[j]
            size = max(scale, float(abs(ue - fl.k)), float(abs(due)))
            assert abs(u[j] - complex(ue)) <= 4e-15 * size * (1 + t), (label, t, u[j], complex(ue))
            assert abs(du[j] - complex(due)) <= 4e-15 * size * (1 + t), (label, t, du[j], complex(due))


def test_free_flight_exact_critical_damping(ref):
    # gamma = 2 omega exactly in floating point: h^2 = gamma^2/4 - omega^2 == 0
    p = Parameters(gamma=1.0, omega=0.5, rho=0.7, mu=0.1, d=0.5, phi=0.4)
    assert 0.25 * p.gamma**2 - p.omega**2 == 0.0
    u0, du0 = 0.3 - 0.6j, 0.8 + 0.1j
    fl = ref.MPFlightCritical(p.gamma, p.omega, p.rho, p.phi, u0, du0)
    times = np.array([0.0, 0.5, 1.0, 4.0, 17.0, 40.0])
    u, du = free_flight(p, u0, du0, times)
    for j, t in enumerate(times):
        ue, due = fl.state(t)
        assert abs(u[j] - complex(ue)) < 1e-14
        assert abs(du[j] - complex(due)) < 1e-14


def test_mpmath_reference_satisfies_the_ode(ref):
    """Sanity check of the reference itself: U'' + (g + 2i) U' + (w^2 - 1 + i g) U = rho e^{i phi}."""
    for label, kw, u0, du0 in FLOWS:
        p = Parameters(**kw)
        critical = 0.25 * p.gamma**2 - p.omega**2 == 0.0
        fl = (ref.MPFlightCritical if critical else ref.MPFlight)(p.gamma, p.omega, p.rho, p.phi, u0, du0)
        with mp.workdps(ref.DPS):
            g, w = mp.mpf(p.gamma), mp.mpf(p.omega)
            forcing = mp.mpf(p.rho) * mp.expj(mp.mpf(p.phi))
            u, du = fl.state(0)
            assert abs(u - mp.mpc(u0)) < mp.mpf(10) ** -30 and abs(du - mp.mpc(du0)) < mp.mpf(10) ** -30
            for t in (0.0, 0.7, 5.0):
                U, dU, ddU = fl.derivs(t, 2)
                res = ddU + mp.mpc(g, 2) * dU + mp.mpc(w**2 - 1, g) * U - forcing
                assert abs(res) < mp.mpf(10) ** -28, label


def test_equilibrium_point_hand_formula():
    p = Parameters(gamma=0.1, omega=0.76, rho=3 / 7, mu=0.15, d=0.95, phi=0.21)
    k = (3 / 7) * complex(math.cos(0.21), math.sin(0.21)) / complex(0.76**2 - 1, 0.1)
    assert abs(equilibrium_point(p.gamma, p.omega, p.rho, p.phi) - k) < 1e-15
    assert abs(p.k - k) < 1e-15
    # MODEL.md §4: |k| = rho / sqrt(gamma^2 + (1 - omega^2)^2)
    assert abs(abs(p.k) - (3 / 7) / math.hypot(0.1, 1 - 0.76**2)) < 1e-15
    # U = k is a rest point of the flow
    u, du = free_flight(p, k, 0.0, [0.0, 3.0, 100.0])
    assert np.max(np.abs(u - k)) < 1e-15 and np.max(np.abs(du)) < 1e-15


def test_free_flight_backward_in_time_inverts_forward(ref):
    p = Parameters(gamma=0.2, omega=0.9, rho=0.5, mu=0.2, d=0.8, phi=1.0)
    u0, du0 = 0.2 + 0.3j, -0.4 + 0.9j
    fl = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u0, du0)
    u, du = free_flight(p, u0, du0, [-2.5, -0.5])
    for j, t in enumerate([-2.5, -0.5]):
        ue, due = fl.state(t)
        assert abs(u[j] - complex(ue)) < 1e-13 and abs(du[j] - complex(due)) < 1e-13
    u1, du1 = free_flight(p, u0, du0, 1.7)
    u2, du2 = free_flight(p, complex(u1), complex(du1), -1.7)
    assert abs(complex(u2) - u0) < 1e-13 and abs(complex(du2) - du0) < 1e-13


def test_free_flight_shapes_and_initial_value():
    p = Parameters(gamma=0.1, omega=0.76, rho=0.4, mu=0.1, d=0.9)
    t = np.linspace(0, 3, 12).reshape(3, 4)
    u, du = free_flight(p, 0.1 + 0.2j, -0.3j, t)
    assert u.shape == (3, 4) and du.shape == (3, 4)
    assert u.dtype == complex and du.dtype == complex
    assert abs(u[0, 0] - (0.1 + 0.2j)) < 1e-15 and du[0, 0] == -0.3j
    u, du = free_flight(p, 0.1, 0.2, 1.5)
    assert np.shape(u) == ()


@pytest.mark.parametrize("gamma", [0.1, 2.0])
def test_inertial_frame_matches_solve_ivp_of_inertial_equation(gamma):
    """Z = U e^{it} solves z'' + gamma z' + omega^2 z = rho e^{i(t + phi)} (MODEL.md §1-§2)."""
    p = Parameters(gamma=gamma, omega=0.76, rho=3 / 7, mu=0.15, d=0.95, phi=0.21)
    u0, du0 = 0.2 - 0.1j, 0.5 + 0.3j
    # inertial initial state: Z(0) = U(0), Z'(0) = U'(0) + i U(0)
    z0, dz0 = u0, du0 + 1j * u0

    def rhs(t, y):
        z, dz = complex(y[0], y[1]), complex(y[2], y[3])
        ddz = p.rho * np.exp(1j * (t + p.phi)) - p.gamma * dz - p.omega**2 * z
        return [dz.real, dz.imag, ddz.real, ddz.imag]

    times = np.linspace(0, 20, 41)
    sol = solve_ivp(rhs, (0, 20), [z0.real, z0.imag, dz0.real, dz0.imag], method="DOP853",
                    rtol=1e-12, atol=1e-13, t_eval=times)
    z_ref = sol.y[0] + 1j * sol.y[1]
    u, _ = free_flight(p, u0, du0, times)
    z = to_inertial(u, times)
    assert np.max(np.abs(z - z_ref)) < 1e-9
    # a rotation keeps the modulus, to the rounding of e^{it}, of the product and of |.| (a few ulps)
    assert np.allclose(np.abs(z), np.abs(u), rtol=0, atol=8 * np.finfo(float).eps)


@pytest.mark.parametrize("args, match", [
    ((None, 0j, 0j, [1.0]), "^params "),
    ((REF, math.nan, 0j, [1.0]), r"^u0 \(real part\) = "),
    ((REF, "1+1j", 0j, [1.0]), "^u0 = "),
    ((REF, 0j, None, [1.0]), "^du0 = "),
    ((REF, 0.1, 0j, [math.nan]), "^t = "),
    ((REF, 0.1, 0j, ["1"]), "^t = "),
    ((REF.replace(gamma=0.1), 0.1, 0j, [-1e6]), "^t = .* overflows"),
])
def test_free_flight_refuses_bad_input(args, match):
    with pytest.raises(ParameterError, match=match):
        free_flight(*args)


@pytest.mark.parametrize("u, t", [("a", 1.0), (1.0, math.inf), (complex(math.nan, 0), 1.0), (1.0, "1")])
def test_to_inertial_refuses_bad_input(u, t):
    with pytest.raises(ParameterError, match="^[ut] = "):
        to_inertial(u, t)


def test_to_inertial_takes_shapes_that_broadcast_and_refuses_others():
    u = np.array([1.0 + 0.5j, -0.2j, 0.3])
    t = np.array([0.0, 1.0, 2.0])
    assert np.allclose(to_inertial(u, t), [u[i] * complex(math.cos(t[i]), math.sin(t[i])) for i in range(3)],
                       rtol=1e-15, atol=0.0)
    assert to_inertial(u, 0.0).shape == (3,) and to_inertial(1j, t).shape == (3,)
    with pytest.raises(ParameterError, match=r"^u of shape \(3,\) and t of shape \(2,\) do not match"):
        to_inertial(u, [0.0, 1.0])
