"""Local analysis at a boundary equilibrium: claims checked against independent global computations.

* The generic numerics (e^{-AT} by Cayley-Hamilton, zeros of F1 on a grid) reproduce the rotor's
  closed-form a_ij and guaranteed zeros of `impactmap`.
* For the rotor, the first-order slopes equal the slopes of the global branches at gamma*, which
  are obtained by Richardson-extrapolated central differences of `one_impact_orbits` at gamma* +- h.
* The error of the first-order estimate is O(eps^2) (fitted order over a decade of eps).
* A second, non-rotor instance: its global fixed points (the fixed-point equations solved without
  expansion) are confirmed by an independent event-driven simulation with solve_ivp, and the local
  estimate matches them in the same way.
* The NSFH criterion: the small orbits are admissible on the predicted side of eps = 0 only.
"""

from __future__ import annotations

import cmath
import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import solve_ivp

from rotorcontact import ParameterError
from rotorcontact.analysis.equilibria import boundary_gamma
from rotorcontact.maps.impact_map import a_matrix as rotor_a_matrix
from rotorcontact.maps.impact_map import f1_zeros as rotor_f1_zeros
from rotorcontact.maps.impact_map import one_impact_orbits
from rotorcontact.analysis.local import (
    LinearImpactingSystem,
    LocalComparison,
    compare_local_global,
    expm2,
    global_fixed_points,
    local_analysis,
)
from reference_parameters import REF


DECADE = np.geomspace(1e-3, 1e-2, 5)
QUANTITIES = ("theta", "rdot", "thetadot")


def _wrap(x):
    return math.remainder(x, 2.0 * math.pi)


def _fitted_order(comp, label, quantity):
    """Slope of log|local - global| against log|eps| (least squares), from the table's raw values."""
    eps, err = [], []
    for row in comp.select(label):
        loc, glo = getattr(row, f"{quantity}_local"), getattr(row, f"{quantity}_global")
        diff = _wrap(loc - glo) if quantity == "theta" else loc - glo
        eps.append(abs(row.eps))
        err.append(abs(diff))
    order = float(np.polyfit(np.log(eps), np.log(err), 1)[0])
    assert comp.error_order(label, quantity) == pytest.approx(order, rel=1e-12)
    return order


@pytest.fixture(scope="module")
def rotor():
    return REF


@pytest.fixture(scope="module")
def rotor_analysis(rotor):
    return local_analysis(rotor)


@pytest.fixture(scope="module")
def general():
    """A non-rotor instance: complex alpha, beta with unequal decay rates, sigma != 1, Gamma1 != 0.

    Its first pair of zeros of F1 has Re(q a12) > 0 at T0,1,a (the small orbit is the larger root,
    B1,c, admissible where the equilibrium is virtual) and Re(q a12) < 0 at T0,1,b (B1,b, on the
    side of the admissible equilibrium): both cases of the criterion.
    """
    return LinearImpactingSystem.on_boundary(
        0.18 + 1.9j, 1.7 + 0.3j, 0.7, mu=0.3, d=0.8, sigma=0.8,
        alpha1=0.5 - 0.2j, beta1=0.4 + 0.3j, Gamma1=0.1 - 0.2j,
    )


@pytest.fixture(scope="module")
def general_analysis(general):
    return local_analysis(general)


# ---------------------------------------------------------------------------
# The system and its validation
# ---------------------------------------------------------------------------


def test_rotor_is_an_instance_of_the_general_system(rotor):
    s = LinearImpactingSystem.from_parameters(rotor)
    gs = boundary_gamma(rotor)
    for eps in (0.0, 0.013, -0.02):
        g = gs + eps
        alpha, beta, big_gamma = s.coefficients(eps)
        assert alpha == pytest.approx(complex(g, 2.0), abs=1e-15)
        assert beta == pytest.approx(complex(rotor.omega**2 - 1.0, g), abs=1e-15)
        assert big_gamma == pytest.approx(rotor.rho * cmath.exp(1j * rotor.phi), abs=1e-15)
        assert s.equilibrium(eps) == pytest.approx(rotor.replace(gamma=g).k, rel=1e-14)
    assert abs(s.z0) == pytest.approx(1.0, rel=1e-12)
    # the shift of the equilibrium: d|k|/dgamma = -gamma*/rho^2, dArg k/dgamma = (1 - omega^2)/rho^2
    an = local_analysis(s)
    assert an.radial_shift == pytest.approx(-gs / rotor.rho**2, rel=1e-12)
    assert an.tangential_shift == pytest.approx((1.0 - rotor.omega**2) / rotor.rho**2, rel=1e-12)
    assert an.equilibrium_side == 1


