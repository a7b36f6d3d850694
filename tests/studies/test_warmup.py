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
    for bad in (5, {"simulate": 1}.items()):
        with pytest.raises(ParameterError, match=r"^groups = .* is invalid; allowed: a group name, a list"):
            warm_up(bad)
    with pytest.raises(ParameterError, match=r"^group = 1 is not a kernel group"):
        warm_up([1])


def test_one_group_may_be_given_by_its_name():
    assert list(warm_up("simulate")) == ["simulate"]


def test_warm_up_of_the_studies_compiles_the_batch_kernel_and_the_comparison_of_angles():
    # in a fresh process on one thread
    import os
    import subprocess
    import sys

    code = ("from rotorcontact.studies.warmup import warm_up\n"
            "from rotorcontact.studies.batch import _batch_serial\n"
            "from rotorcontact.model.angles import _wrap_many\n"
            "warm_up(['studies'])\n"
            "print(len(_batch_serial.signatures), len(_wrap_many.signatures))\n")
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    # and the classification's comparison of angles, which a study runs on all its points at once
    assert out.stdout.split() == ["1", "1"]
