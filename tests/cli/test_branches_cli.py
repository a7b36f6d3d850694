"""``rotorcontact branches``: JSON contract, agreement with the library, plots and bad input."""

from __future__ import annotations

import pytest

from rotorcontact.continuation.branches import EVENT_TYPES, orbit_branches
from reference_parameters import REF


@pytest.fixture(scope="module")
def reference_json(program):
    return program.exe_json("branches", "--param", "gamma", "--from", "-0.6", "--to", "0.25")


def test_json_contract_at_the_reference(reference_json):
    data = reference_json
    assert set(data) == {"parameters", "param", "events", "branches"}
    assert data["param"] == "gamma"
    for e in data["events"]:
        assert set(e) == {"type", "value", "orbits"}
        assert e["type"] in EVENT_TYPES and isinstance(e["value"], float)
        assert e["orbits"] and all(isinstance(o, str) and o.startswith("B") for o in e["orbits"])
    assert [e["value"] for e in data["events"]] == sorted(e["value"] for e in data["events"])
    assert {"B1,a", "B1,b", "B1,c", "B1,d"} <= set(data["branches"])
    for label, arrays in data["branches"].items():
        assert set(arrays) == {"gamma", "T", "rdot", "thetadot", "stable"}
        n = len(arrays["gamma"])
        assert n > 1 and all(len(v) == n for v in arrays.values())
        assert all(s in (True, False, None) for s in arrays["stable"])
    types = {e["type"] for e in data["events"]}
    assert {"fold", "nsfh", "grazing", "period-doubling", "extrema-change", "ac-coalescence"} <= types


def test_json_agrees_with_the_library(reference_json):
    lib = orbit_branches(REF, "gamma", -0.6, 0.25)
    assert reference_json["events"] == [e.to_dict() for e in lib.events]
    b = lib.branch("B1,d")
    assert reference_json["branches"]["B1,d"]["T"] == [None if x != x else x for x in b.T.tolist()]


def test_other_parameter_and_options(cli):
    data = cli.json("branches", "--param", "omega", "--from", "0.7", "--to", "0.9", "--t-max", "4", "--seeds", "5",
                    "--gamma", "0.1")
    assert data["param"] == "omega"
    assert all(set(v) == {"omega", "T", "rdot", "thetadot", "stable"} for v in data["branches"].values())
    assert all(T is None or T <= 4.0 for v in data["branches"].values() for T in v["T"])
    assert any(e["type"] == "nsfh" for e in data["events"])


def test_table_and_plot(tmp_path, cli):
    png = tmp_path / "b.png"
    code, out, err = cli.run("branches", "--from", "0.05", "--to", "0.2", "--t-max", "4", "--seeds", "4", "--plot", png)
    assert code == 0, err
    assert "fold" in out and "B1,a, B1,b" in out and "figure written" in out
    assert png.stat().st_size > 0


@pytest.mark.parametrize(
    "args",
    [
        ["--param", "phi"],
        ["--from", "0.3", "--to", "0.1"],
        ["--from", "abc"],
        ["--t-max", "-1"],
        ["--seeds", "1"],
        ["--rdot-max", "0"],
        ["--param", "d", "--from", "0.5", "--to", "1.5"],
        ["--plot", "out.txt"],
        ["--gamma", "nan"],
        ["--grid", "12,4,4"],  # seeds --impacts P >= 2 only
        ["--impacts", "1", "--grid", "12,4,4"],
    ],
)
def test_bad_input_exits_2(args, cli):
    code, _, err = cli.run("branches", *args)
    assert code == 2
    assert "error" in err and "Traceback" not in err


def test_bad_input_in_a_real_process_has_no_traceback(cli):
    code, _, err = cli.exe("branches", "--from", "abc")
    assert code == 2
    assert "Traceback" not in err and "error" in err