def test_invalid_systems_are_rejected():
    with pytest.raises(ParameterError, match="not on the boundary"):
        LinearImpactingSystem(0.2 + 1j, 1.0, 1.1, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match="not stable"):
        LinearImpactingSystem.on_boundary(-0.1 + 0j, 1.0, 0.3, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match="not stable"):
        LinearImpactingSystem.on_boundary(0.0, 1.0, 0.3, mu=0.1, d=0.9)  # undamped
    with pytest.raises(ParameterError, match="beta0 = 0"):
        LinearImpactingSystem(0.2, 0.0, 0.0, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match="not finite"):
        LinearImpactingSystem.on_boundary(complex(math.nan, 0.0), 1.0, 0.3, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match="d = 1.5"):
        LinearImpactingSystem.on_boundary(0.2, 1.0, 0.3, mu=0.1, d=1.5)
    with pytest.raises(ParameterError, match="sigma"):
        LinearImpactingSystem.on_boundary(0.2, 1.0, 0.3, mu=0.1, d=0.5, sigma=0.0)


def test_rotor_without_a_stable_boundary_equilibrium_is_rejected(rotor):
    with pytest.raises(ParameterError, match="no real gamma"):
        LinearImpactingSystem.from_parameters(rotor.replace(omega=0.3))
    with pytest.raises(ParameterError, match="no real gamma"):
        local_analysis(rotor.replace(rho=0.0))
    # rho = |1 - omega^2| exactly: gamma* = 0, an undamped boundary equilibrium
    with pytest.raises(ParameterError, match="not asymptotically stable"):
        LinearImpactingSystem.from_parameters(rotor.replace(omega=0.5, rho=0.75))


# ---------------------------------------------------------------------------
# Generic numerics against the rotor's closed forms
# ---------------------------------------------------------------------------


def test_expm2_matches_scipy_expm_including_near_double_eigenvalues():
    rng = np.random.default_rng(7)
    mats = [(rng.standard_normal((2, 2)) + 1j * rng.standard_normal((2, 2))) * s for s in (1e-8, 1e-3, 0.5, 3.0)]
    mats.append(np.array([[1.0, 1.0], [0.0, 1.0]], dtype=complex))  # a Jordan block
    mats.append(np.array([[0.3j, 1.0], [1e-14, 0.3j]], dtype=complex))  # nearly defective
    for m in mats:
        ref = scipy.linalg.expm(m)
        assert np.max(np.abs(expm2(m) - ref)) <= 1e-14 * max(1.0, np.max(np.abs(ref)))
    stacked = expm2(np.stack(mats))
    assert np.allclose(stacked, np.stack([scipy.linalg.expm(m) for m in mats]), rtol=1e-14, atol=1e-14)


def _f1_mpmath(system, T):
    """F1(T) = 1 + Re(q a22), a = (e^{-AT} - I)^{-1}, at 50 digits."""
    import mpmath

    with mpmath.workdps(50):
        a = mpmath.matrix([[0, 1], [-mpmath.mpc(system.beta0), -mpmath.mpc(system.alpha0)]])
        inv = (mpmath.expm(-a * mpmath.mpf(T)) - mpmath.eye(2)) ** -1
        return float(1 + mpmath.re(mpmath.mpc(system.q) * inv[1, 1]))


@pytest.mark.parametrize("which", ["rotor", "general"])
def test_f1_matches_mpmath_down_to_tiny_periods(rotor, general, which):
    # e^{-AT} - I has an entry of order T^2: at small T it must not come from a difference of O(1) terms
    system = LinearImpactingSystem.from_parameters(rotor) if which == "rotor" else general
    periods = np.array([1e-10, 1e-8, 3e-8, 1e-7, 1e-5, 1e-3, 0.3, 0.99, 1.0, 1.01, 2.5, 7.0])
    ref = np.array([_f1_mpmath(system, t) for t in periods])
    scale = np.maximum(1.0, np.abs(ref))
    assert np.all(np.abs(system.f1(periods) - ref) <= 1e-13 * scale)
    assert all(abs(system.f1(float(t)) - r) <= 1e-13 * s for t, r, s in zip(periods, ref, scale))


