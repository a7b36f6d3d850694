"""The impact map P_I, F1 and the orbits with one impact per period (MODEL.md §5).

Each test states a claim about the mathematics and checks it against a
computation that does not share code with the library: scipy.linalg.expm for
e^{AT}, finite differences of the map for its Jacobian, the simulator for the
fixed points, and dense sampling for the extrema of r.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import minimize_scalar

from rotorcontact import ParameterError, Parameters, simulate
from rotorcontact.maps import impact_map as im
from reference_parameters import REF


# ---------------------------------------------------------------------------
# independent references
# ---------------------------------------------------------------------------


def A_of(p: Parameters) -> np.ndarray:
    return np.array([[0.0, 1.0], [1.0 - p.omega**2 - 1j * p.gamma, -p.gamma - 2j]], dtype=complex)


def a_expm(p: Parameters, T: float) -> np.ndarray:
    return np.linalg.inv(scipy.linalg.expm(-A_of(p) * T) - np.eye(2))


def f1_expm(p: Parameters, T: float) -> float:
    q = (1.0 + p.d) * complex(1.0, p.mu)
    return 1.0 + (q * a_expm(p, T)[1, 1]).real


def flight_expm(p: Parameters, u0: complex, du0: complex, t_end: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(U, U') of free flight at n equally spaced times on [0, t_end], by powers of e^{A dt}."""
    k = p.rho * np.exp(1j * p.phi) / complex(p.omega**2 - 1.0, p.gamma)
    step = scipy.linalg.expm(A_of(p) * (t_end / (n - 1)))
    out = np.empty((n, 2), dtype=complex)
    out[0] = (u0 - k, du0)
    for j in range(1, n):
        out[j] = step @ out[j - 1]
    return k + out[:, 0], out[:, 1]


def angle_diff(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 2.0 * math.pi))


def fd_jacobian(p: Parameters, x: np.ndarray, h: float, law: str) -> tuple[np.ndarray, np.ndarray]:
    """Central differences with one Richardson step (error O(h^4))."""

    def central(step):
        jac = np.empty((3, 3))
        dt = np.empty(3)
        for j in range(3):
            e = np.zeros(3)
            e[j] = step
            plus = im.impact_map(p, x + e, law=law)
            minus = im.impact_map(p, x - e, law=law)
            assert plus.status == minus.status == "impact"
            diff = plus.state - minus.state
            diff[0] = math.remainder(diff[0], 2.0 * math.pi)
            jac[:, j] = diff / (2.0 * step)
            dt[j] = (plus.time - minus.time) / (2.0 * step)
        return jac, dt

    j1, t1 = central(h)
    j2, t2 = central(h / 2.0)
    return (4.0 * j2 - j1) / 3.0, (4.0 * t2 - t1) / 3.0


# ---------------------------------------------------------------------------
# a_ij and F1
# ---------------------------------------------------------------------------

A_CASES = [
    REF.replace(gamma=0.1),
    REF.replace(gamma=-0.3),
    REF.replace(gamma=0.15, d=1.0, mu=0.0),
    Parameters(gamma=1.6, omega=0.7, rho=2.0, mu=0.3, d=0.8, phi=-1.0, r_ratio=20.0),  # overdamped
    Parameters(gamma=1.4, omega=0.7, rho=0.5, mu=0.2, d=0.5),  # critical damping gamma = 2 omega
]


@pytest.mark.parametrize("p", A_CASES)
@pytest.mark.parametrize("T", [0.05, 0.3, 0.7, 1.3, 2.86, 6.0, 11.5])
def test_a_matrix_and_f1_match_expm(p, T):
    ref = a_expm(p, T)
    got = im.a_matrix(p, T)
    assert np.abs(got - ref).max() <= 1e-11 * np.abs(ref).max()
    assert im.f1(p, T) == pytest.approx(f1_expm(p, T), abs=1e-11)


def test_f1_tends_to_its_limit_at_zero_and_one_at_infinity():
    # F1(0+) = 1 - (1 + d)/2 and F1 -> 1 as T -> infinity for gamma > 0
    p = REF.replace(gamma=0.1)
    assert im.f1(p, 1e-9) == pytest.approx((1.0 - p.d) / 2.0, abs=1e-9)
    assert im.f1(p, 400.0) == pytest.approx(1.0, abs=1e-6)
    # and -> 1 - (1 + d) = -d for gamma < 0
    assert im.f1(REF.replace(gamma=-0.2), 400.0) == pytest.approx(-0.95, abs=1e-6)


def test_f1_vectorised_and_derivative_by_finite_differences():
    p = REF.replace(gamma=0.1)
    T = np.linspace(0.1, 12.0, 37)
    vals = im.f1(p, T)
    assert vals.shape == T.shape
    assert np.allclose(vals, [f1_expm(p, t) for t in T], atol=1e-11)
    h = 1e-5
    fd = (im.f1(p, T + h) - im.f1(p, T - h)) / (2 * h)
    assert np.allclose(im.f1_derivative(p, T), fd, atol=1e-8)


