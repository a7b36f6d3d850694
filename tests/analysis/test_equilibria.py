"""Equilibria and boundary equilibrium bifurcations (MODEL.md §4).

Each test states the claim about the model that it checks.
"""

from __future__ import annotations

import cmath
import dataclasses
import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve

from rotorcontact import ParameterError, Parameters, reference_machine, simulate
from rotorcontact.analysis.equilibria import (
    BRANCH_PARAMETERS,
    beb_omega_ranges,
    boundary_equilibrium,
    boundary_gamma,
    classify_beb_analytic,
    contact_field,
    contact_jacobian,
    equilibria,
    equilibrium_branches,
    friction_sign,
    impact_direction,
    normal_force,
    polar_field,
    polar_field_gamma,
    polar_jacobian,
    pseudo_equilibria,
    regular_equilibrium,
    system_matrix,
)
from rotorcontact.model.angles import wrap_angle
from reference_parameters import REF


TOL = 1e-12


def random_params(rng, n, *, gamma=(0.01, 1.0), omega=(0.05, 1.6), rho=(0.05, 1.0)):
    out = []
    for _ in range(n):
        out.append(
            Parameters(
                gamma=rng.uniform(*gamma),
                omega=rng.uniform(*omega),
                rho=rng.uniform(*rho),
                mu=rng.uniform(0.0, 1.0),
                d=rng.uniform(0.0, 1.0),
                phi=rng.uniform(-math.pi, math.pi),
                r_ratio=rng.uniform(0.0, 80.0),
            )
        )
    return out


def in_angle_range(theta):
    return -math.pi < theta <= math.pi


def model_pseudo_thetas(p):
    """theta_P1,P2 written exactly as in MODEL.md §4 (needs mu > 0)."""
    s = (p.gamma + p.mu * (1 - p.omega**2)) / (p.rho * math.sqrt(1 + p.mu**2))
    base = p.phi - math.pi + math.atan(1 / p.mu)
    return base - math.acos(s), base + math.acos(s)


# ---------------------------------------------------------------------------
# The vector fields
# ---------------------------------------------------------------------------


def test_polar_field_is_the_complex_equation_of_motion_in_polar_coordinates():
    """F of MODEL.md §2 equals U'' + (gamma + 2i)U' + (omega^2 - 1 + i gamma)U = rho e^{i phi} in polar form."""
    rng = np.random.default_rng(1)
    for p in random_params(rng, 50, gamma=(-0.5, 1.0)):
        r, th, rd, thd = rng.uniform(0.1, 1.5), rng.uniform(-3, 3), rng.normal(), rng.normal()
        e = cmath.exp(1j * th)
        u = r * e
        du = (rd + 1j * r * thd) * e
        ddu = p.rho * cmath.exp(1j * p.phi) - complex(p.gamma, 2) * du - complex(p.omega**2 - 1, p.gamma) * u
        # U'' = (rdd - r thd^2 + i (r thdd + 2 rd thd)) e^{i theta}
        w = ddu / e
        rdd = w.real + r * thd**2
        thdd = (w.imag - 2 * rd * thd) / r
        f = polar_field([r, th, rd, thd], p)
        assert f[0] == rd and f[1] == thd
        assert f[2] == pytest.approx(rdd, abs=1e-12)
        assert f[3] == pytest.approx(thdd, abs=1e-12)


def _fd_jacobian(fun, x, h=1e-6):
    x = np.asarray(x, float)
    cols = []
    for j in range(len(x)):
        e = np.zeros_like(x)
        e[j] = h
        cols.append((fun(x + e) - fun(x - e)) / (2 * h))
    return np.array(cols).T


def test_polar_jacobian_matches_finite_differences():
    rng = np.random.default_rng(2)
    for p in random_params(rng, 30):
        x = np.array([rng.uniform(0.2, 1.5), rng.uniform(-3, 3), rng.normal(), rng.normal()])
        fd = _fd_jacobian(lambda y: polar_field(y, p), x)
        assert np.allclose(polar_jacobian(x, p), fd, rtol=1e-7, atol=1e-7)
        fg = (polar_field(x, p.replace(gamma=p.gamma + 1e-6)) - polar_field(x, p.replace(gamma=p.gamma - 1e-6))) / 2e-6
        assert np.allclose(polar_field_gamma(x, p), fg, rtol=1e-7, atol=1e-7)


def test_contact_jacobian_matches_finite_differences():
    rng = np.random.default_rng(3)
    for p in random_params(rng, 30):
        x = np.array([rng.uniform(-3, 3), rng.uniform(-0.5, 0.5)])
        fd = _fd_jacobian(lambda y: contact_field(y[0], y[1], p), x)
        assert np.allclose(contact_jacobian(x[0], x[1], p), fd, rtol=1e-7, atol=1e-7)


def test_contact_field_keeps_r_constant_with_the_normal_force():
    """On r = 1, rdot = 0 the free-flight rddot equals N: subtracting it gives rddot = 0 (MODEL.md §4)."""
    rng = np.random.default_rng(4)
    for p in random_params(rng, 20):
        th, thd = rng.uniform(-3, 3), rng.normal()
        assert polar_field([1.0, th, 0.0, thd], p)[2] == pytest.approx(normal_force(th, thd, p), abs=1e-14)