def test_no_orbit_is_found_below_the_smallest_period_of_f1_s_first_zero(rotor):
    # F1 stays near (1 - d)/2 > 0 for small T at gamma*: a search up to 1e-4 or 2e-5 finds nothing
    system = LinearImpactingSystem.from_parameters(rotor)
    for t_max in (1e-4, 2e-5):
        assert system.f1_zeros(t_max) == ()
        assert system.fixed_points(0.0, t_max) == ()


def test_generic_a_matrix_matches_the_rotor_closed_form(rotor):
    s = LinearImpactingSystem.from_parameters(rotor)
    gs = boundary_gamma(rotor)
    for eps in (0.0, 0.05):
        p = rotor.replace(gamma=gs + eps)
        for t in (0.3, 0.6679, 3.07, 9.5):
            assert np.allclose(s.a_matrix(t, eps), rotor_a_matrix(p, t), rtol=1e-12, atol=1e-12)


def test_periods_beyond_the_accurate_range_of_e_minus_at_are_refused(general):
    from rotorcontact.maps.impact_map import MAX_GROWTH

    # the largest |Re lambda| of A, from numpy, sets the limit as period_limit does for the rotor
    growth = float(np.max(np.abs(np.linalg.eigvals(general.matrix(0.0)).real)))
    limit = MAX_GROWTH / growth
    assert np.all(np.isfinite(general.a_matrix(0.999 * limit)))
    for call in (lambda T: general.a_matrix(T), lambda T: general.f1(T), lambda T: general.f1_derivatives(T),
                 lambda T: general.f1_zeros(T)):
        with pytest.raises(ParameterError, match=rf"allowed: .* <= {limit:.6g}$"):
            call(limit * (1 + 1e-9))
    with pytest.raises(ParameterError, match=r"^max\(T\) = "):
        general.f1([1.0, 1.001 * limit])
    for bad in (True, "3", [1.0, True], None, [1.0, -1.0], [[1.0], [1.0, 2.0]]):
        with pytest.raises(ParameterError, match="^T = "):
            general.a_matrix(bad)


@pytest.mark.parametrize("omega, t_max", [(0.76, 12.0), (0.7565, 40.0)])
def test_generic_f1_zeros_match_the_guaranteed_isolation(rotor, omega, t_max):
    p = rotor.replace(omega=omega)
    gs = boundary_gamma(p)
    mine = LinearImpactingSystem.from_parameters(p).f1_zeros(t_max)
    ref = rotor_f1_zeros(p.replace(gamma=gs), t_max)
    assert len(mine) == len(ref) >= 2
    for a, b in zip(mine, ref):
        assert (a.n, a.kind) == (b.n, b.kind)
        # a zero is located to rounding of F1 over its slope
        assert a.T == pytest.approx(b.T, abs=1e-12 / abs(b.slope))
        assert a.slope == pytest.approx(b.slope, rel=1e-9)


# ---------------------------------------------------------------------------
# Rotor: local slopes against the global branches
# ---------------------------------------------------------------------------


def _central(fun, h):
    """Central difference (fun(h) - fun(-h)) / 2h of a function of eps."""
    return (fun(h) - fun(-h)) / (2.0 * h)


def _global_slopes(model, label, h):
    """Slopes at eps = 0 of the global branch `label` by Richardson extrapolation of central differences.

    D(h) = x' + c h^2 + O(h^4), so R = (4 D(h/2) - D(h)) / 3 = x' + O(h^4), and
    E = |D(h) - D(h/2)| / 3 estimates the truncation error c h^2 / 4 of D(h/2).
    Returns {quantity: (R, E)}.
    """
    cache = {}

    def orbit(eps):
        if eps not in cache:
            cache[eps] = {o.label: o for o in global_fixed_points(model, eps)}[label]
        return cache[eps]

    out = {}
    for q in QUANTITIES + ("T",):
        if q == "theta":
            def fun(e):
                return _wrap(orbit(e).theta - orbit(0.0).theta)
        else:
            def fun(e, q=q):
                return getattr(orbit(e), q)
        d1, d2 = _central(fun, h), _central(fun, h / 2.0)
        out[q] = ((4.0 * d2 - d1) / 3.0, abs(d1 - d2) / 3.0)
    return out


