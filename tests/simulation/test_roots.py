"""Guaranteed impact location (MODEL.md §3, last paragraph).

References are computed in mpmath from the closed form: crossings are bracketed by
dense sampling of |U|^2 - 1 and its derivative and refined with ``mp.findroot``.
The near-grazing states are constructed exactly: a tangency of |U| = 1 + delta is
placed at a chosen time T, point and tangential velocity, and the flow is run
backwards in mpmath to t = 0.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from rotorcontact import Parameters
from rotorcontact.simulation.roots import CROSSING, NO_CROSSING, STUCK, next_crossing
from reference_parameters import REF, REF_VALUES


PI = math.pi

# (label, params, T of the tangency, angle of the tangency point, tangential speed there)
# At r = 1 with rdot = 0 and thetadot = beta, (|U|^2)''/2 = (1 + beta)^2 - omega^2 + rho cos(phi - alpha),
# which is negative for these choices: an interior maximum of r.
GRAZE_CASES = [
    ("reference-gamma0.1", dict(REF_VALUES, gamma=0.1), 1.5, 0.21 + PI, -0.5),
    ("reference-gamma0.1-other-point", dict(REF_VALUES, gamma=0.1), 2.0, 0.21 + 2.5, -0.7),
    ("critical-damping", dict(REF_VALUES, gamma=2 * 0.760043431053203), 1.0, 0.21 + PI, -0.5),
    ("overdamped", dict(REF_VALUES, gamma=2.0), 1.0, 0.21 + PI, -1.0),
]
EXTRA = 0.3  # the runs end at T + EXTRA


def k_of(p):
    return p.rho * complex(math.cos(p.phi), math.sin(p.phi)) / complex(p.omega**2 - 1, p.gamma)


def grazing_state(ref, p, delta, T, alpha, beta):
    """Initial state (double) whose flight has a maximum |U| = 1 + delta at t = T (tangency)."""
    with mp.workdps(ref.DPS):
        um = (1 + mp.mpf(delta)) * mp.expj(alpha)
        dum = mp.mpc(0, beta) * mp.expj(alpha)
        back = ref.flight(p, um, dum)
        u0, du0 = back.state(-T)
    return complex(u0), complex(du0)


def excursion(ref, p, u0, du0, T):
    """mpmath facts about the flight from the double initial state: (flight, t_max, max|U| - 1)."""
    fl = ref.flight(p, u0, du0)
    with mp.workdps(ref.DPS):
        tm = mp.findroot(fl.fp, mp.mpf(T))
        assert fl.fpp(tm) < 0
        return fl, tm, abs(fl.U(tm)) - 1


@pytest.fixture(params=GRAZE_CASES, ids=[c[0] for c in GRAZE_CASES])
def graze_case(request):
    label, kw, T, alpha, beta = request.param
    return Parameters(**kw), T, alpha, beta


def grazing_flight(ref, graze_case, delta, beta_scale):
    """The flight of a grazing case from inside the clearance, with a maximum |U| = 1 + delta (to rounding):
    (p, T, u0, du0, flight, t_max, max|U| - 1); the test is skipped where the backward flight leaves the
    clearance."""
    p, T, alpha, beta = graze_case
    u0, du0 = grazing_state(ref, p, delta, T, alpha, beta * beta_scale)
    fl = ref.flight(p, u0, du0)
    with mp.workdps(ref.DPS):
        if fl.f(0) >= 0:
            pytest.skip("the backward flight leaves the clearance: no flight from inside")
    fl, tm, top = excursion(ref, p, u0, du0, T)
    return p, T, u0, du0, fl, tm, top


EPS = np.finfo(float).eps


@pytest.mark.parametrize("beta_scale", [0.9, 1.0, 1.1])
@pytest.mark.parametrize("delta", [1e-8, 1e-10, 1e-12, 1e-13, 1e-14])
def test_grazing_crossing_is_found_to_the_rounding_limit(ref, graze_case, delta, beta_scale):
    p, T, u0, du0, fl, tm, top = grazing_flight(ref, graze_case, delta, beta_scale)
    assert abs(tm - T) < 1e-9
    assert abs(top / delta - 1) < 2e-2  # the construction: max |U| = 1 + delta (to rounding of u0)
    t_hit = ref.mp_first_crossing(fl, T + EXTRA, dt=0.01)
    assert t_hit is not None and t_hit < tm
    with mp.workdps(ref.DPS):
        rdot_hit = float(fl.fp(t_hit) / 2)  # r = 1 there
        half_fpp = float(abs(fl.fpp(t_hit)) / 2)

    traj = ref.run(p, u0, du0, T + EXTRA, max_impacts=1, chatter_rdot=1e-300)
    assert len(traj.impacts) == 1, traj.message
    t_sim = traj.impacts.t[0]
    # located to the rounding limit of f: the exact f at the reported time is within a few ulps of
    # the size of the terms of |U|^2 = |k + V|^2, S = (|k| + |V|)^2 + 1 (the backward error of f)
    with mp.workdps(ref.DPS):
        f_sim = float(fl.f(mp.mpf(t_sim)))
        scale = float((abs(fl.k) + abs(fl.U(mp.mpf(t_sim)) - fl.k)) ** 2 + 1)
    f_max = 8 * EPS * scale
    assert abs(f_sim) <= f_max, (f_sim, f_max)
    # so the time is off by at most that over f' = 2 rdot
    dt_max = f_max / (2.0 * rdot_hit)
    assert abs(t_sim - float(t_hit)) <= dt_max, (t_sim - float(t_hit), dt_max)
    # and rdot = f'/2 with the error that this time error carries (rdot' = f''/2 at r = 1)
    assert abs(traj.impacts.rdot[0] - rdot_hit) <= half_fpp * dt_max + 1e-12 * rdot_hit


@pytest.mark.parametrize("beta_scale", [0.9, 1.0, 1.1])
@pytest.mark.parametrize("delta", [-1e-10, -1e-12, -1e-14])
def test_tangency_just_below_is_not_an_impact(ref, graze_case, delta, beta_scale):
    """The guarantee's other edge: a maximum 1e-14 below the wall is no impact."""
    p, T, u0, du0, fl, tm, top = grazing_flight(ref, graze_case, delta, beta_scale)
    assert abs(top / delta - 1) < 2e-2 and top < 0
    # the reference confirms there is no crossing at all up to the end of the run
    assert ref.mp_first_crossing(fl, T + EXTRA, dt=0.01) is None
    traj = ref.run(p, u0, du0, T + EXTRA)
    assert len(traj.impacts) == 0
    assert traj.status == "completed"
    # dense output passes within 2|delta| of the wall at the tangency
    assert 1 + 2 * delta < traj.r(float(tm)) < 1


