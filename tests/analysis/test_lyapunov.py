"""Lyapunov exponents with saltation corrections.

Each test states a claim about the tangent dynamics of the hybrid system and
checks it against something computed independently: the multipliers of the
impact map, the eigenvalues of A, the linearisation of the contact dynamics
at a pseudo-equilibrium, and finite differences of perturbed simulations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError, Parameters, reference_machine, simulate
from rotorcontact.analysis.equilibria import pseudo_equilibria
from rotorcontact.model.flow import free_flight
from rotorcontact.maps.impact_map import one_impact_orbits
from rotorcontact.analysis.lyapunov import (
    COORDINATES,
    accumulation_saltation,
    contact_projection,
    contact_variational_matrix,
    flight_tangent,
    impact_saltation,
    liftoff_saltation,
    lyapunov_spectrum,
    trajectory_lyapunov,
    trajectory_tangent,
)
from reference_parameters import REF


def _x(u: complex, du: complex) -> np.ndarray:
    return np.array([u.real, u.imag, du.real, du.imag])


def _real_form(a: np.ndarray) -> np.ndarray:
    """Real 4x4 form of the complex 2x2 matrix A acting on (U, U')."""
    out = np.zeros((4, 4))
    for i in range(2):
        for j in range(2):
            z = a[i, j]
            out[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] = [[z.real, -z.imag], [z.imag, z.real]]
    return out


def _matrix_a(p: Parameters) -> np.ndarray:
    return np.array([[0.0, 1.0], [1.0 - p.omega**2 - 1j * p.gamma, -p.gamma - 2j]])


# ---------------------------------------------------------------------------
# the claims of the issue
# ---------------------------------------------------------------------------


def test_spectrum_on_the_stable_orbit_b1d_is_zero_and_the_log_multipliers_over_t():
    """Along a periodic orbit the spectrum is 0 (the flow) and log|lambda_i| / T (MODEL.md §5)."""
    p = REF.replace(gamma=0.1)
    b1d = next(o for o in one_impact_orbits(p) if o.label == "B1,d")
    assert b1d.stable and b1d.T == pytest.approx(2.8635, abs=1e-4)
    expected = sorted([0.0] + [math.log(abs(m)) / b1d.T for m in b1d.multipliers], reverse=True)
    res = lyapunov_spectrum(p, 0j, 0j, 1200.0, t_transient=300.0)
    # the run settles on B1,d
    assert res.trajectory.summary.impacts_per_period == 1
    assert res.trajectory.summary.period == pytest.approx(b1d.T, abs=1e-9)
    assert res.aligned and res.n_impacts > 250 and res.collapsed == 0
    assert np.all(np.diff(res.exponents) <= 0.0)
    np.testing.assert_allclose(res.exponents, expected, atol=2e-3)
    assert res.exponents[0] == pytest.approx(0.0, abs=1e-6)
    # the sum is exact whatever the rotation within the complex pair
    assert sum(res.exponents) == pytest.approx(sum(expected), abs=1e-6)


@pytest.mark.parametrize(
    "changes",
    [dict(gamma=0.3), dict(gamma=1.0, omega=0.3)],
    ids=["underdamped", "overdamped"],
)
def test_pure_free_flight_spectrum_is_the_real_parts_of_the_eigenvalues_of_a(changes):
    """Without impacts the tangent map is e^{At}: the exponents are Re(eig) of A's real form."""
    p = REF.replace(**changes)
    assert abs(p.k) < 1.0
    res = lyapunov_spectrum(p, p.k + 0.1, 0.05j, 500.0, t_transient=100.0)
    assert len(res.trajectory.impacts) == 0 and not res.aligned
    expected = np.sort(np.linalg.eigvals(_real_form(_matrix_a(p))).real)[::-1]
    np.testing.assert_allclose(res.exponents, expected, atol=1e-3)
    assert sum(res.exponents) == pytest.approx(-2.0 * p.gamma, abs=1e-12)


# ---------------------------------------------------------------------------
# saltation matrices against finite differences
# ---------------------------------------------------------------------------


def _simulated_map(p, x0, t, **kw):
    tr = simulate(p, complex(x0[0], x0[1]), complex(x0[2], x0[3]), t, **kw)
    u, du = tr.state(t)
    return _x(complex(u), complex(du)), tr


def _fd_jacobian(p, x0, t, eps, **kw):
    cols = []
    for j in range(4):
        d = np.zeros(4)
        d[j] = eps
        cols.append((_simulated_map(p, x0 + d, t, **kw)[0] - _simulated_map(p, x0 - d, t, **kw)[0]) / (2 * eps))
    return np.array(cols).T


@pytest.mark.parametrize(
    "r_ratio, thetadot, sticks",
    [(None, 0.3, False), (0.0, -0.95, True), (0.0, -1.2, False)],
    ids=["slip-forward", "stick", "slip-backward"],
)
def test_saltation_matches_perturbed_simulations_across_one_impact(r_ratio, thetadot, sticks):
    """e^{A s2} S e^{A s1} is the derivative of the simulated flow across an impact."""
    p = REF.replace(gamma=0.1)
    if r_ratio is not None:
        p = p.replace(r_ratio=r_ratio)
    theta, rdot, s1, s2 = 0.4, 0.5, 0.2, 0.3
    e = complex(math.cos(theta), math.sin(theta))
    # a state s1 before an impact at theta with (rdot, thetadot), by the exact backward flow
    ua, dua = free_flight(p, e, e * complex(rdot, thetadot), -s1)
    x0 = _x(complex(ua), complex(dua))
    _, tr = _simulated_map(p, x0, s1 + s2)
    assert len(tr.impacts) == 1
    t_i = tr.impacts.t[0]
    u = tr.impacts.point[0]
    du_minus = u * complex(tr.impacts.rdot[0], tr.impacts.thetadot[0])
    s, du_plus, sticking = impact_saltation(p, u, du_minus)
    assert sticking == sticks
    assert du_plus == pytest.approx(complex(tr.impacts.du_plus[0]), abs=1e-14)
    analytic = flight_tangent(p, s1 + s2 - t_i) @ s @ flight_tangent(p, t_i)
    fd = _fd_jacobian(p, x0, s1 + s2, 1e-6)
    np.testing.assert_allclose(analytic, fd, atol=1e-7 * np.abs(analytic).max())
    # a sticking impact annihilates the variation of thetadot-: rank 3
    sv = np.linalg.svd(s, compute_uv=False)
    assert (sv[-1] < 1e-12 * sv[0]) == sticks


def test_saltation_maps_the_field_before_onto_the_field_after():
    """S f- = f+ (the defining property of the saltation matrix)."""
    p = REF.replace(gamma=0.1)
    u = complex(math.cos(1.0), math.sin(1.0))
    du = u * complex(0.6, -1.4)
    s, du_plus, _ = impact_saltation(p, u, du)

    def field(v):
        return _x(v, -complex(p.gamma, 2.0) * v + complex(1 - p.omega**2, -p.gamma) * (u - p.k))

    np.testing.assert_allclose(s @ field(du), field(du_plus), atol=1e-13)
    with pytest.raises(ParameterError):
        impact_saltation(p, u, u * complex(-0.2, 0.0))


def test_tangent_through_chatter_contact_and_liftoff_matches_perturbed_simulations():
    """Flight, impact into an accumulation, sliding contact, lift-off and flight: the chain of saltations is exact."""
    p = REF.replace(gamma=0.15)
    kw = dict(chatter_height=1e-3)
    base = simulate(p, 0.01537771389735243 - 0.21057118597757246j, 2.324838719898679 - 0.49181888055741263j,
                    25.0, **kw)
    u, du = base.state(11.68)
    x0 = _x(complex(u), complex(du))
    horizon = 3.06
    _, tr = _simulated_map(p, x0, horizon, **kw)
    kinds = [c.kind for c in tr.contact_intervals]
    assert kinds == ["sliding-forward"]
    assert tr.in_contact(horizon) == -1 and len(tr.impacts) == 1  # ends in flight, after the lift-off
    analytic = trajectory_tangent(tr)
    assert analytic.shape == (4, 4)
    fd = _fd_jacobian(p, x0, horizon, 1e-7, **kw)
    np.testing.assert_allclose(analytic, fd, atol=1e-6 * np.abs(analytic).max())


def test_tangent_into_rolling_annihilates_the_slip_direction():
    """Accumulation, sliding, then rolling: the 2x4 tangent map matches finite differences and dthetadot = 0."""
    p = REF.replace(gamma=0.15)
    kw = dict(chatter_height=1e-3)
    base = simulate(p, 0.00709297482015403 + 0.2702782177955612j, -1.7792019364018312 + 2.243247235686219j, 12.0,
                    **kw)
    u, du = base.state(6.163544673474731)
    x0 = np.array([u.real, u.imag, du.real, du.imag])
    t = 8.199986662565646 - 6.163544673474731

    def contact_state(x):
        tr = simulate(p, complex(x[0], x[1]), complex(x[2], x[3]), t, **kw)
        _r, theta, _rd, thetadot = tr.polar(t)
        return np.array([theta, thetadot]), tr

    _, tr = contact_state(x0)
    assert [c.kind for c in tr.contact_intervals][-1] == "rolling"
    analytic = trajectory_tangent(tr)
    assert analytic.shape == (2, 4)
    eps = 1e-7
    fd = np.array(
        [(contact_state(x0 + eps * e)[0] - contact_state(x0 - eps * e)[0]) / (2 * eps) for e in np.eye(4)]
    ).T
    np.testing.assert_allclose(analytic, fd, atol=1e-7 * np.abs(analytic).max())
    assert np.all(analytic[1] == 0.0)


def test_accumulation_saltation_has_rank_two():
    p = REF.replace(gamma=0.15)
    u = complex(math.cos(-0.5), math.sin(-0.5))
    s = accumulation_saltation(p, u, u * complex(0.01, -2.0), np.array([-2.0, 0.3]))
    assert s.shape == (2, 4) and np.linalg.matrix_rank(s) == 2


# ---------------------------------------------------------------------------
# contact: the exponents of the sliding and rolling dynamics
# ---------------------------------------------------------------------------


def test_forward_rub_spectrum_is_that_of_the_pseudo_equilibrium_and_two_minus_inf():
    """Settling onto the stable pseudo-equilibrium P2: Re of its contact eigenvalues, and -inf twice."""
    p = REF.replace(gamma=0.15)
    p2 = next(e for e in pseudo_equilibria(p) if e.name == "P2")
    assert p2.stable and p2.admissible
    res = lyapunov_spectrum(p, 0j, 0j, 1500.0, t_transient=300.0)
    assert res.trajectory.summary.regime == "forward-rub"
    expected = sorted((e.real for e in p2.eigenvalues), reverse=True)
    assert res.collapsed == 2
    np.testing.assert_allclose(res.exponents[:2], expected, atol=2e-3)
    assert res.exponents[2:] == (-math.inf, -math.inf)
    assert res.to_dict()["exponents"][2:] == [None, None]


def test_backward_whirl_keeps_only_the_direction_of_the_rolling_motion():
    """Rolling holds v_rel = 0: one exponent 0 (along the motion), three -inf."""
    p = REF.replace(gamma=0.065)
    res = lyapunov_spectrum(p, 0j, 0j, 400.0, t_transient=200.0)
    assert res.trajectory.summary.regime == "backward-whirl"
    assert res.exponents[0] == pytest.approx(0.0, abs=1e-12)
    assert res.exponents[1:] == (-math.inf,) * 3 and res.collapsed == 3


# ---------------------------------------------------------------------------
# chaos, options and input
# ---------------------------------------------------------------------------


#: Starts near rest spread well beyond rounding, so that their fates are independent draws.
CHAOS_STARTS = [0j, 1e-3, 1e-3j, -1e-3, -1e-3j, 2e-3, 2e-3j, -2e-3, -2e-3j, 3e-3, 3e-3j, -3e-3]


def test_irregular_impacting_motion_has_a_positive_exponent_and_a_zero_one():
    """At gamma = 0.08 (beyond the period-doubled branch of B1,d) the impacting attractor is chaotic."""
    p = REF.replace(gamma=0.08)
    # the chaotic set can also be left for contact (a transient), and which runs do so is as
    # sensitive to rounding as the trajectory itself: take the first of several starts that stays on it
    for u0 in CHAOS_STARTS:
        res = lyapunov_spectrum(p, u0, 0j, 3000.0, t_transient=500.0)
        if res.trajectory.summary.motion == "irregular" and res.collapsed == 0:
            break
    else:
        pytest.fail(f"none of {len(CHAOS_STARTS)} starts stays on the chaotic set")
    assert res.exponents[0] > 0.05
    assert abs(res.exponents[1]) < 2e-3
    assert sum(res.exponents) < 0.0


def test_the_qr_interval_and_reusing_a_trajectory_do_not_change_the_spectrum():
    p = REF.replace(gamma=0.1)
    a = lyapunov_spectrum(p, 0j, 0j, 600.0, t_transient=200.0, qr_interval=0.25)
    b = lyapunov_spectrum(p, 0j, 0j, 600.0, t_transient=200.0, qr_interval=5.0)
    np.testing.assert_allclose(a.exponents, b.exponents, atol=1e-9)
    c = trajectory_lyapunov(a.trajectory, t_transient=200.0, qr_interval=0.25)
    assert c.exponents == a.exponents
    assert a.coordinates == COORDINATES == ("Re U", "Im U", "Re U'", "Im U'")


def test_bad_input_raises_parameter_error():
    p = REF.replace(gamma=0.1)
    with pytest.raises(ParameterError):
        lyapunov_spectrum(p, 0j, 0j, 100.0, t_transient=100.0)
    with pytest.raises(ParameterError):
        lyapunov_spectrum(p, 0j, 0j, 100.0, qr_interval=0.0)
    with pytest.raises(ParameterError):
        lyapunov_spectrum(p, 2.0, 0j, 100.0)
    with pytest.raises(ParameterError):
        lyapunov_spectrum("gamma=0.1", 0j, 0j, 100.0)
    with pytest.raises(ParameterError):
        trajectory_lyapunov(simulate(REF.replace(gamma=0.15), 0j, 0j, 300.0, on_chatter="stop"))
    with pytest.raises(ParameterError):
        trajectory_tangent(None)
    with pytest.raises(ParameterError, match=r"^align = 'no' is invalid; allowed: True or False$"):
        lyapunov_spectrum(p, 0j, 0j, 100.0, align="no")
    with pytest.raises(ParameterError, match=r"^align = 0 is invalid; allowed: True or False$"):
        trajectory_lyapunov(simulate(p, 0j, 0j, 10.0), align=0)
    with pytest.raises(ParameterError, match=r"^traj = None is not a Trajectory object"):
        trajectory_lyapunov(None)
    # a run cut short by its event budget, before the averaging window starts: the message says so
    with pytest.raises(ParameterError, match=r"^t_transient = 25.0 is not below the end of the run t = .*, where it "
                                             r"stopped early \(max-events: "):
        lyapunov_spectrum(p, 0j, 0j, 100.0, max_events=1)


# ---------------------------------------------------------------------------
# bad input to the tangent maps, refused by name
# ---------------------------------------------------------------------------

U = complex(math.cos(1.0), math.sin(1.0))
DU = U * complex(0.6, -1.4)
G = np.array([-2.0, 0.3])
MAPS = {
    "flight_tangent": lambda p: flight_tangent(p, 1.3),
    "impact_saltation": lambda p: impact_saltation(p, U, DU),
    "accumulation_saltation": lambda p: accumulation_saltation(p, U, DU, G),
    "liftoff_saltation": lambda p: liftoff_saltation(p, 0.1, 0.2, G),
    "contact_variational_matrix": lambda p: contact_variational_matrix(p, 0.1, 0.2, 1.0),
}


@pytest.mark.parametrize("params", [None, reference_machine(), "REF"])
@pytest.mark.parametrize("name", sorted(MAPS))
def test_the_maps_need_parameters(name, params):
    with pytest.raises(ParameterError, match=r"^params = .* is not a Parameters object; allowed: rotorcontact\."):
        MAPS[name](params)


@pytest.mark.parametrize("s", [math.inf, math.nan, None, "1", [1.0], True, 1j])
def test_the_length_of_a_flight_is_a_finite_real_number(s):
    with pytest.raises(ParameterError, match=r"^s = .* is invalid; allowed: a finite number$"):
        flight_tangent(REF, s)


def test_a_flight_is_refused_where_its_tangent_map_would_overflow():
    """Backwards the reference flight grows like e^(gamma |s| / 2): NaN by s = -1e4, refused from |s| = 300 / 0.076."""
    limit = 300.0 / (0.5 * REF.gamma)
    assert np.all(np.isfinite(flight_tangent(REF, -0.999 * limit)))
    with pytest.raises(ParameterError, match=rf"^s = -10000.0 is invalid: the flight grows like e\^\(0.076 \|s\|\) at "
                                             rf"gamma = 0.152009, omega = 0.760043; allowed: \|s\| <= {limit:.6g}$"):
        flight_tangent(REF, -1e4)
    assert np.all(flight_tangent(REF, 1e6) == 0.0)  # forwards it decays: any length is fine


@pytest.mark.parametrize("call", [lambda u: impact_saltation(REF, u, DU), lambda u: contact_projection(u, DU),
                                  lambda u: accumulation_saltation(REF, u, DU, G)])
@pytest.mark.parametrize("u", [math.nan, None, "x", True, [U], 0j, 2.0, complex(math.inf, 0.0)])
def test_an_impact_point_lies_on_the_stator(call, u):
    with pytest.raises(ParameterError, match=r"^u = .* is invalid; allowed: a complex number on the stator, "
                                             r"\| \|u\| - 1 \| <= 1e-06$"):
        call(u)


@pytest.mark.parametrize("call, name", [(lambda v: impact_saltation(REF, U, v), "du_minus"),
                                        (lambda v: accumulation_saltation(REF, U, v, G), "du_minus"),
                                        (lambda v: contact_projection(U, v), "du")])
@pytest.mark.parametrize("v", [math.nan, None, [1.0], "1", True, 2e12j])
def test_a_velocity_is_a_bounded_complex_number(call, name, v):
    with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: a finite complex number with "
                                             rf"\|{name}\| <= 1e\+12$"):
        call(v)