@pytest.mark.parametrize("label", ["B1,a", "B1,b"])
def test_rotor_local_slopes_equal_the_global_slopes_at_gamma_star(rotor, rotor_analysis, label):
    """The local slopes lie within the O(h^2) truncation error of the global central differences."""
    loc = rotor_analysis.orbit(label)
    # at gamma* the global small orbit sits on the boundary equilibrium with period T0
    at_star = {o.label: o for o in one_impact_orbits(rotor.replace(gamma=boundary_gamma(rotor)))}[label]
    # the small root is (1 - |k|^2) / (2 |Re q a12|) with |1 - |k|^2| a few ulps at gamma*
    assert abs(at_star.rdot) <= 1e-14 and abs(at_star.thetadot) <= 1e-14
    assert loc.T == pytest.approx(at_star.T, abs=1e-11)
    assert loc.theta0 == pytest.approx(at_star.theta, abs=1e-12)
    slopes = _global_slopes(rotor, label, h=1e-3)
    for q, mine in (("rdot", loc.rdot_slope), ("thetadot", loc.thetadot_slope),
                    ("theta", loc.theta_slope), ("T", loc.T_slope)):
        ref, trunc = slopes[q]
        assert trunc < 1e-4 * (1.0 + abs(ref))  # the branch is smooth on the difference stencil
        assert abs(mine - ref) <= trunc, (q, mine, ref, trunc)


@pytest.fixture(scope="module")
def rotor_branches(rotor):
    """The global branches through gamma* by pseudo-arclength continuation."""
    from rotorcontact.continuation.branches import orbit_branches

    gs = boundary_gamma(rotor)
    return orbit_branches(rotor, "gamma", gs - 0.01, gs + 0.01, t_max=12.0, n_seeds=3)


def test_rotor_local_slopes_equal_the_tangent_of_the_continued_branches(rotor, rotor_analysis, rotor_branches):
    """At the located NSFH point of each continued branch, the tangent of the curve R(T, rdot; gamma) = 0
    gives d(rdot)/d(gamma) and dT/d(gamma).

    The gamma-column of the continuation Jacobian is a central difference with relative step h = 1e-6:
    truncation O(h^2) ~ 1e-12, rounding ~ eps_mach / h ~ 2e-10 relative, amplified in the null vector by
    at most the condition number of the (T, rdot) block. The tolerance is 10 times that rounding bound.
    """
    from rotorcontact.continuation.engine import null_vector
    from rotorcontact.maps.orbit_system import OneImpactSystem

    gs = boundary_gamma(rotor)
    system = OneImpactSystem(rotor, "gamma", fd_step=1e-6)
    events = {e.orbits[0]: e for e in rotor_branches.select(type="nsfh")}
    assert set(events) == {"B1,a", "B1,b"}
    for label, ev in events.items():
        loc = rotor_analysis.orbit(label)
        assert ev.value == pytest.approx(gs, abs=1e-11)
        assert ev.T == pytest.approx(loc.T, abs=1e-11)
        jac = system.jacobian(np.array([ev.T, ev.rdot, ev.value]))
        tangent = null_vector(jac)
        tol = 10.0 * (2.2e-16 / 1e-6) * np.linalg.cond(jac[:, :2])
        assert tangent[1] / tangent[2] == pytest.approx(loc.rdot_slope, rel=tol)
        assert tangent[0] / tangent[2] == pytest.approx(loc.T_slope, rel=tol)


@pytest.mark.parametrize("label", ["B1,a", "B1,b"])
def test_rotor_local_estimate_against_the_continued_branch_is_second_order(rotor, rotor_analysis,
                                                                          rotor_branches, label):
    """On both sides of gamma*, at the continuation's own points with 1e-3 <= |eps| <= 1e-2."""
    gs = boundary_gamma(rotor)
    branch = rotor_branches.branch(label)
    loc = rotor_analysis.orbit(label)
    eps = branch.values - gs
    for side in (1.0, -1.0):
        sel = (np.sign(eps) == side) & (np.abs(eps) >= 1e-3) & (np.abs(eps) <= 1e-2)
        assert sel.sum() >= 4
        est = np.array([loc.estimate(e) for e in eps[sel]])
        for col, q in enumerate(("T",) + QUANTITIES):
            diff = est[:, col] - getattr(branch, q)[sel]
            if q == "theta":
                diff = np.remainder(diff + np.pi, 2.0 * np.pi) - np.pi
            order = np.polyfit(np.log(np.abs(eps[sel])), np.log(np.abs(diff)), 1)[0]
            assert 1.8 <= order <= 2.2, (label, side, q, order)
        # admissible exactly on the predicted side
        assert np.all(branch.admissible[sel] == (side * loc.side > 0))


