"""The allocation-free items of the GPU backend against the simulator's kernel, on the CPU.

The reference runs every item through the simulator's kernel alone (`batch._run_item`). An item that
`flight_batch` finishes must have its results bit for bit (the same operations in the same order); an
item it defers must be one whose motion enters continuous contact; and both the batch kernel
(`run_lanes`) and the completion of the deferred steps must give the reference for the whole batch.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorcontact.studies.batch import (
    _run_item,
    REGIME_NAMES, S_DU_IM, S_DU_RE, S_N_CONTACTS, S_REGIME, S_U_IM, S_U_RE, BatchSettings, parameter_array, run_lanes,
)
from rotorcontact.simulation.simulator import new_tables
from rotorcontact.studies.cuda_batch import complete_deferred
from rotorcontact.studies.flight_batch import RING, flight_lanes
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


def _flight(params, u0, du0, settings, carry):
    n_lanes = params.shape[0]
    sections = np.full(params.shape[:2] + (settings.keep, 4), -7.0)
    summary = np.full(params.shape[:2] + (16,), -7.0)
    deferred = np.empty(n_lanes, np.int64)
    start_u = np.empty(n_lanes, complex)
    start_du = np.empty(n_lanes, complex)
    flight_lanes(params, u0, du0, carry, settings.n_transient, settings.n_record, settings.transient_time,
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
    sec, summ, deferred, start_u, start_du = _flight(params, u0, du0, settings, False)
    done = deferred < 0
    regimes = set(summary[:, 0, S_REGIME].astype(int))
    # the batch holds impacting, contact-free and contact items, so both paths are exercised
    assert {REGIME_CODES["periodic-impacting"], REGIME_CODES["no-contact"], REGIME_CODES["forward-rub"]} <= regimes
    assert 0 < done.sum() < done.size
    assert np.array_equal(sec[done], sections[done], equal_nan=True)
    assert np.array_equal(summ[done], summary[done], equal_nan=True)
    # deferred items are those whose motion entered continuous contact; for them the start state is the item's
    assert np.array_equal(start_u[~done], u0[~done, 0]) and np.array_equal(start_du[~done], du0[~done, 0])
    contact = (summary[:, 0, S_N_CONTACTS] > 0) | np.isin(summary[:, 0, S_REGIME], [
        REGIME_CODES["forward-rub"], REGIME_CODES["backward-whirl"], REGIME_CODES["mixed"]])
    assert np.all(~done[contact])
    complete_deferred(params, u0, du0, settings, False, sec, summ, deferred, start_u, start_du)
    assert np.array_equal(sec, sections, equal_nan=True) and np.array_equal(summ, summary, equal_nan=True)


@pytest.mark.parametrize("gammas, step", [([0.1, 0.08, 0.06, 0.05, 0.04], 2), ([0.1, 0.14, 0.18, 0.22, 0.26], 3)])
def test_a_carried_lane_is_deferred_from_its_first_contact_step_and_completed_from_its_state(gammas, step):
    settings = BatchSettings(n_transient=300, n_record=50, settle=25, n_keep=8)
    params = np.array([[parameter_array(REF.replace(gamma=g)) for g in gammas]])
    u0 = np.zeros((1, len(gammas)), complex)
    sections, summary = _reference(params, u0, u0, settings, True)
    batch_sections, batch_summary = run_lanes(params, u0, u0, settings, carry=True)
    assert np.array_equal(batch_sections, sections, equal_nan=True)
    assert np.array_equal(batch_summary, summary, equal_nan=True)
    sec, summ, deferred, start_u, start_du = _flight(params, u0, u0, settings, True)
    assert deferred[0] == step
    assert np.array_equal(sec[0, :step], sections[0, :step], equal_nan=True)
    assert np.array_equal(summ[0, :step], summary[0, :step], equal_nan=True)
    # the start of the deferred step is where the previous step ended
    assert start_u[0] == complex(summary[0, step - 1, S_U_RE], summary[0, step - 1, S_U_IM])
    assert start_du[0] == complex(summary[0, step - 1, S_DU_RE], summary[0, step - 1, S_DU_IM])
    complete_deferred(params, u0, u0, settings, True, sec, summ, deferred, start_u, start_du)
    assert np.array_equal(sec, sections, equal_nan=True) and np.array_equal(summ, summary, equal_nan=True)
