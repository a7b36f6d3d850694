"""``rotorcontact simulate --json`` with continuous contact: contact intervals, the regime,
and the SI forces, impulses and friction power when a machine is given (MODEL.md §1, §4).

The SI values are checked against the dimensionless quantities recomputed here from
MODEL.md and the scales m c_r Omega^2 (force), m c_r Omega (impulse) and c_r Omega (speed).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rotorcontact import load_machine, simulate
from reference_parameters import REF, REF_MACHINE_TOML, replace_line


KINDS = {"sliding-forward", "rolling", "sliding-backward"}
REGIMES = {"no-contact", "periodic-impacting", "irregular-impacting", "forward-rub", "backward-whirl", "mixed"}

# the reference rig with the bearing damping lowered to c = 460.5 N s/m (gamma = c / (m Omega) = 0.05)
TOML_LOW_DAMPING = replace_line(REF_MACHINE_TOML, "damping", "damping = 460.5")


def normal(p, theta, thetadot):
    return (1.0 + thetadot) ** 2 - p.omega**2 + p.rho * np.cos(p.phi - theta)


def tangential(p, theta, thetadot):
    return -(1.0 + thetadot) * p.gamma + p.rho * np.sin(p.phi - theta)


def check_intervals(data):
    ci = data["contact_intervals"]
    assert isinstance(ci, list)
    for row in ci:
        assert {"t_start", "t_end", "kind"} <= set(row)
        assert row["kind"] in KINDS
        assert isinstance(row["t_start"], float) and isinstance(row["t_end"], float)
        assert 0.0 <= row["t_start"] <= row["t_end"] <= data["t_stop"]
    for a, b in zip(ci, ci[1:]):
        assert a["t_end"] <= b["t_start"]
    return ci


@pytest.mark.parametrize("d,regime,kinds", [
    ("0", "forward-rub", ["sliding-forward"]),
    ("0.5", "forward-rub", ["sliding-forward"]),
    ("0.95", "backward-whirl", ["sliding-forward", "rolling"]),
])
def test_json_contact_intervals_and_regime(d, regime, kinds, cli):
    data = cli.json("simulate", "--gamma=0.05", f"--d={d}", "--u0=0.5,0", "--du0=0.8,0.3", "--t-end=120")
    assert data["status"] == "completed"
    ci = check_intervals(data)
    assert [row["kind"] for row in ci] == kinds
    assert set(ci[0]) == {"t_start", "t_end", "kind"}  # no SI fields without a machine
    assert data["summary"]["regime"] == regime
    assert data["summary"]["regime"] in REGIMES
    assert ci[-1]["t_end"] == 120.0
    traj = simulate(REF.replace(gamma=0.05, d=float(d)), 0.5, 0.8 + 0.3j, 120.0)
    assert ci == [c.to_dict() for c in traj.contact_intervals]
    # every impact comes before the contact
    assert all(row["t"] <= ci[0]["t_start"] for row in data["impacts"])


@pytest.mark.parametrize("argv,regime", [
    (["--gamma=0.1", "--t-end=300"], "periodic-impacting"),
    (["--gamma=0.5", "--t-end=100"], "no-contact"),
])
def test_json_regime_without_contact(argv, regime, cli):
    data = cli.json("simulate", *argv)
    assert data["contact_intervals"] == []
    assert data["summary"]["regime"] == regime


def test_json_chatter_stop_has_the_regime_key(cli):
    data = cli.json("simulate", "--gamma=0.05", "--d=0.5", "--u0=0.5,0", "--du0=0.8,0.3", "--t-end=120",
                    "--on-chatter=stop")
    assert data["status"] == "chatter"
    assert "regime" in data["summary"]
    assert data["contact_intervals"] == []
    traj = simulate(REF.replace(gamma=0.05, d=0.5), 0.5, 0.8 + 0.3j, 120.0)
    assert data["t_stop"] == pytest.approx(traj.contact_intervals[0].t_start, abs=1e-12)


def _check_si(data, machine):
    p = machine.parameters()
    fs = machine.mass * machine.clearance * machine.speed**2
    js = machine.mass * machine.clearance * machine.speed
    vs = machine.clearance * machine.speed
    traj = simulate(p, complex(*data["initial_state"]["u0"]), complex(*data["initial_state"]["du0"]),
                    data["t_end"], machine=machine)
    for row in data["impacts"]:
        for key in ("normal_impulse_Ns", "tangential_impulse_Ns", "t_s"):
            assert isinstance(row[key], float) and math.isfinite(row[key])
        # normal impulse (1 + d) rdot- per unit mass (MODEL.md §2)
        assert row["normal_impulse_Ns"] == pytest.approx((1.0 + p.d) * row["rdot"] * js, rel=1e-12)
        assert abs(row["tangential_impulse_Ns"]) <= p.mu * row["normal_impulse_Ns"] * (1 + 1e-12)
        assert row["t_s"] == pytest.approx(row["t"] / machine.speed, rel=1e-12)
    ci = check_intervals(data)
    assert ci
    for row in ci:
        for key in ("max_normal_force_N", "max_friction_force_N", "mean_friction_power_W", "t_start_s", "t_end_s"):
            assert isinstance(row[key], float) and math.isfinite(row[key]), (key, row)
        # N, the friction force and |F_t v_rel| of the row's kind (MODEL.md §4), recomputed from the state on a
        # dense grid of the closed interval; the friction law of a sliding phase holds up to its end
        a, b = row["t_start"], min(row["t_end"], data["t_stop"])
        sign = {"sliding-forward": 1.0, "sliding-backward": -1.0}.get(row["kind"])

        def law(t):
            u, du = traj.state(t)
            r = np.abs(u)
            w = np.conj(u / r) * du
            th, thd = np.angle(u), w.imag / r
            n = normal(p, th, thd)
            ft = -tangential(p, th, thd) if sign is None else -p.mu * n * sign
            return n, ft, np.abs(ft * (p.r_ratio + 1.0 + thd))

        n, ft, _power = law(np.linspace(a, b, 20001))
        # the largest sample, and at most the largest change between neighbouring samples above it
        for key, v in (("max_normal_force_N", n), ("max_friction_force_N", np.abs(ft))):
            assert v.max() * fs * (1 - 1e-12) <= row[key] <= (v.max() + np.abs(np.diff(v)).max()) * fs, (key, row)
        if sign is not None:  # |F_t| = mu N throughout a sliding phase
            assert row["max_friction_force_N"] == pytest.approx(p.mu * row["max_normal_force_N"], rel=1e-12)
        if sign is None:  # rolling: no slip, so no friction power but rounding
            assert abs(row["mean_friction_power_W"]) <= 1e-9 * fs * vs
        else:
            mean_power = quad(lambda t: law(np.array([t]))[2][0], a, b, epsabs=0.0, epsrel=1e-11, limit=500)[0]
            assert row["mean_friction_power_W"] == pytest.approx(mean_power / (b - a) * fs * vs, rel=1e-8)
        assert row["max_normal_force_N"] > 0
        assert row["max_friction_force_N"] <= p.mu * row["max_normal_force_N"] * (1 + 1e-9)
        assert row["t_start_s"] == pytest.approx(row["t_start"] / machine.speed, rel=1e-12)
    return ci


def test_json_with_a_machine_file_has_finite_si_values(tmp_path, cli):
    path = tmp_path / "low_damping.toml"
    path.write_text(TOML_LOW_DAMPING)
    data = cli.json("simulate", f"--machine={path}", "--u0=0.5,0", "--du0=0.8,0.3", "--t-end=60")
    machine = load_machine(path)
    assert data["machine"] == machine.as_dict()
    assert machine.parameters().gamma == pytest.approx(0.05, rel=1e-12)
    ci = _check_si(data, machine)
    assert [row["kind"] for row in ci] == ["sliding-forward", "rolling"]
    assert len(data["impacts"]) > 10
    # rolling: no slip, no friction power; the rotor is held by a force of order m c_r Omega^2 r_ratio^2
    roll = ci[-1]
    assert roll["mean_friction_power_W"] == pytest.approx(0.0, abs=1e-6)
    assert roll["max_normal_force_N"] > 1e6
    # sliding forward dissipates power
    assert ci[0]["mean_friction_power_W"] > 0


def test_json_with_the_reference_machine(cli):
    """--machine reference: a rub started on the stator near x_P2, and an impacting run."""
    from rotorcontact.analysis.equilibria import pseudo_equilibria

    machine = load_machine("reference")
    th = pseudo_equilibria(machine.parameters())[1].theta + 0.1
    data = cli.json("simulate", "--machine=reference", f"--u0={math.cos(th)!r},{math.sin(th)!r}", "--du0=0,0",
                    "--t-end=50")
    ci = _check_si(data, machine)
    assert [row["kind"] for row in ci] == ["sliding-forward"]
    assert data["summary"]["regime"] == "forward-rub"
    data = cli.json("simulate", "--machine=reference", "--u0=0.5,0", "--du0=0.8,0.3", "--t-end=60")
    assert len(data["impacts"]) > 10 and data["contact_intervals"] == []
    for row in data["impacts"]:
        assert math.isfinite(row["normal_impulse_Ns"]) and row["normal_impulse_Ns"] > 0


def test_json_contact_through_the_installed_command(tmp_path, cli):
    code, out, err = cli.exe("simulate", "--gamma", "0.05", "--u0", "0.5,0", "--du0", "0.8,0.3", "--t-end", "60",
                             "--on-chatter", "contact", "--json", cwd=tmp_path)
    assert code == 0, err
    data = cli.loads(out)
    ci = check_intervals(data)
    assert [row["kind"] for row in ci] == ["sliding-forward", "rolling"]
    assert data["summary"]["regime"] == "backward-whirl"
