"""``rotorcontact orbits``: JSON contract, table, and bad input."""

from __future__ import annotations

import math

import pytest

from rotorcontact import reference_machine
from rotorcontact.maps.impact_map import one_impact_orbits
from reference_parameters import REF


KEYS = {
    "label", "n", "branch", "T", "theta", "rdot", "thetadot", "admissible", "plausible",
    "r_max_interior", "interior_extrema", "multipliers", "stable", "friction_reverses",
}


def test_json_contract_at_the_reference_with_gamma_01(cli):
    data = cli.json("orbits", "--gamma", "0.1")
    assert set(data) == {"parameters", "orbits"}
    assert data["parameters"] == REF.replace(gamma=0.1).as_dict()
    orbits = data["orbits"]
    assert [o["label"] for o in orbits] == ["B1,a", "B1,b", "B1,c", "B1,d"]
    lib = one_impact_orbits(REF.replace(gamma=0.1), 12.0)
    for o, ref in zip(orbits, lib):
        assert set(o) == KEYS
        assert o["label"] == f"B{o['n']},{o['branch']}"
        for key in ("T", "theta", "rdot", "thetadot", "admissible", "plausible", "interior_extrema", "stable",
                    "friction_reverses"):
            assert o[key] == getattr(ref, key)
        assert o["r_max_interior"] == ref.r_max_interior
        assert o["multipliers"] == [[m.real, m.imag] for m in ref.multipliers]
        assert -math.pi < o["theta"] <= math.pi
    d = orbits[3]
    assert d["stable"] is True and d["plausible"] is True and d["T"] == pytest.approx(2.8635, abs=1e-4)
    # at the reference machine (R/c_r = 57) friction never reverses at an impact
    assert all(o["friction_reverses"] is False for o in orbits)
    assert all(len(m) == 2 for m in d["multipliers"]) and len(d["multipliers"]) == 3


def test_virtual_orbits_have_null_multipliers_and_stability(cli):
    orbits = cli.json("orbits", "--gamma", "0.05", "--t-max", "40")["orbits"]
    virtual = [o for o in orbits if not o["admissible"]]
    assert virtual and all(o["multipliers"] is None and o["stable"] is None for o in virtual)
    assert all(o["plausible"] is False for o in virtual)
    admissible = [o for o in orbits if o["admissible"]]
    assert admissible and all(isinstance(o["stable"], bool) for o in admissible)
    # the pairs beyond T = 12 appear only with the larger --t-max
    assert {o["n"] for o in orbits} == {1, 2}
    assert {o["n"] for o in cli.json("orbits", "--gamma", "0.05")["orbits"]} == {1}


def test_no_orbits_above_the_first_fold(cli):
    assert cli.json("orbits", "--gamma", "0.2")["orbits"] == []


def test_machine_and_parameter_options(cli):
    a = cli.json("orbits", "--machine", "reference", "--gamma", "0.1")
    b = cli.json("orbits", "--gamma", "0.1")
    assert a == b
    c = cli.json("orbits", "--gamma", "0.1", "--phi", "1.0")["orbits"]
    # the phase only rotates theta (MODEL.md §5)
    for o1, o2 in zip(b["orbits"], c):
        assert o1["T"] == pytest.approx(o2["T"], abs=1e-13) and o1["rdot"] == pytest.approx(o2["rdot"], abs=1e-12)
        assert math.remainder(o2["theta"] - o1["theta"] - (1.0 - 0.21), 2 * math.pi) == pytest.approx(0.0, abs=1e-9)


def test_an_orbit_whose_friction_would_reverse_is_flagged_and_not_stable_or_plausible(cli):
    # with R/c_r = 0.2, v_rel = r_ratio + 1 + thetadot- at the impact of B1,d is negative: the law of
    # MODEL.md §5 (F1) has a fixed point there that the simulator, whose friction stops at v_rel = 0,
    # does not have
    orbits = {o["label"]: o for o in cli.json("orbits", "--gamma", "0.1", "--r-ratio", "0.2")["orbits"]}
    d = orbits["B1,d"]
    assert d["admissible"] is True and 0.2 + 1.0 + d["thetadot"] < 0.0
    assert d["friction_reverses"] is True and d["stable"] is None and d["plausible"] is False
    # the others slip as the law assumes
    assert all(o["friction_reverses"] is False for label, o in orbits.items() if label != "B1,d")
    code, text, err = cli.run("orbits", "--gamma", "0.1", "--r-ratio", "0.2")
    assert code == 0, err
    row = next(line for line in text.splitlines() if line.startswith("B1,d"))
    assert "reverses" in row and "stable" not in row and " yes " not in row
    assert "friction reverses at the impact of B1,d" in text


def test_with_a_machine_orbits_carry_si_values(cli):
    data = cli.json("orbits", "--machine", "reference")
    m = reference_machine()
    assert data["machine"] == m.as_dict() and data["parameters"] == m.parameters().as_dict()
    lib = {o.label: o for o in one_impact_orbits(m.parameters(), 12.0)}
    for o in data["orbits"]:
        ref = lib[o["label"]]
        assert o["T_s"] == pytest.approx(ref.T / m.speed, rel=1e-12)
        assert o["impact_rate_hz"] == pytest.approx(m.speed / ref.T, rel=1e-12)
        assert o["rdot_m_per_s"] == pytest.approx(ref.rdot * m.clearance * m.speed, rel=1e-12)
        assert o["thetadot_rad_per_s"] == pytest.approx(ref.thetadot * m.speed, rel=1e-12)
        assert o["normal_impulse_Ns"] == pytest.approx((1 + m.restitution) * ref.rdot * m.mass * m.clearance
                                                       * m.speed, rel=1e-12)
        assert o["amplitude_um"] == pytest.approx(700.0, rel=1e-12)
    code, out, err = cli.run("orbits", "--machine", "reference")
    assert code == 0, err
    assert "T ms" in out
    # without a machine there are no SI keys
    assert "T_s" not in cli.json("orbits")["orbits"][0]


def test_text_table(cli):
    code, out, err = cli.run("orbits", "--gamma", "0.1")
    assert code == 0, err
    for label in ("B1,a", "B1,b", "B1,c", "B1,d"):
        assert label in out
    assert "stable" in out and "admissible" in out
    code, out, err = cli.run("orbits", "--gamma", "0.3")
    assert code == 0, err
    assert "no one-impact periodic orbit" in out


@pytest.mark.parametrize(
    "args",
    [
        ["--t-max", "-1"],
        ["--t-max", "abc"],
        ["--t-max", "nan"],
        ["--t-max", "1e7"],
        ["--gamma", "x"],
        ["--d", "2"],
        ["--omega", "1", "--gamma", "0"],
    ],
)
def test_bad_input_exit_status_2_without_traceback(cli, args):
    code, _, err = cli.run("orbits", *args)
    assert code == 2
    assert "error" in err and "Traceback" not in err


def test_console_script(cli):
    data = cli.exe_json("orbits", "--gamma", "0.1")
    assert [o["label"] for o in data["orbits"]] == ["B1,a", "B1,b", "B1,c", "B1,d"]
    code, _, err = cli.exe("orbits", "--t-max", "0", timeout=300)
    assert code == 2 and "Traceback" not in err and "--t-max" in err
