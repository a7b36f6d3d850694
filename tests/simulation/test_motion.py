"""Summary of the long-run motion: period detection on synthetic impact sequences and
the classification of real runs (no contact, periodic impacting, irregular, chatter)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import Parameters
from rotorcontact.simulation.motion import classify, detect_period
from reference_parameters import REF


def synthetic(p, n=60, noise=0.0, seed=0, theta_base=None):
    """n impacts repeating every p impacts; the period is the sum of p different intervals."""
    rng = np.random.default_rng(seed)
    base_dt = rng.uniform(0.5, 2.0, p)
    base_th = rng.uniform(-math.pi, math.pi, p) if theta_base is None else np.asarray(theta_base)
    base_rd = rng.uniform(0.1, 1.0, p)
    base_td = rng.uniform(-2, 1, p)
    idx = np.arange(n) % p
    t = np.cumsum(base_dt[idx])
    th = base_th[idx] + noise * rng.standard_normal(n)
    th = np.angle(np.exp(1j * th))
    return th, base_rd[idx] + noise * rng.standard_normal(n), base_td[idx], t, float(base_dt.sum())


@pytest.mark.parametrize("p", [1, 2, 3, 5, 16])
def test_detect_period_on_exact_sequences(p):
    th, rd, td, t, period = synthetic(p, n=max(60, 4 * p + 10))
    got_p, got_T = detect_period(th, rd, td, t)
    assert got_p == p
    assert got_T == pytest.approx(period, rel=1e-12)


def test_detect_period_tolerates_rounding_but_not_real_differences():
    th, rd, td, t, period = synthetic(2, noise=1e-9)
    assert detect_period(th, rd, td, t)[0] == 2
    th, rd, td, t, period = synthetic(2, noise=1e-3)
    assert detect_period(th, rd, td, t) == (None, None)


def test_detect_period_period_longer_than_the_cap():
    th, rd, td, t, _ = synthetic(17, n=200)
    assert detect_period(th, rd, td, t) == (None, None)


def test_detect_period_across_the_branch_cut():
    """theta alternating just above -pi and just below pi is one angle."""
    n = 40
    th = np.where(np.arange(n) % 2 == 0, math.pi - 1e-9, -math.pi + 1e-9)
    rd = np.full(n, 0.5)
    td = np.full(n, -1.0)
    t = 2.5 * np.arange(1, n + 1)
    p, T = detect_period(th, rd, td, t)
    assert p == 1 and T == pytest.approx(2.5)


def test_detect_period_too_few_impacts():
    th, rd, td, t, _ = synthetic(1, n=5)
    assert detect_period(th, rd, td, t) == (None, None)


def test_summary_no_contact(ref):
    p = REF.replace(gamma=0.3)
    tr = ref.run(p, p.k, 0j, 200.0)
    s = tr.summary
    assert s.motion == "no-contact"
    assert s.n_impacts == 0
    assert s.period is None and s.impacts_per_period is None


def test_summary_early_impacts_then_settling_is_no_contact(ref):
    """Impacts only in the first part of the run, then free decay to the equilibrium."""
    p = Parameters(gamma=0.3, omega=0.76, rho=0.1, mu=0.15, d=0.9, phi=0.0, r_ratio=50.0)
    tr = ref.run(p, 0.5 + 0j, 2.0 + 0.5j, 300.0)
    assert len(tr.impacts) >= 1
    assert tr.impacts.t[-1] < 100.0
    assert tr.summary.motion == "no-contact"


def test_summary_periodic(ref):
    p = REF.replace(gamma=0.1)
    tr = ref.run(p, 0j, 0j, 1000.0)
    s = tr.summary
    assert s.motion == "periodic-impacting"
    assert s.impacts_per_period == 1
    assert s.period == pytest.approx(tr.impacts.t[-1] - tr.impacts.t[-2], rel=1e-12)
    d = s.to_dict()
    assert d["motion"] == "periodic-impacting" and d["impacts_per_period"] == 1
    assert d["n_impacts"] == len(tr.impacts)


def test_summary_irregular(ref):
    """gamma = 0.08 from rest: impacts keep coming without any period of up to 16 impacts."""
    p = REF.replace(gamma=0.08)
    # the chaotic set can be left for contact, and which runs do so is as sensitive to rounding as
    # the trajectory: take the first of several starts near rest that keeps impacting to the end
    for u0 in (0j, 1e-3, 1e-3j, -1e-3, -1e-3j, 2e-3, 2e-3j, -2e-3, -2e-3j, 3e-3, 3e-3j, -3e-3):
        tr = ref.run(p, u0, 0j, 1000.0)
        imp = tr.impacts
        late = imp.t > 2000.0 / 3.0
        if tr.status == "completed" and not tr.contact_intervals and late.sum() > 50:
            break
    else:
        pytest.fail("no start near rest stays on the chaotic set")
    # independent check: no p <= 16 makes the last 40 impacts repeat to 1e-6
    th = imp.theta[-60:]
    for p_ in range(1, 17):
        assert np.max(np.abs(np.angle(np.exp(1j * (th[p_:] - th[:-p_]))))) > 1e-6
    assert tr.summary.motion == "irregular"
    assert tr.summary.period is None


def test_summary_chatter(ref):
    tr = ref.run(REF.replace(gamma=0.2), 0j, 0j, 100.0, stop_on_chatter=True)
    assert tr.status == "chatter"
    assert tr.summary.motion == "chatter"


def test_summary_undetermined_with_few_impacts(ref):
    tr = ref.run(REF.replace(gamma=0.1), 0j, 0j, 1000.0, max_impacts=5)
    assert tr.summary.motion == "undetermined"
    assert classify(tr) == tr.summary


def test_a_failed_run_claims_no_regime():
    import dataclasses

    from rotorcontact import simulate

    tr = simulate(REF.replace(gamma=0.1), 0j, 0j, 50.0)
    failed = dataclasses.replace(tr, status="failed", failure="the impact search exceeded its step limit")
    s = failed.summary
    assert s.motion == "failed" and s.regime is None and s.contact_fraction is None
    assert s.n_impacts == len(tr.impacts)
    assert failed.to_dict()["summary"]["regime"] is None


def test_regime_codes_name_the_regimes_then_undetermined_and_failed():
    from rotorcontact.simulation.motion import REGIME_NAMES, REGIMES, MotionSummary, regime_code

    assert REGIME_NAMES == (*REGIMES, "undetermined", "failed")
    for name in REGIMES:
        assert REGIME_NAMES[regime_code(MotionSummary("contact", name, 0))] == name
    assert REGIME_NAMES[regime_code(MotionSummary("undetermined", "irregular-impacting", 3))] == "undetermined"
    assert REGIME_NAMES[regime_code(MotionSummary("failed", None, 3, contact_fraction=None))] == "failed"


def test_the_motion_helpers_refuse_what_they_cannot_read():
    from rotorcontact import ParameterError
    from rotorcontact.simulation.motion import canonical_regime, classify, detect_period, regime_code

    t = np.arange(20.0)
    ones = np.ones(20)
    assert detect_period(ones, ones, ones, t) == (1, 1.0)
    for args in ((ones, ones, ones, t[:5]), (None, ones, ones, t), (ones.reshape(4, 5), ones, ones, t),
                 (["a"] * 20, ones, ones, t)):
        with pytest.raises(ParameterError, match=r"^theta, rdot, thetadot, t = .* are invalid; allowed: four 1-D"):
            detect_period(*args)
    with pytest.raises(ParameterError, match=r"^max_p = 0 is invalid"):
        detect_period(ones, ones, ones, t, max_p=0)
    with pytest.raises(ParameterError, match=r"^tol = -1.0 is invalid"):
        detect_period(ones, ones, ones, t, tol=-1.0)
    assert canonical_regime("rub") == "forward-rub" and canonical_regime("B1,d") == "B1,d"
    for bad in (None, 1):
        with pytest.raises(ParameterError, match=r"^name = .* is invalid; allowed: a regime or class name"):
            canonical_regime(bad)
    with pytest.raises(ParameterError, match=r"^summary = None is not a MotionSummary object"):
        regime_code(None)
    with pytest.raises(ParameterError, match=r"^traj = None is not a Trajectory object"):
        classify(None)
