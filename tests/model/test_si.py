"""SI values of dimensionless results: the scales against the machine's own, and bad arguments refused."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError, reference_machine
from rotorcontact.analysis.equilibria import equilibria
from rotorcontact.model import si

MACHINE = reference_machine()


def test_scales_are_those_of_the_machine():
    m = MACHINE
    assert si.velocity_scale(m) == pytest.approx(m.clearance * m.speed, rel=1e-14)
    assert si.rate_scale(m) == pytest.approx(m.speed, rel=1e-14)
    assert si.parameter_si(m, "rho", 0.5) == {"eccentricity_m": pytest.approx(0.5 * m.clearance, rel=1e-14)}
    assert si.parameter_si(m, "gamma", math.nan) == {"damping_Ns_per_m": None}
    assert si.parameter_si(m, "gamma", None) == {"damping_Ns_per_m": None}
    assert si.times_si(m, T=2.0, none=None) == {"T_s": pytest.approx(2.0 / m.speed, rel=1e-14), "none_s": None}
    # numpy's scalars and 0-d arrays (as xarray gives) are numbers too
    assert si.times_si(m, T=np.array(2.0), U=np.float32(2.0)) == si.times_si(m, T=2.0, U=2.0)
    assert si.parameter_si(m, "rho", np.array(0.5)) == si.parameter_si(m, "rho", 0.5)


@pytest.mark.parametrize("call", [
    lambda bad: si.velocity_scale(bad),
    lambda bad: si.rate_scale(bad),
    lambda bad: si.parameter_si(bad, "gamma", 0.1),
    lambda bad: si.times_si(bad, T=1.0),
    lambda bad: si.orbit_si(bad, None),
    lambda bad: si.regular_si(bad, None),
    lambda bad: si.pseudo_si(bad, None),
])
@pytest.mark.parametrize("bad", [None, "x", MACHINE.parameters()])
def test_a_machine_is_required(call, bad):
    with pytest.raises(ParameterError, match=r"^machine = .* is not a Machine object; allowed: rotorcontact.Machine$"):
        call(bad)


def test_results_of_the_wrong_kind_are_refused():
    eq = equilibria(MACHINE.parameters())
    assert si.equilibria_si(MACHINE, eq)["regular"]["amplitude_um"] == pytest.approx(
        eq.regular.r * MACHINE.clearance * 1e6, rel=1e-14)
    for call, name in ((lambda: si.orbit_si(MACHINE, eq), "orbit"), (lambda: si.regular_si(MACHINE, eq), "regular"),
                       (lambda: si.pseudo_si(MACHINE, eq.regular), "pseudo"),
                       (lambda: si.equilibria_si(MACHINE, eq.regular), "eq")):
        with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: an? "):
            call()
    for bad in ("0.1", True, np.bool_(True), 1j, np.array([0.1]), np.array("0.1")):
        with pytest.raises(ParameterError, match=r"^value = .* is invalid; allowed: a real number or None$"):
            si.parameter_si(MACHINE, "gamma", bad)
        with pytest.raises(ParameterError, match=r"^T = .* is invalid; allowed: a real number or None$"):
            si.times_si(MACHINE, T=bad)
