"""The final regime of a trajectory: bad arguments refused by name."""

from __future__ import annotations

import math

import pytest

from rotorcontact import ParameterError, simulate
from rotorcontact.analysis.regime_change import final_regime
from reference_parameters import REF


def test_a_run_that_starts_at_x_R_never_touches():
    # x_R = k is the equilibrium of the free flight (MODEL.md §4): inside the clearance, no contact ever
    p = REF.replace(gamma=0.3)
    assert abs(p.k) < 1.0
    traj = simulate(p, p.k, 0.0, 200.0)
    assert len(traj.impacts) == 0 and not traj.contact_intervals
    assert final_regime(traj).kind == "no-contact"


@pytest.mark.parametrize("traj", [None, "x", REF])
def test_a_trajectory_is_required(traj):
    with pytest.raises(ParameterError, match=r"^traj = .* is not a Trajectory object; allowed: a Trajectory"):
        final_regime(traj)


@pytest.mark.parametrize("tol", [0.0, -1.0, math.nan, "1e-6", True])
def test_the_tolerance_is_a_positive_number(tol):
    traj = simulate(REF.replace(gamma=0.3), 0.5, 0.0, 10.0)
    with pytest.raises(ParameterError, match=r"^tol = .* is invalid; allowed: a finite number > 0"):
        final_regime(traj, tol)
