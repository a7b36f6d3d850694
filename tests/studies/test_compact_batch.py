"""The allocation-free items of the GPU backend against the simulator's kernel, on the CPU.

The reference runs every item through the simulator's kernel alone (`batch._run_item`). An item that
`compact_batch` finishes, contact phases included, must have its results bit for bit (the same operations
in the same order); and both the batch kernel (`run_lanes`) and the completion of the deferred steps
must give the reference for the whole batch.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorcontact.studies.batch import (
    _run_item,
    _run_steps,
    REGIME_NAMES, S_DU_IM, S_DU_RE, S_N_CONTACTS, S_REGIME, S_U_IM, S_U_RE, BatchSettings, parameter_array, run_lanes,
)
from rotorcontact.simulation.simulator import new_tables
from rotorcontact.studies.cuda_batch import complete_deferred
from rotorcontact.studies.compact_batch import RING, compact_lanes
from reference_parameters import REF


REGIME_CODES = {name: code for code, name in enumerate(REGIME_NAMES)}


def _reference(params, u0, du0, settings, carry):
    """Every item through the simulator's kernel alone (tables of its own), lane by lane."""
    sections = np.empty(params.shape[:2] + (settings.keep, 4))
    summary = np.empty(params.shape[:2] + (16,))
    for lane in range(params.shape[0]):
        u, du = u0[lane, 0], du0[lane, 0]
        for s in range(params.shape[1]):
            if not carry:
                u, du = u0[lane, s], du0[lane, s]
            u, du, _ = _run_item(params[lane, s], u, du, settings.n_transient, settings.n_record,
                                 settings.transient_time, settings.record_time, settings.settle,
                                 settings.chatter_values, sections[lane, s], summary[lane, s], new_tables())
    return sections, summary


def _compact(params, u0, du0, settings, carry):
    n_lanes = params.shape[0]
    sections = np.full(params.shape[:2] + (settings.keep, 4), -7.0)
    summary = np.full(params.shape[:2] + (16,), -7.0)
    deferred = np.empty(n_lanes, np.int64)
    start_u = np.empty(n_lanes, complex)
    start_du = np.empty(n_lanes, complex)
    compact_lanes(params, u0, du0, carry, settings.n_transient, settings.n_record, settings.transient_time,
                 settings.record_time, settings.settle, *settings.chatter_values, sections, summary, deferred,
                 start_u, start_du)
    return sections, summary, deferred, start_u, start_du


def _mixed_items(n=160, seed=1):
    """Random starts at parameters that end in impacts, no contact, rub and rolling."""
    rng = np.random.default_rng(seed)
    rows = np.array([parameter_array(REF.replace(gamma=g, omega=om, mu=mu))
                     for g in (0.05, 0.1, 0.15) for om in (0.5, 0.76, 1.3, 2.5) for mu in (0.0, 0.15)])
    params = rows[rng.integers(0, len(rows), n)][:, None, :]
    u0 = (np.sqrt(rng.uniform(0, 1, n)) * np.exp(2j * np.pi * rng.uniform(0, 1, n)))[:, None]
    du0 = (0.5 * (rng.normal(size=n) + 1j * rng.normal(size=n)))[:, None]
    return params, u0, du0


def _same(a, b):
    """Per item (first axis), whether two result arrays hold the same bits (nan equal to nan)."""
    return np.all((a == b) | (np.isnan(a) & np.isnan(b)), axis=tuple(range(1, a.ndim)))


@pytest.mark.parametrize("settings", [
    BatchSettings(n_transient=300, n_record=50, settle=0),
    BatchSettings(n_transient=300, n_record=50, settle=25),
    # a section shorter than the window (its ring is put in order) and a window longer than the ring
    BatchSettings(n_transient=200, n_record=3 * RING, settle=25, n_keep=7),
])
def test_finished_items_are_the_batch_kernels_bit_for_bit(settings):
    params, u0, du0 = _mixed_items()
    sections, summary = _reference(params, u0, du0, settings, False)
    batch_sections, batch_summary = run_lanes(params, u0, du0, settings, carry=False)
    assert np.array_equal(batch_sections, sections, equal_nan=True)
    assert np.array_equal(batch_summary, summary, equal_nan=True)
    sec, summ, deferred, start_u, start_du = _compact(params, u0, du0, settings, False)
    done = deferred < 0
    regimes = summary[:, 0, S_REGIME].astype(int)
    # the batch holds impacting, contact-free, rubbing and rolling items, and items that end in contact
    assert {REGIME_CODES[n] for n in ("periodic-impacting", "no-contact", "forward-rub", "backward-whirl")} <= \
        set(regimes)
    # every finished item is the batch kernel's, bit for bit, and items of every regime are finished, contact
    # phases included
    assert np.all(_same(sec, sections)[done]) and np.all(_same(summ, summary)[done])
    assert set(regimes) == set(regimes[done])
    assert np.any(done & (summary[:, 0, S_N_CONTACTS] > 0))
    # an item left to the batch kernel starts from its own initial state
    assert np.array_equal(start_u[~done], u0[~done, 0]) and np.array_equal(start_du[~done], du0[~done, 0])
    complete_deferred(params, u0, du0, settings, False, sec, summ, deferred, start_u, start_du)
    assert np.array_equal(sec, sections, equal_nan=True) and np.array_equal(summ, summary, equal_nan=True)


