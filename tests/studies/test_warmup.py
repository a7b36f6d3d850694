"""Compiling the kernels ahead (`studies.warmup`)."""

from __future__ import annotations

import pytest

from rotorcontact import ParameterError
from rotorcontact.studies.warmup import WARMUP_GROUPS, warm_up


def test_warm_up_compiles_the_groups_kernels():
    from rotorcontact.simulation.drop import drop_kernel
    from rotorcontact.simulation.simulator import simulate_kernel

    seconds = warm_up(["drop", "simulate"])
    assert list(seconds) == ["drop", "simulate"] and all(s > 0.0 for s in seconds.values())
    # the kernels now hold a compiled specialisation (compiled, or loaded from the cache)
    assert drop_kernel.signatures and simulate_kernel.signatures


def test_an_unknown_group_is_refused_by_name():
    with pytest.raises(ParameterError, match=r"group = 'fast'.*allowed: " + ", ".join(WARMUP_GROUPS)):
        warm_up(["simulate", "fast"])


def test_warm_up_of_the_studies_compiles_the_kernels_of_threads_and_of_worker_processes():
    from rotorcontact.studies.batch import _batch_parallel, _batch_serial

    warm_up(["studies"])
    # the parallel kernel runs in this process; worker processes and a single thread run the serial one
    assert _batch_parallel.signatures and _batch_serial.signatures
