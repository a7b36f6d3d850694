"""Arguments of the zero curves of F1 in one parameter (`rotorcontact.continuation.zero_curves`)."""

from __future__ import annotations

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation.branches import MAX_SEEDS
from rotorcontact.continuation.zero_curves import f1_zero_curves
from reference_parameters import REF


@pytest.mark.parametrize("n_seeds", [1, MAX_SEEDS + 1, 10**9, True])
def test_the_seed_scan_is_bounded_as_for_the_orbit_branches(n_seeds):
    with pytest.raises(ParameterError, match=rf"^n_seeds = .* is invalid; allowed: an integer from 2 to {MAX_SEEDS}$"):
        f1_zero_curves(REF, "gamma", 0.0, 0.25, n_seeds=n_seeds)


def test_settings_that_are_not_continuation_settings_are_refused():
    with pytest.raises(ParameterError, match=r"^settings = 'x' is not a ContinuationSettings"):
        f1_zero_curves(REF, "gamma", 0.0, 0.25, settings="x")


def _curves():
    from rotorcontact.continuation.results import BranchEvent
    from rotorcontact.continuation.zero_curves import F1ZeroCurves

    folds = (BranchEvent(kind="fold", value=0.17, param="gamma", orbits=("T0,1,a", "T0,1,b"), T=2.0, n=1),)
    return F1ZeroCurves(param="gamma", events=folds, start=0.0, stop=0.25, base=REF, t_max=12.0, curves=())


@pytest.mark.parametrize("n", [None, "x", 0, -1, 1.5, True])
def test_fold_values_refuse_what_is_not_a_pair_index(n):
    with pytest.raises(ParameterError, match=r"^n = .* is invalid; allowed: an integer >= 1$"):
        _curves().fold_values(n)


def test_fold_values_take_numpy_integers():
    assert _curves().fold_values(np.int64(1)) == _curves().fold_values(1) == (0.17,)
    assert _curves().fold_values(np.int32(2)) == ()
