"""The batch kernel: the single simulator's results, many at a time, in parallel.

Claims checked here:

* an item of a batch is the single simulator run twice (transient, then the
  recorded window from the state where the transient stopped), bit for bit;
* a chain with the state carried along is the same runs one after the other;
* lanes shared out among threads and run on one core agree bit for bit;
* the simulations of a lane share one set of tables, and an item gives the same
  bits wherever it runs in a lane, after long or short, impacting or contact runs;
* the window's regime is `rotorcontact.simulation.motion.classify`'s verdict on the same
  window, and the period detection is `motion.detect_period`;
* ending the transient early (``settle``) changes nothing about where the
  motion goes, and its contact-free certificate is a true statement about
  free flight.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorcontact import ParameterError, simulate
from rotorcontact.studies.batch import (
    PARAMETER_ORDER,
    REGIME_NAMES,
    BatchResult,
    BatchSettings,
    SECTION_BYTES,
    check_batch_settings,
    final_state,
    lane_arguments,
    parameter_array,
    run_lane_block,
    run_lanes,
    simulate_batch,
)
from rotorcontact.studies.window import never_touches
from rotorcontact.simulation.motion import REGIME_ALIASES, REGIMES, canonical_regime, detect_period, regime_code
from reference_parameters import REF


# (gamma, u0, du0): rolling, periodic impacting, rub, kicked starts, no contact
CASES = [
    (0.05, 0j, 0j),
    (0.1, 0j, 0j),
    (0.15, 0j, 0j),
    (0.1, 0.3 + 0.2j, -0.5j),
    (0.2, 0.9 + 0j, 1 + 1j),
    (0.12, -0.2j, 0.8 + 0j),
    (0.3, 0.5 + 0.1j, 0j),
    (0.0825, 0j, 0j),
]


def _two_runs(p, u0, du0, st: BatchSettings):
    """The reference: the single simulator, transient then window."""
    tr1 = simulate(p, u0, du0, st.transient_time, max_events=st.n_transient)
    u, du, _ = final_state(tr1)
    tr2 = simulate(p, u, du, st.record_time, max_events=st.n_record)
    return tr1, tr2


def _same(a, b) -> bool:
    """Equal bit for bit, NaN included."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.fixture(scope="module")
def batch_cases():
    st = BatchSettings(n_transient=400, n_record=100)
    params = [REF.replace(gamma=g) for g, _, _ in CASES]
    res = simulate_batch(params, [c[1] for c in CASES], [c[2] for c in CASES], settings=st)
    return st, res


def test_each_item_is_the_single_simulator_bit_for_bit(batch_cases):
    st, res = batch_cases
    seen = set()
    for i, (g, u0, du0) in enumerate(CASES):
        tr1, tr2 = _two_runs(REF.replace(gamma=g), u0, du0, st)
        rec = tr2.records[:, :4]
        n = rec.shape[0]
        assert res.n_impacts[i] == n and res.transient_impacts[i] == len(tr1.records)
        for j, name in enumerate(("t", "theta", "rdot", "thetadot")):
            assert _same(getattr(res, name)[i, :n], rec[:, j]), (g, name)
        assert np.all(np.isnan(res.theta[i, n:]))
        u, du, kind = final_state(tr2)
        assert _same(res.final_u[i], u) and _same(res.final_du[i], du)
        assert res.t_window[i] == tr2.t_stop and res.t_transient[i] == tr1.t_stop
        assert res.n_contacts[i] == len(tr2.contact_intervals)
        seen.add(res.regime_names[i])
    # the cases cover impacting, rub and rolling motion
    assert {"periodic-impacting", "forward-rub", "backward-whirl"} <= seen


def test_regime_is_motion_classify_on_the_window(batch_cases):
    st, res = batch_cases
    for i, (g, u0, du0) in enumerate(CASES):
        _, tr2 = _two_runs(REF.replace(gamma=g), u0, du0, st)
        s = tr2.summary
        assert res.regime[i] == regime_code(s), (g, s)
        if s.motion == "periodic-impacting":
            assert res.impacts_per_period[i] == s.impacts_per_period
            assert res.period[i] == s.period
        else:
            assert res.impacts_per_period[i] == 0 and np.isnan(res.period[i])