def test_impacts_that_do_not_approach_or_graze_are_refused():
    # |conj(u) du-| is 0 (the tester's u = 1j, du- = 0.5 divided by zero) or so small that S overflows
    with pytest.raises(ParameterError, match=r"^du_minus = \(0.5\+0j\) does not approach the stator at u = 1j"):
        accumulation_saltation(REF, 1j, 0.5, G)
    for v in (complex(1e-310, 1.0), complex(5e-324, -2.0)):
        for call in (lambda: impact_saltation(REF, 1.0, v), lambda: accumulation_saltation(REF, 1.0, v, G)):
            with pytest.raises(ParameterError, match=r"^du_minus = .* is invalid: .*so the tangent map is not finite"):
                call()
    assert np.all(np.isfinite(impact_saltation(REF, 1.0, complex(1e-300, 1.0))[0]))  # large, still finite


@pytest.mark.parametrize("call", [lambda g: liftoff_saltation(REF, 0.1, 0.2, g),
                                  lambda g: accumulation_saltation(REF, U, DU, g)])
@pytest.mark.parametrize("g", [None, [1.0], [1.0, 2.0, 3.0], [math.nan, 0.0], "ab", [True, 0.0], [1j, 0.0]])
def test_the_contact_field_is_two_finite_real_numbers(call, g):
    with pytest.raises(ParameterError, match=r"^contact_field = .* is invalid; allowed: \(thetadot, theta''\), "
                                             r"2 finite real numbers$"):
        call(g)


