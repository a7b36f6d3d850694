"""The impact law (MODEL.md §2): Newton restitution and Coulomb friction whose impulse
is bounded so that it never reverses the relative surface velocity
v_rel = r_ratio + 1 + thetadot; for v_rel > 0 and no sticking it is the complex form
U'+ = U'- - q rdot- U with q = (1 + d)(1 + i mu)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import Parameters
from rotorcontact.model.impact_law import apply_reset, polar_velocity
from reference_parameters import REF


def unpack(out):
    du_plus, rdot, thetadot, rdot_plus, thetadot_plus, v_rel, p_n, p_t = out
    return complex(du_plus), rdot, thetadot, rdot_plus, thetadot_plus, v_rel, p_n, p_t


def test_polar_velocity_by_hand():
    u = 0.5 * complex(math.cos(0.3), math.sin(0.3))
    # U' = (rdot + i r thetadot) e^{i theta}
    du = complex(0.7, 0.5 * -1.3) * complex(math.cos(0.3), math.sin(0.3))
    rdot, thetadot = polar_velocity(u, du)
    assert rdot == pytest.approx(0.7, abs=1e-15)
    assert thetadot == pytest.approx(-1.3, abs=1e-15)


def random_impact(rng):
    """A random impact point u on |u| = 1, restitution d, friction mu, R / c_r and incoming rdot > 0."""
    th = rng.uniform(-math.pi, math.pi)
    u = complex(math.cos(th), math.sin(th))
    d, mu = rng.uniform(0, 1), rng.uniform(0, 1)
    r_ratio = rng.uniform(0, 80)
    rdot = rng.uniform(1e-6, 3)
    return u, d, mu, r_ratio, rdot


def test_complex_form_for_forward_slip():
    rng = np.random.default_rng(1)
    for _ in range(300):
        u, d, mu, r_ratio, rdot = random_impact(rng)
        # thetadot such that v_rel exceeds the Coulomb impulse mu (1 + d) rdot
        thetadot = -(r_ratio + 1) + mu * (1 + d) * rdot + rng.uniform(1e-3, 5)
        du = u * complex(rdot, thetadot)
        du_plus, rd, td, rdp, tdp, v_rel, p_n, p_t = unpack(apply_reset(u, du, d, mu, r_ratio))
        q = (1 + d) * complex(1, mu)
        expected = du - q * rdot * u
        assert abs(du_plus - expected) < 1e-13 * (1 + abs(du))
        assert rd == pytest.approx(rdot, abs=1e-13 * (1 + abs(du)))
        assert td == pytest.approx(thetadot, abs=1e-13 * (1 + abs(du)))
        assert v_rel == pytest.approx(r_ratio + 1 + thetadot, abs=1e-12 * (1 + abs(du)))
        assert rdp == pytest.approx(-d * rdot, abs=1e-13 * (1 + abs(du)))
        assert tdp == pytest.approx(thetadot - mu * (1 + d) * rdot, abs=1e-12 * (1 + abs(du)))
        assert p_n == pytest.approx((1 + d) * rdot, rel=1e-13)
        assert p_t == pytest.approx(-mu * (1 + d) * rdot, rel=1e-12, abs=1e-15)


def test_mirror_form_for_backward_slip():
    """v_rel < 0: the friction impulse acts along +theta: U'+ = U'- - (1 + d)(1 - i mu) rdot U."""
    rng = np.random.default_rng(2)
    for _ in range(300):
        u, d, mu, r_ratio, rdot = random_impact(rng)
        thetadot = -(r_ratio + 1) - mu * (1 + d) * rdot - rng.uniform(1e-3, 5)
        du = u * complex(rdot, thetadot)
        du_plus, rd, td, rdp, tdp, v_rel, p_n, p_t = unpack(apply_reset(u, du, d, mu, r_ratio))
        expected = du - (1 + d) * complex(1, -mu) * rdot * u
        assert abs(du_plus - expected) < 1e-13 * (1 + abs(du))
        assert v_rel < 0
        assert p_t == pytest.approx(mu * (1 + d) * rdot, rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_friction_stops_at_rolling_and_never_reverses_slip(sign):
    """Where mu (1 + d) rdot exceeds |v_rel| the impulse only brings v_rel to 0."""
    rng = np.random.default_rng(3 if sign > 0 else 4)
    for _ in range(300):
        th = rng.uniform(-math.pi, math.pi)
        u = complex(math.cos(th), math.sin(th))
        d, mu = rng.uniform(0, 1), rng.uniform(0.05, 1)
        r_ratio = rng.uniform(0, 80)
        rdot = rng.uniform(0.01, 3)
        slip = mu * (1 + d) * rdot
        v_rel = sign * rng.uniform(0, 0.999) * slip
        thetadot = v_rel - (r_ratio + 1)
        du = u * complex(rdot, thetadot)
        du_plus, rd, td, rdp, tdp, vr, p_n, p_t = unpack(apply_reset(u, du, d, mu, r_ratio))
        assert abs(r_ratio + 1 + tdp) < 1e-12 * (1 + r_ratio)  # rolling after the impact
        assert abs(p_t) <= mu * p_n * (1 + 1e-12)  # bounded by Coulomb
        assert abs(p_t + vr) < 1e-12 * (1 + r_ratio)
        assert rdp == pytest.approx(-d * rdot, rel=1e-13)
        assert abs(du_plus - u * complex(-d * rdot, -(r_ratio + 1))) < 1e-12 * (1 + r_ratio)


def test_zero_friction_and_plastic_and_elastic_limits():
    u = complex(math.cos(2.0), math.sin(2.0))
    du = u * complex(0.8, 0.3)
    # mu = 0: tangential velocity unchanged
    du_plus, rd, td, rdp, tdp, vr, p_n, p_t = unpack(apply_reset(u, du, 0.6, 0.0, 10.0))
    assert tdp == pytest.approx(0.3, abs=1e-15) and p_t == 0.0
    assert rdp == pytest.approx(-0.48, abs=1e-15)
    # d = 0: plastic, radial velocity removed
    du_plus, rd, td, rdp, tdp, vr, p_n, p_t = unpack(apply_reset(u, du, 0.0, 0.2, 10.0))
    assert rdp == 0.0 or abs(rdp) < 1e-16
    assert p_n == pytest.approx(0.8, abs=1e-15)
    # d = 1: elastic, radial velocity reversed
    du_plus, rd, td, rdp, tdp, vr, p_n, p_t = unpack(apply_reset(u, du, 1.0, 0.2, 10.0))
    assert rdp == pytest.approx(-0.8, abs=1e-15)
    assert tdp == pytest.approx(0.3 - 0.2 * 2 * 0.8, abs=1e-15)


def test_impact_table_obeys_the_law(ref):
    """Every impact of real runs: rdot+ = -d rdot, impulses, slip bound and no reversal."""
    runs = [
        (REF.replace(gamma=0.1), 0j, 0j),
        # small rotor radius and strong friction: impacts that stick (v_rel -> 0)
        (Parameters(gamma=0.1, omega=0.76, rho=0.6, mu=1.0, d=0.9, phi=0.0, r_ratio=0.05), 0.5 + 0j, 1.0 - 0.5j),
        (Parameters(gamma=0.05, omega=1.3, rho=1.2, mu=0.8, d=0.5, phi=2.0, r_ratio=0.0), -0.3j, 2.0 + 1.0j),
    ]
    n_stick = 0
    for p, u0, du0 in runs:
        traj = ref.run(p, u0, du0, 100.0, max_impacts=300)
        imp = traj.impacts
        assert len(imp) > 5
        assert np.all(imp.rdot > 0)
        np.testing.assert_allclose(imp.rdot_plus, -p.d * imp.rdot, rtol=1e-14, atol=0)
        np.testing.assert_allclose(imp.normal_impulse, (1 + p.d) * imp.rdot, rtol=1e-14, atol=0)
        np.testing.assert_allclose(imp.v_rel, p.r_ratio + 1 + imp.thetadot, rtol=0, atol=1e-12 * (1 + p.r_ratio))
        np.testing.assert_allclose(imp.tangential_impulse, imp.thetadot_plus - imp.thetadot, rtol=0, atol=1e-12)
        assert np.all(np.abs(imp.tangential_impulse) <= p.mu * imp.normal_impulse * (1 + 1e-12) + 1e-15)
        v_after = p.r_ratio + 1 + imp.thetadot_plus
        assert np.all(v_after * imp.v_rel >= -1e-12 * (1 + p.r_ratio))  # never reversed
        stick = np.abs(v_after) < 1e-12 * (1 + p.r_ratio)
        n_stick += int(stick.sum())
        # where it does not stick, the full Coulomb impulse acts against v_rel
        slide = ~stick
        np.testing.assert_allclose(
            imp.tangential_impulse[slide], -np.sign(imp.v_rel[slide]) * p.mu * imp.normal_impulse[slide],
            rtol=1e-12, atol=1e-15,
        )
        # the stored post-impact velocity is e^{i theta} (rdot+ + i thetadot+)
        e = np.exp(1j * imp.theta)
        np.testing.assert_allclose(imp.du_plus, e * (imp.rdot_plus + 1j * imp.thetadot_plus), rtol=0, atol=1e-12)
    assert n_stick > 0  # the sticking branch of the law was exercised


def test_radial_impacts_without_unbalance_stay_radial(ref):
    """rho = 0 and r_ratio = 0: a rotor thrown radially in the inertial frame hits with
    thetadot = -1 (no whirl), so v_rel = 0 and friction does nothing."""
    p = Parameters(gamma=0.05, omega=0.5, rho=0.0, mu=0.5, d=0.8, phi=0.0, r_ratio=0.0)
    u0 = 0.5 + 0j
    # inertial Z' = 1 (radial); co-rotating U' = Z' - i U
    du0 = 1.0 - 0.5j
    traj = ref.run(p, u0, du0, 30.0, max_impacts=5)
    imp = traj.impacts
    assert len(imp) >= 2
    np.testing.assert_allclose(imp.thetadot, -1.0, atol=1e-12)
    np.testing.assert_allclose(imp.v_rel, 0.0, atol=1e-12)
    np.testing.assert_allclose(imp.tangential_impulse, 0.0, atol=1e-12)
    # the inertial angle Theta = theta + t stays 0 (or pi after passing through the centre)
    Theta = np.angle(np.exp(1j * (imp.theta + imp.t)))
    assert np.all(np.minimum(np.abs(Theta), np.abs(np.abs(Theta) - math.pi)) < 1e-9)


# ---------------------------------------------------------------------------
# q, the slip test and the reset Jacobian
# ---------------------------------------------------------------------------


def test_q_is_one_plus_d_times_one_plus_i_mu():
    from rotorcontact.model.impact_law import impact_q

    for d, mu in [(0.95, 0.15), (0.0, 0.0), (1.0, 1.0), (0.3, -0.2)]:
        assert impact_q(d, mu) == pytest.approx((1.0 + d) * (1.0 + 1j * mu), abs=1e-15)


def test_sticking_and_forward_slip_tests_agree_with_the_law():
    from rotorcontact.model.impact_law import relative_velocity, slides_forward, slip_bound, sticks

    rng = np.random.default_rng(7)
    for _ in range(500):
        th = rng.uniform(-math.pi, math.pi)
        e = complex(math.cos(th), math.sin(th))
        d, mu, rr = rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 5)
        rdot, thetadot = rng.uniform(1e-3, 2), rng.uniform(-8, 3)
        _, rdot, thetadot, _, _, v_rel, p_n, p_t = apply_reset(e, e * complex(rdot, thetadot), d, mu, rr)
        assert v_rel == relative_velocity(rr, thetadot)
        slip = slip_bound(d, mu, rdot)
        assert slip == mu * p_n
        assert sticks(v_rel, slip) == (abs(v_rel) <= slip)
        if sticks(v_rel, slip):
            assert p_t == -v_rel  # the tangential impulse brings v_rel to 0
        else:
            assert abs(p_t) == slip
        assert slides_forward(thetadot, rdot, d, mu, rr) == (v_rel > mu * (1.0 + d) * rdot)


@pytest.mark.parametrize("ideal", [False, True])
def test_reset_jacobian_against_central_differences_of_the_law(ideal):
    from rotorcontact.model.impact_law import ideal_reset, impact_q, reset_jacobian, slip_bound

    rng = np.random.default_rng(11)
    h = 1e-7
    for _ in range(200):
        th = rng.uniform(-math.pi, math.pi)
        e = complex(math.cos(th), math.sin(th))
        d, mu, rr = rng.uniform(0, 1), rng.uniform(0, 1), rng.uniform(0, 5)
        rdot, thetadot = rng.uniform(0.05, 2), rng.uniform(-8, 3)

        def post(rd: float, td: float) -> tuple[float, float]:
            du = e * complex(rd, td)
            du_plus = ideal_reset(e, du, rd, impact_q(d, mu)) if ideal else apply_reset(e, du, d, mu, rr)[0]
            w = e.conjugate() * du_plus
            return w.real, w.imag

        v_rel = rr + 1.0 + thetadot
        slip = slip_bound(d, mu, rdot)
        if not ideal and abs(abs(v_rel) - slip) < 1e-4:
            continue  # the law has a kink there
        r11, r12, r21, r22, sticking = reset_jacobian(v_rel, slip, d, mu, ideal)
        col_r = (np.array(post(rdot + h, thetadot)) - np.array(post(rdot - h, thetadot))) / (2 * h)
        col_t = (np.array(post(rdot, thetadot + h)) - np.array(post(rdot, thetadot - h))) / (2 * h)
        assert np.allclose([[r11, r12], [r21, r22]], np.column_stack([col_r, col_t]), atol=1e-7)
        assert sticking == (not ideal and abs(v_rel) <= slip)