def test_period_detection_matches_motion_detect_period(batch_cases):
    st, res = batch_cases
    for i, (g, u0, du0) in enumerate(CASES):
        _, tr2 = _two_runs(REF.replace(gamma=g), u0, du0, st)
        imp = tr2.impacts
        p, period = detect_period(imp.theta, imp.rdot, imp.thetadot, imp.t)
        if res.regime_names[i] in ("periodic-impacting", "irregular-impacting", "undetermined"):
            assert (p or 0) == res.impacts_per_period[i]


def test_parallel_and_single_core_kernels_agree_bit_for_bit():
    st = BatchSettings(n_transient=200, n_record=50)
    gammas = np.linspace(0.06, 0.2, 12)
    u0 = np.linspace(-0.5, 0.5, 12) * (1 + 0.5j)
    a = simulate_batch([REF.replace(gamma=g) for g in gammas], u0, 0j, settings=st, parallel=True)
    b = simulate_batch([REF.replace(gamma=g) for g in gammas], u0, 0j, settings=st, parallel=False)
    for name in ("t", "theta", "rdot", "thetadot", "regime", "final_u", "final_du", "period", "contact_time"):
        assert _same(getattr(a, name), getattr(b, name)), name


@pytest.mark.parametrize("carry", [False, True])
@pytest.mark.parametrize("n_lanes", [1, 2, 3, 7])
def test_every_lane_is_run_once_whatever_the_workers(n_lanes, carry):
    # threads share out the lanes: fewer lanes than threads, as many, and more; the threads may be more
    # than numba's
    st = BatchSettings(n_transient=120, n_record=30)
    rows = parameter_array([REF.replace(gamma=g) for g in np.linspace(0.07, 0.19, 2 * n_lanes)])
    rows = rows.reshape(n_lanes, 2, -1)
    u0 = np.linspace(-0.4, 0.4, 2 * n_lanes).reshape(n_lanes, 2) * (1 - 0.3j)
    du0 = np.zeros_like(u0)
    ref = run_lanes(rows, u0, du0, st, carry=carry, parallel=False)
    for workers in (2, 3, 5, 7, 11):
        got = run_lanes(rows, u0, du0, st, carry=carry, parallel=True, workers=workers)
        for g, r in zip(got, ref):
            assert _same(g, r), workers
    # the default, as many workers as the threads
    for g, r in zip(run_lanes(rows, u0, du0, st, carry=carry), ref):
        assert _same(g, r)
    # and each lane alone gives the same bits as among the others
    for lane in range(n_lanes):
        alone = run_lanes(rows[lane:lane + 1], u0[lane:lane + 1], du0[lane:lane + 1], st, carry=carry)
        for g, r in zip(alone, ref):
            assert _same(g[0], r[lane])


@pytest.mark.parametrize("carry", [False, True])
def test_blocks_of_lanes_fill_their_rows_with_the_bits_of_one_call(carry):
    st = BatchSettings(n_transient=120, n_record=30)
    rows = parameter_array([REF.replace(gamma=g) for g in np.linspace(0.07, 0.19, 14)]).reshape(7, 2, -1)
    u0 = np.linspace(-0.4, 0.4, 14).reshape(7, 2) * (1 - 0.3j)
    du0 = np.zeros_like(u0)
    ref = run_lanes(rows, u0, du0, st, carry=carry, parallel=False)
    args = lane_arguments(rows, u0, du0, st, carry=carry)
    # out of order, of uneven sizes, each written into its own rows and nowhere else
    args[-2].fill(np.pi)
    args[-1].fill(np.pi)
    written = np.zeros(7, bool)
    for start, stop in [(5, 7), (0, 1), (1, 5)]:
        run_lane_block(args, start, stop)
        written[start:stop] = True
        assert np.all(args[-2][~written] == np.pi) and np.all(args[-1][~written] == np.pi)
    for got, want in zip(args[-2:], ref):
        assert _same(got, want)


