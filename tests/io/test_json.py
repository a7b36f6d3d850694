"""JSON data: complex numbers as pairs, non-finite numbers as null, numpy types as plain ones."""

from __future__ import annotations

import io
import json
import math

import numpy as np

from rotorcontact.io.json import dump_json, jsonable


def test_jsonable_makes_plain_data():
    data = {1: (np.int32(2), np.float64(0.5), np.bool_(True)), "c": 1 + 2j, "a": np.array([1.0, math.nan]),
            "inf": math.inf, "s": "x", "n": None}
    assert jsonable(data) == {"1": [2, 0.5, True], "c": [1.0, 2.0], "a": [1.0, None], "inf": None, "s": "x",
                              "n": None}
    assert type(jsonable(np.int64(3))) is int


def test_dump_json_writes_indented_json_and_a_newline():
    buf = io.StringIO()
    dump_json({"x": math.nan, "y": [1, 2]}, buf)
    text = buf.getvalue()
    assert text.endswith("}\n")
    assert json.loads(text) == {"x": None, "y": [1, 2]}
    assert text == json.dumps({"x": None, "y": [1, 2]}, indent=2) + "\n"


def test_an_object_json_cannot_hold_is_refused_by_its_type():
    import pytest

    from rotorcontact import ParameterError
    from reference_parameters import REF

    for bad, kind in (({1, 2}, "set"), (REF, "Parameters"), (b"x", "bytes"), ([object()], "object")):
        with pytest.raises(ParameterError, match=rf"^data holds a {kind} \(.*\), which JSON cannot hold; allowed: "):
            dump_json({"a": bad}, io.StringIO())
    assert jsonable({"a": None, "b": "text", "c": np.str_("s")}) == {"a": None, "b": "text", "c": "s"}