def test_rotor_local_estimate_error_is_second_order(rotor):
    comp = compare_local_global(rotor, DECADE, labels=("B1,a", "B1,b"))
    assert comp.offset == pytest.approx(boundary_gamma(rotor))
    for label in ("B1,a", "B1,b"):
        rows = comp.select(label)
        assert len(rows) == len(DECADE) and all(r.rdot_global is not None for r in rows)
        for q in QUANTITIES + ("T",):
            order = _fitted_order(comp, label, q)
            assert 1.8 <= order <= 2.2, (label, q, order)
        # and the estimate is useful: relative error of rdot about eps (<= 20% at eps = 0.01)
        worst = rows[-1]
        assert worst.error("rdot") <= 0.2 * abs(worst.rdot_global)


def test_rotor_nsfh_criterion(rotor, rotor_analysis):
    """B1,a and B1,b are admissible exactly for gamma > gamma*, together with x_R (MODEL.md §5)."""
    gs = boundary_gamma(rotor)
    for o in rotor_analysis.orbits:
        assert o.label in ("B1,a", "B1,b") and o.side == 1 and o.qa12.real < 0
    for eps in (1e-3, 1e-2, -1e-3, -1e-2):
        glob = {o.label: o for o in global_fixed_points(rotor, eps)}
        for o in rotor_analysis.orbits:
            assert glob[o.label].admissible == (eps * o.side > 0)
            assert math.copysign(1.0, glob[o.label].rdot) == math.copysign(1.0, eps * o.rdot_slope)
        x_r_admissible = abs(rotor.replace(gamma=gs + eps).k) < 1.0
        assert x_r_admissible == (eps * rotor_analysis.equilibrium_side > 0)


# ---------------------------------------------------------------------------
# A second instance of the general system
# ---------------------------------------------------------------------------


def _polar(system, z, dz):
    e = z / abs(z)
    w = e.conjugate() * dz
    return cmath.phase(z), w.real, w.imag / abs(z)


def _first_impact(ref, system, eps, z, dz, t_end):
    """Event-driven flight: the first outward crossing of |z| = sigma after t = 0 (solve_ivp, DOP853)."""
    def hit(t, y):
        return y[0] ** 2 + y[1] ** 2 - system.sigma**2

    hit.terminal = True
    hit.direction = 1.0
    alpha, beta, big_gamma = system.coefficients(eps)
    sol = solve_ivp(ref.linear_rhs(big_gamma, alpha, beta), (0.0, t_end), [z.real, z.imag, dz.real, dz.imag], method="DOP853",
                    rtol=1e-12, atol=1e-13, events=hit)
    assert sol.success
    if not sol.t_events[0].size:
        return None
    y = sol.y_events[0][0]
    return float(sol.t_events[0][0]), complex(y[0], y[1]), complex(y[2], y[3])


def _reset(system, z, dz):
    """The reset law as stated: z'+ = z'- - (1 + d)(1 + i mu) Re(conj(z) z'-) z / |z|^2."""
    q = (1.0 + system.d) * complex(1.0, system.mu)
    return dz - q * (z.conjugate() * dz).real * z / abs(z) ** 2