def test_wrap_angle_range():
    for a in np.linspace(-20, 20, 4001):
        w = wrap_angle(a)
        assert in_angle_range(w)
        assert math.isclose(math.cos(w), math.cos(a), abs_tol=1e-12)
        assert math.isclose(math.sin(w), math.sin(a), abs_tol=1e-12)
    assert wrap_angle(-math.pi) == math.pi
    assert wrap_angle(math.pi) == math.pi


# ---------------------------------------------------------------------------
# Regular equilibrium
# ---------------------------------------------------------------------------


def test_regular_equilibrium_solves_F_equal_zero():
    """x_R = (|k|, arg k, 0, 0) is a zero of F to 1e-12, and scipy finds the same zero."""
    rng = np.random.default_rng(5)
    for p in random_params(rng, 100, gamma=(-0.5, 1.0)):
        reg = regular_equilibrium(p)
        assert reg.exists and in_angle_range(reg.theta)
        assert reg.r == pytest.approx(p.rho / math.hypot(p.gamma, 1 - p.omega**2), rel=1e-14)
        assert np.max(np.abs(polar_field(reg.state, p))) < TOL
        assert reg.admissible == (reg.r < 1)
        x0 = reg.state + np.array([0.02 * reg.r, 0.05, 0.01, -0.01])
        sol = fsolve(lambda x: polar_field(x, p), x0, fprime=lambda x: polar_jacobian(x, p), xtol=1e-13)
        assert np.max(np.abs(polar_field(sol, p))) < 1e-10
        assert sol[0] == pytest.approx(reg.r, rel=1e-10)
        assert wrap_angle(sol[1] - reg.theta) == pytest.approx(0.0, abs=1e-10)


def test_regular_eigenvalues_are_those_of_A_and_of_the_polar_jacobian():
    """The four eigenvalues are lambda_pm of MODEL.md §3 and their conjugates, = eig F_x(x_R)."""
    rng = np.random.default_rng(6)
    for p in random_params(rng, 60, gamma=(-0.5, 3.0)):
        reg = regular_equilibrium(p)
        ev = np.array(reg.eigenvalues)
        root = cmath.sqrt(4 * p.omega**2 - p.gamma**2)
        lam = [(-p.gamma + 1j * (-2 + root)) / 2, (-p.gamma + 1j * (-2 - root)) / 2]
        expected = np.array(lam + [z.conjugate() for z in lam])
        polar = np.linalg.eigvals(polar_jacobian(reg.state, p))
        for ref in (expected, polar):
            # match as multisets
            d = np.abs(ev[:, None] - ref[None, :])
            assert np.all(d.min(axis=1) < 1e-9) and np.all(d.min(axis=0) < 1e-9)
        assert reg.stable == (p.gamma > 0)


def test_regular_equilibrium_at_resonance_and_at_zero_unbalance_is_defined():
    res = regular_equilibrium(Parameters(gamma=0.0, omega=1.0, rho=0.3, mu=0.1, d=0.5))
    assert not res.exists and res.r is None and res.theta is None and "resonance" in res.reason
    assert not res.admissible and not res.stable
    zero = regular_equilibrium(Parameters(gamma=0.2, omega=0.8, rho=0.0, mu=0.1, d=0.5))
    assert zero.exists and zero.r == 0.0 and zero.theta is None and zero.admissible and zero.reason
    json.dumps(res.to_dict(), allow_nan=False)
    json.dumps(zero.to_dict(), allow_nan=False)


# ---------------------------------------------------------------------------
# Pseudo-equilibria
# ---------------------------------------------------------------------------


def _numerical_pseudo_roots(p, n=2000):
    """Zeros of thetaddot(theta, thetadot = 0) on the stator, by bracketing and brentq."""
    g = lambda th: contact_field(th, 0.0, p)[1]  # noqa: E731
    grid = np.linspace(-math.pi, math.pi, n + 1)
    vals = [g(t) for t in grid]
    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if fa == 0:
            roots.append(a)
        elif fa * fb < 0:
            roots.append(brentq(g, a, b, xtol=1e-15))
    return roots


