"""Arguments of the two-parameter curves of orbits (`rotorcontact.continuation.codim2_orbits`): labels,
curve names and the ``--curves`` specifications are refused by name before anything is computed."""

from __future__ import annotations

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation import codim2_orbits
from rotorcontact.continuation.codim2 import Codim2Curve
from rotorcontact.continuation.codim2_orbits import (
    MAX_SPECS,
    extra_curves,
    grazing_curve_of,
    orbit_by_label,
    orbit_curve,
)
from reference_parameters import REF

PLANE = ("gamma", "omega")
BOX = ((0.09, 0.11), (0.75, 0.77))


@pytest.fixture(scope="module")
def b1d():
    return orbit_by_label(REF.replace(gamma=0.1), "B1,d")


@pytest.mark.parametrize("label", [None, 1, ("B1,d",), "X1", "M0-1", "M99-1", "B1,e"])
def test_orbit_by_label_refuses_what_is_not_a_label(label):
    with pytest.raises(ParameterError, match=r"^label = .* is invalid; allowed: B<n>,<m> \(B1,d\) or M<p>-<j>"):
        orbit_by_label(REF, label)


def test_orbit_by_label_checks_its_parameters_and_takes_numpy_scalars(b1d):
    with pytest.raises(ParameterError, match=r"^params = None is not a Parameters object"):
        orbit_by_label(None, "B1,d")
    same = orbit_by_label(REF.replace(gamma=np.float64(0.1)), "B1,d", t_max=np.float32(12.0))
    assert same.label == b1d.label and np.allclose(same.states, b1d.states)


def test_the_name_of_a_curve_is_text(b1d):
    with pytest.raises(ParameterError, match=r"^name = 1 is not a str object; allowed: the name of the curve"):
        orbit_curve(b1d, "fold", PLANE, BOX, name=1)
    with pytest.raises(ParameterError, match=r"^name = \['x'\] is not a str object"):
        grazing_curve_of(b1d, PLANE, BOX, name=["x"])


@pytest.mark.parametrize("specs, match", [
    (None, r"^specs = None is invalid; allowed: a list of at most 40 of coalescence, pd:<orbit>"),
    ("coalescence", r"^specs = 'coalescence' is invalid"),
    ([1], r"^specs\[0\] = 1 is invalid; allowed: coalescence, pd:<orbit>"),
    (["coalescence", "pd:Q9"], r"^specs\[1\] = 'pd:Q9' is invalid"),
    (["pd:"], r"^specs\[0\] = 'pd:' is invalid"),
    (["xx:B1,d"], r"^specs\[0\] = 'xx:B1,d' is invalid"),
    (["pd:B9,a"] * (MAX_SPECS + 1), r"^specs = .* is invalid; allowed: a list of at most 40"),
])
def test_extra_curves_refuse_bad_specifications_before_computing(specs, match):
    with pytest.raises(ParameterError, match=match):
        extra_curves(REF, PLANE, None, specs)


@pytest.mark.parametrize("kw, match", [(dict(t_max=-1.0), r"^t_max = -1.0 is "), (dict(n_seeds=0), r"^n_seeds = 0 "),
                                       (dict(n_scan=10**9), r"^n_scan = 1000000000 ")])
def test_extra_curves_check_every_option_whatever_the_specifications(kw, match):
    with pytest.raises(ParameterError, match=match):
        extra_curves(REF, PLANE, None, [], **kw)


def test_a_specification_given_twice_is_computed_once(monkeypatch):
    calls = []

    def fake_curve(orbit, kind, param, ranges):
        calls.append(kind)
        return Codim2Curve(name=f"pd_{orbit}", kind=kind, params=tuple(param), pieces=())

    monkeypatch.setattr(codim2_orbits, "orbit_by_label", lambda params, label, t_max: label)
    monkeypatch.setattr(codim2_orbits, "orbit_curve", fake_curve)
    out = extra_curves(REF, PLANE, None, ["pd:B1,d", "pd:B1,d"], n_seeds=np.int64(3), n_scan=np.int32(5),
                       t_max=np.float64(12.0))
    assert calls == ["period-doubling"] and list(out) == ["pd_B1,d"]


def test_an_orbit_that_is_not_there_is_named_by_its_label():
    with pytest.raises(ParameterError, match=r"^label = 'B9,a' is not an admissible orbit here; allowed: an orbit"):
        orbit_by_label(REF, "B9,a")