def test_general_fixed_points_are_periodic_orbits_of_the_simulated_system(ref, general):
    """Each fixed point, started just after its impact, returns to the same impact state after T.

    Admissible orbits whose flight stays inside are run event-driven (first crossing of the boundary,
    then the reset, then the second crossing); the others (virtual, or crossing the boundary in
    flight) by the exact flight over the time T (matrix exponential), which checks the equations.
    """
    event_checked = set()
    for eps in (-0.01, -0.003, 0.003, 0.01):
        fps = general.fixed_points(eps)
        assert {o.label for o in fps} == {"B1,a", "B1,b", "B1,c", "B1,d"}
        for fp in fps:
            z = general.sigma * cmath.exp(1j * fp.theta)
            dz_minus = cmath.exp(1j * fp.theta) * complex(fp.rdot, general.sigma * fp.thetadot)
            dz = _reset(general, z, dz_minus)
            state = None
            if fp.admissible:
                hit = _first_impact(ref, general, eps, z, dz, 3.0 * fp.T)
                if hit is not None and abs(hit[0] - fp.T) < 1e-6:
                    tau, z1, dz1 = hit
                    assert tau == pytest.approx(fp.T, abs=1e-8)
                    state = (z1, dz1)
                    # one more impact: the orbit repeats
                    hit2 = _first_impact(ref, general, eps, z1, _reset(general, z1, dz1), 3.0 * fp.T)
                    assert hit2 is not None and hit2[0] == pytest.approx(fp.T, abs=1e-8)
                    assert abs(hit2[1] - z1) < 1e-8 and abs(hit2[2] - dz1) < 1e-8
                    event_checked.add((fp.label, math.copysign(1.0, eps)))
            if state is None:
                alpha, beta, big_gamma = general.coefficients(eps)
                zeq = big_gamma / beta
                mat = np.array([[0.0, 1.0], [-beta, -alpha]], dtype=complex)
                w = scipy.linalg.expm(mat * fp.T) @ np.array([z - zeq, dz])
                state = (w[0] + zeq, w[1])
            theta, rdot, thetadot = _polar(general, *state)
            assert abs(state[0]) == pytest.approx(general.sigma, abs=1e-8)
            assert abs(_wrap(theta - fp.theta)) < 1e-8
            assert rdot == pytest.approx(fp.rdot, abs=1e-8)
            assert thetadot == pytest.approx(fp.thetadot, abs=1e-8)
    # the small orbits are real impacting orbits on their side, checked event by event
    assert {("B1,c", -1.0), ("B1,b", 1.0)} <= event_checked


def test_general_small_orbits_and_their_labels(general, general_analysis):
    an = general_analysis
    assert [o.label for o in an.orbits] == ["B1,c", "B1,b"]
    small_c, small_b = an.orbits
    assert small_c.qa12.real > 0 and small_c.side == -1
    assert small_b.qa12.real < 0 and small_b.side == 1
    assert an.equilibrium_side == 1 and an.radial_shift < 0
    glob = {o.label: o for o in general.fixed_points(0.0)}
    # at eps = 0: the small roots vanish, the other roots are -2 sigma Re(q a12) / |q a12|^2
    assert abs(glob["B1,c"].rdot) < 1e-12 and abs(glob["B1,b"].rdot) < 1e-12
    for small, other in ((small_c, "B1,a"), (small_b, "B1,d")):
        assert glob[other].rdot == pytest.approx(-2.0 * general.sigma * small.qa12.real / abs(small.qa12) ** 2,
                                                 rel=1e-10)
        assert glob[small.label].theta == pytest.approx(general.psi, abs=1e-12)


@pytest.mark.parametrize("label", ["B1,c", "B1,b"])
def test_general_local_slopes_equal_the_global_slopes(general, general_analysis, label):
    loc = general_analysis.orbit(label)
    slopes = _global_slopes(general, label, h=1e-3)
    for q, mine in (("rdot", loc.rdot_slope), ("thetadot", loc.thetadot_slope),
                    ("theta", loc.theta_slope), ("T", loc.T_slope)):
        ref, trunc = slopes[q]
        assert trunc < 1e-4 * (1.0 + abs(ref))
        assert abs(mine - ref) <= trunc, (q, mine, ref, trunc)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_general_local_estimate_error_is_second_order(general, sign):
    comp = compare_local_global(general, sign * DECADE, labels=("B1,c", "B1,b"))
    for label in ("B1,c", "B1,b"):
        for q in QUANTITIES + ("T",):
            order = _fitted_order(comp, label, q)
            assert 1.8 <= order <= 2.2, (label, q, order)


def test_general_nsfh_criterion(general, general_analysis):
    for eps in (1e-3, 1e-2, -1e-3, -1e-2):
        glob = {o.label: o for o in general.fixed_points(eps)}
        for o in general_analysis.orbits:
            assert glob[o.label].admissible == (eps * o.side > 0), (o.label, eps)
        assert (abs(general.equilibrium(eps)) < general.sigma) == (eps * general_analysis.equilibrium_side > 0)


# ---------------------------------------------------------------------------
# Results and their contracts
# ---------------------------------------------------------------------------


def test_estimate_and_plain_data(rotor_analysis):
    o = rotor_analysis.orbit("B1,a")
    t, theta, rdot, thetadot = o.estimate(0.0)
    assert (t, theta, rdot, thetadot) == (o.T, o.theta0, 0.0, 0.0)
    t, theta, rdot, thetadot = o.estimate(2e-3)
    assert rdot == pytest.approx(2e-3 * o.rdot_slope) and thetadot == pytest.approx(2e-3 * o.thetadot_slope)
    assert -math.pi < theta <= math.pi
    assert set(o.to_dict()) == {"label", "T", "rdot_slope", "thetadot_slope", "theta_slope"}
    with pytest.raises(ParameterError, match="no local orbit"):
        rotor_analysis.orbit("B7,a")
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.T = 1.0  # type: ignore[misc]