@pytest.mark.parametrize("start, stop", [(-1, 2), (0, 0), (3, 2), (0, 8), (7, 8), (1.5, 3)])
def test_a_block_of_lanes_must_lie_within_the_lanes(start, stop):
    st = BatchSettings(n_transient=10, n_record=5)
    args = lane_arguments(parameter_array([REF] * 7).reshape(7, 1, -1), np.zeros((7, 1)), np.zeros((7, 1)), st,
                          carry=False)
    with pytest.raises(ParameterError, match=r"^(start|stop) = .* is invalid"):
        run_lane_block(args, start, stop)


def test_workers_must_be_a_positive_integer():
    st = BatchSettings(n_transient=5, n_record=5)
    rows = parameter_array([REF, REF]).reshape(2, 1, -1)
    u0 = np.zeros((2, 1), dtype=complex)
    with pytest.raises(ParameterError, match="workers = 0 is invalid; allowed: an integer >= 1"):
        run_lanes(rows, u0, u0, st, carry=False, workers=0)


@pytest.mark.parametrize("settle", [0, 30])
def test_an_item_gives_the_same_bits_wherever_it_runs_in_a_lane(settle):
    # the items of CASES run one per lane, then all in one lane (in both orders): the tables the lane's
    # simulations share then hold the rows of longer runs, rolling and rubbing before each item
    st = BatchSettings(n_transient=400, n_record=100, settle=settle)
    rows = parameter_array([REF.replace(gamma=g) for g, _, _ in CASES])
    u0 = np.array([c[1] for c in CASES], dtype=complex)
    du0 = np.array([c[2] for c in CASES], dtype=complex)
    n = len(CASES)
    alone = run_lanes(rows[:, None], u0[:, None], du0[:, None], st, carry=False)
    for order in (np.arange(n), np.arange(n)[::-1]):
        lane = run_lanes(rows[None, order], u0[None, order], du0[None, order], st, carry=False, parallel=False)
        for got, ref in zip(lane, alone):
            assert _same(got[0], ref[order, 0])
    summary = alone[1][:, 0]
    res = BatchResult.from_arrays(alone[0][:, 0], summary, st)
    assert {"periodic-impacting", "forward-rub", "backward-whirl"} <= set(res.regime_names)


def test_carried_chain_is_the_runs_one_after_the_other():
    st = BatchSettings(n_transient=150, n_record=40)
    gammas = [0.14, 0.16, 0.18, 0.16]
    res = simulate_batch([REF.replace(gamma=g) for g in gammas], 0.2 + 0.1j, 0j, settings=st, carry=True)
    u, du = 0.2 + 0.1j, 0j
    for i, g in enumerate(gammas):
        _, tr2 = _two_runs(REF.replace(gamma=g), u, du, st)
        n = len(tr2.records)
        assert _same(res.theta[i, :n], tr2.records[:, 1])
        u, du, _ = final_state(tr2)
        assert _same(res.final_u[i], u) and _same(res.final_du[i], du)
    # and two chains at once give the same as each chain alone
    both = simulate_batch(
        [[REF.replace(gamma=g) for g in gammas], [REF.replace(gamma=g) for g in gammas[::-1]]],
        [0.2 + 0.1j, 0j], 0j, settings=st, carry=True,
    )
    assert _same(both.theta[0], res.theta)
    alone = simulate_batch([REF.replace(gamma=g) for g in gammas[::-1]], 0j, 0j, settings=st, carry=True)
    assert _same(both.theta[1], alone.theta)


def test_final_state_of_a_flight_is_the_exact_flow():
    p = REF.replace(gamma=0.3)
    tr = simulate(p, p.k + 0.05, 0j, 40.0)
    assert len(tr.impacts) == 0 and len(tr.contacts) == 0
    u, du, kind = final_state(tr)
    uu, dd = tr.state(tr.t_stop)
    assert kind == "flight" and u == uu and du == dd


def test_final_state_after_an_impact_is_the_post_impact_state():
    tr = simulate(REF.replace(gamma=0.1), 0j, 0j, 1e4, max_events=7)
    assert tr.status == "max-events" and len(tr.impacts) == 7
    u, du, kind = final_state(tr)
    assert kind == "flight"
    assert u == tr.impacts.point[-1] and du == tr.impacts.du_plus[-1]


