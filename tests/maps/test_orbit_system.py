"""The parameter points of a continuation (`maps.orbit_system.with_parameters`)."""

from __future__ import annotations

import cmath
import math

import numpy as np
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


def test_with_parameters_needs_parameters_and_a_dict():
    from rotorcontact import reference_machine

    for bad in (None, reference_machine()):
        with pytest.raises(ParameterError, match=r"^base = .* is not a Parameters object"):
            with_parameters(bad, {"gamma": 0.1})
    for bad in (None, [("gamma", 0.1)], "gamma"):
        with pytest.raises(ParameterError, match=r"^changes = .* is invalid; allowed: a dict of parameter names"):
            with_parameters(REF, bad)
    assert with_parameters(REF, {"gamma": 0.1}).gamma == 0.1
    # beyond a physical bound with extend, numpy's floats as well as Python's
    assert with_parameters(REF, {"d": np.float32(1.25)}, extend=True).d == 1.25
    with pytest.raises(ParameterError, match=r"^d = "):
        with_parameters(REF, {"d": np.float32(1.25)})
    with pytest.raises(ParameterError, match=r"^d = "):
        with_parameters(REF, {"d": math.inf}, extend=True)


def test_closed_form_is_finite_or_refused():
    from rotorcontact.maps.impact_map import flight_growth, period_limit
    from rotorcontact.maps.orbit_system import LN_MAX_FLOAT, closed_form

    p = REF.replace(gamma=-1.0)
    limit = period_limit(p)
    cf = closed_form(0.99 * limit, p.gamma, p.omega)
    assert all(cmath.isfinite(v) for v in (cf.D, cf.P, cf.D_T, cf.P_T, cf.D_TT, cf.P_TT, cf.S, cf.C))
    # the closed form overflows near ln(largest float) / growth, beyond the analyses' limit MAX_GROWTH / growth
    growth = flight_growth(p)
    cf = closed_form(0.95 * LN_MAX_FLOAT / growth, p.gamma, p.omega)
    assert cmath.isfinite(cf.D) and cmath.isfinite(cf.P)
    with pytest.raises(ParameterError, match=rf"^T = .* is too large at gamma = -1, omega = .*: the flight's closed "
                                             rf"form, growing like e\^\{{{growth:.3g} T\}} at most, overflows; "
                                             r"allowed: a smaller T$"):
        closed_form(1.05 * LN_MAX_FLOAT / growth, p.gamma, p.omega)
    for name, args in (("T", (math.nan, 0.1, 0.5)), ("T", (0.0, 0.1, 0.5)), ("T", (-1.0, 0.1, 0.5)),
                       ("gamma", (1.0, math.inf, 0.5)), ("omega", (1.0, 0.1, "x"))):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            closed_form(*args)


def test_an_orbit_needs_a_period_a_velocity_and_a_label_that_exist():
    from rotorcontact import reference_machine
    from rotorcontact.maps.impact_map import one_impact_orbits
    from rotorcontact.maps.orbit_system import orbit_at

    o = next(o for o in one_impact_orbits(REF, 20.0) if o.admissible)
    again = orbit_at(REF, np.float64(o.T), np.array(o.rdot), n=np.int64(o.n), branch=o.branch)
    assert (again.theta, again.thetadot, again.label) == (o.theta, o.thetadot, o.label)
    for kw, name in ((dict(params=reference_machine()), "params"), (dict(T=-1.0), "T"), (dict(T="1"), "T"),
                     (dict(rdot=1e300), "rdot"), (dict(rdot=True), "rdot"), (dict(n=-1), "n"), (dict(n=1.5), "n"),
                     (dict(n=True), "n"), (dict(branch="e"), "branch"), (dict(branch=1), "branch")):
        args = dict(params=REF, T=o.T, rdot=o.rdot, n=o.n, branch=o.branch)
        args.update(kw)
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            orbit_at(args.pop("params"), args.pop("T"), args.pop("rdot"), **args)


def test_root_branches_of_a_zero_kind():
    from rotorcontact.maps.impact_map import root_branches

    assert root_branches("a") == ("a", "c") and root_branches("b") == ("b", "d")
    for bad in ("c", None, 1):
        with pytest.raises(ParameterError, match=r"^kind = .* is invalid; allowed: 'a', 'b'$"):
            root_branches(bad)


def test_the_branch_system_checks_its_options_and_points():
    from rotorcontact import reference_machine
    from rotorcontact.maps.orbit_system import OneImpactSystem, orbit_angles, regularised_residual

    system = OneImpactSystem(REF, "gamma")
    y = np.array([2.5, 0.3, REF.gamma])
    assert np.array_equal(system.residual(y), regularised_residual(REF, 2.5, 0.3)[0])
    assert np.array_equal(system.residual(list(y)), system.residual(y))
    for bad in ("x", [1.0, 2.0], [[1.0, 2.0, 3.0]], None):
        with pytest.raises(ParameterError, match=r"^y = .* is invalid; allowed: \(T, rdot, lambda\)"):
            system.residual(bad)
    with pytest.raises(ParameterError, match=r"^rdot = nan is invalid"):
        system.jacobian([2.5, math.nan, REF.gamma])
    with pytest.raises(ParameterError, match=r"^value = '0.1' is invalid"):
        system.params_at("0.1")
    for kw, name in ((dict(fd_step=0.0), "fd_step"), (dict(fd_step="x"), "fd_step"), (dict(extend="no"), "extend")):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            OneImpactSystem(REF, "gamma", **kw)
    for call in (lambda: regularised_residual(reference_machine(), 2.5, 0.3),
                 lambda: orbit_angles(reference_machine(), 2.5, 0.3)):
        with pytest.raises(ParameterError, match=r"^params = .* is not a Parameters object"):
            call()
    for call in (lambda: regularised_residual(REF, 2.5, None), lambda: orbit_angles(REF, 2.5, math.nan)):
        with pytest.raises(ParameterError, match=r"^rdot = .* is invalid; allowed: a finite number$"):
            call()