def test_comparison_table_and_bad_input(rotor, general):
    comp = compare_local_global(rotor, [1e-3, 2e-3], labels=("B1,b",))
    text = comp.table()
    assert "B1,b" in text and len(text.splitlines()) == 4
    row = comp.rows[0].to_dict()
    assert row["rdot_error"] == pytest.approx(abs(row["rdot_local"] - row["rdot_global"]))
    with pytest.raises(ParameterError, match="fewer than two"):
        compare_local_global(rotor, [1e-3], labels=("B1,b",)).error_order("B1,b", "rdot")
    with pytest.raises(ParameterError, match=r"^labels = \('B1,a',\) is invalid \(no local orbit 'B1,a'\); allowed: "):
        compare_local_global(general, [1e-3], labels=("B1,a",))
    with pytest.raises(ParameterError, match="quantity"):
        comp.rows[0].error("r")
    with pytest.raises(ParameterError, match="t_max"):
        general.f1_zeros(-1.0)


@pytest.mark.parametrize("epsilons", [0.001, None, ["0.001"], [], [0.001] * 1001])
def test_compare_local_global_refuses_a_malformed_or_huge_list_of_eps(rotor, epsilons):
    with pytest.raises(ParameterError, match=r"^epsilons = .* allowed: a list of 1 to 1000 numbers$"):
        compare_local_global(rotor, epsilons)


def test_compare_local_global_takes_one_label_as_a_label(rotor):
    one = compare_local_global(rotor, [0.001], labels="B1,a")
    assert [r.label for r in one.rows] == ["B1,a"]
    assert one.rows == compare_local_global(rotor, [0.001], labels=["B1,a"]).rows
    with pytest.raises(ParameterError, match=r"^labels = 3 is invalid"):
        compare_local_global(rotor, [0.001], labels=3)


# ---------------------------------------------------------------------------
# Bad input, refused by name
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("m", [None, "x", 1.0, np.zeros(2), np.zeros((3, 3)), np.zeros((2, 2, 3)),
                               [[math.nan, 0], [0, 0]], [[True, 0], [0, 0]], [[1.0, 0.0], [0.0]]])
def test_expm2_takes_finite_two_by_two_matrices(m):
    with pytest.raises(ParameterError, match=r"^m = .* is invalid; allowed: finite \(complex\) 2x2 matrices, an array "
                                             r"of shape \(\.\.\., 2, 2\)$"):
        expm2(m)


def test_expm2_refuses_a_matrix_whose_exponential_overflows():
    for m in (1e300 * np.eye(2), [[800.0, 0.0], [0.0, 0.0]], np.stack([np.eye(2), [[0.0, 1e200], [1e200, 0.0]]])):
        with pytest.raises(ParameterError, match=r"^m = .* is invalid: e\^m overflows; allowed: "):
            expm2(m)
    assert np.all(np.isfinite(expm2([[300.0, 0.0], [0.0, -300.0]])))
    assert expm2(np.zeros((0, 2, 2))).shape == (0, 2, 2)


def test_expm2_takes_real_lists_and_numpy_scalars_as_complex_matrices():
    m = [[0.1, 1.0], [-2.0, -0.3]]
    want = expm2(np.array(m, dtype=complex))
    assert expm2(m).tobytes() == want.tobytes()
    assert expm2([[np.float64(v) for v in row] for row in m]).tobytes() == want.tobytes()
    assert expm2([[1, 2], [3, 4]]).tobytes() == expm2([[1.0, 2.0], [3.0, 4.0]]).tobytes()


@pytest.mark.parametrize("name, value", [("alpha0", 1e300 + 0j), ("beta0", complex(0.0, 2e7)), ("alpha1", 1.1e7),
                                         ("beta1", (0.0, -1e300)), ("Gamma1", 1e300j)])
def test_coefficients_are_bounded(name, value):
    args = dict(alpha0=0.2 + 1j, beta0=1.0, psi=0.3, mu=0.1, d=0.9) | {name: value}
    with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: a complex number with \|{name}\| "
                                             r"<= 1e\+07 \("):
        LinearImpactingSystem.on_boundary(**args)