def test_final_state_in_contact_restarts_in_contact_without_a_spurious_impact():
    p = REF.replace(gamma=0.15)
    tr = simulate(p, 0j, 0j, 2000.0)
    u, du, kind = final_state(tr)
    assert kind == "sliding-forward" and abs(abs(u) - 1.0) < 1e-15
    again = simulate(p, u, du, 200.0)
    assert len(again.impacts) == 0
    assert [c.kind for c in again.contact_intervals] == ["sliding-forward"]


def test_final_state_at_the_end_of_an_accumulation_is_where_contact_begins():
    """A run stopped right after a chatter sequence continues where the full run slides on."""
    from rotorcontact.simulation.contact import ACCUMULATION

    p = REF.replace(gamma=0.15)
    full = simulate(p, 0j, 0j, 500.0)
    i = [j for j, c in enumerate(full.contacts) if int(c[2]) == ACCUMULATION][0]
    flights_before = int(np.sum(full.flights[:, 0] <= full.contacts[i, 0]))
    short = simulate(p, 0j, 0j, 500.0, max_events=flights_before - 1)
    assert int(short.contacts[-1, 2]) == ACCUMULATION
    u, du, kind = final_state(short)
    slide = full.path[int(full.contacts[i + 1, 3])]  # first row of the sliding phase that follows
    assert kind == "accumulation"
    assert abs(np.angle(u) - slide[1]) < 1e-14
    assert abs((np.conj(u) * du).imag - slide[2]) < 1e-14


def test_settle_reaches_the_same_attractor():
    """Ending the transient once the impacts repeat leaves the recorded orbit unchanged."""
    full = BatchSettings(n_transient=2000, n_record=60)
    early = BatchSettings(n_transient=2000, n_record=60, settle=50)
    gammas = [0.09, 0.1, 0.12, 0.14, 0.15, 0.05, 0.3]
    u0 = [0j, 0.5 + 0j, -0.3j, 0.2 + 0.2j, 0j, 0j, 0.3 + 0j]
    params = [REF.replace(gamma=g) for g in gammas]
    a = simulate_batch(params, u0, 0j, settings=full)
    b = simulate_batch(params, u0, 0j, settings=early)
    assert a.regime_names.tolist() == b.regime_names.tolist()
    periodic = a.regime == REGIME_NAMES.index("periodic-impacting")
    assert periodic.sum() >= 3
    assert np.array_equal(a.impacts_per_period, b.impacts_per_period)
    # the settled transient is shorter, and the orbit is the same to the period tolerance
    assert np.all(b.transient_impacts[periodic] < a.transient_impacts[periodic])
    for name in ("rdot", "thetadot"):
        diff = np.abs(getattr(a, name)[periodic, -1] - getattr(b, name)[periodic, -1])
        assert np.all(diff < 1e-5), name
    assert np.allclose(a.period[periodic], b.period[periodic], rtol=0, atol=1e-6)


def test_contact_free_certificate_is_true_and_its_window_is_exact():
    p = REF.replace(gamma=0.3)
    pars = tuple(getattr(p, n) for n in ("gamma", "omega", "rho", "phi"))
    k = p.k
    rng = np.random.default_rng(3)
    certified = 0
    for _ in range(40):
        u = k + 0.05 * complex(*rng.normal(size=2))
        du = 0.05 * complex(*rng.normal(size=2))
        if abs(u) >= 1:
            continue
        if never_touches(u, du, *pars):
            certified += 1
            # free flight from there never reaches the stator
            tr = simulate(p, u, du, 300.0)
            assert len(tr.impacts) == 0 and len(tr.contacts) == 0
            r = np.abs(tr.U(np.linspace(0, 300.0, 3001)))
            assert r.max() < 1.0
            # and the closed-form window equals the simulator's
            st = BatchSettings(n_transient=0, n_record=10, t_record=77.0, settle=10)
            res = simulate_batch(p, u, du, settings=st)
            uu, dd, kind = final_state(tr if tr.t_stop == 77.0 else simulate(p, u, du, 77.0))
            assert res.regime_names[0] == "no-contact"
            assert _same(res.final_u[0], uu) and _same(res.final_du[0], dd)
    assert certified >= 5
    # a state that does reach the stator is never certified
    assert not never_touches(0.95 + 0j, 0.5 + 0j, *pars)