def test_a_crossing_between_samples_is_found(ref):
    """A free-flight arc whose maximum of |U| exceeds 1 by only 1e-10: a dense fixed sampling of
    the exact solution sees nothing, the guaranteed search finds the crossing."""
    p = REF.replace(gamma=0.1)
    T, alpha, beta = 1.5, 0.21 + PI, -0.5
    u0, du0 = grazing_state(ref, p, 1e-10, T, alpha, beta)
    fl, tm, top = excursion(ref, p, u0, du0, T)
    assert 0.99e-10 < top < 1.01e-10
    t_end = T + EXTRA
    # a fixed sampling of the exact solution with 10^4 points sees nothing either
    k = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u0, du0)
    lp, lm, cp, cm, kk = (complex(k.lp), complex(k.lm), complex(k.cp), complex(k.cm), complex(k.k))
    ts = np.linspace(0, t_end, 10_000)
    r = np.abs(kk + cp * np.exp(lp * ts) + cm * np.exp(lm * ts))
    assert r.max() < 1
    # the exact simulator finds it
    traj = ref.run(p, u0, du0, t_end, chatter_rdot=1e-300)
    assert len(traj.impacts) >= 1
    t_hit = float(ref.mp_first_crossing(fl, t_end, dt=0.01))
    assert abs(traj.impacts.t[0] - t_hit) < 1e-10


