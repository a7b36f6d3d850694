"""The argument checks shared by the public functions (`rotorcontact.model.validation`)."""

from __future__ import annotations

import math

import pytest

from rotorcontact import ParameterError
from rotorcontact.continuation.engine import ContinuationSettings
import numpy as np

from rotorcontact.model.validation import real_array, settings_or_default


def test_settings_or_default_keeps_settings_builds_the_default_and_refuses_anything_else():
    given = ContinuationSettings(step=0.02)
    assert settings_or_default(given, ContinuationSettings, ContinuationSettings) is given
    assert settings_or_default(None, ContinuationSettings, lambda: given) is given
    for bad in ("x", 3, {"step": 0.02}, ContinuationSettings):
        with pytest.raises(ParameterError, match=r"^settings = .* is not a ContinuationSettings object; allowed: a "
                                                 r"ContinuationSettings or None$"):
            settings_or_default(bad, ContinuationSettings, ContinuationSettings)


@pytest.mark.parametrize("value, expected", [([1, 2.5], [1.0, 2.5]), (np.arange(3), [0.0, 1.0, 2.0]), (3, 3.0),
                                             ((0.5,), [0.5])])
def test_real_array_reads_numbers(value, expected):
    assert real_array(value).tolist() == expected


@pytest.mark.parametrize("value", [True, [True], [0.1, True], [1, np.bool_(False)], [[1.0], [2.0, True]], "1",
                                   ["1", 2], [1j], None, [[1.0], [1.0, 2.0]], {"a": 1}, np.array([True])])
def test_real_array_refuses_bools_text_complex_and_ragged_lists(value):
    assert real_array(value) is None


def test_check_bool_takes_true_and_false_only():
    from rotorcontact.model.validation import check_bool

    assert check_bool("flag", True) is True and check_bool("flag", np.bool_(False)) is False
    for bad in ("False", "yes", 0, 1, None, 1.0):
        with pytest.raises(ParameterError, match=r"^flag = .* is invalid; allowed: True or False$"):
            check_bool("flag", bad)


@pytest.mark.parametrize("bad", [None, 1, "", "   ", b"x.nc", ["a.nc"], "a\0b.nc"])
def test_a_path_is_a_non_empty_name(bad, tmp_path):
    import matplotlib.pyplot as plt
    import xarray as xr

    from rotorcontact.io.netcdf import write_netcdf
    from rotorcontact.model.params import load_machine
    from rotorcontact.model.validation import check_path
    from rotorcontact.plotting.style import save_figure
    from rotorcontact.report.reproduce import reproduce

    assert check_path("out", tmp_path / "a.nc") == tmp_path / "a.nc"
    with pytest.raises(ParameterError, match=r"^out = .* is not a path; allowed: a non-empty file or folder name "
                                             r"\(without NUL characters\)$"):
        check_path("out", bad)
    with pytest.raises(ParameterError, match="^out = "):
        write_netcdf(xr.Dataset(), bad)
    with pytest.raises(ParameterError, match="^out = "):
        reproduce(bad, progress=False)
    with pytest.raises(ParameterError, match="^machine = "):
        load_machine(bad)
    fig = plt.figure()
    with pytest.raises(ParameterError, match="^path = "):
        save_figure(fig, bad)
    plt.close(fig)


def test_reproduce_refuses_a_file_for_its_folder(tmp_path):
    from rotorcontact.report.reproduce import reproduce

    f = tmp_path / "report"
    f.write_text("x")
    with pytest.raises(ParameterError, match=r"^out = .* is a file; allowed: a folder, new or existing$"):
        reproduce(f, progress=False)


def test_check_type_names_the_argument_and_cuts_a_long_value():
    from rotorcontact.model.params import Parameters
    from rotorcontact.model.validation import MAX_QUOTED, check_type, quoted

    assert check_type("x", 3, int, "an int") == 3
    assert check_type("x", None, int, "an int", optional=True) is None
    with pytest.raises(ParameterError, match=r"^x = 'a' is not an int or float object; allowed: a number or None$"):
        check_type("x", "a", (int, float), "a number", optional=True)
    with pytest.raises(ParameterError, match=r"^params = None is not a Parameters object"):
        check_type("params", None, Parameters, "rotorcontact.Parameters")
    long = list(range(1000))
    text = quoted(long)
    assert len(text) == MAX_QUOTED and text.endswith("...") and text.startswith("[0, 1, 2")
    assert quoted("a\n  b") == repr("a\n  b")  # short values are quoted whole
    assert quoted(np.arange(40).reshape(4, 10)).count("\n") == 0


def test_check_fields_takes_an_object_with_every_field():
    from types import SimpleNamespace

    from rotorcontact.model.validation import check_fields

    ok = SimpleNamespace(a=1, b=2)
    assert check_fields("v", ok, ("a", "b"), "an object with a and b") is ok
    with pytest.raises(ParameterError, match=r"^v = namespace\(a=1\) is invalid; allowed: an object with a and b$"):
        check_fields("v", SimpleNamespace(a=1), ("a", "b"), "an object with a and b")


def test_0d_arrays_are_their_value():
    from rotorcontact.model.validation import check_bool, check_float, check_int

    assert check_float("x", np.array(0.5)) == 0.5 and type(check_float("x", np.array(0.5))) is float
    assert check_int("n", np.array(5), 1) == 5 and type(check_int("n", np.array(5), 1)) is int
    assert check_bool("f", np.array(True)) is True
    with pytest.raises(ParameterError, match=r"^n = 0 is invalid; allowed: an integer >= 1$"):
        check_int("n", np.array(0), 1)
    with pytest.raises(ParameterError, match=r"^x = .* is invalid; allowed: a finite number$"):
        check_float("x", np.array([0.5]))
    with pytest.raises(ParameterError, match=r"^f = .* is invalid; allowed: True or False$"):
        check_bool("f", np.array("True"))


def test_finite_array_reads_finite_reals_of_a_shape():
    from rotorcontact.model.validation import finite_array

    assert finite_array("v", [1, 2.5], "numbers").tolist() == [1.0, 2.5]
    assert finite_array("m", [[1.0], [2.0]], "rows", ndims=(2,), rows=2).shape == (2, 1)
    for value, kw in (([], {}), ([1.0, math.nan], {}), ([[1.0]], {}), ("x", {}), ([1.0], dict(min_rows=2)),
                      ([1.0, 2.0], dict(rows=3)), ([1.0, True], {})):
        with pytest.raises(ParameterError, match=r"^v = .* is invalid; allowed: what v may be$"):
            finite_array("v", value, "what v may be", **kw)