def test_pseudo_equilibria_satisfy_their_equations_and_match_a_numerical_solve():
    """theta_P solves rho(sin psi - mu cos psi) = gamma + mu(1 - omega^2) and thetaddot = 0 to 1e-12;
    the closed forms are exactly the two zeros found by brentq, labelled as in MODEL.md §4."""
    rng = np.random.default_rng(7)
    checked = 0
    for p in random_params(rng, 200, gamma=(-0.5, 1.0)):
        pes = pseudo_equilibria(p)
        assert [pe.name for pe in pes] == ["P1", "P2"]
        if not pes[0].exists:
            continue
        checked += 1
        for pe in pes:
            psi = p.phi - pe.theta
            assert in_angle_range(pe.theta)
            assert abs(p.rho * (math.sin(psi) - p.mu * math.cos(psi)) - (p.gamma + p.mu * (1 - p.omega**2))) < TOL
            assert np.max(np.abs(contact_field(pe.theta, 0.0, p))) < TOL
            assert pe.normal_force == pytest.approx(1 - p.omega**2 + p.rho * math.cos(psi), abs=1e-15)
            assert pe.admissible == (pe.normal_force > 0)
        roots = _numerical_pseudo_roots(p)
        found = sorted(pe.theta for pe in pes)
        if abs(wrap_angle(found[0] - found[1])) > 1e-6:  # distinct roots: both are seen by bracketing
            assert len(roots) == 2
            for r_ in roots:
                assert min(abs(wrap_angle(r_ - t)) for t in found) < 1e-10
        if p.mu > 0:
            t1, t2 = model_pseudo_thetas(p)
            assert abs(wrap_angle(pes[0].theta - t1)) < 1e-10
            assert abs(wrap_angle(pes[1].theta - t2)) < 1e-10
    assert checked > 50


def test_pseudo_equilibria_stability_P1_saddle_P2_stable():
    """det J = rho sqrt(1+mu^2) (-/+ sin alpha): P1 is a saddle; P2 is stable when gamma + 2 mu > 0."""
    rng = np.random.default_rng(8)
    for p in random_params(rng, 200, gamma=(-0.5, 1.0)):
        p1, p2 = pseudo_equilibria(p)
        if not p1.exists or abs(wrap_angle(p1.theta - p2.theta)) < 1e-6:
            continue
        assert np.linalg.det(contact_jacobian(p1.theta, 0.0, p)) < 0 and p1.stable is False
        assert p2.stable == (p.gamma + 2 * p.mu > 0)
        for pe in (p1, p2):
            ev = np.linalg.eigvals(contact_jacobian(pe.theta, 0.0, p))
            assert sorted(np.round(ev.real, 12)) == sorted(np.round([z.real for z in pe.eigenvalues], 12))


def test_pseudo_equilibria_stability_by_integrating_the_contact_dynamics():
    """Integrating the 2D contact dynamics with solve_ivp: from near P2 (stable) the rotor settles on P2,
    from near P1 (saddle) it leaves."""
    p = REF.replace(omega=0.76, gamma=0.15)
    p1, p2 = pseudo_equilibria(p)
    assert p1.admissible and p2.admissible and p2.stable and not p1.stable

    def rhs(t, y):
        return contact_field(y[0], y[1], p)

    sol = solve_ivp(rhs, (0, 200), [p2.theta + 0.05, 0.0], rtol=1e-11, atol=1e-12)
    assert abs(wrap_angle(sol.y[0, -1] - p2.theta)) < 1e-8 and abs(sol.y[1, -1]) < 1e-8
    sol = solve_ivp(rhs, (0, 50), [p1.theta + 1e-4, 0.0], rtol=1e-11, atol=1e-12)
    assert abs(wrap_angle(sol.y[0, -1] - p1.theta)) > 1e-2


def _pseudo_convergence_cases():
    rng = np.random.default_rng(16)
    cases = [REF, REF.replace(omega=1.0, gamma=0.3)]
    for p in random_params(rng, 400, gamma=(0.05, 1.0), omega=(0.2, 1.4)):
        p2 = pseudo_equilibria(p)[1]
        if p2.exists and p2.admissible and p2.normal_force > 0.1 and p2.stable and len(cases) < 6:
            if -max(z.real for z in p2.eigenvalues) > 0.02:
                cases.append(p)
    return cases


@pytest.mark.parametrize("p", _pseudo_convergence_cases())
def test_simulation_near_stable_admissible_pseudo_equilibrium_converges_to_it(p):
    """Started on the stator at rest near x_P2 (admissible, stable), the hybrid simulator slides into it."""
    pe = pseudo_equilibria(p)[1]
    decay = -max(z.real for z in pe.eigenvalues)
    t_end = min(30.0 / decay, 2000.0)
    traj = simulate(p, cmath.exp(1j * (pe.theta + 0.02)), 0j, t_end)
    assert traj.status == "completed"
    r, th, rd, thd = traj.polar(np.array([t_end]))
    assert abs(r[0] - 1) < 1e-12 and traj.in_contact(np.array([t_end]))[0] >= 0
    assert abs(wrap_angle(th[0] - pe.theta)) < 1e-8 and abs(thd[0]) < 1e-8


def test_simulation_near_the_saddle_pseudo_equilibrium_leaves_it():
    p = REF
    p1 = pseudo_equilibria(p)[0]
    assert p1.admissible and not p1.stable
    traj = simulate(p, cmath.exp(1j * (p1.theta + 1e-4)), 0j, 200.0)
    th = traj.theta(traj.sample(2000))
    assert np.max(np.abs([wrap_angle(t - p1.theta) for t in th])) > 0.1