def test_next_crossing_on_grazing_pair(ref):
    p = REF.replace(gamma=0.1)
    k = k_of(p)
    T, alpha, beta = 1.5, 0.21 + PI, -0.5
    for delta, expected in ((1e-10, CROSSING), (-1e-10, NO_CROSSING)):
        u0, du0 = grazing_state(ref, p, delta, T, alpha, beta)
        code, tau = next_crossing(u0 - k, du0, k, p.gamma, p.omega, T + EXTRA, False)
        assert code == expected
        if expected == NO_CROSSING:
            assert tau == T + EXTRA
        else:
            fl = ref.flight(p, u0, du0)
            assert abs(tau - float(ref.mp_first_crossing(fl, T + EXTRA))) < 1e-10


TRANSVERSAL = [
    (dict(REF_VALUES, gamma=0.1), 0.0, 0.0),
    (dict(REF_VALUES, gamma=0.1), 0.5 - 0.5j, 0.2 + 0.1j),
    (dict(REF_VALUES, gamma=0.0), -0.3j, 0.9 - 0.4j),
    (dict(REF_VALUES, gamma=0.6, omega=1.7, rho=1.4, phi=-1.2), 0.1, 0.0),
    (dict(REF_VALUES, gamma=2.5, omega=0.4, rho=1.9, phi=2.2), -0.2 + 0.6j, 1.5j),
    (dict(REF_VALUES, gamma=0.01, omega=0.1, rho=0.05, phi=0.0), 0.0, 0.3),
]


@pytest.mark.parametrize("kw,u0,du0", TRANSVERSAL)
def test_next_crossing_matches_mpmath(ref, kw, u0, du0):
    p = Parameters(**kw)
    k = k_of(p)
    horizon = 60.0
    fl = ref.flight(p, u0, du0)
    t_ref = ref.mp_first_crossing(fl, horizon, dt=0.01)
    code, tau = next_crossing(u0 - k, du0, k, p.gamma, p.omega, horizon, False)
    if t_ref is None:
        assert code == NO_CROSSING and tau == horizon
    else:
        assert code == CROSSING
        assert abs(tau - float(t_ref)) <= 1e-12 * float(t_ref), (tau, float(t_ref))
        # a horizon just short of the crossing gives no crossing
        code2, tau2 = next_crossing(u0 - k, du0, k, p.gamma, p.omega, float(t_ref) * (1 - 1e-9), False)
        assert code2 == NO_CROSSING


def test_next_crossing_from_the_boundary_moving_inwards(ref):
    p = REF.replace(gamma=0.1)
    k = k_of(p)
    u = complex(math.cos(0.4), math.sin(0.4))
    du = u * complex(-0.3, -1.2)  # rdot = -0.3, thetadot = -1.2
    fl = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u, du)
    t_ref = ref.mp_first_crossing(fl, 30.0)
    assert t_ref is not None
    code, tau = next_crossing(u - k, du, k, p.gamma, p.omega, 30.0, True)
    assert code == CROSSING
    assert abs(tau - float(t_ref)) <= 1e-12 * float(t_ref)


def test_next_crossing_on_boundary_at_rest_pressed_outwards_is_stuck():
    p = REF.replace(gamma=0.1)
    k = k_of(p)
    # at theta = phi, rdot = 0, thetadot = 0: N = 1 - omega^2 + rho > 0 (pressed outwards)
    u = complex(math.cos(p.phi), math.sin(p.phi))
    assert 1 - p.omega**2 + p.rho * math.cos(p.phi - p.phi) > 0
    code, tau = next_crossing(u - k, 0j, k, p.gamma, p.omega, 10.0, True)
    assert code == STUCK and tau == 0.0


