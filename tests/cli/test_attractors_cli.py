"""``rotorcontact attractors``: JSON contract, machine quantities with units, figure, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact.model.params import reference_machine
from rotorcontact.studies.attractors import attractors
from reference_parameters import REF

ITEM_KEYS = {"name", "label", "appears", "disappears", "present", "count", "fraction", "ci_low", "ci_high",
             "exponent", "exponent_error", "labels"}


def test_json_contract_matches_the_library(cli, tmp_path):
    args = ("attractors", "--param", "gamma", "--from", "0.08", "--to", "0.16", "--n", "3", "--grid", "plane:7",
            "--t-lyapunov", "100", "--no-progress", "--out", tmp_path / "a.nc", "--plot", tmp_path / "a.png")
    data = cli.json(*args)
    assert next(iter(data)) == "parameters"
    assert {"out", "param", "unit", "values", "grid", "simulated_per_value", "confidence", "attractors", "impacts",
            "chunks_computed", "chunks_reused", "seconds", "plot"} <= set(data)
    assert data["param"] == "gamma" and data["unit"] == "1" and data["values"] == [0.08, 0.12, 0.16]
    assert (tmp_path / "a.png").stat().st_size > 0 and (tmp_path / "a.nc").exists()
    lib = attractors(REF, "gamma", [0.08, 0.12, 0.16], "plane:7", t_lyapunov=100.0,
                     progress=False)
    assert [a["name"] for a in data["attractors"]] == list(lib.names)
    for item, att in zip(data["attractors"], lib.attractors):
        assert set(item) == ITEM_KEYS
        assert item["count"] == att.count.tolist() and item["fraction"] == att.fraction.tolist()
        assert item["label"] == att.label and item["appears"] == att.appears
        assert [x is None for x in item["exponent"]] == [not p for p in att.present]
    total = np.sum([a["fraction"] for a in data["attractors"]], axis=0)
    np.testing.assert_allclose(total, 1.0, atol=1e-12)
    # the same command again reads the finished file back
    code, _out, err = cli.run(*args, "--json")
    assert code == 0 and "read back" in err


def test_machine_speed_in_rpm(cli, tmp_path):
    data = cli.json("attractors", "--machine", "reference", "--param", "speed", "--from", "3000rpm", "--to",
                    "4000rpm", "--n", "2", "--grid", "plane:5", "--no-lyapunov", "--no-progress",
                    "--out", tmp_path / "s.nc")
    rpm = 2.0 * math.pi / 60.0
    assert data["unit"] == "rad/s"
    assert data["values"] == pytest.approx([3000 * rpm, 4000 * rpm], rel=1e-12)
    assert data["values_rpm"] == pytest.approx([3000.0, 4000.0], rel=1e-12)
    assert "machine" in data
    m = reference_machine()
    lib = attractors(m.parameters(), "speed", data["values"], "plane:5", lyapunov=False, progress=False, machine=m)
    assert [a["count"] for a in data["attractors"]] == [a.count.tolist() for a in lib.attractors]
    assert all("exponent_per_s" in a for a in data["attractors"])


@pytest.mark.parametrize("param, start, stop", [("speed", "1500rpm", "2000rpm"), ("stiffness", "9e5", "1.1e6")])
def test_exponents_per_second_use_the_speed_of_each_value(cli, tmp_path, param, start, stop):
    # per second = dimensionless times Omega (time in units of 1 / Omega, MODEL.md §2): the Omega of each value
    # along the speed, the machine's own along the stiffness
    data = cli.json("attractors", "--machine", "reference", "--param", param, "--from", start, "--to", stop,
                    "--n", "2", "--grid", "plane:3", "--t-lyapunov", "200", "--no-progress", "--out",
                    tmp_path / "s.nc")
    speeds = data["values"] if param == "speed" else [reference_machine().speed] * 2
    exponents = 0
    for item in data["attractors"]:
        for x, per_s, omega in zip(item["exponent"], item["exponent_per_s"], speeds):
            assert per_s is None if x is None else per_s == pytest.approx(x * omega, rel=1e-14)
            exponents += x is not None
    assert exponents >= 2


@pytest.mark.parametrize("extra, word", [
    (["--param", "nonsense", "--from", "0", "--to", "1"], "--param"),
    (["--param", "speed", "--from", "1", "--to", "2"], "--machine"),
    (["--param", "gamma", "--from", "0.2", "--to", "0.1"], "--from"),
    (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--t-lyapunov", "0"], "t-lyapunov"),
    (["--param", "omega", "--from", "-1", "--to", "0.2"], "--from"),
    # keys of the general model, which the study on the paper's model leaves out (a flat sweep), refused
    (["--machine", "reference", "--param", "gravity", "--from", "0", "--to", "10"], "general model"),
    (["--machine", "reference", "--param", "contact_stiffness", "--from", "1e9", "--to", "1e10"], "general model"),
    (["--machine", "reference", "--param", "speed", "--from", "2000rpm", "--to", "1500rpm"],
     "--from = 2000rpm must be smaller than --to = 1500rpm"),
    # a rubbing point is matched by its angle: refused before anything is computed
    (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--match-tol", "4"], "--match-tol"),
])
def test_bad_input_exits_2_with_one_line(cli, tmp_path, extra, word):
    code, _out, err = cli.run("attractors", *extra, "--n", "3", "--grid", "plane:3", "--out", tmp_path / "x.nc")
    assert code == 2 and word in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []  # neither the file nor a folder of chunks


def test_one_value_with_equal_ends(cli, tmp_path):
    data = cli.json("attractors", "--param", "gamma", "--from", "0.1", "--to", "0.1", "--n", "1", "--grid",
                    "plane:3", "--no-lyapunov", "--no-progress", "--out", tmp_path / "a.nc")
    assert data["values"] == [0.1] and all(len(a["count"]) == 1 for a in data["attractors"])