def test_a_tangent_lift_off_is_refused():
    thetadot = 0.2
    # at theta = phi, grad N = (0, 2 (1 + thetadot)): grad N . g = -1e-310 makes the correction overflow
    g = [1.0, -1e-310 / (2.0 * (1.0 + thetadot))]
    with pytest.raises(ParameterError, match=r"^contact_field = .* is invalid: N = 0 is reached tangentially"):
        liftoff_saltation(REF, REF.phi, thetadot, g)


@pytest.mark.parametrize("call", [lambda a, b: liftoff_saltation(REF, a, b, G),
                                  lambda a, b: contact_variational_matrix(REF, a, b, 1.0)])
def test_the_contact_state_is_a_finite_angle_and_a_bounded_velocity(call):
    for theta in (math.inf, math.nan, True, None, "0.1"):
        with pytest.raises(ParameterError, match=r"^theta = .* is invalid; allowed: a finite number$"):
            call(theta, 0.2)
    for thetadot in (math.inf, -2e12, [0.2]):
        with pytest.raises(ParameterError, match=r"^thetadot = .* is invalid; allowed: a finite number >= -1e\+12"):
            call(0.1, thetadot)


@pytest.mark.parametrize("sgn", [math.nan, 0.5, None, True, "1", 2])
def test_the_sign_of_v_rel_is_minus_one_zero_or_one(sgn):
    with pytest.raises(ParameterError, match=r"^sgn = .* is invalid; allowed: "):
        contact_variational_matrix(REF, 0.1, 0.2, sgn)