def test_pseudo_equilibria_without_real_arccos_do_not_exist_with_a_reason():
    p = REF.replace(gamma=0.8)  # (gamma + mu(1 - omega^2)) / (rho sqrt(1 + mu^2)) > 1
    for pe in pseudo_equilibria(p):
        assert not pe.exists and pe.theta is None and pe.normal_force is None
        assert not pe.admissible and pe.stable is None
        assert "arccos" in pe.reason
        json.dumps(pe.to_dict(), allow_nan=False)
    for pe in pseudo_equilibria(Parameters(gamma=0.1, omega=0.8, rho=0.0, mu=0.1, d=0.5)):
        assert not pe.exists and "rho = 0" in pe.reason


def test_pseudo_equilibria_at_zero_friction_are_the_limit_and_solve_the_frictionless_balance():
    """mu = 0, where arctan(1/mu) is undefined: a defined answer, the mu -> 0+ limit, rho sin psi = gamma."""
    p0 = REF.replace(mu=0.0)
    p_small = p0.replace(mu=1e-10)
    for pe0, pes in zip(pseudo_equilibria(p0), pseudo_equilibria(p_small)):
        assert pe0.exists and math.isfinite(pe0.theta) and math.isfinite(pe0.normal_force)
        assert abs(wrap_angle(pe0.theta - pes.theta)) < 1e-8
        assert abs(p0.rho * math.sin(p0.phi - pe0.theta) - p0.gamma) < TOL
    b = boundary_equilibrium(p0)
    assert b.kind == "nonsmooth-fold" and b.partner == "P1"  # omega < 1 = omega_switch at mu = 0


# ---------------------------------------------------------------------------
# Boundary equilibrium and its bifurcation
# ---------------------------------------------------------------------------


def test_boundary_equilibrium_lies_on_the_stator_and_solves_F_equal_zero():
    rng = np.random.default_rng(9)
    n = 0
    for p in random_params(rng, 200, omega=(0.3, 1.4)):
        b = boundary_equilibrium(p)
        if b.gamma_star is None:
            assert boundary_gamma(p) is None and b.kind is None and b.reason
            assert p.rho < abs(1 - p.omega**2)
            continue
        n += 1
        pb = p.replace(gamma=b.gamma_star)
        assert abs(abs(pb.k) - 1) < TOL
        assert in_angle_range(b.theta)
        assert np.max(np.abs(polar_field(b.state, pb))) < TOL
        # gamma* from a numerical solve of |k(gamma)| = 1
        g = brentq(lambda gam: abs(p.replace(gamma=gam).k) - 1, 0.0, 10.0, xtol=1e-15)
        assert b.gamma_star == pytest.approx(g, abs=1e-12)
    assert n > 50


def test_reference_omega_076_is_a_nonsmooth_fold_with_P1():
    """MODEL.md §4: omega = 0.76 gives a non-smooth fold of x_R with x_P1 at gamma* ~ 0.072;
    both virtual below, both admissible above."""
    p = REF.replace(omega=0.76)
    b = boundary_equilibrium(p)
    assert round(b.gamma_star, 3) == 0.072
    assert b.kind == "nonsmooth-fold" and b.partner == "P1"
    assert b.coefficient > 0 and b.transversality != 0 and b.det_jacobian != 0
    for eps, admissible in ((-0.01, False), (0.01, True)):
        q = p.replace(gamma=b.gamma_star + eps)
        assert regular_equilibrium(q).admissible == admissible
        assert pseudo_equilibria(q)[0].admissible == admissible


def test_reference_omega_1_is_persistence_with_P2_at_gamma_star_rho():
    """MODEL.md §4: omega = 1 gives persistence of x_P2 into x_R at gamma* = rho."""
    p = REF.replace(omega=1.0)
    b = boundary_equilibrium(p)
    assert b.gamma_star == pytest.approx(p.rho, rel=1e-15)
    assert b.kind == "persistence" and b.partner == "P2" and b.coefficient < 0
    for eps, reg_adm in ((-0.01, False), (0.01, True)):
        q = p.replace(gamma=b.gamma_star + eps)
        assert regular_equilibrium(q).admissible == reg_adm
        assert pseudo_equilibria(q)[1].admissible == (not reg_adm)


def test_partner_coincides_with_x_R_at_gamma_star():
    """The partner is the pseudo-equilibrium equal to x_B (N = 0 there); the other one is not."""
    rng = np.random.default_rng(10)
    for p in random_params(rng, 200, omega=(0.3, 1.4)):
        b = boundary_equilibrium(p)
        if b.kind is None:
            continue
        pes = {pe.name: pe for pe in pseudo_equilibria(b.params)}
        partner = pes[b.partner]
        assert abs(wrap_angle(partner.theta - b.theta)) < 1e-7
        assert abs(partner.normal_force) < 1e-7