def test_the_rotor_at_the_largest_parameters_is_within_the_bounds(rotor):
    big = rotor.replace(rho=1e6, omega=1.0, mu=1e6)
    s = LinearImpactingSystem.from_parameters(big)
    assert abs(s.alpha0) > 1e6 and abs(s.beta0) == pytest.approx(1e6) and abs(s.Gamma0) == pytest.approx(1e6)


def test_gamma0_mu_and_sigma_are_bounded_too():
    with pytest.raises(ParameterError, match=r"^alpha0 = \(1e\+300\+0j\) is invalid; allowed: "):
        LinearImpactingSystem(1e300 + 0j, 1.0, 1.0, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match=r"^Gamma0 = \(1e\+300\+0j\) is invalid; allowed: "):
        LinearImpactingSystem(0.2 + 1j, 1.0, 1e300 + 0j, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match=r"^mu = 1e\+300 is out of range; allowed: \[0, 1e\+06\]"):
        LinearImpactingSystem.on_boundary(0.2 + 1j, 1.0, 0.3, mu=1e300, d=0.9)
    with pytest.raises(ParameterError, match=r"^sigma = 1e\+300 is out of range; allowed: \(0, 1e\+06\]"):
        LinearImpactingSystem.on_boundary(0.2 + 1j, 1.0, 0.3, mu=0.1, d=0.9, sigma=1e300)


def test_an_unstable_or_off_boundary_system_is_refused_by_name():
    with pytest.raises(ParameterError, match=r"^alpha0 = \(-0.1\+0j\) is invalid with beta0 = \(1\+0j\): A0 has "
                                             r"eigenvalues .*, so the boundary equilibrium is not stable; allowed: "):
        LinearImpactingSystem.on_boundary(-0.1 + 0j, 1.0, 0.3, mu=0.1, d=0.9)
    with pytest.raises(ParameterError, match=r"^Gamma0 = \(1.1\+0j\) is invalid: \|Gamma0 / beta0\| = 1.1 is not "
                                             r"sigma = 1.0, the equilibrium is not on the boundary; allowed: "):
        LinearImpactingSystem(0.2 + 1j, 1.0, 1.1, mu=0.1, d=0.9)


def test_an_empty_array_of_periods_gives_an_empty_result(general):
    assert general.f1([]).shape == (0,) and general.f1(np.array([])).dtype == float
    assert general.a_matrix([]).shape == (0, 2, 2)
    assert general.f1(np.zeros((2, 0))).shape == (2, 0)


def test_periods_given_as_numpy_scalars_give_the_same_values(general):
    assert general.f1(np.float64(2.0)) == general.f1(2.0) and general.f1(np.array(2.0)) == general.f1(2.0)
    assert general.f1(np.int64(2)) == general.f1(2.0)
    assert general.a_matrix(np.float64(2.0)).tobytes() == general.a_matrix(2.0).tobytes()


@pytest.fixture(scope="module")
def comparison(rotor):
    return compare_local_global(rotor, [1e-3, 2e-3])


@pytest.mark.parametrize("label", [None, 1, "zz", "B7,a", ["B1,a"]])
def test_orbits_and_rows_are_selected_by_known_labels(rotor_analysis, comparison, label):
    allowed = r"allowed: 'B1,a', 'B1,b'$"
    with pytest.raises(ParameterError, match=rf"^label = .* is invalid \(no local orbit has this label\); {allowed}"):
        rotor_analysis.orbit(label)
    with pytest.raises(ParameterError, match=rf"^label = .* is invalid \(no local orbit has this label\); {allowed}"):
        comparison.select(label)
    with pytest.raises(ParameterError, match=rf"^label = .* is invalid \(no local orbit has this label\); {allowed}"):
        comparison.error_order(label, "rdot")


def test_labels_and_quantities_that_are_known_still_work(rotor_analysis, comparison):
    assert rotor_analysis.orbit("B1,b") is rotor_analysis.orbits[1]
    assert [r.eps for r in comparison.select("B1,a")] == [1e-3, 2e-3]
    with pytest.raises(ParameterError, match=r"^quantity = 'zz' is invalid; allowed: 'T', 'theta', 'rdot', "
                                             r"'thetadot'$"):
        comparison.error_order("B1,a", "zz")
    empty = LocalComparison(analysis=rotor_analysis, rows=(), offset=0.0)
    with pytest.raises(ParameterError, match=r"^label = 'B1,a' is invalid .*; allowed: none"):
        empty.select("B1,a")