def test_numpy_scalars_give_the_same_maps_to_the_bit():
    def same(a, b):
        return np.asarray(a).tobytes() == np.asarray(b).tobytes()

    assert same(flight_tangent(REF, np.float64(1.3)), flight_tangent(REF, 1.3))
    assert same(flight_tangent(REF, np.array(2)), flight_tangent(REF, 2.0))
    s, du_plus, sticking = impact_saltation(REF, np.complex128(U), np.array(DU))
    assert same(s, impact_saltation(REF, U, DU)[0]) and du_plus == impact_saltation(REF, U, DU)[1]
    assert same(impact_saltation(REF, 1, 1 + 1j)[0], impact_saltation(REF, 1.0 + 0j, 1.0 + 1j)[0])
    assert same(contact_projection(np.complex128(U), np.complex128(DU)), contact_projection(U, DU))
    assert same(accumulation_saltation(REF, U, DU, [np.float64(-2.0), 0.3]), accumulation_saltation(REF, U, DU, G))
    assert same(liftoff_saltation(REF, np.float64(0.1), np.array(0.2), (-2, 0.3)), liftoff_saltation(REF, 0.1, 0.2, G))
    assert same(contact_variational_matrix(REF, np.float64(0.1), np.array(0.2), np.int64(-1)),
                contact_variational_matrix(REF, 0.1, 0.2, -1.0))