def test_a_derivatives_and_fixed_point_residual_jacobian():
    p = REF.replace(gamma=0.1)
    h = 1e-6
    for T, rdot in [(0.7, 0.1), (2.8, 0.7), (5.0, 0.3)]:
        a12, a22, da12, da22 = im.a_derivatives(p, T)
        ref = a_expm(p, T)
        assert a12 == pytest.approx(ref[0, 1], rel=1e-11) and a22 == pytest.approx(ref[1, 1], rel=1e-11)
        fd = (a_expm(p, T + h) - a_expm(p, T - h)) / (2 * h)
        assert abs(da12 - fd[0, 1]) <= 1e-7 * abs(fd[0, 1])
        assert abs(da22 - fd[1, 1]) <= 1e-7 * abs(fd[1, 1])
        res, jac = im.fixed_point_residual(p, T, rdot)
        fd_jac = np.column_stack(
            [
                (im.fixed_point_residual(p, T + h, rdot)[0] - im.fixed_point_residual(p, T - h, rdot)[0]) / (2 * h),
                (im.fixed_point_residual(p, T, rdot + h)[0] - im.fixed_point_residual(p, T, rdot - h)[0]) / (2 * h),
            ]
        )
        assert np.abs(jac - fd_jac).max() <= 1e-7 * max(1.0, np.abs(jac).max())


# ---------------------------------------------------------------------------
# zeros of F1
# ---------------------------------------------------------------------------


def f1_expm_grid(p: Parameters, T: np.ndarray) -> np.ndarray:
    """F1 on a grid of T, by stacked scipy.linalg.expm."""
    q = (1.0 + p.d) * complex(1.0, p.mu)
    A = A_of(p)
    a = np.linalg.inv(np.array([scipy.linalg.expm(-A * t) for t in T]) - np.eye(2)[None, :, :])
    return 1.0 + (q * a[:, 1, 1]).real


def sign_changes_expm(p, t_max, n=6000, t0=0.02):
    T = np.linspace(t0, t_max, n)
    F = f1_expm_grid(p, T)
    assert np.allclose(F[::500], [f1_expm(p, t) for t in T[::500]], atol=1e-12)
    idx = np.nonzero(np.sign(F[1:]) != np.sign(F[:-1]))[0]
    return T[idx], T[idx + 1]


@pytest.mark.parametrize(
    "gamma,t_max",
    [(0.1, 30.0), (0.05, 40.0), (0.03, 30.0), (0.01, 30.0), (0.17, 12.0), (-0.2, 12.0), (0.25, 12.0)],
)
def test_every_zero_of_f1_is_found_and_is_a_zero(gamma, t_max):
    p = REF.replace(gamma=gamma)
    zeros = im.f1_zeros(p, t_max)
    lo, hi = sign_changes_expm(p, t_max)
    # each sign change of the independent F1 on a fine grid holds exactly one reported zero
    assert len(zeros) == len(lo)
    for z, a, b in zip(zeros, lo, hi):
        assert a <= z.T <= b
        assert abs(f1_expm(p, z.T)) < 1e-10
        # F1 changes sign across the zero in the reported direction
        eps = 1e-7
        down = f1_expm(p, z.T - eps) > 0 > f1_expm(p, z.T + eps)
        assert down == (z.kind == "a") and z.slope * (1 if z.kind == "b" else -1) > 0