def test_independent_items_and_shapes():
    st = BatchSettings(n_transient=50, n_record=10, n_keep=3)
    u0 = np.zeros((2, 3), dtype=complex)
    res = simulate_batch(REF.replace(gamma=0.1), u0, 0j, settings=st)
    assert res.shape == (2, 3) and res.theta.shape == (2, 3, 3)
    # the kept impacts are the last ones of the window
    single = simulate_batch(REF.replace(gamma=0.1), 0j, 0j, settings=BatchSettings(n_transient=50, n_record=10))
    assert _same(res.theta[0, 0], single.theta[0, -3:])


def test_parameter_rows_and_validation():
    rows = parameter_array([REF, REF.replace(gamma=0.2)])
    assert rows.shape == (2, 7) and rows[1, PARAMETER_ORDER.index("gamma")] == 0.2
    bad = rows.copy()
    bad[0, PARAMETER_ORDER.index("d")] = 1.5
    with pytest.raises(ParameterError, match="d = 1.5"):
        simulate_batch(bad, 0j, 0j, n_transient=1, n_record=1)
    with pytest.raises(ParameterError, match="outside the clearance"):
        simulate_batch(REF, 1.2 + 0j, 0j, n_transient=1, n_record=1)
    with pytest.raises(ParameterError, match="n_record"):
        BatchSettings(n_record=0)
    with pytest.raises(ParameterError, match="settle"):
        BatchSettings(settle=-1)
    with pytest.raises(ParameterError, match="shape"):
        simulate_batch(rows, np.zeros(3), 0j, n_transient=1, n_record=1)
    with pytest.raises(ParameterError, match="rows of 7"):
        simulate_batch(np.zeros((2, 5)), 0j, 0j)


def test_one_vocabulary_of_regimes_with_the_former_names_as_aliases():
    # the batch kernel's regime names are those of a single simulation (motion.classify)
    assert REGIME_NAMES[: len(REGIMES)] == REGIMES
    assert "rub" not in REGIME_NAMES and "rolling" not in REGIME_NAMES
    assert REGIME_ALIASES == {"rub": "forward-rub", "rolling": "backward-whirl"}
    assert canonical_regime("rub") == "forward-rub" and canonical_regime("rolling") == "backward-whirl"
    assert canonical_regime("B1,d") == "B1,d" and canonical_regime("mixed") == "mixed"


def test_the_chatter_criteria_are_the_kernel_arguments_with_the_defaults_of_simulate():
    import inspect

    from rotorcontact.simulation.simulator import CHATTER_DEFAULTS, simulate_kernel

    names = list(inspect.signature(simulate_kernel.py_func).parameters)
    assert list(CHATTER_DEFAULTS) == names[names.index("max_events") + 1 : names.index("stop_on_chatter")]
    front = inspect.signature(simulate).parameters
    assert {name: front[name].default for name in CHATTER_DEFAULTS} == CHATTER_DEFAULTS
    assert dict(BatchSettings().chatter) == CHATTER_DEFAULTS


def test_bad_batches_are_refused_by_name():
    from rotorcontact.model.params import MAX_VELOCITY

    with pytest.raises(ParameterError, match="^du0 = .* is too fast"):  # the bound of simulate
        simulate_batch(REF, du0=[0j, 2 * MAX_VELOCITY + 0j], n_transient=2, n_record=1)
    with pytest.raises(ParameterError, match="^the batch is empty"):
        simulate_batch(REF, u0=[], n_transient=2, n_record=1)
    with pytest.raises(ParameterError, match=r"^foo = 3 is not a setting \(unknown setting 'foo'\); allowed: "
                                             r"n_transient"):
        simulate_batch(REF, foo=3)


