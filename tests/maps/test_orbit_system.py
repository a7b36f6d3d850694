"""The parameter points of a continuation (`maps.orbit_system.with_parameters`)."""

from __future__ import annotations

import cmath

import pytest

from rotorcontact import ParameterError
from rotorcontact.maps.orbit_system import with_parameters
from reference_parameters import REF


def _k(p) -> complex:
    """k = rho e^{i phi} / (omega^2 - 1 + i gamma) (MODEL.md §3), written out here."""
    return p.rho * cmath.exp(1j * p.phi) / complex(p.omega**2 - 1.0, p.gamma)


@pytest.mark.parametrize("changes", [{"rho": -0.1, "gamma": 0.2}, {"d": 1.05}, {"omega": -0.3}])
def test_a_point_beyond_a_bound_has_its_own_equilibrium_not_the_bases(changes):
    base = REF.replace(gamma=0.1)
    assert base.k == pytest.approx(_k(base), rel=1e-14)  # now cached on the base
    with pytest.raises(ParameterError):
        with_parameters(base, changes)  # without extend, the bound holds
    p = with_parameters(base, changes, extend=True)
    assert all(getattr(p, name) == value for name, value in changes.items())
    assert p.k == pytest.approx(_k(p), rel=1e-14)
    assert (p.k != base.k) == ("d" not in changes)  # the restitution does not enter k