def test_beb_classification_predicts_admissibility_on_both_sides():
    """What the classification means: just past gamma*, x_R and its partner are admissible on the same
    side (non-smooth fold) or on opposite sides (persistence). Checked directly at gamma* +- eps."""
    rng = np.random.default_rng(11)
    counts = {"nonsmooth-fold": 0, "persistence": 0}
    for p in random_params(rng, 300, omega=(0.3, 1.4)):
        b = boundary_equilibrium(p)
        if b.kind is None or b.gamma_star < 1e-3:
            continue
        eps = 1e-5 * b.gamma_star
        same_side = []
        for s in (-1, 1):
            q = p.replace(gamma=b.gamma_star + s * eps)
            reg = regular_equilibrium(q)
            pe = {x.name: x for x in pseudo_equilibria(q)}[b.partner]
            if not pe.exists or abs(pe.normal_force) < 1e-13:
                break
            same_side.append(reg.admissible == pe.admissible)
        else:
            assert same_side == [b.kind == "nonsmooth-fold"] * 2
            counts[b.kind] += 1
    assert min(counts.values()) >= 10


def test_numerical_beb_quantities_equal_their_closed_forms():
    """-H_x F_x^-1 W = (1 + d)(1 - omega^2 - mu gamma*) / rho^2 and
    H_gamma - H_x F_x^-1 F_gamma = gamma* / rho^2 (docs/equilibria.md)."""
    rng = np.random.default_rng(12)
    for p in random_params(rng, 200, omega=(0.3, 1.4)):
        b = boundary_equilibrium(p)
        if b.gamma_star is None or b.gamma_star == 0:
            continue
        a = 1 - p.omega**2
        assert b.coefficient == pytest.approx((1 + p.d) * (a - p.mu * b.gamma_star) / p.rho**2, rel=1e-9, abs=1e-12)
        assert b.transversality == pytest.approx(b.gamma_star / p.rho**2, rel=1e-9)


def test_analytic_and_numerical_classification_agree_on_random_parameters():
    """The analytic omega-ranges and the numerical Jacobian conditions give the same type and partner
    on 400 random (omega, rho, d, mu) in (0, 1)^4 (with random phi, gamma, r_ratio)."""
    rng = np.random.default_rng(13)
    counts = {"nonsmooth-fold": 0, "persistence": 0, None: 0}
    for _ in range(400):
        p = Parameters(
            gamma=rng.uniform(0.0, 1.0),
            omega=rng.uniform(0.0, 1.0) or 0.5,
            rho=rng.uniform(0.0, 1.0) or 0.5,
            mu=rng.uniform(0.0, 1.0),
            d=rng.uniform(0.0, 1.0),
            phi=rng.uniform(-math.pi, math.pi),
            r_ratio=rng.uniform(0.0, 80.0),
        )
        b = boundary_equilibrium(p)
        ranges = beb_omega_ranges(p.rho, p.mu)
        assert b.kind == ranges.kind(p.omega) == classify_beb_analytic(p)
        assert b.partner == ranges.partner(p.omega)
        assert (b.gamma_star is not None) == (ranges.omega_min < p.omega < ranges.omega_max)
        counts[b.kind] += 1
    assert all(c >= 20 for c in counts.values()), counts


def test_analytic_ranges_beyond_unit_omega_agree_too():
    rng = np.random.default_rng(14)
    for p in random_params(rng, 300, omega=(0.5, 1.5), rho=(0.05, 1.5)):
        b = boundary_equilibrium(p)
        assert b.kind == classify_beb_analytic(p)
        assert b.partner == beb_omega_ranges(p.rho, p.mu).partner(p.omega)


def test_analytic_ranges_at_the_reference():
    r = beb_omega_ranges(3 / 7, 0.15)
    assert r.omega_min == pytest.approx(math.sqrt(1 - 3 / 7))
    assert r.omega_max == pytest.approx(math.sqrt(1 + 3 / 7))
    assert r.omega_min < 0.76 < r.omega_switch < 1.0 < r.omega_max
    assert r.kind(0.76) == "nonsmooth-fold" and r.kind(1.0) == "persistence"
    assert r.kind(0.5) is None and r.kind(1.3) is None
    assert r.nonsmooth_fold == (r.omega_min, r.omega_switch)
    assert r.persistence == (r.omega_switch, r.omega_max)
    none = beb_omega_ranges(0.0, 0.15)
    assert none.kind(1.0) is None and none.nonsmooth_fold is None and none.persistence is None


def test_degenerate_boundary_equilibria_are_unclassified_with_a_reason():
    # omega_switch: the coefficient vanishes
    rho, mu = 3 / 7, 0.15
    w = math.sqrt(1 - mu * rho / math.sqrt(1 + mu**2))
    b = boundary_equilibrium(Parameters(gamma=0.1, omega=w, rho=rho, mu=mu, d=0.9))
    assert b.gamma_star is not None and b.kind is None and b.partner is None and "degenerate" in b.reason
    # gamma* = 0: transversality fails
    b0 = boundary_equilibrium(Parameters(gamma=0.1, omega=0.75, rho=1 - 0.75**2, mu=mu, d=0.9))  # exact in binary
    assert b0.gamma_star == 0.0 and b0.kind is None and "transversality" in b0.reason


