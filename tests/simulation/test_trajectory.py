"""The Trajectory result: exact dense output between impacts (against solve_ivp and
the mpmath closed form), the impact table, sampling, status, message and the
JSON-ready dict."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rotorcontact import ParameterError, Parameters, reference_machine
from reference_parameters import REF


@pytest.fixture(scope="module")
def traj(ref):
    return ref.run(REF.replace(gamma=0.1), 0j, 0j, 60.0, impacts_only=True)


def segments(traj):
    """(t_start, t_next, U, U') of each free flight, from the impact table."""
    imp = traj.impacts
    starts = np.concatenate(([0.0], imp.t))
    ends = np.concatenate((imp.t, [traj.t_stop]))
    us = np.concatenate(([traj.u0], imp.point))
    dus = np.concatenate(([traj.du0], imp.du_plus))
    return list(zip(starts, ends, us, dus))


def test_dense_output_matches_solve_ivp_between_impacts(ref, traj):
    p = traj.params
    rng = np.random.default_rng(7)
    segs = segments(traj)
    assert len(segs) > 15
    worst = 0.0
    for t0, t1, u, du in segs:
        times = np.sort(rng.uniform(t0, t1, 6))
        u_ref, du_ref = ref.ivp_state(p, t0, complex(u), complex(du), times)
        u_lib, du_lib = traj.state(times)
        worst = max(worst, np.max(np.abs(u_lib - u_ref)), np.max(np.abs(du_lib - du_ref)))
    assert worst < 1e-9


def test_dense_output_matches_mpmath_closed_form(ref, traj):
    p = traj.params
    rng = np.random.default_rng(8)
    for t0, t1, u, du in segments(traj)[::3]:
        fl = ref.flight(p, complex(u), complex(du))
        for t in rng.uniform(t0, t1, 3):
            ue, due = fl.state(t - t0)
            u_lib, du_lib = traj.state(t)
            assert abs(complex(u_lib) - complex(ue)) < 1e-13
            assert abs(complex(du_lib) - complex(due)) < 1e-13


def test_dense_output_against_an_independent_full_integration(ref, traj):
    """solve_ivp with its own impacts and restarts: the whole trajectory agrees to 1e-7."""
    p = traj.params
    rows, segs = ref.ivp_simulate(p, traj.u0, traj.du0, 10_000, t_end=traj.t_stop)
    assert len(rows) == len(traj.impacts)
    rng = np.random.default_rng(9)
    starts = [s[0] for s in segs] + [traj.t_stop]
    for j, (t0, u, du) in enumerate(segs):
        times = np.sort(rng.uniform(t0, starts[j + 1], 3))
        # keep clear of the impacts, where a time shift of 1e-9 changes the velocity by O(1)
        times = times[(times > t0 + 1e-6) & (times < starts[j + 1] - 1e-6)]
        if times.size == 0:
            continue
        u_ref, du_ref = ref.ivp_state(p, t0, u, du, times)
        u_lib, du_lib = traj.state(times)
        assert np.max(np.abs(u_lib - u_ref)) < 1e-7
        assert np.max(np.abs(du_lib - du_ref)) < 1e-7


def test_state_at_and_around_impacts(traj):
    imp = traj.impacts
    u0, du0 = traj.state(0.0)
    assert complex(u0) == traj.u0 and complex(du0) == traj.du0
    for j in range(len(imp)):
        u, du = traj.state(imp.t[j])
        assert abs(complex(u) - imp.point[j]) < 1e-15 * 4
        assert abs(complex(du) - imp.du_plus[j]) < 1e-13  # just after the impact
        # just before: radius below 1, radial velocity close to the table's rdot
        r, th, rdot, thetadot = traj.polar(imp.t[j] - 1e-8)
        assert r < 1
        assert abs(rdot - imp.rdot[j]) < 1e-6
        assert abs(thetadot - imp.thetadot[j]) < 1e-6


def test_frames_and_polar_consistency(traj):
    # (the run starts at the centre U = 0, where the polar angle is undefined)
    t = np.linspace(1e-3, traj.t_stop, 777)
    u, du = traj.state(t)
    np.testing.assert_array_equal(traj.U(t), u)
    np.testing.assert_array_equal(traj.dU(t), du)
    np.testing.assert_allclose(traj.Z(t), u * np.exp(1j * t), rtol=0, atol=1e-15)
    np.testing.assert_allclose(traj.r(t), np.abs(u), rtol=0, atol=0)
    th = traj.theta(t)
    assert np.all(th > -math.pi) and np.all(th <= math.pi)
    np.testing.assert_allclose(np.exp(1j * th), u / np.abs(u), rtol=0, atol=1e-14)
    r, th2, rdot, thetadot = traj.polar(t)
    np.testing.assert_allclose(r, np.abs(u), rtol=0, atol=1e-15)
    np.testing.assert_allclose(th2, th, rtol=0, atol=0)
    np.testing.assert_allclose(rdot, (np.conj(u) * du).real / np.abs(u), rtol=0, atol=1e-13)
    np.testing.assert_allclose(thetadot, (np.conj(u) * du).imag / np.abs(u) ** 2, rtol=0, atol=1e-13)
    assert np.all(r <= 1 + 1e-12)
    t2 = t.reshape(37, 21)
    assert traj.U(t2).shape == (37, 21)


def test_theta_wraps_to_minus_pi_pi(ref):
    # a flight along the negative real axis: theta = pi, never -pi
    p = Parameters(gamma=0.1, omega=0.8, rho=0.0, mu=0.1, d=0.9, phi=0.0, r_ratio=0.0)
    tr = ref.run(p, -0.5 + 0j, -0.1 - 0.5j, 3.0)
    th = tr.theta(np.array([0.0]))
    assert th[0] == pytest.approx(math.pi) and th[0] > 0


def test_impact_table(traj):
    imp = traj.impacts
    p = traj.params
    n = len(imp)
    assert n > 10
    for name in ("t", "theta", "rdot", "thetadot", "rdot_plus", "thetadot_plus", "v_rel",
                 "normal_impulse", "tangential_impulse", "point"):
        assert len(getattr(imp, name)) == n
    assert np.all(np.diff(imp.t) > 0)
    assert imp.t[0] > 0 and imp.t[-1] <= traj.t_stop
    assert np.all(imp.theta > -math.pi) and np.all(imp.theta <= math.pi)
    np.testing.assert_allclose(np.abs(imp.point), 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(imp.point, np.exp(1j * imp.theta), rtol=0, atol=1e-15)
    assert np.all(imp.rdot > 0)
    np.testing.assert_allclose(imp.rdot_plus, -p.d * imp.rdot, rtol=1e-15)


def test_sample_times(traj):
    s = traj.sample(500)
    assert s[0] == 0.0 and s[-1] == traj.t_stop
    assert np.all(np.diff(s) > 0)
    assert set(traj.impacts.t).issubset(set(s))
    assert len(s) >= 500


TIME_METHODS = ("state", "U", "polar", "in_contact", "contact_forces", "friction_power")


@pytest.mark.parametrize("method", TIME_METHODS)
def test_state_rejects_times_outside_the_run(traj, method):
    for bad in (-1e-3, traj.t_stop + 1.0, math.nan, math.inf):
        with pytest.raises(ParameterError) as exc:
            getattr(traj, method)(bad)
        assert "t must lie in" in str(exc.value)


@pytest.mark.parametrize("method", TIME_METHODS)
@pytest.mark.parametrize("bad", ["1", [True], True, 1 + 0j, None])
def test_state_refuses_what_is_not_a_time(traj, bad, method):
    with pytest.raises(ParameterError, match=r"^t = .* is invalid; allowed: real numbers in \[0, t_stop\]"):
        getattr(traj, method)(bad)


@pytest.mark.parametrize("n", [-1, 1, 2.5, None, True, 10**9])
def test_sample_refuses_a_bad_count(traj, n):
    with pytest.raises(ParameterError, match="^n = "):
        traj.sample(n)


def test_status_message_success(ref, traj):
    assert traj.status == "completed" and traj.success
    assert "60" in traj.message and str(len(traj.impacts)) in traj.message
    capped = ref.run(traj.params, 0j, 0j, 60.0, max_impacts=3)
    assert capped.status in ref.MAX_STATUSES and not capped.success
    assert "3" in capped.message
    chat = ref.run(REF.replace(gamma=0.2), 0j, 0j, 100.0, stop_on_chatter=True)
    assert chat.status == "chatter" and not chat.success
    assert "chatter" in chat.message and f"{chat.t_stop:.6g}"[:6] in chat.message


def test_dense_output_stays_inside_up_to_the_chatter_stop(ref):
    traj = ref.run(REF.replace(gamma=0.2), 0j, 0j, 100.0, stop_on_chatter=True)
    assert traj.status == "chatter"
    t = np.linspace(traj.impacts.t[-1], traj.t_stop, 1001)
    assert np.max(traj.r(t)) <= 1 + 1e-12


def test_to_dict_is_json_ready(traj):
    d = traj.to_dict()
    for key in ("parameters", "status", "impacts", "summary"):
        assert key in d
    assert d["parameters"] == traj.params.as_dict()
    assert d["status"] == traj.status
    assert len(d["impacts"]) == len(traj.impacts)
    first = d["impacts"][0]
    for key in ("t", "theta", "rdot", "thetadot", "rdot_plus", "thetadot_plus", "v_rel",
                "normal_impulse", "tangential_impulse"):
        assert isinstance(first[key], float)
    assert first["t"] == traj.impacts.t[0] and first["rdot"] == traj.impacts.rdot[0]
    json.dumps(d, allow_nan=False)


def test_to_dict_with_machine_has_si_values(ref):
    m = reference_machine()
    tr = ref.run(m.parameters(), 0j, 0j, 60.0, machine=m)
    d = tr.to_dict()
    assert "machine" in d and d["machine"]["speed"] == 184.2
    if d["impacts"]:
        row = d["impacts"][0]
        assert row["t_s"] == pytest.approx(row["t"] / 184.2, rel=1e-15)
        assert row["normal_impulse_Ns"] == pytest.approx(
            row["normal_impulse"] * 50.0 * 0.7e-3 * 184.2, rel=1e-14
        )
    json.dumps(d, allow_nan=False)


def test_state_between_the_last_impact_of_a_chatter_stop_and_the_accumulation_point(ref):
    """From the last resolved impact to the accumulation point the rotor stays on the stator."""
    traj = ref.run(REF.replace(gamma=0.2), 0j, 0j, 100.0, stop_on_chatter=True)
    assert traj.status == "chatter"
    imp = traj.impacts
    assert traj.t_stop > imp.t[-1]
    t = np.linspace(imp.t[-1], traj.t_stop, 101)
    r, th, rdot, thetadot = traj.polar(t)
    np.testing.assert_allclose(r, 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(rdot, 0.0, rtol=0, atol=1e-15)
    # it leaves from the last impact point; its tangential velocity differs from the one after
    # that impact by at most the friction of the remaining bounces, mu sum_j (1+d) d^j rdot
    assert abs(complex(traj.U(imp.t[-1])) - imp.point[-1]) < 1e-15
    d, mu = traj.params.d, traj.params.mu
    tail = mu * imp.normal_impulse[-1] * d / (1 - d)
    assert np.all(np.abs(thetadot - imp.thetadot_plus[-1]) <= tail)


def test_to_dict_keeps_the_first_and_last_impacts_past_max_rows():
    from rotorcontact import simulate

    tr = simulate(REF.replace(gamma=0.1), 0j, 0j, 400.0)
    n = len(tr.impacts)
    assert n > 100
    d = tr.to_dict(max_rows=11)
    assert len(d["impacts"]) == 11
    assert d["impacts_total"] == n and d["impacts_truncated"] is True
    assert [row["t"] for row in d["impacts"]] == list(tr.impacts.t[:5]) + list(tr.impacts.t[-6:])
    assert d["summary"]["n_impacts"] == n
    json.dumps(d, allow_nan=False)
    # no more impacts than the limit: the same keys as without it
    full = tr.to_dict(max_rows=n)
    assert full.keys() == tr.to_dict().keys()
    assert "impacts_truncated" not in full and "impacts_total" not in full
    assert len(full["impacts"]) == n


def test_to_dict_keeps_the_first_and_last_contact_intervals_past_max_rows():
    from rotorcontact import simulate

    base = REF.replace(gamma=0.15)
    for changes in (dict(d=0.3, mu=0.6, omega=0.9), dict(d=0.3, mu=0.6, omega=1.1), dict(d=0.3, mu=0.6)):
        tr = simulate(base.replace(**changes), 0.5, 1.5j, 500.0)
        if len(tr.contact_intervals) >= 3:
            break
    intervals = tr.contact_intervals
    assert len(intervals) >= 3
    d = tr.to_dict(max_rows=2)
    assert d["contact_intervals_total"] == len(intervals) and d["contact_intervals_truncated"] is True
    assert d["contact_intervals"] == [intervals[0].to_dict(), intervals[-1].to_dict()]


@pytest.mark.parametrize("bad", [0, 1, 2.5, True, "10"])
def test_to_dict_refuses_a_bad_max_rows(traj, bad):
    with pytest.raises(ParameterError, match="max_rows"):
        traj.to_dict(max_rows=bad)


@pytest.mark.parametrize("bad", ["x", [1, 2], ("x",), 3])
def test_contact_dicts_refuses_what_is_not_a_list_of_intervals(bad):
    from rotorcontact import simulate

    t = simulate(REF.replace(gamma=0.15, d=0.3, mu=0.6), 0.5, 1.5j, 200.0)
    assert t.contact_intervals
    assert t.contact_dicts(list(t.contact_intervals[:1])) == t.contact_dicts()[:1]
    with pytest.raises(ParameterError, match=r"^intervals = .* allowed: a list of ContactInterval"):
        t.contact_dicts(bad)


@pytest.mark.parametrize("bad", ["x", REF])
def test_the_impact_table_refuses_what_is_not_a_machine(traj, bad):
    assert traj.impacts.to_dicts(reference_machine())[0]["t_s"] > 0.0
    with pytest.raises(ParameterError, match=r"^machine = .* is not a Machine object"):
        traj.impacts.to_dicts(bad)


@pytest.mark.parametrize("t_end", [1e3, 1e5, 1e7])
def test_a_slide_at_rest_on_the_stable_pseudo_equilibrium_stays_there_until_the_end(t_end):
    from rotorcontact import simulate
    from rotorcontact.analysis.equilibria import pseudo_equilibria

    p = Parameters.reference()
    stable = [pe for pe in pseudo_equilibria(p) if pe.exists and pe.stable]
    assert len(stable) == 1
    tr = simulate(p, t_end=t_end)
    last = tr.contact_intervals[-1]
    assert last.kind == "sliding-forward" and last.t_end == t_end
    t = np.linspace(last.t_start + 100.0, t_end, 1001)
    r, theta, rdot, thetadot = tr.polar(t)
    # the analytic pseudo-equilibrium, whatever the length of the hold
    np.testing.assert_allclose(theta, stable[0].theta, rtol=0, atol=1e-8)
    np.testing.assert_allclose(thetadot, 0.0, rtol=0, atol=1e-9)
    n, f = tr.contact_forces(t)
    assert np.all(n > 0.0) and np.allclose(f, -p.mu * n, rtol=1e-12)
    assert np.allclose(n, stable[0].normal_force, rtol=1e-8)


def test_an_impact_table_needs_impact_records():
    from rotorcontact import simulate
    from rotorcontact.simulation.trajectory import ImpactTable

    traj = simulate(REF, 0.5, 0.0, 50.0)
    assert len(ImpactTable(traj.records)) == len(traj.impacts)
    for bad in (None, "x", np.zeros(5), np.zeros((3, 2)), traj.records.tolist()):
        with pytest.raises(ParameterError, match=r"^records = .* is invalid; allowed: the \(n, 14\) float array"):
            ImpactTable(bad)