def test_sections_beyond_the_machines_memory_are_refused_before_the_run(monkeypatch):
    import rotorcontact.studies.batch as batch

    assert SECTION_BYTES == 8 * len(batch.SECTION_COLUMNS)
    # a machine of 2 GiB does not hold the sections of 10^8 impacts (2.98 GiB)
    monkeypatch.setattr(batch, "physical_memory", lambda: 2 * 2**30)
    with pytest.raises(ParameterError, match=r"^n_record = 100000000, n_keep = None: 1 simulation keeping "
                                             r"100000000 impacts each need 2\.98 GiB of sections"):
        simulate_batch(REF, n_record=10**8, t_record=1e7)
    # the bound is the memory itself: three simulations keeping 100 impacts need 300 * SECTION_BYTES
    monkeypatch.setattr(batch, "physical_memory", lambda: 300 * SECTION_BYTES)
    settings = BatchSettings(n_transient=5, n_record=100)
    assert check_batch_settings(settings, 3) is settings
    with pytest.raises(ParameterError, match="allowed: at most this machine's memory"):
        check_batch_settings(settings, 4)
    with pytest.raises(ParameterError, match="keep fewer impacts .n_keep., run fewer simulations or split"):
        check_batch_settings(BatchSettings(n_record=101), 3)
    assert check_batch_settings(BatchSettings(n_record=10**6, n_keep=100), 3).keep == 100
    res = simulate_batch(REF, u0=[0j, 0.1 + 0j, 0.2 + 0j], settings=settings)  # fits: runs
    assert res.shape == (3,)
    with pytest.raises(ParameterError, match="need"):
        simulate_batch(REF, u0=[0j, 0.1 + 0j, 0.2 + 0j, 0.3 + 0j], settings=settings)
    # where the system does not tell its memory, nothing is refused for it
    monkeypatch.setattr(batch, "physical_memory", lambda: None)
    assert check_batch_settings(BatchSettings(n_record=10**8, t_record=1e7), 10**6) is not None


def test_physical_memory_is_positive_where_the_system_tells_it():
    from rotorcontact.studies.batch import physical_memory

    have = physical_memory()
    assert have is None or have > 2**20


@pytest.mark.parametrize("bad", ["x", 3, {"n_record": 5}, BatchSettings])
def test_settings_that_are_not_batch_settings_are_refused(bad):
    with pytest.raises(ParameterError, match=r"^settings = .* is not a BatchSettings"):
        simulate_batch(REF, settings=bad)
    with pytest.raises(ParameterError, match=r"^settings = .* is not a BatchSettings"):
        check_batch_settings(bad, 1)


@pytest.mark.parametrize("name, value", [("u0", "0.5"), ("u0", np.array(["0.5"])), ("du0", "1"), ("du0", ["1", "2j"]),
                                         ("u0", True), ("du0", [True, False]), ("u0", [0.1, True]),
                                         ("u0", [[0.1], [0.1, 0.2]]), ("u0", None)])
def test_initial_states_that_are_not_complex_numbers_are_refused(name, value):
    with pytest.raises(ParameterError, match=rf"^{name} = .* is not a complex number or an array of them"):
        simulate_batch(REF, **{name: value}, n_transient=2, n_record=1)


@pytest.mark.parametrize("name", ["parallel", "carry"])
def test_yes_no_flags_of_a_batch_are_bools(name):
    with pytest.raises(ParameterError, match=rf"^{name} = 'False' is invalid; allowed: True or False$"):
        simulate_batch(REF, **{name: "False"}, n_transient=2, n_record=1)


@pytest.mark.parametrize("chatter", ["x", [1, 2], 3])
def test_chatter_criteria_are_a_dict(chatter):
    with pytest.raises(ParameterError, match=r"^chatter = .* is invalid; allowed: a dict of criteria by name"):
        BatchSettings(chatter=chatter)


