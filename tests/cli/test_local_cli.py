"""``rotorcontact local``: JSON contract, table, and bad input."""

from __future__ import annotations


import pytest

from rotorcontact.analysis.equilibria import boundary_gamma
from rotorcontact.maps.impact_map import f1_zeros
from rotorcontact.analysis.local import local_analysis
from reference_parameters import REF


ORBIT_KEYS = {"label", "T", "rdot_slope", "thetadot_slope", "theta_slope"}


def test_json_contract_at_the_reference(cli):
    data = cli.json("local")
    assert set(data) == {"parameters", "gamma_star", "orbits"}
    p = REF
    assert data["gamma_star"] == boundary_gamma(p)
    assert [o["label"] for o in data["orbits"]] == ["B1,a", "B1,b"]
    lib = local_analysis(p, 12.0)
    for o, ref in zip(data["orbits"], lib.orbits):
        assert set(o) == ORBIT_KEYS
        assert o == ref.to_dict()
        assert all(isinstance(o[k], float) for k in ORBIT_KEYS - {"label"})
    # the periods are the zeros of F1 at gamma*
    zeros = f1_zeros(p.replace(gamma=data["gamma_star"]), 12.0)
    assert [o["T"] for o in data["orbits"]] == pytest.approx([z.T for z in zeros], abs=1e-10)
    # the small orbits grow for gamma > gamma*
    assert all(o["rdot_slope"] > 0 for o in data["orbits"])


def test_gamma_is_replaced_by_gamma_star_and_options_apply(cli):
    assert cli.json("local", "--gamma", "0.3") == cli.json("local")
    data = cli.json("local", "--omega", "0.7565", "--t-max", "40")
    p = REF.replace(omega=0.7565)
    assert data["gamma_star"] == pytest.approx(boundary_gamma(p))
    zeros = f1_zeros(p.replace(gamma=data["gamma_star"]), 40.0)
    assert len(data["orbits"]) == len(zeros) == 10
    # one small orbit per zero: branch a or c at T0,n,a, b or d at T0,n,b (a/b where it is the smaller root)
    partner = {"a": "ac", "b": "bd"}
    for o, z in zip(data["orbits"], zeros):
        n, branch = o["label"][1:].split(",")
        assert int(n) == z.n and branch in partner[z.kind]
        assert o["T"] == pytest.approx(z.T, abs=1e-10)
    assert [o["label"] for o in data["orbits"]] == [o.label for o in local_analysis(p, 40.0).orbits]
    assert cli.json("local", "--t-max", "0.5")["orbits"] == []  # T0,1,a is about 0.67


def test_table_output(cli):
    code, out, err = cli.run("local")
    assert code == 0, err
    assert "gamma*" in out and "B1,a" in out and "B1,b" in out and "gamma > gamma*" in out


@pytest.mark.parametrize(
    "args, message",
    [
        (["--rho", "0"], "no real gamma*"),
        (["--omega", "0.3"], "no real gamma*"),
        (["--omega", "0.5", "--rho", "0.75"], "not asymptotically stable"),
        (["--t-max", "-1"], "--t-max"),
        (["--t-max", "abc"], "--t-max"),
        (["--d", "2"], "--d"),
    ],
)
def test_bad_input_exits_2_with_a_message(cli, args, message):
    code, out, err = cli.run("local", "--json", *args)
    assert code == 2
    assert out == ""
    assert message in err and "Traceback" not in err


def test_installed_command_exits_2_without_traceback(cli):
    code, _, err = cli.exe("local", "--json", "--rho", "0.75", "--omega", "0.5")
    assert code == 2
    assert "not asymptotically stable" in err and "Traceback" not in err