@pytest.mark.parametrize("border", ["omega_min", "omega_switch", "omega_max"])
@pytest.mark.parametrize("ulps", [-2, 0, 2])
def test_both_classifications_leave_a_border_of_the_omega_ranges_unclassified(border, ulps):
    # a border as beb_omega_ranges returns it, and a few ulps either side: the square root's rounding puts
    # omega^2 off the border, and gamma* = sqrt(rho^2 - a^2) magnifies it at the borders of existence
    ranges = beb_omega_ranges(REF.rho, REF.mu)
    omega = getattr(ranges, border)
    for _ in range(abs(ulps)):
        omega = float(np.nextafter(omega, 0.0 if ulps < 0 else 2.0))
    p = REF.replace(omega=omega)
    b = boundary_equilibrium(p)
    assert b.kind is None and ranges.kind(omega) is None and classify_beb_analytic(p) is None
    if b.gamma_star is not None:
        assert "degenerate" in b.reason
    # off the border by far more than rounding, both classify, alike
    for side in (-1.0, 1.0):
        q = REF.replace(omega=getattr(ranges, border) * (1.0 + side * 1e-6))
        assert boundary_equilibrium(q).kind == classify_beb_analytic(q)


def test_no_real_gamma_star_gives_none_and_a_reason():
    p = REF.replace(omega=0.3)
    b = boundary_equilibrium(p)
    assert b.gamma_star is None and b.theta is None and b.kind is None and b.partner is None
    assert "no real gamma*" in b.reason
    d = equilibria(p).to_dict()
    assert d["boundary"]["gamma_star"] is None
    json.dumps(d, allow_nan=False)
    b = boundary_equilibrium(p.replace(rho=0.0))
    assert b.gamma_star is None and "rho = 0" in b.reason


def test_results_are_frozen():
    eq = equilibria(REF)
    for obj in (eq, eq.regular, eq.pseudo[0], eq.boundary):
        with pytest.raises(dataclasses.FrozenInstanceError):
            obj.theta = 0.0  # type: ignore[misc]


def test_bad_input_raises_parameter_error():
    with pytest.raises(ParameterError):
        regular_equilibrium("reference")
    with pytest.raises(ParameterError, match=r"^x = \[0.0, 0.0, 0.0, 0.0\] is invalid \(r = 0.0: the polar field is "
                       "singular at r = 0\\); allowed: "):
        polar_field([0.0, 0.0, 0.0, 0.0], REF)
    with pytest.raises(ParameterError, match="rho"):
        beb_omega_ranges(-1.0, 0.1)
    with pytest.raises(ParameterError, match="mu"):
        beb_omega_ranges(0.4, float("nan"))


# ---------------------------------------------------------------------------
# Simulations near the regular equilibrium
# ---------------------------------------------------------------------------


def _convergence_cases():
    rng = np.random.default_rng(15)
    cases = [REF.replace(gamma=0.3), REF.replace(omega=0.76, gamma=0.1)]
    for p in random_params(rng, 200, gamma=(0.05, 1.5), omega=(0.2, 1.6)):
        if regular_equilibrium(p).r < 0.95 and len(cases) < 8:
            cases.append(p)
    return cases


@pytest.mark.parametrize("p", _convergence_cases())
def test_simulation_near_stable_admissible_regular_equilibrium_converges_to_it(p):
    reg = regular_equilibrium(p)
    assert reg.admissible and reg.stable
    decay = -max(z.real for z in reg.eigenvalues)
    t_end = 30.0 / decay
    delta = 0.2 * (1 - reg.r) * cmath.exp(0.7j)
    traj = simulate(p, reg.u + delta, 0.05 * delta, t_end)
    assert traj.status == "completed"
    u, du = traj.state(np.array([t_end]))
    assert abs(u[0] - reg.u) < 1e-9
    assert abs(du[0]) < 1e-9


def test_simulation_near_unstable_regular_equilibrium_leaves_it():
    p = Parameters(gamma=-0.05, omega=0.5, rho=3 / 7, mu=0.15, d=0.95, phi=0.21)
    reg = regular_equilibrium(p)
    assert reg.admissible and not reg.stable
    traj = simulate(p, reg.u + 1e-4, 0j, 400.0)
    u = traj.U(traj.sample(4000))
    assert np.max(np.abs(u - reg.u)) > 1e-2


# ---------------------------------------------------------------------------
# Branches
# ---------------------------------------------------------------------------


def test_gamma_branch_locates_the_boundary_equilibrium_exactly():
    p = REF.replace(omega=0.76)
    br = equilibrium_branches(p, "gamma", 0.0, 0.2, 101)
    gs = boundary_gamma(p)
    (beb,) = br.boundary_points
    assert beb.value == pytest.approx(gs, abs=1e-13)
    assert (beb.before, beb.after, beb.partner) == ("virtual", "admissible", "P1")
    (p1ev,) = br.select("P1", "admissibility")
    assert p1ev.value == pytest.approx(gs, abs=1e-12) and (p1ev.before, p1ev.after) == ("virtual", "admissible")
    assert gs in br.values or np.min(np.abs(br.values - gs)) < 1e-13
    assert br.partners == ("P1",)
    assert np.allclose(br.regular_r, [abs(p.replace(gamma=g).k) for g in br.values], rtol=1e-14)


