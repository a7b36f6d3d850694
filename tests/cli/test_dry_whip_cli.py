"""``rotorcontact dry-whip``: the steady dry whip (MODEL.md §8) through the command line."""

from __future__ import annotations

import pytest

from rotorcontact import load_machine
from rotorcontact.analysis.dry_whip import steady_dry_whip
from rotorcontact.simulation.drop_run import RPM

STATOR_MACHINE = """
mass = 50.0
damping = 1400.0
stiffness = 9.8e5
eccentricity = 0.0
clearance = "0.7 mm"
rotor_radius = 0.04
unbalance_phase = 0.0
speed = "12000 rpm"
friction = 0.15
restitution = 0.9
contact = "compliant"
contact_stiffness = "1e10 N/m**1.5"
stator_mass = "20 kg"
stator_stiffness = "5 MN/m"
stator_damping = "2 kN*s/m"
"""

KEYS = {"machine", "speed_rpm", "bearing", "whirl_rate_rad_per_s", "whirl_frequency_hz", "coupled_frequency_hz",
        "rotor_orbit_m", "stator_orbit_m", "stator_phase_rad", "normal_force_N", "friction_force_N",
        "penetration_m", "slip_velocity_m_per_s"}


@pytest.fixture
def machine_file(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(STATOR_MACHINE)
    return str(path)


def test_dry_whip_json_contract_matches_the_python_api(cli, machine_file):
    data = cli.json("dry-whip", machine_file, "--speed", "6000rpm")
    assert set(data) == KEYS and data["bearing"] == "failed"
    api = steady_dry_whip(load_machine(machine_file).with_speed(6000 * RPM)).to_dict()
    assert data == api  # JSON keeps every float exactly
    assert data["speed_rpm"] == pytest.approx(6000.0, rel=1e-14)
    assert data["machine"]["speed"] == pytest.approx(6000 * RPM, rel=1e-14)  # the machine whose whip it is
    assert data["whirl_frequency_hz"] < 0.0 < data["coupled_frequency_hz"]
    assert abs(data["whirl_frequency_hz"]) < data["coupled_frequency_hz"]
    code, out, _err = cli.run("dry-whip", machine_file)
    assert code == 0 and "dry whip at 12000 rpm" in out and "coupled natural frequency" in out


@pytest.mark.parametrize("args,match", [
    (["--bearing", "sideways"], "--bearing = 'sideways'"),
    (["--bearing", "acting"], "no steady dry whip"),
    (["--speed", "10rpm"], "--speed = "),
])
def test_dry_whip_errors_exit_2(cli, machine_file, args, match):
    code, out, err = cli.run("dry-whip", machine_file, *args)
    assert code == 2 and match in err and "Traceback" not in err and out == ""


def test_a_whip_deeper_than_the_compliant_laws_range_is_warned(cli, tmp_path, machine_file):
    """A stiff support (k_s = 5e7 N/m) makes the whip press more than a clearance into the stator: the result
    is printed, with one warning line on stderr; the whip of the machine above has none."""
    path = tmp_path / "stiff.toml"
    path.write_text(STATOR_MACHINE.replace('stator_stiffness = "5 MN/m"', 'stator_stiffness = "50 MN/m"')
                    .replace("friction = 0.15", "friction = 0.2"))
    whip = steady_dry_whip(load_machine(path))
    assert whip.penetration > load_machine(path).clearance
    code, out, err = cli.run("dry-whip", str(path), "--json")
    assert code == 0 and cli.loads(out)["penetration_m"] == whip.penetration
    assert err.count("\n") == 1 and "warning: the whip presses" in err and "clearances into the stator" in err
    code, out, err = cli.run("dry-whip", machine_file, "--json")
    assert code == 0 and err == ""


def test_dry_whip_of_a_fixed_stator_is_refused(cli, tmp_path):
    path = tmp_path / "fixed.toml"
    path.write_text("\n".join(line for line in STATOR_MACHINE.splitlines() if not line.startswith("stator_")))
    code, _out, err = cli.run("dry-whip", str(path))
    assert code == 2 and "stator_mass = None" in err
