"""Arguments of the zero curves of F1 in one parameter (`rotorcontact.continuation.zero_curves`)."""

from __future__ import annotations

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
