"""Every ``--json`` output carries the parameters it was computed at; with ``--machine``, SI values too."""

from __future__ import annotations

import math

import pytest

from rotorcontact import reference_machine
from rotorcontact.analysis.equilibria import equilibria
from rotorcontact.analysis.lyapunov import lyapunov_spectrum
from reference_parameters import REF


MACHINE = reference_machine()


COMMANDS = [
    ["simulate", "--t-end", "20"],
    ["equilibria"],
    ["orbits", "--gamma", "0.1"],
    ["orbits", "--impacts", "2", "--gamma", "0.083"],
    ["branches", "--from", "0.1", "--to", "0.12", "--seeds", "3"],
    ["codim2", "--grazing", "none", "--from", "0.1,0.7", "--to", "0.2,0.8"],
    ["local"],
    ["lyapunov", "--t-end", "60"],
    ["lyapunov", "--t-end", "60", "--details"],
]


@pytest.mark.parametrize("args", COMMANDS, ids=lambda a: " ".join(a))
def test_every_json_output_carries_the_parameters(args, cli):
    data = cli.json(*args, "--rho=0.45")
    gamma = float(args[args.index("--gamma") + 1]) if "--gamma" in args else REF.gamma
    if args[0] == "local":  # the local analysis is made at gamma*
        gamma = data["gamma_star"]
    assert data["parameters"] == REF.replace(gamma=gamma, rho=0.45).as_dict()
    assert next(iter(data)) == "parameters"


def test_sweep_basins_and_design_map_json_carry_the_parameters(tmp_path, cli):
    sweep = cli.json("sweep", "--param", "gamma", "--from", "0.1", "--to", "0.11", "--n", "2",
                  "--transient", "20", "--record", "5", "--out", str(tmp_path / "s.nc"), "--no-progress")
    assert sweep["parameters"] == REF.as_dict()
    basins = cli.json("basins", "--gamma", "0.1", "--grid", "plane:3", "--transient", "20", "--record", "5",
                   "--out", str(tmp_path / "b.nc"), "--no-progress")
    assert basins["parameters"] == REF.replace(gamma=0.1).as_dict()
    dmap = cli.json("design-map", "--machine", "reference", "--speed", "1500:2000rpm", "--n", "2")
    assert dmap["parameters"] == MACHINE.parameters().as_dict() and dmap["machine"] == MACHINE.as_dict()


def test_equilibria_with_a_machine_give_micrometres_newtons_and_damping(cli):
    data = cli.json("equilibria", "--machine", "reference", "--from", "0.05", "--to", "0.1")
    eq = equilibria(MACHINE.parameters())
    m = MACHINE
    assert data["machine"] == m.as_dict()
    assert data["regular"]["amplitude_um"] == pytest.approx(eq.regular.r * m.clearance * 1e6, rel=1e-12)
    for row, pe in zip(data["pseudo"], eq.pseudo):
        assert row["normal_force_N"] == pytest.approx(pe.normal_force * m.mass * m.clearance * m.speed**2, rel=1e-12)
        v_rel = (m.rotor_radius + m.clearance) * m.speed
        assert row["friction_power_W"] == pytest.approx(m.friction * row["normal_force_N"] * v_rel, rel=1e-12)
    # gamma* = c* / (m Omega)
    assert data["boundary"]["damping_star_Ns_per_m"] == pytest.approx(
        eq.boundary.gamma_star * m.mass * m.speed, rel=1e-12)
    for e in data["branches"]["events"]:
        assert e["damping_Ns_per_m"] == pytest.approx(e["value"] * m.mass * m.speed, rel=1e-12)
    # without a machine: no SI keys
    plain = cli.json("equilibria")
    assert "amplitude_um" not in plain["regular"] and "machine" not in plain


def test_branches_local_and_lyapunov_with_a_machine_give_seconds(cli):
    m = MACHINE
    br = cli.json("branches", "--machine", "reference", "--from", "0.17", "--to", "0.19", "--seeds", "3")
    assert br["events"] and br["machine"] == m.as_dict()
    for e in br["events"]:
        assert e["damping_Ns_per_m"] == pytest.approx(e["value"] * m.mass * m.speed, rel=1e-12)
        assert e["T_s"] > 0 and e["rdot_m_per_s"] is not None
    for arrays in br["branches"].values():
        for g, c, t, ts in zip(arrays["gamma"], arrays["damping_Ns_per_m"], arrays["T"], arrays["T_s"]):
            assert (g is None) == (c is None) and (t is None) == (ts is None)
            if g is not None:
                assert c == pytest.approx(g * m.mass * m.speed, rel=1e-12)
                assert ts == pytest.approx(t / m.speed, rel=1e-12)
    loc = cli.json("local", "--machine", "reference")
    assert loc["damping_star_Ns_per_m"] == pytest.approx(loc["gamma_star"] * m.mass * m.speed, rel=1e-12)
    assert all(o["T_s"] == pytest.approx(o["T"] / m.speed, rel=1e-12) for o in loc["orbits"])
    ly = cli.json("lyapunov", "--machine", "reference", "--t-end", "200", "--details")
    res = lyapunov_spectrum(m.parameters(), 0j, 0j, 200.0)
    for x, per_s in zip(res.exponents, ly["exponents_per_s"]):
        assert (per_s is None) if not math.isfinite(x) else per_s == pytest.approx(x * m.speed, rel=1e-12)
    assert ly["t_stop_s"] == pytest.approx(res.t_stop / m.speed, rel=1e-12)
