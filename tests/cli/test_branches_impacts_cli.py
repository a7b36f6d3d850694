"""``rotorcontact branches --impacts p --doublings K``: JSON contract, agreement with the library, bad input."""

from __future__ import annotations

import pytest

from rotorcontact.continuation.multi_impact_families import multi_impact_branches
from reference_parameters import REF

BASE = ["--gamma", "0.0818", "--from", "0.075", "--to", "0.09"]


def test_json_contract_and_agreement_with_the_library(cli):
    data = cli.json("branches", "--impacts", "2", "--doublings", "1", *BASE)
    assert set(data) == {"parameters", "param", "events", "branches", "impacts"}
    assert data["impacts"] == 2 and data["param"] == "gamma"
    for e in data["events"]:
        assert {"type", "value", "orbits", "impacts"} <= set(e)
        assert e["type"] in ("fold", "branch-point", "period-doubling", "neimark-sacker", "grazing", "slip")
    for label, arrays in data["branches"].items():
        assert {"gamma", "T", "rdot", "thetadot", "stable", "impacts"} <= set(arrays)
        assert arrays["impacts"] == 2 * 2 ** label.count("/PD")
        n = len(arrays["gamma"])
        assert all(len(arrays[k]) == n for k in ("T", "rdot", "thetadot", "stable"))
    lib = multi_impact_branches(REF.replace(gamma=0.0818), 2, "gamma", 0.075, 0.09, doublings=1)
    assert list(data["branches"]) == list(lib.labels)
    assert [e["value"] for e in data["events"]] == [e.value for e in lib.events]
    assert any(label.endswith("/PD") for label in data["branches"])


def test_one_impact_branches_with_their_doubled_branches(cli):
    data = cli.json("branches", "--impacts", "1", "--doublings", "1", "--gamma", "0.1", "--from", "0.08",
                    "--to", "0.1", "--t-max", "4", "--seeds", "4")
    assert data["impacts"] == 1
    assert data["branches"]["B1,d"]["impacts"] == 1 and data["branches"]["B1,d/PD"]["impacts"] == 2
    pd = [e for e in data["events"] if e["type"] == "period-doubling" and e["orbits"] == ["B1,d"]]
    assert len(pd) == 1 and pd[0]["impacts"] == 1
    # the doubled branch starts at the doubling and lies below it (where B1,d has a multiplier below -1)
    g = data["branches"]["B1,d/PD"]["gamma"]
    assert abs(g[0] - pd[0]["value"]) < 1e-4 and max(g) <= pd[0]["value"] + 1e-9
    assert [e["value"] for e in data["events"]] == sorted(e["value"] for e in data["events"])


def test_text_output(cli):
    code, out, err = cli.run("branches", "--impacts", "2", *BASE)
    assert code == 0, err
    assert "orbits with 2 impact(s) per period" in out and "M2-1" in out


@pytest.mark.parametrize("args", [
    ["--impacts", "0"], ["--impacts", "x"], ["--doublings", "99"], ["--doublings", "-1"],
    ["--impacts", "2", "--grid", "1,2"], ["--impacts", "2", "--grid", "200,200,2"],
    ["--impacts", "2", "--gamma", "0.2", "--from", "0.075", "--to", "0.09"],
    ["--impacts", "2", "--plot", "x.png", *BASE],
])
def test_bad_input_exits_2(cli, args):
    code, _out, err = cli.run("branches", *args)
    assert code == 2 and "error" in err and "Traceback" not in err