def test_gamma_branch_persistence_and_pseudo_fold():
    p = REF.replace(omega=1.0)
    br = equilibrium_branches(p, "gamma", 0.01, 0.8)
    (beb,) = br.boundary_points
    assert beb.value == pytest.approx(p.rho, abs=1e-13) and beb.partner == "P2"
    (p2ev,) = br.select("P2", "admissibility")
    assert (p2ev.before, p2ev.after) == ("admissible", "virtual")
    for name in ("P1", "P2"):
        (ex,) = br.select(name, "existence")
        # P1 and P2 meet where (gamma + mu(1 - omega^2)) = rho sqrt(1 + mu^2)
        assert ex.value == pytest.approx(p.rho * math.sqrt(1 + p.mu**2) - p.mu * (1 - p.omega**2), abs=1e-12)
        assert (ex.before, ex.after) == ("exists", "absent")
        assert not br.pseudo_by_name(name).exists[br.values > ex.value + 1e-9].any()


def test_stability_changes_are_located():
    """x_R changes stability at gamma = 0, P2 at gamma = -2 mu (trace of the contact Jacobian)."""
    p = REF.replace(rho=0.9)
    br = equilibrium_branches(p, "gamma", -0.55, 0.47, 203)
    (reg,) = br.select("x_R", "stability")
    assert reg.value == pytest.approx(0.0, abs=1e-12) and (reg.before, reg.after) == ("unstable", "stable")
    (p2,) = br.select("P2", "stability")
    assert p2.value == pytest.approx(-2 * p.mu, abs=1e-12) and (p2.before, p2.after) == ("unstable", "stable")
    assert not br.select("P1", "stability")


def test_omega_and_rho_branches_locate_the_closed_form_crossings():
    p = REF
    br = equilibrium_branches(p, "omega", 0.3, 1.6)
    root = math.sqrt(p.rho**2 - p.gamma**2)
    expected = sorted([math.sqrt(1 - root), math.sqrt(1 + root)])
    got = [e.value for e in br.boundary_points]
    assert got == pytest.approx(expected, abs=1e-12)
    assert [e.partner for e in br.boundary_points] == ["P1", "P2"]
    br = equilibrium_branches(p, "rho", 0.0, 1.0)
    (beb,) = br.boundary_points
    assert beb.value == pytest.approx(math.hypot(p.gamma, 1 - p.omega**2), abs=1e-12)
    for name in ("mu", "d"):
        br = equilibrium_branches(p, name, 0.0, 1.0, 51)
        assert not br.boundary_points  # |k| does not depend on mu or d


def test_branches_reject_bad_input():
    p = REF
    with pytest.raises(ParameterError, match="phi"):
        equilibrium_branches(p, "phi", 0.0, 1.0)
    with pytest.raises(ParameterError, match="start < stop"):
        equilibrium_branches(p, "gamma", 0.2, 0.1)
    with pytest.raises(ParameterError, match="omega"):
        equilibrium_branches(p, "omega", 0.0, 1.0)
    with pytest.raises(ParameterError, match="d = "):
        equilibrium_branches(p, "d", 0.5, 1.5)
    with pytest.raises(ParameterError, match="n = "):
        equilibrium_branches(p, "gamma", 0.0, 1.0, 1)
    assert set(BRANCH_PARAMETERS) == {"gamma", "omega", "rho", "mu", "d"}


def test_equilibrium_branches_bound_their_grid():
    from rotorcontact.model.validation import MAX_EQUILIBRIUM_POINTS

    allowed = f"allowed: an integer from 2 to {MAX_EQUILIBRIUM_POINTS}"
    with pytest.raises(ParameterError, match=f"^n = {10**9} is invalid; {allowed}"):
        equilibrium_branches(REF, "gamma", 0.0, 0.2, n=10**9)


# ---------------------------------------------------------------------------
# Bad input to the fields and to the results, refused by name
# ---------------------------------------------------------------------------

X = [0.9, 0.3, 0.1, -0.4]
FIELDS = [polar_field, polar_jacobian, polar_field_gamma]
CONTACT = [normal_force, contact_field, contact_jacobian]


@pytest.mark.parametrize("params", [None, reference_machine(), {}, "REF"])
@pytest.mark.parametrize("call", [
    system_matrix, impact_direction, lambda p: friction_sign(0.1, p),
    *[lambda p, f=f: f(X, p) for f in FIELDS], *[lambda p, f=f: f(0.3, -0.2, p) for f in CONTACT],
])
def test_params_that_are_not_parameters_are_refused(call, params):
    with pytest.raises(ParameterError, match=r"^params = .* is not a Parameters object; allowed: rotorcontact\."):
        call(params)


@pytest.mark.parametrize("func", FIELDS)
@pytest.mark.parametrize("x", ["x", None, [1j, 0, 0, 0], [True, 0, 0, 0], [1.0, 0.0, 0.0], [[1.0, 0, 0, 0]],
                               [1e300] * 4, [math.nan, 0, 0, 0], [1.0, math.inf, 0, 0], [1e-13, 0, 0, 0],
                               [1.0, 0, 2e12, 0], [1.0, 0, 0, -2e12], [-1.0, 0, 0, 0]])
