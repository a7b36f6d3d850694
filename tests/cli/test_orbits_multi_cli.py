"""``rotorcontact orbits --impacts p``: the multi-impact JSON contract; p = 1 keeps the one-impact contract."""

from __future__ import annotations

import math

import pytest

from rotorcontact.maps.impact_map import impact_map
from rotorcontact.continuation.multi_impact_branches import multi_impact_orbits
from reference_parameters import REF


KEYS = {"label", "impacts", "period", "points", "multipliers", "stable", "plausible"}
POINT_KEYS = {"theta", "rdot", "thetadot", "dt"}


def test_period_two_orbit_json_contract(cli):
    data = cli.json("orbits", "--impacts", "2", "--gamma", "0.083")
    assert set(data) == {"parameters", "orbits"} and data["parameters"]["gamma"] == 0.083
    (orbit,) = data["orbits"]
    assert set(orbit) == KEYS
    assert orbit["label"] == "B1,d/PD" and orbit["impacts"] == 2
    assert len(orbit["points"]) == 2 and all(set(q) == POINT_KEYS for q in orbit["points"])
    assert orbit["period"] == pytest.approx(sum(q["dt"] for q in orbit["points"]), abs=1e-12)
    assert len(orbit["multipliers"]) == 3 and all(len(m) == 2 for m in orbit["multipliers"])
    assert orbit["stable"] is True and orbit["plausible"] is True
    # dt is the time to the next impact, and the points follow each other under P_I
    p = REF.replace(gamma=0.083)
    for i, q in enumerate(orbit["points"]):
        nxt = orbit["points"][(i + 1) % 2]
        step = impact_map(p, (q["theta"], q["rdot"], q["thetadot"]))
        assert step.time == pytest.approx(q["dt"], abs=1e-10)
        assert math.remainder(step.state[0] - nxt["theta"], 2 * math.pi) == pytest.approx(0.0, abs=1e-10)
        assert step.state[1] == pytest.approx(nxt["rdot"], abs=1e-10)
        assert -math.pi < q["theta"] <= math.pi
    lib = multi_impact_orbits(p, 2)
    assert [o.to_dict() for o in lib] == data["orbits"]


def test_one_impact_contract_is_unchanged(cli):
    plain = cli.json("orbits", "--gamma", "0.1")
    assert cli.json("orbits", "--gamma", "0.1", "--impacts", "1") == plain
    assert [o["label"] for o in plain["orbits"]] == ["B1,a", "B1,b", "B1,c", "B1,d"]
    assert "impacts" not in plain["orbits"][0] and "n" in plain["orbits"][0]


def test_no_orbit_is_an_empty_list(cli):
    # beyond the grazing that ends the period-2 branch, B1,d's period-doubled orbit is gone
    assert cli.json("orbits", "--impacts", "2", "--gamma", "0.1")["orbits"] == []


def test_no_orbit_found_says_how_it_was_looked_for(cli):
    code, out, _err = cli.run("orbits", "--impacts", "2", "--gamma", "0.1")
    assert code == 0 and "found by simulation (stable orbits reached from its starts) or at a period doubling" in out
    assert "--grid NT,NR,ND also searches" in out
    code, out, _err = cli.run("orbits", "--impacts", "2", "--gamma", "0.1", "--grid", "1,1,1")
    assert code == 0 and "found from the grid of impact states, by simulation or at a period doubling" in out


def test_text_table(cli):
    code, out, err = cli.run("orbits", "--impacts", "2", "--gamma", "0.083")
    assert code == 0, err
    assert "B1,d/PD" in out and "2 impacts" in out and "stable" in out


@pytest.mark.parametrize("value", ["0", "-2", "x", "2.5"])
def test_bad_impacts_exit_2_without_traceback(cli, value):
    code, out, err = cli.run("orbits", "--impacts", value, "--json")
    assert code == 2
    assert out == ""
    assert "--impacts" in err and "Traceback" not in err


def test_bad_impacts_from_the_shell(cli):
    code, out, err = cli.exe("orbits", "--impacts", "0", "--json")
    assert code == 2
    assert out == ""
    assert "--impacts" in err and "Traceback" not in err


def test_grid_adds_the_unstable_orbits(cli):

    plain = cli.json("orbits", "--impacts", "2", "--gamma", "0.083")
    data = cli.json("orbits", "--impacts", "2", "--gamma", "0.083", "--grid", "12,4,4")
    labels = [o["label"] for o in data["orbits"]]
    assert [o["label"] for o in plain["orbits"]] == labels[: len(plain["orbits"])]
    extra = data["orbits"][len(plain["orbits"]):]
    assert extra and all(not o["stable"] for o in extra)
    p = REF.replace(gamma=0.083)
    for o in extra:
        a, b = ([q["theta"], q["rdot"], q["thetadot"]] for q in o["points"])
        once = impact_map(p, a)
        assert abs(once.state[1] - b[1]) < 1e-9 and abs(once.time - o["points"][0]["dt"]) < 1e-9
    code, out, err = cli.run("orbits", "--grid", "2,2,2")
    assert code == 2 and "--grid" in err