def test_next_crossing_on_boundary_tangent_pulled_inwards_leaves(ref):
    p = REF.replace(gamma=0.1)
    k = k_of(p)
    alpha, beta = p.phi + PI, -0.5
    # N = (1 + beta)^2 - omega^2 + rho cos(phi - alpha) < 0: r has a maximum here
    assert (1 + beta) ** 2 - p.omega**2 + p.rho * math.cos(p.phi - alpha) < 0
    u = complex(math.cos(alpha), math.sin(alpha))
    du = 1j * beta * u
    code, tau = next_crossing(u - k, du, k, p.gamma, p.omega, 30.0, True)
    assert code in (CROSSING, NO_CROSSING)
    assert tau > 0.1
    if code == CROSSING:
        # reference: start the search just after the tangency, where r < 1
        fl = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u, du)
        with mp.workdps(ref.DPS):
            s = mp.mpf("1e-3")
            assert fl.f(s) < 0
            u1, du1 = fl.state(s)
        fl1 = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u1, du1)
        t_ref = ref.mp_first_crossing(fl1, 30.0) + mp.mpf("1e-3")
        assert abs(tau - float(t_ref)) <= 1e-12 * float(t_ref)


def test_no_crossing_for_a_decaying_flight():
    q = Parameters(gamma=0.2, omega=0.9, rho=0.0, mu=0.1, d=0.5)
    code, tau = next_crossing(0.5 + 0j, 0.1j, 0j, q.gamma, q.omega, 1e4, False)
    assert code == NO_CROSSING and tau == 1e4
    p = REF.replace(gamma=0.3)
    k = k_of(p)
    assert abs(k) < 1
    assert next_crossing(0j, 0j, k, p.gamma, p.omega, 1e4, False) == (NO_CROSSING, 1e4)


def test_no_crossing_at_the_regular_equilibrium_over_a_long_horizon():
    p = REF.replace(gamma=0.3)
    k = k_of(p)
    assert next_crossing(0j, 0j, k, p.gamma, p.omega, 1e6, False) == (NO_CROSSING, 1e6)


def f_derivative(d, n):
    """The n-th derivative of f = |U|^2 - 1 from [U, U', ..., U^(n)] (Leibniz)."""
    return sum(math.comb(n, j) * (mp.conj(d[j]) * d[n - j]).real for j in range(n + 1))


@pytest.mark.parametrize("gamma", [0.0, 0.1, 0.6])
@pytest.mark.parametrize("start", [(0.3 + 0.2j, 0.4 - 0.1j), (-0.5j, 0.9 + 0.3j), (0.7, 0j)])
def test_whirl_moments_bound_the_flight_and_every_derivative_of_f_ahead(ref, gamma, start):
    """(|A| + |B|) e^{-gamma s/2} >= |W(s)| and slow_n e^{-gamma s/2} + fast_n e^{-gamma s} >= |f^(n)(s)|
    (n = 2..7) at every time of the flight, f and its derivatives from mpmath's closed form."""
    from rotorcontact.simulation.roots import _whirl_moments

    p = REF.replace(gamma=gamma)
    k = k_of(p)
    u0, du0 = start
    h2 = 0.25 * gamma * gamma - p.omega * p.omega
    m = _whirl_moments(k, u0 - k, du0 + 1j * (u0 - k), gamma, h2)  # W, W' = V, V' + iV at s = 0
    fl = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u0, du0)
    with mp.workdps(30):
        for s in np.linspace(0.0, 12.0, 97):
            d = fl.derivs(s, 7)
            decay = math.exp(-0.5 * gamma * s)
            assert float(abs(d[0] - fl.k)) <= m[0] * decay * (1 + 1e-13)
            for n in range(2, 8):
                bound = m[2 * n - 3] * decay + m[2 * n - 2] * decay * decay
                assert abs(float(f_derivative(d, n))) <= bound * (1 + 1e-13)