def test_a_polar_state_is_four_bounded_real_numbers(func, x):
    """Text, complex numbers, bools, other shapes and values where the fields overflow or are singular."""
    with pytest.raises(ParameterError, match=r"^x = .* is invalid.*; allowed: a polar state \(r, theta, rdot, "
                                             r"thetadot\) of 4 finite real numbers with 1e-12 <= r <= 1e\+12"):
        func(x, REF)


@pytest.mark.parametrize("func", CONTACT)
@pytest.mark.parametrize("theta", [math.nan, math.inf, None, [1.0], "1.0", True, 1j])
def test_the_contact_angle_is_a_finite_real_number(func, theta):
    with pytest.raises(ParameterError, match=r"^theta = .* is invalid; allowed: a finite number$"):
        func(theta, 0.0, REF)


@pytest.mark.parametrize("call", [*[lambda v, f=f: f(0.3, v, REF) for f in CONTACT], lambda v: friction_sign(v, REF),
                                  lambda v: impact_direction(REF, v)])
@pytest.mark.parametrize("thetadot", [math.nan, -math.inf, None, [0.0], "1.0", True, 1j, 2e12])
def test_the_angular_velocity_is_a_bounded_real_number(call, thetadot):
    with pytest.raises(ParameterError, match=r"^thetadot = .* is invalid; allowed: a finite number >= -1e\+12 and "
                                             r"<= 1e\+12$"):
        call(thetadot)


def test_numpy_scalars_and_integers_give_the_same_fields_to_the_bit():
    x = np.array(X)
    for func in FIELDS:
        want = func(X, REF)
        for same in (x, tuple(X), [np.float64(v) for v in X]):
            assert func(same, REF).tobytes() == want.tobytes()
    assert polar_field([1, 2, 3, 4], REF).tobytes() == polar_field([1.0, 2.0, 3.0, 4.0], REF).tobytes()
    for func in CONTACT:
        want = np.asarray(func(0.3, -0.2, REF))
        for theta, thetadot in ((np.float64(0.3), np.float64(-0.2)), (np.array(0.3), np.array(-0.2))):
            assert np.asarray(func(theta, thetadot, REF)).tobytes() == want.tobytes()
        assert np.asarray(func(np.int64(2), -1, REF)).tobytes() == np.asarray(func(2.0, -1.0, REF)).tobytes()
    assert friction_sign(np.float64(-0.5), REF) == 1.0 and friction_sign(np.int64(-2 - REF.r_ratio), REF) == -1.0
    assert impact_direction(REF, np.array(-0.2)).tobytes() == impact_direction(REF, -0.2).tobytes()


def test_the_omega_of_the_analytic_ranges_is_that_of_the_parameters():
    ranges = beb_omega_ranges(REF.rho, REF.mu)
    for omega in (-1.0, 0.0, math.nan, 2e6, "0.76", True, None):
        for call in (ranges.kind, ranges.partner):
            with pytest.raises(ParameterError, match=r"^omega = .* is invalid; allowed: a finite number > 0 and "
                                                     r"<= 1e\+06$"):
                call(omega)
    assert ranges.kind(np.float64(0.76)) == ranges.kind(0.76) == "nonsmooth-fold"
    assert ranges.partner(np.array(1.0)) == "P2"


@pytest.mark.parametrize("rho, mu, name", [(1e300, 0.15, "rho"), (-1.0, 0.15, "rho"), (0.4, 2e6, "mu"),
                                           (0.4, math.nan, "mu"), (True, 0.15, "rho"), (0.4, "0.1", "mu")])
def test_the_analytic_ranges_take_rho_and_mu_in_their_ranges(rho, mu, name):
    with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: a finite number >= 0 and <= 1e\+06$"):
        beb_omega_ranges(rho, mu)
    assert beb_omega_ranges(np.float64(REF.rho), np.int64(0)) == beb_omega_ranges(REF.rho, 0.0)


def test_events_are_selected_by_known_branches_and_kinds_only():
    br = equilibrium_branches(REF.replace(omega=0.76), "gamma", 0.0, 0.2, 21)
    assert br.select() == br.events and br.select("x_R", "admissibility") == br.boundary_points
    for branch in (1, "x", "R", ["x_R"]):
        with pytest.raises(ParameterError, match=r"^branch = .* is invalid; allowed: 'x_R', 'P1', 'P2' or None$"):
            br.select(branch=branch)
    for kind in (["R"], "admissible", 0):
        with pytest.raises(ParameterError, match=r"^kind = .* is invalid; allowed: 'admissibility', 'stability', "
                                                 r"'existence' or None$"):
            br.select(kind=kind)


def test_pseudo_equilibria_are_looked_up_by_name():
    eq = equilibria(REF)
    br = equilibrium_branches(REF, "gamma", 0.0, 0.2, 21)
    for owner in (eq, br):
        assert owner.pseudo_by_name("P2") is owner.pseudo[1]
        for name in (None, "P3", 1, "p1"):
            with pytest.raises(ParameterError, match=r"^name = .* is invalid; allowed: 'P1', 'P2'$"):
                owner.pseudo_by_name(name)
