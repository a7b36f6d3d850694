"""Arguments of the result types of `rotorcontact.continuation.results`: the events, the selections of a
branch result and its serialisation refuse what they cannot use by name."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation.results import (
    EVENT_KINDS,
    ORBIT_COLUMNS,
    BranchEvent,
    BranchResult,
    OrbitBranches,
    OrbitCurve,
    branch_to_dict,
    check_interval,
    check_param_range,
)
from rotorcontact.maps.impact_map import one_impact_orbits
from reference_parameters import REF


@pytest.fixture(scope="module")
def curve():
    p = REF.replace(gamma=0.1)
    orbits = one_impact_orbits(p, 4.0)
    return OrbitCurve(param="gamma", values=np.full(len(orbits), 0.1), orbits=orbits,
                      extrema=tuple((np.zeros(0), np.zeros(0, bool)) for _ in orbits), event_index=(),
                      ends=("", ""))


@pytest.fixture(scope="module")
def branches(curve):
    fold = BranchEvent(kind="fold", value=0.17, param="gamma", orbits=("B1,a", "B1,b"))
    return OrbitBranches(param="gamma", events=(fold,), start=0.0, stop=0.2, base=REF, t_max=4.0, curves=(curve,))


@pytest.mark.parametrize("kw, match", [
    (dict(type=1), r"^type = 1 is invalid; allowed: 'fold', "),
    (dict(type="x"), r"^type = 'x' is invalid"),
    (dict(orbit=1), r"^orbit = 1 is not a str object; allowed: an orbit label"),
    (dict(orbit=("B1,a",)), r"^orbit = .* is not a str object"),
])
def test_select_refuses_an_unknown_type_or_a_label_that_is_not_text(branches, kw, match):
    with pytest.raises(ParameterError, match=match):
        branches.select(**kw)
    assert len(branches.select(type="fold", orbit="B1,a")) == 1 and branches.select(type="grazing") == ()


def test_branch_names_the_label(branches):
    for label in (None, 1):
        with pytest.raises(ParameterError, match=r"^label = .* is not a str object"):
            branches.branch(label)
    with pytest.raises(ParameterError, match=r"^label = 'B9,a' is invalid; allowed: an orbit with a branch here: "):
        branches.branch("B9,a")
    assert branches.branch(branches.labels[0]).label == branches.labels[0]


@pytest.mark.parametrize("name", [None, 1, "x", "label", "params", "multipliers"])
def test_column_takes_the_numeric_attributes_only(curve, name):
    with pytest.raises(ParameterError, match=r"^name = .* is invalid; allowed: 'T', 'theta'"):
        curve.column(name)


def test_every_column_is_a_float_array(curve):
    for name in ORBIT_COLUMNS:
        col = curve.column(name)
        assert col.dtype == float and col.shape == (len(curve.orbits),)


@pytest.mark.parametrize("result", [None, "x", {}, BranchEvent])
def test_branch_to_dict_needs_a_branch_result(result):
    with pytest.raises(ParameterError, match=r"^result = .* is not a BranchResult object"):
        branch_to_dict(result)


def test_the_branch_result_is_an_abstract_base(branches):
    with pytest.raises(TypeError):
        BranchResult(param="gamma", events=())
    assert branch_to_dict(branches)["param"] == "gamma"


@pytest.mark.parametrize("args, match", [
    ((None, REF, 0.0, 0.1), r"^param = None is invalid; allowed: 'gamma', 'omega', 'rho', 'mu', 'd'$"),
    (("phi", REF, 0.0, 0.1), r"^param = 'phi' is invalid"),
    (("gamma", None, 0.0, 0.1), r"^base = None is not a Parameters object"),
    (("gamma", REF, 0.2, 0.1), r"^stop = 0.1 is invalid; allowed: a number > start = 0.2"),
    (("d", REF, 0.5, 1.5), r"^stop = 1.5 is invalid; allowed: a value that d may take \(d = 1.5 is out of range"),
    (("omega", REF, -1.0, 0.5), r"^start = -1.0 is invalid; allowed: a value that omega may take"),
])
def test_check_param_range_names_the_bad_argument(args, match):
    with pytest.raises(ParameterError, match=match):
        check_param_range(*args)


def test_ranges_take_numpy_scalars():
    assert check_param_range("gamma", REF, np.float32(0.0), np.int64(1)) == (0.0, 1.0)
    start, stop = check_interval(np.float64(-0.5), np.float32(0.25))
    assert (start, stop) == (-0.5, 0.25) and type(start) is float


@pytest.mark.parametrize("kw, match", [
    (dict(kind="x"), r"^kind = 'x' is invalid; allowed: 'fold', "),
    (dict(kind=None), r"^kind = None is invalid"),
    (dict(value="x"), r"^value = 'x' is invalid; allowed: a number, the value of gamma"),
    (dict(value=True), r"^value = True is invalid"),
    (dict(param=1), r"^param = 1 is invalid; allowed: a parameter name, or a tuple of names"),
    (dict(param=("gamma", "omega")), r"^value = 0.1 is invalid; allowed: a tuple of 2 numbers"),
    (dict(param=("gamma", "omega"), value=(0.1,)), r"^value = \(0.1,\) is invalid"),
    (dict(orbits="B1,d"), r"^orbits = 'B1,d' is invalid; allowed: a tuple of orbit labels"),
])
def test_branch_events_are_checked(kw, match):
    args = dict(kind="fold", value=0.1, param="gamma")
    args.update(kw)
    with pytest.raises(ParameterError, match=match):
        BranchEvent(**args)


def test_every_kind_of_event_is_known():
    for kind in EVENT_KINDS:
        assert BranchEvent(kind=kind, value=np.float32(0.1), param="gamma").values == (np.float32(0.1),)
    pt = BranchEvent(kind="fold-dib", value=(np.float64(0.1), 1), param=("gamma", "omega"))
    assert pt.values == (0.1, 1) and pt.params == ("gamma", "omega")
    assert math.isnan(BranchEvent(kind="fold", value=math.nan, param="gamma").value)
