"""``rotorcontact equilibria``: JSON contract, text, figure, and bad input."""

from __future__ import annotations

import math

import pytest

from rotorcontact.analysis.equilibria import equilibria
from reference_parameters import REF


def test_json_contract_at_the_reference(cli):
    data = cli.json("equilibria")
    assert {"regular", "pseudo", "boundary"} <= set(data)
    reg = data["regular"]
    assert {"r", "theta", "admissible", "stable", "eigenvalues"} <= set(reg)
    assert all(isinstance(z, list) and len(z) == 2 for z in reg["eigenvalues"]) and len(reg["eigenvalues"]) == 4
    assert [pe["name"] for pe in data["pseudo"]] == ["P1", "P2"]
    for pe in data["pseudo"]:
        assert {"name", "theta", "normal_force", "admissible", "stable"} <= set(pe)
    b = data["boundary"]
    assert {"gamma_star", "theta", "kind", "partner"} <= set(b)
    # the numbers are the library's
    eq = equilibria(REF)
    assert reg["r"] == eq.regular.r and reg["theta"] == eq.regular.theta
    assert reg["admissible"] is True and reg["stable"] is True
    assert [pe["theta"] for pe in data["pseudo"]] == [pe.theta for pe in eq.pseudo]
    assert [pe["normal_force"] for pe in data["pseudo"]] == [pe.normal_force for pe in eq.pseudo]
    assert b["gamma_star"] == eq.boundary.gamma_star and b["kind"] == eq.boundary.kind
    for angle in [reg["theta"], b["theta"]] + [pe["theta"] for pe in data["pseudo"]]:
        assert -math.pi < angle <= math.pi


def test_json_reference_classifications(cli):
    fold = cli.json("equilibria", "--omega", "0.76")["boundary"]
    assert fold["kind"] == "nonsmooth-fold" and fold["partner"] == "P1" and round(fold["gamma_star"], 3) == 0.072
    pers = cli.json("equilibria", "--omega", "1")["boundary"]
    assert pers["kind"] == "persistence" and pers["partner"] == "P2"
    assert pers["gamma_star"] == pytest.approx(3 / 7, rel=1e-15)


def test_json_without_real_gamma_star_and_without_pseudo_equilibria(cli):
    data = cli.json("equilibria", "--omega", "0.3", "--gamma", "0.9")
    assert data["boundary"]["gamma_star"] is None
    assert data["boundary"]["kind"] is None and data["boundary"]["partner"] is None
    for pe in data["pseudo"]:
        assert pe["theta"] is None and pe["normal_force"] is None and pe["admissible"] is False
        assert pe["stable"] is None and pe["reason"]


def test_json_mu_zero_is_defined(cli):
    data = cli.json("equilibria", "--mu", "0")
    assert all(isinstance(pe["theta"], float) for pe in data["pseudo"])


def test_json_with_a_range_reports_the_events(cli):
    data = cli.json("equilibria", "--omega", "0.76", "--param", "gamma", "--from", "0", "--to", "0.2")
    events = data["branches"]["events"]
    beb = [e for e in events if e["branch"] == "x_R" and e["kind"] == "admissibility"]
    assert len(beb) == 1 and beb[0]["partner"] == "P1"
    assert beb[0]["value"] == pytest.approx(data["boundary"]["gamma_star"], abs=1e-12)


def test_text_output(cli):
    code, out, err = cli.run("equilibria", "--omega", "1")
    assert code == 0, err
    assert "x_R" in out and "x_P1" in out and "x_P2" in out and "persistence with x_P2" in out


def test_plot(tmp_path, cli):
    path = tmp_path / "fig3a.png"
    code, out, _ = cli.run("equilibria", "--omega", "0.76", "--plot", path, "--param", "gamma", "--from", "0",
                           "--to", "0.2")
    assert code == 0 and path.is_file() and path.stat().st_size > 1000
    assert "figure written" in out


@pytest.mark.parametrize(
    "args, word",
    [
        (["--omega", "0"], "omega"),
        (["--mu", "-1"], "mu"),
        (["--gamma", "abc"], "gamma"),
        (["--plot", "x.png"], "--from"),
        (["--from", "0"], "--to"),
        (["--param", "phi", "--from", "0", "--to", "1"], "phi"),
        (["--from", "0.3", "--to", "0.1"], "start < stop"),
        (["--param", "d", "--from", "0", "--to", "2"], "d = "),
        (["--plot", "x.txt", "--from", "0", "--to", "0.1"], "suffix"),
        (["--from", "0", "--to", "0.1", "--points", "1"], "points"),
        (["--points", "5"], "--points = '5' sets the grid of a parameter range"),
    ],
)
def test_bad_input_exits_2_with_a_message(args, word, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = cli.run("equilibria", *args)
    assert code == 2
    assert word in err and "Traceback" not in err
    assert not list(tmp_path.iterdir())


def test_subprocess_exit_status(cli):
    assert cli.exe_json("equilibria")["boundary"]["kind"] in ("nonsmooth-fold", "persistence")
    code, _, err = cli.exe("equilibria", "--mu", "-1", timeout=300)
    assert code == 2
    assert "mu" in err and "Traceback" not in err