def test_zeros_are_labelled_in_pairs():
    zeros = im.f1_zeros(REF.replace(gamma=0.01), 30.0)
    assert [z.kind for z in zeros] == ["a", "b"] * (len(zeros) // 2)
    assert [z.n for z in zeros] == [i // 2 + 1 for i in range(len(zeros))]
    assert all(z1.T < z2.T for z1, z2 in zip(zeros, zeros[1:]))
    # negative damping: F1 -> -d, the last zero has no partner
    neg = im.f1_zeros(REF.replace(gamma=-0.3), 12.0)
    assert [(z.n, z.kind) for z in neg] == [(1, "a")]


def test_restitution_one_starts_from_the_sign_of_gamma_minus_two_mu():
    # d = 1: F1(0) = 0 and F1 ~ 2 (gamma - 2 mu) T / 12 near 0
    for gamma in (0.1, 0.5):
        p = REF.replace(gamma=gamma, d=1.0)
        zeros = im.f1_zeros(p, 20.0)
        lo, hi = sign_changes_expm(p, 20.0, t0=1e-3)
        assert len(zeros) == len(lo)
        if zeros:
            first = zeros[0]
            assert first.kind == ("b" if gamma < 2 * p.mu else "a") and first.n == 1


def _min_f1_expm(gamma):
    p = REF.replace(gamma=gamma)
    r = minimize_scalar(lambda T: f1_expm(p, T), bounds=(1.0, 2.5), method="bounded", options={"xatol": 1e-12})
    return r.fun, r.x


def test_first_smooth_fold_and_near_merging_zeros():
    # gamma_F,1: where the minimum of F1 between T0,1,a and T0,1,b touches 0 (independent bisection)
    lo, hi = 0.15, 0.2
    assert _min_f1_expm(lo)[0] < 0 < _min_f1_expm(hi)[0]
    while hi - lo > 1e-11:
        mid = 0.5 * (lo + hi)
        if _min_f1_expm(mid)[0] < 0:
            lo = mid
        else:
            hi = mid
    gamma_f = 0.5 * (lo + hi)
    assert round(gamma_f, 2) == 0.18 and abs(gamma_f - 0.178) < 2e-3  # MODEL.md: gamma_F,1 ~ 0.178
    t_star = _min_f1_expm(gamma_f)[1]
    # just below the fold both zeros of the pair are reported, however close
    for delta, gap in [(1e-3, 1e-2), (1e-6, 1e-4), (1e-9, 5e-6)]:
        p = REF.replace(gamma=gamma_f - delta)
        zeros = im.f1_zeros(p)
        assert [(z.n, z.kind, z.double) for z in zeros] == [(1, "a", False), (1, "b", False)], delta
        a, b = zeros
        assert a.T < t_star < b.T and b.T - a.T > gap
        assert f1_expm(p, 0.5 * (a.T + b.T)) < 0
        assert len(im.one_impact_orbits(p)) == 4
    # just above it there is none
    for delta in (1e-9, 1e-6, 1e-3):
        assert im.f1_zeros(REF.replace(gamma=gamma_f + delta)) == ()
    # the library's own zero count changes at the same gamma
    lo2, hi2 = 0.15, 0.2
    while hi2 - lo2 > 1e-11:
        mid = 0.5 * (lo2 + hi2)
        if im.f1_zeros(REF.replace(gamma=mid)):
            lo2 = mid
        else:
            hi2 = mid
    assert abs(lo2 - gamma_f) < 1e-9


def test_gamma_zero_skips_the_poles_of_f1():
    p = REF.replace(gamma=0.0)
    zeros = im.f1_zeros(p, 12.0)
    nu = p.omega
    poles = [2 * math.pi * j / (1 + nu) for j in range(1, 4)]
    for z in zeros:
        assert abs(f1_expm(p, z.T)) < 1e-9
        assert min(abs(z.T - t) for t in poles) > 1e-3
    # the labels are those of gamma -> 0+ (the poles are the limits of the b zeros)
    small = im.f1_zeros(REF.replace(gamma=1e-9), 12.0)
    assert {(z.n, z.kind) for z in zeros} <= {(z.n, z.kind) for z in small}


# ---------------------------------------------------------------------------
# the impact map and its Jacobian
# ---------------------------------------------------------------------------

MAP_CASES = [
    ("slipping", REF.replace(gamma=0.1), [0.3, 0.4, -0.2], "slip-bounded", False),
    ("slow-impact", REF.replace(gamma=0.1), [-2.69, 0.0022, -0.00025], "slip-bounded", False),
    ("sticking", REF.replace(gamma=0.1, r_ratio=0.0), [0.5, 0.6, -1.05], "slip-bounded", True),
    ("slipping-backwards", REF.replace(gamma=0.1, r_ratio=0.0), [0.5, 0.3, -1.5], "slip-bounded", False),
    ("ideal-law", REF.replace(gamma=0.1, r_ratio=0.0), [0.5, 0.6, -1.05], "ideal", False),
    ("overdamped", Parameters(gamma=1.6, omega=0.7, rho=2.0, mu=0.3, d=0.8, phi=-1.0, r_ratio=20.0),
     [0.2, 0.5, 0.3], "slip-bounded", False),
    ("negative-gamma", REF.replace(gamma=-0.1), [1.0, 0.2, 0.1], "slip-bounded", False),
]


@pytest.mark.parametrize("label,p,x,law,sticks", MAP_CASES, ids=[c[0] for c in MAP_CASES])
def test_jacobian_matches_finite_differences(label, p, x, law, sticks):
    x = np.array(x)
    res = im.impact_map(p, x, law=law, jacobian=True)
    assert res.status == "impact" and res.sticking == sticks
    fd, fd_t = fd_jacobian(p, x, 1e-5, law)
    scale = max(1.0, np.abs(fd).max())
    assert np.abs(res.jacobian - fd).max() <= 1e-6 * scale
    assert np.abs(res.time_gradient - fd_t).max() <= 1e-6 * max(1.0, np.abs(fd_t).max())
    if sticks:
        # a sticking contact forgets thetadot-: the reset maps it to -(r_ratio + 1)
        assert np.allclose(res.jacobian[:, 2], 0.0, atol=1e-12)


def test_map_reproduces_one_simulator_step():
    p = REF.replace(gamma=0.12)
    x = np.array([0.4, 0.3, -0.5])
    res = im.impact_map(p, x)
    u0, du0 = im.post_impact_state(p, x)
    traj = simulate(p, u0, du0, res.time + 1.0)
    imp = traj.impacts
    assert imp.t[0] == pytest.approx(res.time, abs=1e-12)
    assert angle_diff(imp.theta[0], res.state[0]) < 1e-12
    assert imp.rdot[0] == pytest.approx(res.state[1], abs=1e-12)
    assert imp.thetadot[0] == pytest.approx(res.state[2], abs=1e-12)


def test_map_without_an_impact_reports_it():
    # gamma = 0.3: x_R is admissible and stable; after this bounce the flight settles onto it
    p = REF.replace(gamma=0.3)
    res = im.impact_map(p, [-3.0, 0.3, 0.0], horizon=200.0)
    assert res.status == "no-impact" and res.state is None and res.time is None
    u0, du0 = im.post_impact_state(p, [-3.0, 0.3, 0.0])
    assert len(simulate(p, u0, du0, 200.0).impacts) == 0


def test_bad_input_raises_parameter_error():
    p = REF.replace(gamma=0.1)
    with pytest.raises(ParameterError):
        im.impact_map(p, [0.0, 0.1])
    with pytest.raises(ParameterError):
        im.impact_map(p, [0.0, 0.1, float("nan")])
    with pytest.raises(ParameterError, match=r"^state = .* three real numbers$"):
        im.impact_map(p, np.array([0.0, 0.1 + 1j, 0.0]))
    with pytest.raises(ParameterError):
        im.impact_map(p, [0.0, 0.1, 0.0], law="elastic")
    for law in (["ideal"], {}, None):
        with pytest.raises(ParameterError, match="^law = "):
            im.impact_map(p, [0.0, 0.1, 0.0], law=law)
    with pytest.raises(ParameterError, match="^jacobian = 'yes'"):
        im.impact_map(p, [0.0, 0.1, 0.0], jacobian="yes")
    # velocities beyond the simulator's bound: refused by every function of an impact state, not overflowed
    fast = [0.0, 1e300, 0.0]
    for call in (lambda: im.impact_map(p, fast), lambda: im.post_impact_state(p, fast),
                 lambda: im.impact_map_jacobian(p, fast, 1.0), lambda: im.flight_extrema(p, fast, 1.0)):
        with pytest.raises(ParameterError, match=r"^\(rdot, thetadot\) = 1e\+300,0.0 is too fast .* allowed: "
                                                 r"\|\(rdot, thetadot\)\| <= 1e\+06"):
            call()
    with pytest.raises(ParameterError, match=r"^rdot = 1e\+300 is out of range"):
        im.fixed_point_residual(p, 1.0, 1e300)
    with pytest.raises(ParameterError):
        im.impact_map(p, [0.0, 0.1, 0.0], horizon=-1.0)
    with pytest.raises(ParameterError):
        im.f1_zeros(p, t_max=0.0)
    with pytest.raises(ParameterError):
        im.f1(p, -1.0)
    with pytest.raises(ParameterError):
        im.one_impact_orbits(p, t_max=1e7)
    with pytest.raises(ParameterError):
        im.one_impact_orbits(Parameters(gamma=0.0, omega=1.0, rho=0.4, mu=0.1, d=0.9))
    # conservative flight with elastic, frictionless impacts: F1 = 0 for every T
    conservative = Parameters(gamma=0.0, omega=0.54, rho=0.5, mu=0.0, d=1.0)
    assert np.all(np.abs(im.f1(conservative, np.linspace(0.1, 10.0, 50))) < 1e-12)
    with pytest.raises(ParameterError):
        im.f1_zeros(conservative)


PERIOD_FUNCTIONS = [
    ("a_matrix", lambda p, T: im.a_matrix(p, T)),
    ("a_derivatives", lambda p, T: im.a_derivatives(p, T)),
    ("f1", lambda p, T: im.f1(p, T)),
    ("f1 of an array", lambda p, T: im.f1(p, np.array([1.0, T]))),
    ("f1_derivative", lambda p, T: im.f1_derivative(p, T)),
    ("rdot_roots", lambda p, T: im.rdot_roots(p, T)),
    ("fixed_point_residual", lambda p, T: im.fixed_point_residual(p, T, 0.1)),
    ("impact_map_jacobian", lambda p, T: im.impact_map_jacobian(p, [0.0, 0.1, 0.0], T)),
    ("flight_extrema", lambda p, T: im.flight_extrema(p, [0.0, 0.1, 0.0], T)),
]


@pytest.mark.parametrize("name, call", PERIOD_FUNCTIONS, ids=[n for n, _ in PERIOD_FUNCTIONS])
def test_a_period_beyond_the_limit_of_the_flight_is_refused(name, call):
    # at gamma = 0.1 the flight grows like e^{0.05 T}: beyond T = 300 / 0.05 e^{-AT} leaves the floats
    p = REF.replace(gamma=0.1)
    limit = im.period_limit(p)
    assert limit == pytest.approx(300.0 / 0.05)
    for T in (2e4, limit * (1 + 1e-9)):
        with pytest.raises(ParameterError, match=r"T|time") as err:
            call(p, T)
        assert f"{limit:.6g}" in str(err.value)
    scalars = (True, "3", None, [1.0, "x"], float("nan"), 0.0)
    arrays = ([1.0, "x"], [1.0, float("nan")], [1.0, 0.0], [], [1.0, True], [[1.0], [1.0, 2.0]])
    for bad in scalars if name != "f1 of an array" else arrays:
        with pytest.raises(ParameterError):
            call(p, bad) if name != "f1 of an array" else im.f1(p, bad)


@pytest.mark.parametrize("gamma, omega", [(0.1, 0.5), (-0.1, 0.5), (-0.6, 0.2), (-2.0, 0.1), (3.0, 0.4), (0.0, 0.7)])
def test_the_growth_rate_is_the_largest_real_part_of_the_flights_eigenvalues(gamma, omega):
    p = REF.replace(gamma=gamma, omega=omega)
    assert im.flight_growth(p) == pytest.approx(np.max(np.abs(np.linalg.eigvals(A_of(p)).real)), rel=1e-12, abs=1e-15)
    if gamma == 0.0:
        assert im.period_limit(p) == math.inf
        return
    # the flight of a whole period just inside the limit is still finite: forward for gamma < 0, backward else
    T = 0.999 * im.period_limit(p)
    x1, jac, dtau = im.impact_map_jacobian(p, [0.0, 0.1, 0.0], T)
    assert np.all(np.isfinite(x1)) and np.all(np.isfinite(jac)) and np.all(np.isfinite(dtau))
    assert np.all(np.isfinite(im.a_matrix(p, T)))


def test_values_just_inside_the_period_limit_are_finite_and_exact():
    p = REF.replace(gamma=0.1)
    T = 0.999 * im.period_limit(p)
    a = im.a_matrix(p, T)
    assert np.all(np.isfinite(a))
    assert np.allclose(a, a_expm(p, T), rtol=1e-8, atol=0.0)
    assert math.isfinite(im.f1(p, T)) and math.isfinite(im.f1_derivative(p, T))
    assert np.all(np.isfinite(im.fixed_point_residual(p, T, 0.1)[0]))


# ---------------------------------------------------------------------------
# one-impact orbits
# ---------------------------------------------------------------------------

ORBIT_CASES = [(0.1, 12.0), (0.15, 12.0), (0.08, 12.0), (0.05, 40.0), (0.01, 20.0), (-0.1, 12.0), (-0.3, 12.0)]


@pytest.mark.parametrize("gamma,t_max", ORBIT_CASES)
def test_orbits_solve_the_fixed_point_equations_with_expm(gamma, t_max):
    # e^{AT} (U0 - k, U'+) = (U0 - k, U'-): the flight from the impact returns to it
    p = REF.replace(gamma=gamma)
    orbits = im.one_impact_orbits(p, t_max)
    assert orbits
    k = p.k
    for o in orbits:
        assert o.label == f"B{o.n},{o.branch}" and o.branch in "abcd"
        assert -math.pi < o.theta <= math.pi
        u0 = complex(math.cos(o.theta), math.sin(o.theta))
        du_minus = u0 * complex(o.rdot, o.thetadot)
        q = (1.0 + p.d) * complex(1.0, p.mu)
        du_plus = du_minus - q * o.rdot * u0  # MODEL.md §2
        w = scipy.linalg.expm(A_of(p) * o.T) @ np.array([u0 - k, du_plus])
        assert abs(w[0] - (u0 - k)) < 1e-9 and abs(w[1] - du_minus) < 1e-9
        assert o.admissible == (o.rdot > 0)
        assert (o.multipliers is None) == (not o.admissible)
        assert (o.stable is None) == (not o.admissible or o.friction_reverses)


def test_orbit_roots_are_ordered_as_in_model():
    p = REF.replace(gamma=0.1)
    orbits = {o.label: o for o in im.one_impact_orbits(p)}
    assert set(orbits) == {"B1,a", "B1,b", "B1,c", "B1,d"}
    assert orbits["B1,a"].T == orbits["B1,c"].T < orbits["B1,b"].T == orbits["B1,d"].T
    assert orbits["B1,a"].rdot < orbits["B1,c"].rdot and orbits["B1,b"].rdot < orbits["B1,d"].rdot
    for zero in im.f1_zeros(p):
        disc, roots = im.rdot_roots(p, zero.T)
        assert disc > 0 and len(roots) == 2
        small, large = ("a", "c") if zero.kind == "a" else ("b", "d")
        assert orbits[f"B1,{small}"].rdot == roots[0] and orbits[f"B1,{large}"].rdot == roots[1]


def test_complex_roots_give_no_orbit():
    # at gamma = -0.6 the a and c roots have coalesced (MODEL.md §5): a zero of F1 but no orbit
    p = REF.replace(gamma=-0.6)
    zeros = im.f1_zeros(p)
    assert len(zeros) == 1
    disc, roots = im.rdot_roots(p, zeros[0].T)
    assert disc < 0 and roots == ()
    assert im.one_impact_orbits(p) == ()


@pytest.mark.parametrize("gamma,t_max", ORBIT_CASES)
def test_admissible_orbits_are_fixed_points_of_the_simulator(gamma, t_max):
    p = REF.replace(gamma=gamma)
    checked = 0
    for o in im.one_impact_orbits(p, t_max):
        if not o.admissible:
            continue
        res = im.impact_map(p, o.state, horizon=2.0 * o.T + 10.0)
        u0, du0 = im.post_impact_state(p, o.state)  # the simulator's slip-bounded law
        u0_ideal, du0_ideal = o.initial_condition()  # the law of MODEL.md §5
        if o.slipping:
            assert abs(u0 - u0_ideal) < 1e-15 and abs(du0 - du0_ideal) < 1e-14 * (1.0 + abs(du0))
        traj = simulate(p, u0, du0, o.T * (1.0 + 1e-9) + 1e-9)
        imp = traj.impacts
        if o.plausible:
            assert res.status == "impact"
            assert abs(res.time - o.T) < 1e-10
            assert angle_diff(res.state[0], o.theta) < 1e-10
            assert np.abs(res.state[1:] - o.state[1:]).max() < 1e-10
            assert len(imp) >= 1
            assert abs(imp.t[0] - o.T) < 1e-10
            assert angle_diff(imp.theta[0], o.theta) < 1e-10
            assert abs(imp.rdot[0] - o.rdot) < 1e-10
            assert abs(imp.thetadot[0] - o.thetadot) < 1e-10
            checked += 1
        else:
            # not plausible: the rotor reaches the stator before T
            assert o.r_max_interior is not None and o.r_max_interior >= 1.0
            assert res.status != "impact" or res.time < o.T - 1e-6
    assert checked >= 1


@pytest.mark.parametrize("gamma", [0.1, 0.15, 0.05])
def test_multipliers_match_finite_differences_of_the_simulated_map(gamma):
    p = REF.replace(gamma=gamma)
    for o in im.one_impact_orbits(p):
        if not o.plausible:
            continue
        fd, _ = fd_jacobian(p, o.state, 1e-5, "slip-bounded")
        assert np.abs(o.jacobian() - fd).max() <= 1e-6 * max(1.0, np.abs(fd).max())
        ev = np.linalg.eigvals(fd)
        for m in o.multipliers:
            assert np.min(np.abs(ev - m)) < 1e-6
        assert o.stable == bool(np.all(np.abs(ev) < 1.0))


def test_stable_orbit_is_the_attractor_of_a_long_simulation():
    # reference parameters, gamma = 0.1: from rest the rotor settles onto B1,d (T ~ 2.8635)
    p = REF.replace(gamma=0.1)
    orbits = {o.label: o for o in im.one_impact_orbits(p)}
    stable = [o for o in orbits.values() if o.plausible and o.stable]
    assert [o.label for o in stable] == ["B1,d"]
    d = orbits["B1,d"]
    assert d.T == pytest.approx(2.8635, abs=1e-4)
    traj = simulate(p, 0j, 0j, 3000.0)
    imp = traj.impacts
    assert np.allclose(np.diff(imp.t[-5:]), d.T, atol=1e-9)
    assert angle_diff(imp.theta[-1], d.theta) < 1e-9
    assert abs(imp.rdot[-1] - d.rdot) < 1e-9 and abs(imp.thetadot[-1] - d.thetadot) < 1e-9
    # from a perturbed start near B1,d it returns onto it
    u0, du0 = d.initial_condition()
    traj = simulate(p, 0.98 * u0, du0 + 0.05, 600.0)
    imp = traj.impacts
    assert angle_diff(imp.theta[-1], d.theta) < 1e-8 and abs(imp.rdot[-1] - d.rdot) < 1e-8


def test_unstable_orbit_is_left_by_the_simulation():
    p = REF.replace(gamma=0.1)
    b = {o.label: o for o in im.one_impact_orbits(p)}["B1,b"]
    assert b.plausible and not b.stable and abs(b.multipliers[0]) > 1
    u0, du0 = b.initial_condition()
    traj = simulate(p, u0, du0 * (1 + 1e-6), 300.0)
    imp = traj.impacts
    assert len(imp) < 5 or abs(imp.rdot[-1] - b.rdot) > 1e-3


def test_small_orbits_shrink_onto_the_boundary_equilibrium_at_gamma_star():
    # NSFH (MODEL.md §5): at gamma* = sqrt(rho^2 - (1 - omega^2)^2), |k| = 1 and rdot of B1,a, B1,b is 0
    omega, rho = REF.omega, REF.rho
    gstar = math.sqrt(rho**2 - (1 - omega**2) ** 2)
    assert abs(gstar - 0.072) < 2e-3
    at = {o.label: o for o in im.one_impact_orbits(REF.replace(gamma=gstar))}
    assert abs(at["B1,a"].rdot) < 1e-12 and abs(at["B1,b"].rdot) < 1e-12
    above = {o.label: o for o in im.one_impact_orbits(REF.replace(gamma=gstar + 1e-3))}
    below = {o.label: o for o in im.one_impact_orbits(REF.replace(gamma=gstar - 1e-3))}
    for lab in ("B1,a", "B1,b"):
        assert above[lab].admissible and not below[lab].admissible
        assert above[lab].rdot < 1e-2 and below[lab].rdot > -1e-2


def _sampled_extrema(p, o, n=20001):
    u0, du0 = o.initial_condition()
    u, du = flight_expm(p, u0, du0, o.T, n)
    r = np.abs(u)
    rr = (np.conj(u) * du).real
    idx = np.nonzero(np.sign(rr[1:-1]) != np.sign(rr[2:]))[0] + 1
    maxima = [r[i : i + 2].max() for i in idx if rr[i] > 0]
    return len(idx), (max(maxima) if maxima else None), r[1:-1].max()


@pytest.mark.parametrize("gamma,t_max", [(0.05, 40.0), (0.1, 12.0), (0.065, 12.0), (0.0, 12.0)])
def test_interior_extrema_match_dense_sampling(gamma, t_max):
    p = REF.replace(gamma=gamma)
    for o in im.one_impact_orbits(p, t_max):
        count, r_max, r_sample_max = _sampled_extrema(p, o)
        assert o.interior_extrema == count, o.label
        if r_max is None:
            assert o.r_max_interior is None
        else:
            assert o.r_max_interior == pytest.approx(r_max, abs=1e-6)
            assert o.r_max_interior >= r_max - 1e-12  # the exact maximum is not below a sample
        if o.admissible:
            assert o.plausible == (o.slipping and r_sample_max < 1.0)


def test_grazing_of_b1d_between_gamma_005_and_0072():
    # MODEL.md Fig. 2(b): B1,d is near grazing at gamma = 0.065; its interior maximum crosses r = 1
    below = {o.label: o for o in im.one_impact_orbits(REF.replace(gamma=0.05))}["B1,d"]
    above = {o.label: o for o in im.one_impact_orbits(REF.replace(gamma=0.072))}["B1,d"]
    assert below.r_max_interior > 1.0 and not below.plausible
    assert above.r_max_interior < 1.0 and above.plausible
    assert below.interior_extrema == above.interior_extrema == 3


def test_flight_extrema_function():
    p = REF.replace(gamma=0.05)
    d = {o.label: o for o in im.one_impact_orbits(p)}["B1,d"]
    ext = im.flight_extrema(p, d.state, d.T)
    assert ext.count == 3 and list(ext.maxima) == [False, True, False]
    assert np.all(np.diff(ext.times) > 0) and 0 < ext.times[0] and ext.times[-1] < d.T
    assert ext.r_max == d.r_max_interior


def test_not_slipping_orbits_are_not_plausible():
    # without the rotor's surface speed (r_ratio = 0) some impacts would reverse v_rel = 1 + thetadot
    p = REF.replace(gamma=0.1, r_ratio=0.0)
    orbits = im.one_impact_orbits(p)
    assert orbits
    for o in orbits:
        v_rel = 1.0 + o.thetadot
        assert o.slipping == (v_rel > p.mu * (1 + p.d) * o.rdot)
        if not o.slipping:
            assert not o.plausible


@pytest.mark.parametrize("r_ratio", [0.0, 0.2, 0.35])
def test_an_orbit_whose_friction_would_reverse_is_neither_stable_nor_plausible(r_ratio):
    # below r_ratio ~ 0.37 the relative surface velocity at the impact of B1,d is at most
    # mu (1 + d) rdot-: the law of F1 would reverse the slip, the simulator's friction stops at v_rel = 0
    p = REF.replace(gamma=0.1, r_ratio=r_ratio)
    d = {o.label: o for o in im.one_impact_orbits(p)}["B1,d"]
    assert d.admissible and r_ratio + 1.0 + d.thetadot <= p.mu * (1 + p.d) * d.rdot
    assert d.friction_reverses is True
    assert d.stable is None and not d.plausible
    assert d.multipliers is not None  # the multipliers of the law of MODEL.md §5 are still reported
    assert d.to_dict()["friction_reverses"] is True and d.to_dict()["stable"] is None


def test_at_the_reference_friction_never_reverses():
    orbits = im.one_impact_orbits(REF.replace(gamma=0.1))
    assert orbits and not any(o.friction_reverses for o in orbits)
    d = {o.label: o for o in orbits}["B1,d"]
    assert d.stable is True and d.plausible
    assert im.orbit_stability(d.multipliers, False) is None


# ---------------------------------------------------------------------------
# the bounds behind the guarantees
# ---------------------------------------------------------------------------

BOUND_CASES = [
    REF.replace(gamma=0.1),
    REF.replace(gamma=0.01),
    REF.replace(gamma=-0.4),
    REF.replace(gamma=0.15, d=1.0),
    Parameters(gamma=1.6, omega=0.7, rho=2.0, mu=0.3, d=0.8),
    Parameters(gamma=1.4, omega=0.7, rho=0.5, mu=0.2, d=0.5),
]


@pytest.mark.parametrize("p", BOUND_CASES)
def test_second_derivative_bound_of_g_holds(p):
    # the safe steps of the zero search rely on M >= |g''| over each window [t0, t0 + w]
    h2 = 0.25 * p.gamma**2 - p.omega**2
    q = (1.0 + p.d) * complex(1.0, p.mu)
    rng = np.random.default_rng(0)
    for _ in range(60):
        t0 = float(rng.choice([0.0, rng.uniform(0, 0.6), rng.uniform(0, 12.0)]))
        w = float(rng.choice([1e-3, 0.1, 1.0]))
        bound = im._g_bound(t0, t0 + w, p.gamma, h2, abs(q))
        ts = np.linspace(t0, t0 + w, 201)
        g2 = np.array([im._g_eval(t, p.gamma, h2, q)[2] for t in ts])
        assert np.all(np.abs(g2) <= bound)
        # g and g' are consistent with g'' (finite differences of the evaluator)
        g0 = np.array([im._g_eval(t, p.gamma, h2, q)[0] for t in ts])
        g1 = np.array([im._g_eval(t, p.gamma, h2, q)[1] for t in ts])
        dt = ts[1] - ts[0]
        assert np.allclose(np.gradient(g0, dt)[1:-1], g1[1:-1], atol=1e-5 * max(1.0, np.abs(g0).max()) + w * w * bound)


@pytest.mark.parametrize("p", BOUND_CASES)
def test_g_is_f1_times_a_positive_factor(p):
    # the zero search works on g = |D/T^2|^2 F1: same sign as F1 for T > 0
    h2 = 0.25 * p.gamma**2 - p.omega**2
    q = (1.0 + p.d) * complex(1.0, p.mu)
    for T in np.linspace(0.01, 12.0, 50):
        g = im._g_eval(T, p.gamma, h2, q)[0]
        assert np.sign(g) == np.sign(f1_expm(p, T)) or abs(f1_expm(p, T)) < 1e-12
    assert im._g_eval(0.0, p.gamma, h2, q)[0] == pytest.approx(
        abs(complex(p.omega**2 - 1.0, p.gamma)) ** 2 * (1.0 - p.d) / 2.0, rel=1e-12, abs=1e-15
    )


def test_second_derivative_bound_of_r_rdot_holds():
    p = REF.replace(gamma=0.05)
    k = p.k
    for o in im.one_impact_orbits(p, 40.0):
        u0, du0 = o.initial_condition()
        for t0 in np.linspace(0.0, o.T, 7):
            w = 0.5
            bound = im._f_bound(t0, w, p.gamma, p.omega, k, u0 - k, du0)
            ts = np.linspace(t0, t0 + w, 101)
            f2 = np.array([im._f_eval(t, p.gamma, p.omega, k, u0 - k, du0)[2] for t in ts])
            assert np.all(np.abs(f2) <= bound)


def test_the_searchable_t_max_is_the_smallest_of_the_request_the_period_limit_and_the_bound():
    for gamma, t_max in ((0.1, 12.0), (100.0, 12.0), (0.1, 5e4), (1e-9, 2e4)):
        p = REF.replace(gamma=gamma)
        growth = abs(gamma) / 2.0 + math.sqrt(max(gamma**2 / 4.0 - p.omega**2, 0.0))
        expected = min(t_max, 300.0 / growth, 1e4)
        assert im.searchable_t_max(p, t_max) == pytest.approx(expected, rel=1e-14)
    with pytest.raises(ParameterError, match="t_max"):
        im.searchable_t_max(REF, 0.0)


def test_orbits_impacting_faster_than_the_simulator_follows_are_refused_naming_rho():
    # the orbits' impact speeds scale with the unbalance rho: at rho = 1e6 one is above MAX_VELOCITY
    from rotorcontact.model.params import MAX_VELOCITY

    slower = im.one_impact_orbits(REF.replace(rho=1e5))
    fastest = max(abs(complex(o.rdot, o.thetadot)) for o in slower)
    assert MAX_VELOCITY / 10.0 < fastest < MAX_VELOCITY
    with pytest.raises(ParameterError, match=r"^rho = 1e\+06 \(gamma = .*\) gives the orbit B\d,[abcd] an impact at "
                                             r"\|\(rdot, thetadot\)\| = .*; allowed: .* at most 1e\+06"):
        im.one_impact_orbits(REF.replace(rho=1e6))


def test_more_zeros_than_the_isolation_can_follow_are_refused_naming_t_max():
    # at gamma = 0 the flight neither grows nor decays (no period limit) and F1 has a pair of zeros per
    # oscillation: about 0.24 per unit of t_max here, so t_max = 1e4 holds thousands
    p = REF.replace(gamma=0.0)
    assert im.period_limit(p) == math.inf
    assert len(im.f1_zeros(p, 1000.0)) > 200
    with pytest.raises(ParameterError, match=r"^t_max = 10000.0 is too large at gamma = 0, .* needs more than "
                                             r"\d+ steps; allowed: a smaller t_max$"):
        im.f1_zeros(p, 1e4)


def test_the_growth_and_the_period_limit_need_parameters():
    from rotorcontact import reference_machine

    for bad in (None, reference_machine(), "x"):
        for call in (im.flight_growth, im.period_limit):
            with pytest.raises(ParameterError, match=r"^params = .* is not a Parameters object"):
                call(bad)


def test_stable_quadratic_roots_against_the_formula_and_bad_coefficients():
    # (x - 1)(x - 3) = x^2 - 4 x + 3: a = 1, b = -2, c = 3
    disc, roots = im.stable_quadratic_roots(1.0, -2.0, 3.0)
    assert disc == 1.0 and roots == (1.0, 3.0)
    # roots 1e-9 and 1e9 without cancellation: x^2 - (1e9 + 1e-9) x + 1
    disc, roots = im.stable_quadratic_roots(1.0, -0.5 * (1e9 + 1e-9), 1.0)
    assert roots[0] == pytest.approx(1e-9, rel=1e-15) and roots[1] == pytest.approx(1e9, rel=1e-15)
    assert im.stable_quadratic_roots(1.0, 0.0, 1.0) == (-1.0, ())
    for name, args in (("a", (math.nan, 0.0, 1.0)), ("b", (1.0, math.inf, 1.0)), ("c", (1.0, 0.0, "1")),
                       ("a", (1j, 0.0, 1.0))):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            im.stable_quadratic_roots(*args)


def test_stable_quadratic_roots_of_huge_and_tiny_coefficients_are_those_of_the_scaled_equation():
    # the same equation times 1e300 or 1e-300 has the same roots; b^2 - a c overflows or underflows unscaled
    base = im.stable_quadratic_roots(1.0, -2.0, 3.0)[1]
    for scale in (1e300, 1e-300):
        disc, roots = im.stable_quadratic_roots(scale, -2.0 * scale, 3.0 * scale)
        assert roots == pytest.approx(base, rel=1e-14) and not math.isnan(disc) and disc >= 0.0
    disc, roots = im.stable_quadratic_roots(1e300, 1e300, 1e300)  # x^2 + 2x + 1: the double root -1
    assert disc == 0.0 and roots == (-1.0, -1.0)
    assert im.stable_quadratic_roots(1e300, 0.0, 1e300) == (-math.inf, ())
    # tiny: x^2 + 1 has no real root, and its discriminant keeps its sign where it underflows
    disc, roots = im.stable_quadratic_roots(1e-300, 0.0, 1e-300)
    assert disc < 0.0 and roots == ()
    assert im.stable_quadratic_roots(0.0, 0.0, 0.0) == (0.0, ())


def test_a_search_longer_than_the_bound_is_refused_before_it_runs():
    # near the undamped resonance the period limit is far away, and the orbits up to t_max grow like t_max^2
    p = REF.replace(gamma=1e-6)
    assert im.period_limit(p) > 1e6
    for call in (im.f1_zeros, im.one_impact_orbits):
        with pytest.raises(ParameterError, match=rf"^t_max = 20000.0 is too large; allowed: t_max <= "
                                                 rf"{im.MAX_T_MAX:g} "):
            call(p, 2e4)


def test_labels_and_stability_refuse_what_they_cannot_read():
    assert im.label_f1_zeros([-1, 1, -1], True) == [(1, "a"), (1, "b"), (2, "a")]
    assert im.label_f1_zeros(np.array([1.0]), np.bool_(False)) == [(1, "b")]
    for bad in (None, "x", [None], [[1, -1]], [math.nan]):
        with pytest.raises(ParameterError, match=r"^directions = .* is invalid; allowed: a sequence of the signs"):
            im.label_f1_zeros(bad, True)
    with pytest.raises(ParameterError, match=r"^starts_positive = 'x' is invalid"):
        im.label_f1_zeros([1], "x")
    assert im.orbit_stability([0.5, 0.1 + 0.2j], True) is True and im.orbit_stability([1.5], True) is False
    assert im.orbit_stability([0.5], False) is None
    for bad in (None, "x", [], [math.nan], [[0.5, 0.1]]):
        with pytest.raises(ParameterError, match=r"^multipliers = .* is invalid; allowed: a non-empty sequence"):
            im.orbit_stability(bad, True)
    with pytest.raises(ParameterError, match=r"^slipping = 'x' is invalid"):
        im.orbit_stability([0.5], "x")


@pytest.mark.parametrize("gamma, omega", [(0.1, 0.5), (-0.1, 0.5), (-2.0, 0.1), (3.0, 0.4)])
def test_the_growth_forwards_and_backwards_is_that_of_the_flights_eigenvalues(gamma, omega):
    from rotorcontact.model.flow import half_discriminant

    p = REF.replace(gamma=gamma, omega=omega)
    real = np.linalg.eigvals(A_of(p)).real
    h2 = half_discriminant.py_func(gamma, omega)
    assert im.growth_rate(gamma, h2, 1) == pytest.approx(np.max(real), rel=1e-12, abs=1e-15)
    assert im.growth_rate(gamma, h2, -1) == pytest.approx(np.max(-real), rel=1e-12, abs=1e-15)
    assert im.growth_rate(gamma, h2) == im.flight_growth(p)