@pytest.mark.parametrize("gammas", [[0.1, 0.08, 0.06, 0.05, 0.04], [0.1, 0.14, 0.18, 0.22, 0.26]])
def test_a_carried_lane_into_contact_is_the_batch_kernels_bit_for_bit(gammas):
    settings = BatchSettings(n_transient=300, n_record=50, settle=25, n_keep=8)
    params = np.array([[parameter_array(REF.replace(gamma=g)) for g in gammas]])
    u0 = np.zeros((1, len(gammas)), complex)
    sections, summary = _reference(params, u0, u0, settings, True)
    batch_sections, batch_summary = run_lanes(params, u0, u0, settings, carry=True)
    assert np.array_equal(batch_sections, sections, equal_nan=True)
    assert np.array_equal(batch_summary, summary, equal_nan=True)
    # the chain goes from impacts into continuous contact
    assert summary[0, 0, S_N_CONTACTS] == 0 and summary[0, -1, S_N_CONTACTS] > 0
    sec, summ, deferred, start_u, start_du = _compact(params, u0, u0, settings, True)
    s = deferred[0] if deferred[0] >= 0 else len(gammas)
    assert np.all(_same(sec[0], sections[0])[:s]) and np.all(_same(summ[0], summary[0])[:s])
    complete_deferred(params, u0, u0, settings, True, sec, summ, deferred, start_u, start_du)
    assert np.array_equal(sec, sections, equal_nan=True) and np.array_equal(summ, summary, equal_nan=True)


@pytest.mark.parametrize("step", [0, 2, 4])
def test_deferred_steps_are_completed_from_where_the_previous_step_ended(step):
    """`complete_deferred` on lanes stopped at a given step: the later steps are the batch kernel's."""
    settings = BatchSettings(n_transient=300, n_record=50, settle=25, n_keep=8)
    gammas = [0.1, 0.08, 0.06, 0.05, 0.04]
    params = np.array([[parameter_array(REF.replace(gamma=g)) for g in gammas]] * 2)
    u0 = np.zeros(params.shape[:2], complex)
    for carry in (True, False):
        sections, summary = _reference(params, u0, u0, settings, carry)
        sec, summ = sections.copy(), summary.copy()
        sec[0, step:] = summ[0, step:] = -7.0
        deferred = np.array([step, -1])
        start_u = np.zeros(2, complex)
        start_du = np.zeros(2, complex)
        if carry and step > 0:
            start_u[0] = complex(summary[0, step - 1, S_U_RE], summary[0, step - 1, S_U_IM])
            start_du[0] = complex(summary[0, step - 1, S_DU_RE], summary[0, step - 1, S_DU_IM])
        complete_deferred(params, u0, u0, settings, carry, sec, summ, deferred, start_u, start_du)
        assert np.array_equal(sec, sections, equal_nan=True) and np.array_equal(summ, summary, equal_nan=True)


def test_steps_handed_back_run_through_the_simulators_tables_as_the_reference():
    """`batch._run_steps`, what the kernels run from a step the allocation-free form hands back."""
    settings = BatchSettings(n_transient=300, n_record=50, settle=25, n_keep=8)
    params = np.array([[parameter_array(REF.replace(gamma=g)) for g in (0.1, 0.08, 0.06, 0.05, 0.04)]])
    u0 = np.zeros(params.shape[:2], complex)
    for carry in (True, False):
        sections, summary = _reference(params, u0, u0, settings, carry)
        for first in (0, 3):
            sec, summ = sections.copy(), summary.copy()
            sec[0, first:] = summ[0, first:] = -7.0
            u = complex(summary[0, first - 1, S_U_RE], summary[0, first - 1, S_U_IM]) if carry and first else 0j
            du = complex(summary[0, first - 1, S_DU_RE], summary[0, first - 1, S_DU_IM]) if carry and first else 0j
            _run_steps(0, first, u, du, params, u0, u0, carry, settings.n_transient, settings.n_record,
                       settings.transient_time, settings.record_time, settings.settle, settings.chatter_values, sec,
                       summ, new_tables())
            assert np.array_equal(sec, sections, equal_nan=True) and np.array_equal(summ, summary, equal_nan=True)


def test_items_that_start_on_the_stator_are_the_batch_kernels_bit_for_bit():
    """Starts pressed onto the stator go straight into contact: sliding either way, rolling, lift-off."""
    cases = [(REF, 0.3, -10.0), (REF, 0.3, -60.0), (REF.replace(omega=1.2), -2.0, 0.5), (REF, 1.5, 0.0),
             (REF.replace(r_ratio=2.0, gamma=0.05), 0.3, -3.0), (REF.replace(r_ratio=0.0, omega=0.1, mu=0.6),
                                                                 REF.phi + 0.3, -1.0)]
    params = np.array([parameter_array(p) for p, _, _ in cases])[:, None, :]
    e = np.exp(1j * np.array([th for _, th, _ in cases]))
    u0 = e[:, None]
    du0 = (1j * np.array([thd for _, _, thd in cases]) * e)[:, None]
    for settings in (BatchSettings(n_transient=0, n_record=40), BatchSettings(n_transient=40, n_record=40)):
        sections, summary = _reference(params, u0, du0, settings, False)
        sec, summ, deferred, start_u, start_du = _compact(params, u0, du0, settings, False)
        done = deferred < 0
        assert np.any(done & (summary[:, 0, S_N_CONTACTS] > 0))
        assert np.all(_same(sec, sections)[done]) and np.all(_same(summ, summary)[done])