def test_settings_bound_the_events_and_the_times_of_a_simulation():
    from rotorcontact.model.params import MAX_T_END
    from rotorcontact.studies.batch import MAX_BATCH_EVENTS

    for name in ("n_transient", "n_record", "n_keep", "settle"):
        with pytest.raises(ParameterError, match=rf"^{name} = {MAX_BATCH_EVENTS + 1} is invalid; allowed: an integer"):
            BatchSettings(**{name: MAX_BATCH_EVENTS + 1})
    for name in ("t_transient", "t_record"):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            BatchSettings(**{name: 2 * MAX_T_END})
        assert getattr(BatchSettings(**{name: MAX_T_END}), name) == MAX_T_END
    # the default time, 5 per event (at least 100), stops at the bound
    assert BatchSettings(n_transient=10, n_record=1000).transient_time == 100.0
    assert BatchSettings(n_record=1000).record_time == 5000.0
    assert BatchSettings(n_transient=10**7).transient_time == MAX_T_END
    assert BatchSettings(n_record=2 * 10**6 + 1).record_time == MAX_T_END
    assert BatchSettings(n_transient=10**7, t_transient=1e6).transient_time == 1e6


def test_the_count_of_simulations_is_a_whole_number():
    for bad in (0, -1, "x", 1.5, None):
        with pytest.raises(ParameterError, match=r"^simulations = .* is invalid; allowed: an integer >= 1$"):
            check_batch_settings(BatchSettings(), bad)



def test_the_final_state_needs_a_trajectory():
    from rotorcontact.studies.batch import final_state

    traj = simulate(REF, 0.5, 0.0, 20.0)
    u, du, kind = final_state(traj)
    assert isinstance(u, complex) and isinstance(kind, str)
    for bad in (None, REF):
        with pytest.raises(ParameterError, match=r"^traj = .* is not a Trajectory object"):
            final_state(bad)


def test_the_lane_stages_refuse_what_is_not_lanes_by_name():
    """`run_lanes` (and the GPU's `launch_lanes`, before it needs a GPU) take the lanes `parameter_array`
    builds; `BatchResult.from_arrays` the kernel's arrays."""
    from rotorcontact.studies.batch import BatchResult, BatchSettings, check_lanes, parameter_array, run_lanes
    from rotorcontact.studies.cuda_batch import launch_lanes

    st = BatchSettings(n_transient=10, n_record=5)
    params = parameter_array([REF])[:, None, :]
    u0 = np.zeros((1, 1), complex)
    good = check_lanes(params, u0, u0, st)
    assert good[0].shape == (1, 1, 7) and good[1].dtype == complex
    cases = [
        ((None, u0, u0, st), "params = None"),
        ((params[..., :6], u0, u0, st), "params = "),
        ((np.where(True, np.nan, params), u0, u0, st), "params = "),
        ((params, np.zeros((2, 1), complex), u0, st), "u0 = "),
        ((params, u0, np.array([[complex(np.inf, 0)]]), st), "du0 = "),
        ((params, u0, u0, {"n_transient": 10}), "settings = "),
    ]
    for args, words in cases:
        for stage in (run_lanes, launch_lanes):
            with pytest.raises(ParameterError, match=words):
                stage(*args, carry=False)
    sections, summary = run_lanes(params, u0, u0, st, carry=False)
    assert BatchResult.from_arrays(sections, summary, st).shape == (1, 1)
    for bad in ((None, summary, st), (sections, summary[..., :3], st), (sections, summary, None)):
        with pytest.raises(ParameterError):
            BatchResult.from_arrays(*bad)


@pytest.mark.parametrize("given", ["one", "list", "array"])
def test_a_forced_response_beyond_the_simulators_range_is_refused_however_the_parameters_come(given):
    # |k| = rho / |omega^2 - 1 + i gamma| = 2.2e6 clearances at rho = 1e6: one set of parameters is checked as
    # every row of a list or an array
    far = REF.replace(rho=1e6)
    assert abs(far.k) > 1e3
    value = {"one": far, "list": [REF, far], "array": np.array([[getattr(q, n) for n in PARAMETER_ORDER]
                                                                  for q in (REF, far)])}[given]
    with pytest.raises(ParameterError, match=r"forced response \|k\| = .* is beyond the simulator's accurate range"):
        parameter_array(value)
