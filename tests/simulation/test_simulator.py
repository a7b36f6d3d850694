"""The hybrid simulator against independent references.

* impact times against an mpmath (40 digits) evaluation of the closed form with
  mpmath root finding and the impact law applied in mpmath: 1e-12 relative;
* the first 50 impacts against solve_ivp (DOP853, rtol = atol = 1e-12, terminal
  event), each flight started from the simulator's post-impact state: 1e-9;
* trajectories from rest that settle onto a one-impact periodic orbit whose period
  T is a zero of F1 (MODEL.md §5, evaluated with scipy.linalg.expm): 1e-9;
* chatter, run-length caps, restarts and bad arguments.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError, Parameters, simulate
from reference_parameters import REF, REF_VALUES


MP_CASES = [
    # label, parameters, u0, du0
    ("reference-gamma0.1-from-rest", dict(REF_VALUES, gamma=0.1), 0j, 0j),
    ("reference-gamma0.14", dict(REF_VALUES, gamma=0.14), 0.3 - 0.2j, 0.5 + 0.1j),
    ("overdamped", dict(gamma=1.6, omega=0.7, rho=2.0, mu=0.3, d=0.8, phi=-1.0, r_ratio=20.0), 0.2j, 1.5 - 0.5j),
    ("stiff", dict(gamma=0.3, omega=1.2, rho=0.8, mu=0.3, d=0.7, phi=-2.5, r_ratio=5.0), 0.2 + 0.1j, -0.5 + 1j),
]


@pytest.mark.parametrize("label,kw,u0,du0", MP_CASES, ids=[c[0] for c in MP_CASES])
def test_first_impacts_match_mpmath_closed_form(ref, label, kw, u0, du0):
    p = Parameters(**kw)
    if label == "overdamped":
        assert p.gamma > 2 * p.omega
    exact = ref.mp_simulate(p, u0, du0, 10)
    assert len(exact) == 10
    traj = ref.run(p, u0, du0, float(exact[-1]["t"]) + 1.0, max_impacts=10, impacts_only=True)
    imp = traj.impacts
    assert len(imp) == 10
    for j, e in enumerate(exact):
        t_ref = float(e["t"])
        assert abs(imp.t[j] - t_ref) <= 1e-12 * t_ref, (j, imp.t[j], t_ref)
        assert abs(ref.angle_diff(imp.theta[j], float(e["theta"]))) < 1e-11
        assert abs(imp.rdot[j] - float(e["rdot"])) < 1e-11
        assert abs(imp.thetadot[j] - float(e["thetadot"])) < 1e-11
        assert abs(imp.rdot_plus[j] - float(e["rdot_plus"])) < 1e-11
        assert abs(imp.thetadot_plus[j] - float(e["thetadot_plus"])) < 1e-11
        assert abs(imp.v_rel[j] - float(e["v_rel"])) < 1e-11
        assert abs(imp.point[j] - complex(e["point"])) < 1e-11


IVP_CASES = [
    ("reference-gamma0.1-from-rest", dict(REF_VALUES, gamma=0.1), 0j, 0j),
    ("reference-gamma0.08-from-rest", dict(REF_VALUES, gamma=0.08), 0j, 0j),
    ("reference-gamma0.12-other-phase", dict(REF_VALUES, gamma=0.12, phi=-2.0), 0.5j, 0.3 + 0j),
    ("stiff-large-unbalance", dict(gamma=0.2, omega=1.5, rho=1.5, mu=0.2, d=0.9, phi=0.5, r_ratio=30.0), 0j, 0j),
]


@pytest.mark.parametrize("omega, u0, du0", [(1e-14, 0j, 0j), (1e-14, 0.2 + 0.1j, 0.4 - 0.3j), (1e-8, 0.5j, 0.3)])
def test_an_undamped_all_but_free_rotor_matches_solve_ivp(ref, omega, u0, du0):
    """gamma = 0 and omega near 0 (a bearing far softer than the spin): the whirl's two terms, each of size
    |W'| / omega, cancel, so the step bounds of the finite window take over. The run completes, and its first
    30 flights match solve_ivp's, each from the simulator's own state after the impact before."""
    p = Parameters(**dict(REF_VALUES, gamma=0.0, omega=omega))
    assert simulate(p, u0, du0, 50.0).status == "completed"
    imp = ref.run(p, u0, du0, 200.0, max_impacts=30, impacts_only=True).impacts
    assert len(imp.t) == 30
    t0, u, du = 0.0, complex(u0), complex(du0)
    for j in range(30):
        (t, _theta, rdot, *_rest), _, _ = ref.ivp_next_impact(p, t0, u, du, 500.0)
        assert abs(imp.t[j] - t) < 1e-9 * (1.0 + 1.0 / abs(rdot)), (j, imp.t[j], t)
        t0, u, du = imp.t[j], complex(imp.u_re[j], imp.u_im[j]), complex(imp.du_plus_re[j], imp.du_plus_im[j])


@pytest.mark.parametrize("label,kw,u0,du0", IVP_CASES, ids=[c[0] for c in IVP_CASES])
def test_first_50_impacts_match_solve_ivp(ref, label, kw, u0, du0):
    """Each flight of the simulator against solve_ivp started from the simulator's own
    state after the previous impact, so that each comparison is of one flight and one
    impact and does not depend on how the two codes' rounding errors grow over a
    (possibly chaotic) sequence."""
    p = Parameters(**kw)
    traj = ref.run(p, u0, du0, 5000.0, max_impacts=50, impacts_only=True)
    imp = traj.impacts
    assert len(imp) == 50
    t0, u, du = 0.0, complex(u0), complex(du0)
    for j in range(50):
        step = ref.ivp_next_impact(p, t0, u, du, 5000.0)
        assert step is not None, j
        (t, theta, rdot, thetadot, rdot_plus, thetadot_plus), _, _ = step
        # a DOP853 flight at rtol = atol = 1e-12 is good to about 1e-10 in the state; the
        # impact time carries that error divided by the normal speed
        assert abs(imp.t[j] - t) < 1e-9 * (1.0 + 1.0 / abs(rdot)), (j, imp.t[j], t)
        assert abs(ref.angle_diff(imp.theta[j], theta)) < 1e-9 * (1.0 + 1.0 / abs(rdot)), j
        assert abs(imp.rdot[j] - rdot) < 1e-9, j
        assert abs(imp.thetadot[j] - thetadot) < 1e-9, j
        # restart the reference from the simulator's post-impact state
        t0 = imp.t[j]
        e = complex(math.cos(imp.theta[j]), math.sin(imp.theta[j]))
        u, du = e, e * complex(imp.rdot_plus[j], imp.thetadot_plus[j])


def test_bouncing_sequence_matches_mpmath(ref):
    """An undamped rotor that ends up bouncing along the stator, with bounces
    shrinking geometrically: the closed-form simulator follows the 40-digit
    reference impact by impact over 45 impacts."""
    p = Parameters(gamma=0.0, omega=0.9, rho=0.6, mu=0.1, d=0.9, phi=1.0, r_ratio=10.0)
    u0, du0 = 0.1 + 0j, 0.5j
    n = 45
    exact = ref.mp_simulate(p, u0, du0, n)
    t_ref = np.array([float(e["t"]) for e in exact])
    rdot_ref = np.array([float(e["rdot"]) for e in exact])
    traj = ref.run(p, u0, du0, t_ref[-1] + 1e-3, max_impacts=n, impacts_only=True)
    assert len(traj.impacts) == n
    assert np.max(np.abs(traj.impacts.t - t_ref) / t_ref) < 1e-12
    # the last bounces are short: the sequence really is a fast one
    assert np.min(np.diff(t_ref[-5:])) < 0.05
    assert np.max(np.abs(traj.impacts.rdot - rdot_ref)) < 1e-9


# ---------------------------------------------------------------------------
# one-impact periodic orbits (MODEL.md §5)
# ---------------------------------------------------------------------------


def f1_eigen(p, T):
    """F1 from the eigenvalue formula of MODEL.md §5 (independent of expm)."""
    s = math.sqrt(4 * p.omega**2 - p.gamma**2) if 4 * p.omega**2 > p.gamma**2 else 1j * math.sqrt(p.gamma**2 - 4 * p.omega**2)
    lp = (-p.gamma + 1j * (-2 + s)) / 2
    lm = (-p.gamma + 1j * (-2 - s)) / 2
    q = (1 + p.d) * (1 + 1j * p.mu)
    ep, em = np.exp(lp * T), np.exp(lm * T)
    return 1 - (q / (lp - lm) * (lp * ep / (ep - 1) - lm * em / (em - 1))).real


@pytest.mark.parametrize("gamma", [0.1, 0.12, 0.14])
def test_settles_onto_one_impact_orbit_with_period_a_zero_of_F1(ref, gamma):
    p = REF.replace(gamma=gamma)
    traj = ref.run(p, 0j, 0j, 1000.0)
    assert traj.status == "completed"
    imp = traj.impacts
    T = imp.t[-1] - imp.t[-2]
    # the last impacts repeat: one impact per period
    assert np.ptp(np.diff(imp.t[-20:])) < 1e-9
    assert np.max(np.abs(ref.angle_diff(imp.theta[-20:], imp.theta[-1]))) < 1e-9
    # F1(T) = 0 (scipy expm), and the eigenvalue formula of MODEL.md agrees
    assert abs(ref.f1_expm(p, T)) < 1e-9
    assert abs(f1_eigen(p, T) - ref.f1_expm(p, T)) < 1e-12
    # the rest of the fixed point (MODEL.md §5): rdot solves the quadratic,
    # thetadot = -Im(q a22) rdot, theta0 = Arg(k / (1 + q a12 rdot))
    q = (1 + p.d) * complex(1, p.mu)
    a = ref.a_matrix(p, T)
    k = p.rho * complex(math.cos(p.phi), math.sin(p.phi)) / complex(p.omega**2 - 1, p.gamma)
    rdot = imp.rdot[-1]
    qa12 = q * a[0, 1]
    assert abs(abs(qa12) ** 2 * rdot**2 + 2 * qa12.real * rdot + 1 - abs(k) ** 2) < 1e-9
    roots = np.sort(np.roots([abs(qa12) ** 2, 2 * qa12.real, 1 - abs(k) ** 2]).real)
    assert abs(rdot - roots[1]) < 1e-8  # the larger root (orbits c / d), admissible: rdot > 0
    assert abs(imp.thetadot[-1] + (q * a[1, 1]).imag * rdot) < 1e-8
    assert abs(ref.angle_diff(imp.theta[-1], np.angle(k / (1 + qa12 * rdot)))) < 1e-8
    # and the summary reports it
    s = traj.summary
    assert s.motion == "periodic-impacting"
    assert s.impacts_per_period == 1
    assert abs(s.period - T) < 1e-8


def test_gamma_0_2_from_rest_chatters_instead(ref):
    """At gamma = 0.2 (above the fold gamma_F,1 ~ 0.178 of MODEL.md §5) there is no
    one-impact orbit to settle onto: impacts accumulate."""
    p = REF.replace(gamma=0.2)
    traj = ref.run(p, 0j, 0j, 1000.0, stop_on_chatter=True)
    assert traj.status == "chatter"


# ---------------------------------------------------------------------------
# chatter
# ---------------------------------------------------------------------------


def test_chatter_is_detected_with_geometric_accumulation(ref):
    p = REF.replace(gamma=0.2)
    traj = ref.run(p, 0j, 0j, 1000.0, stop_on_chatter=True)
    imp = traj.impacts
    assert traj.status == "chatter"
    assert "chatter" in traj.message
    n = len(imp)
    assert n > 20
    # bounces on a surface with outward pull: intervals and impact speeds shrink by d
    dt = np.diff(imp.t[-6:])
    assert np.all(np.abs(dt[1:] / dt[:-1] - p.d) < 1e-3)
    assert np.all(np.abs(imp.rdot[-5:] / imp.rdot[-6:-1] - p.d) < 1e-3)
    # pressed outwards: N = (1 + thetadot+)^2 - omega^2 + rho cos(phi - theta) > 0
    N = (1 + imp.thetadot_plus[-1]) ** 2 - p.omega**2 + p.rho * math.cos(p.phi - imp.theta[-1])
    assert N > 0
    # the run stops at the accumulation point: t_last + sum of the remaining intervals
    tail = dt[-1] * p.d / (1 - p.d)
    assert traj.t_stop > imp.t[-1]
    assert abs((traj.t_stop - imp.t[-1]) / tail - 1) < 0.05
    assert traj.t_stop < traj.t_end


def test_chatter_at_once_from_rest_on_the_stator_pressed_outwards(ref):
    p = REF.replace(gamma=0.1)
    u0 = complex(math.cos(p.phi), math.sin(p.phi))
    assert 1 - p.omega**2 + p.rho > 0  # N > 0 at rest there
    traj = ref.run(p, u0, 0j, 10.0, stop_on_chatter=True)
    assert traj.status == "chatter"
    assert len(traj.impacts) == 0
    assert traj.t_stop == 0.0


# ---------------------------------------------------------------------------
# statuses, caps, restarts
# ---------------------------------------------------------------------------


def test_run_length_cap(ref):
    p = REF.replace(gamma=0.1)
    traj = ref.run(p, 0j, 0j, 1000.0, max_impacts=7)
    assert traj.status in ref.MAX_STATUSES
    assert len(traj.impacts) == 7
    assert traj.t_stop == pytest.approx(traj.impacts.t[-1], abs=1e-12)
    assert not traj.success
    full = ref.run(p, 0j, 0j, 1000.0)
    assert np.array_equal(full.impacts.t[:7], traj.impacts.t)


def test_no_impact_at_the_regular_equilibrium(ref):
    p = REF.replace(gamma=0.3)
    k = p.rho * complex(math.cos(p.phi), math.sin(p.phi)) / complex(p.omega**2 - 1, p.gamma)
    assert abs(k) < 1
    traj = ref.run(p, k, 0j, 500.0)
    assert traj.status == "completed" and traj.success
    assert len(traj.impacts) == 0
    assert traj.t_stop == 500.0
    assert traj.summary.motion == "no-contact"


def test_long_run_at_the_regular_equilibrium_completes(ref):
    p = REF.replace(gamma=0.3)
    traj = ref.run(p, p.k, 0j, 1e6)
    assert traj.status == "completed"
    assert len(traj.impacts) == 0


def test_impact_at_time_zero_when_starting_on_the_stator_moving_outwards(ref):
    p = REF.replace(gamma=0.1)
    e = complex(math.cos(1.0), math.sin(1.0))
    traj = ref.run(p, e, e * complex(0.4, 0.2), 50.0, max_impacts=3)
    imp = traj.impacts
    assert imp.t[0] == 0.0
    assert imp.rdot[0] == pytest.approx(0.4, abs=1e-15)
    assert imp.thetadot[0] == pytest.approx(0.2, abs=1e-15)
    assert imp.rdot_plus[0] == pytest.approx(-p.d * 0.4, abs=1e-15)
    assert abs(ref.angle_diff(imp.theta[0], 1.0)) < 1e-15


def test_restart_from_an_impact_reproduces_the_rest(ref):
    """Time invariance: restarting at impact j from its post-impact state gives the same later impacts."""
    p = REF.replace(gamma=0.12)
    traj = ref.run(p, 0j, 0j, 200.0, impacts_only=True)
    imp = traj.impacts
    j = 5
    t0 = imp.t[j]
    rest = ref.run(p, imp.point[j], imp.du_plus[j], 200.0 - t0, impacts_only=True)
    n = min(30, len(rest.impacts))
    later = rest.impacts
    # the restart begins on the boundary moving inwards: the first impact is the next one
    assert later.t[0] > 0
    assert np.max(np.abs(later.t[:n] + t0 - imp.t[j + 1 : j + 1 + n])) < 1e-9
    assert np.max(np.abs(ref.angle_diff(later.theta[:n], imp.theta[j + 1 : j + 1 + n]))) < 1e-9


def test_initial_state_forms_and_determinism(ref):
    p = REF.replace(gamma=0.1)
    a = ref.run(p, (0.1, -0.2), [0.3, 0.0], 40.0)
    b = ref.run(p, 0.1 - 0.2j, 0.3 + 0j, 40.0)
    c = ref.run(p, np.array([0.1, -0.2]), 0.3, 40.0)
    assert a.u0 == b.u0 == c.u0 == 0.1 - 0.2j
    assert np.array_equal(a.records, b.records) and np.array_equal(a.records, c.records)


def test_boundary_tolerance_of_the_initial_position(ref):
    p = REF.replace(gamma=0.1)
    # on the stator up to rounding: accepted
    ref.run(p, 1 + 5e-13, 0j, 1.0, stop_on_chatter=True)
    with pytest.raises(ParameterError, match=r"u0"):
        simulate(p, 1 + 1e-9, 0j, 1.0)


# ---------------------------------------------------------------------------
# bad arguments
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "u0,text",
    [
        (1.5 + 0j, "1.5"),
        (0.8 + 0.8j, "0.8"),
        (-2j, "-2"),
    ],
)
def test_initial_position_outside_the_clearance(u0, text):
    p = REF.replace(gamma=0.1)
    with pytest.raises(ParameterError) as info:
        simulate(p, u0, 0j, 10.0)
    msg = str(info.value)
    assert "u0" in msg and text in msg
    assert "|u0| <= 1" in msg or "clearance" in msg


@pytest.mark.parametrize(
    "kwargs,name",
    [
        (dict(u0=complex(math.nan, 0)), "u0"),
        (dict(u0=(0.1, math.inf)), "u0"),
        (dict(du0=complex(0, math.inf)), "du0"),
        (dict(du0=(math.nan, 0.0)), "du0"),
        (dict(u0="abc"), "u0"),
        (dict(t_end=0.0), "t_end"),
        (dict(t_end=-3.0), "t_end"),
        (dict(t_end=math.nan), "t_end"),
        (dict(t_end=math.inf), "t_end"),
        (dict(t_end=1e300), "t_end = 1e+300 is out of range; allowed: (0, 1e+07]"),
        (dict(t_end=np.complex128(5 + 3j)), "t_end"),
        (dict(chatter_rdot=0.0), "chatter_rdot"),
        (dict(chatter_rdot=-1.0), "chatter_rdot"),
        (dict(max_events=2**63), "max_events"),
    ],
)
def test_bad_simulate_arguments(kwargs, name):
    p = REF.replace(gamma=0.1)
    args = dict(u0=0j, du0=0j, t_end=10.0)
    args.update(kwargs)
    u0, du0, t_end = args.pop("u0"), args.pop("du0"), args.pop("t_end")
    with pytest.raises(ParameterError) as info:
        simulate(p, u0, du0, t_end, **args)
    assert name in str(info.value)


@pytest.mark.parametrize("value", [0, -1, 1.5, True])
def test_bad_run_length_cap(ref, value):
    p = REF.replace(gamma=0.1)
    with pytest.raises(ParameterError) as info:
        ref.run(p, 0j, 0j, 10.0, max_impacts=value)
    assert "max_" in str(info.value) and repr(value) in str(info.value)


def test_params_must_be_parameters():
    with pytest.raises(ParameterError, match="params"):
        simulate({"gamma": 0.1}, 0j, 0j, 10.0)


# ---------------------------------------------------------------------------
# near the undamped resonance omega^2 - 1 + i gamma = 0 (k = rho e^{i phi} / that)
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("gamma", [1e-2, 1e-3])
def test_first_impact_close_to_resonance(ref, gamma):
    p = Parameters(gamma=gamma, omega=1.0, rho=0.5, mu=0.1, d=0.9, phi=0.3, r_ratio=10.0)
    t_ref = float(ref.mp_first_crossing(ref.flight(p, 0.3 + 0j, 0.2j), 30.0))
    traj = ref.run(p, 0.3 + 0j, 0.2j, 30.0, impacts_only=True)
    assert abs(traj.impacts.t[0] - t_ref) <= 1e-12 * t_ref


@pytest.mark.parametrize("gamma", [1e-6, 1e-9])
def test_too_close_to_undamped_resonance_is_rejected_clearly(gamma):
    """Within rho/1000 of omega^2 - 1 + i gamma = 0 the forced response k exceeds 1000 clearances
    and the closed form cannot keep its accuracy: the simulator refuses with a clear message."""
    p = Parameters(gamma=gamma, omega=1.0, rho=0.5, mu=0.1, d=0.9, phi=0.3, r_ratio=10.0)
    with pytest.raises(ParameterError) as err:
        simulate(p, 0.3 + 0j, 0.2j, 30.0)
    msg = str(err.value)
    assert "omega" in msg and "gamma" in msg and "resonance" in msg and "allowed" in msg


@pytest.mark.parametrize("rho", [1e6, 500.0])
def test_too_large_an_unbalance_is_rejected_naming_rho(rho):
    """Far from resonance, a forced response beyond 1000 clearances comes from rho: the message gives its bound."""
    p = REF.replace(rho=rho)
    with pytest.raises(ParameterError) as err:
        simulate(p, 0.3 + 0j, 0.2j, 30.0)
    msg = str(err.value)
    bound = 1e3 * abs(complex(p.omega**2 - 1.0, p.gamma))
    assert msg.startswith(f"rho = {rho!r}") and f"allowed: rho <= 1000 |omega^2 - 1 + i gamma| = {bound:.3g}" in msg
    simulate(REF.replace(rho=bound * 0.999), 0.3 + 0j, 0.2j, 1.0)  # just inside: simulated


def test_undamped_resonance_is_simulated_or_rejected_cleanly(ref):
    p = Parameters(gamma=0.0, omega=1.0, rho=0.5, mu=0.1, d=0.9, phi=0.3, r_ratio=10.0)
    try:
        traj = ref.run(p, 0.3 + 0j, 0.2j, 5.0)
    except ParameterError:
        return
    assert traj.status in ref.STATUSES


# ---------------------------------------------------------------------------
# reproducers of defects at the end of a run and in the accumulation criterion
# ---------------------------------------------------------------------------


def test_plastic_impact_near_the_end_keeps_the_rotor_inside(ref):
    p = Parameters(gamma=0.0, omega=1.125, rho=0.5, mu=0.0, d=0.0, phi=0.0, r_ratio=0.0)
    traj = ref.run(p, 0j, -2j, 4.0)
    assert len(traj.impacts) == 3
    t = np.linspace(0.0, traj.t_stop, 4001)
    assert np.max(traj.r(t)) <= 1 + 1e-12


def test_elastic_impacts_are_not_taken_as_an_accumulation(ref):
    p = Parameters(gamma=0.249660287592949, omega=1.9822922262880183, rho=1.4452490185446911,
                   mu=0.6616841453875995, d=1.0, phi=-0.3037106432256955, r_ratio=50.11458474264819)
    u0, du0 = 0.5402134775837618 + 0.4172875273320234j, -2.360356587961414 - 2.9361152714699443j
    # resolved bounce by bounce (chatter_dt = 0), elastic impacts never accumulate
    traj = ref.run(p, u0, du0, 5.0, stop_on_chatter=True, impacts_only=True)
    assert traj.status != "chatter"
    t = traj.sample(5000)
    assert np.max(traj.r(t)) <= 1 + 1e-12
    # by default two bounces in a row shorter than chatter_dt are sustained micro-bouncing: the
    # switch happens at the last resolved impact (d = 1 has no geometric tail) and r stays <= 1
    short = ref.run(p, u0, du0, 5.0, stop_on_chatter=True)
    assert short.status == "chatter"
    imp = short.impacts
    assert short.t_stop == imp.t[-1]
    bounces = 2 * p.d * imp.rdot[-2:] / imp.normal_force[-2:]
    assert np.all(bounces < 1e-3) and np.all(imp.normal_force[-2:] > 0)
    t = short.sample(5000)
    assert np.max(short.r(t)) <= 1 + 1e-12


def test_accumulation_at_a_plastic_impact_is_the_impact_time(ref):
    p = Parameters(gamma=0.24164059372607427, omega=1.2410806112359005, rho=1.0260538435570175,
                   mu=0.35142921922895287, d=0.0, phi=-1.1718331248935523, r_ratio=0.0)
    u0, du0 = 0.5518919380041203 + 0.2963555289028187j, -2.4948621984817074 - 0.24122466435021828j
    traj = ref.run(p, u0, du0, 50.0, stop_on_chatter=True)
    assert traj.status == "chatter"
    assert traj.t_stop == pytest.approx(traj.impacts.t[-1], abs=1e-12)


def test_no_impact_is_recorded_with_inward_velocity(ref):
    # rho = 0, gamma = 0: a straight-line oscillation through the centre of amplitude 1 (to rounding)
    p = Parameters(gamma=0.0, omega=2.88587618350454, rho=0.0, mu=0.0, d=0.7913641666401567, phi=0.0, r_ratio=0.0)
    traj = ref.run(p, 0j, 1e-11 + 2.88587618350454j, 5.0)
    assert np.all(traj.impacts.rdot > 0)


def test_default_run_through_chatter_stays_inside(ref):
    p = REF.replace(gamma=0.2)
    traj = simulate(p, 0j, 0j, 50.0)
    assert len(traj.impacts) > 0
    t = traj.sample(5000)
    assert np.max(traj.r(t)) <= 1 + 1e-12


def test_liftoff_at_rounding_level_does_not_stall():
    """A lift-off whose flight grazes the stator within rounding at once: the crossing found there
    never lies before the lift-off point, so time advances and the run finishes in a few events."""
    p = Parameters(gamma=0.9308174741659798, omega=1.8969756864730352, rho=0.0, mu=0.03203641893996379,
                   d=0.03203641893996379, phi=-0.2717020802885477, r_ratio=4.559516843896395)
    traj = simulate(p, 1 + 0j, -0.2717020802885477 + 1.8969756864730352j, 98.61433052120861, max_events=1000)
    assert traj.status == "completed", traj.message
    assert any(c.kind == "sliding-forward" for c in traj.contact_intervals)


def test_an_initial_state_or_machine_of_the_wrong_kind_is_refused_by_name():
    import numpy as np

    from rotorcontact import ParameterError, simulate
    from reference_parameters import REF

    with pytest.raises(ParameterError, match="^u0 = True is a bool"):
        simulate(REF, u0=True, t_end=1.0)
    with pytest.raises(ParameterError, match="^t_end = '10' is text, not a number"):
        simulate(REF, t_end="10")
    for text in ("0.5", np.array("0.5")):
        with pytest.raises(ParameterError, match=r"^u0 = (np.str_\()?'0.5'\)? is text, not a number"):
            simulate(REF, u0=text, t_end=1.0)
    with pytest.raises(ParameterError, match="^machine = 'x' is not a Machine object"):
        simulate(REF, t_end=1.0, machine="x")
    a = simulate(REF, u0=np.array(0.1 + 0.1j), t_end=5.0)  # a 0-d array is its number
    b = simulate(REF, u0=0.1 + 0.1j, t_end=5.0)
    assert np.array_equal(a.records, b.records)


def test_si_results_need_the_machines_own_parameters():
    from rotorcontact import ParameterError, reference_machine, simulate

    m = reference_machine()
    with pytest.raises(ParameterError, match="^params are not the machine's \\(gamma = 0.3 against"):
        simulate(m.parameters().replace(gamma=0.3), t_end=5.0, machine=m)
    assert simulate(m.parameters(), t_end=5.0, machine=m).machine is m