@pytest.mark.parametrize("gamma", [0.0, 0.1])
def test_whirl_moments_are_exact_for_a_circular_whirl(ref, gamma):
    """With B = 0 (W = A e^{mu_+ s}) the bound on |W| is |W| itself, and over a beat period the bounds on
    f''' and f'''' are reached to within the decay of the terms over it."""
    from rotorcontact.simulation.roots import _whirl_moments

    p = REF.replace(gamma=gamma)
    k = k_of(p)
    h2 = 0.25 * gamma * gamma - p.omega * p.omega
    mu_plus = complex(-0.5 * gamma, math.sqrt(-h2))
    a = 0.4 + 0.1j
    m = _whirl_moments(k, a, mu_plus * a, gamma, h2)
    assert m[0] == pytest.approx(abs(a), rel=1e-14)
    u0, du0 = k + a, (mu_plus - 1j) * a  # co-rotating: V = W e^{-is}
    fl = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u0, du0)
    beat = 2 * math.pi / (1 - math.sqrt(-h2))
    with mp.workdps(30):
        for n in (3, 4):
            ratio = max(abs(float(f_derivative(fl.derivs(s, n), n)))
                        / (m[2 * n - 3] * math.exp(-0.5 * gamma * s) + m[2 * n - 2] * math.exp(-gamma * s))
                        for s in np.linspace(0.0, beat, 400))
            assert math.exp(-0.5 * gamma * beat) * 0.99 <= ratio <= 1 + 1e-13


@pytest.mark.parametrize("start", [(0.3 + 0.2j, 0.4 - 0.1j), (-0.5j, 0.9 + 0.3j), (0.2, 1.2j)])
def test_model_root_brackets_the_crossing_ahead(ref, start):
    """Near a transversal crossing, `_model_root`'s (h, e) holds the first crossing (mpmath) in [h - e, h + e];
    it certifies from 0.1 before it, and within 1e-4 of it e is below the rounding of the crossing time."""
    from rotorcontact.simulation.roots import _model_root, _whirl_moments

    p = REF.replace(gamma=0.1)
    k = k_of(p)
    u0, du0 = start
    h2 = 0.25 * p.gamma * p.gamma - p.omega * p.omega
    m = _whirl_moments(k, u0 - k, du0 + 1j * (u0 - k), p.gamma, h2)
    fl = ref.MPFlight(p.gamma, p.omega, p.rho, p.phi, u0, du0)
    t_cross = ref.mp_first_crossing(fl, 30.0)
    with mp.workdps(30):
        assert fl.fp(t_cross) > 0.1  # transversal
        for gap in (0.1, 1e-2, 1e-3, 1e-4, 1e-7):
            s = float(t_cross) - gap
            d = fl.derivs(s, 6)
            taylor = [float(f_derivative(d, n)) - (1.0 if n == 0 else 0.0) for n in range(7)]
            decay = math.exp(-0.5 * p.gamma * s)
            m3 = m[3] * decay + m[4] * decay * decay
            m7 = m[11] * decay + m[12] * decay * decay
            h, e = _model_root(*taylor, m3, m7)
            assert math.isfinite(h) and 0.0 < e <= 0.25 * h
            # the bracket, widened by the rounding of s and of f and its derivatives in double
            assert abs(float(s + h - t_cross)) <= e + 8 * EPS * float(t_cross)
            if gap <= 1e-4:
                assert e <= 4 * EPS * (1 + s)


def test_model_root_declines_far_from_the_wall_or_at_a_slope_too_small():
    from rotorcontact.simulation.roots import _model_root

    # |f'| small against the bound on f'' over the distance to the model's root: no certificate
    h, e = _model_root(-1e-2, 1e-3, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0)
    assert math.isnan(h) and e == math.inf
    # the remainder bound leaves the crossing anywhere within a quarter of the step
    h, e = _model_root(-0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e6)
    assert math.isnan(h) and e == math.inf
    # and with a small one it is certified: e = M7 h^7 / 5040 over the slope
    h, e = _model_root(-0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)
    assert h == pytest.approx(0.5, rel=1e-15) and e == pytest.approx(0.5**7 / 5040, rel=1e-12)
    # the quadratic model has no root ahead
    h, e = _model_root(-1.0, 0.1, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0)
    assert math.isnan(h) and e == math.inf
