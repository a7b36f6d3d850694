"""``rotorcontact drop`` and ``simulate --machine`` with a general machine (MODEL.md §7)."""

from __future__ import annotations

import math

import pytest

from rotorcontact import Machine, reference_machine
from rotorcontact.simulation.drop_run import RPM, drop, run_general

GENERAL = """
mass = 50.0
damping = 1400.0
stiffness = 9.8e5
eccentricity = 0.3e-3
clearance = "0.7 mm"
rotor_radius = 0.04
unbalance_phase = 0.21
speed = "1759 rpm"
friction = 0.15
restitution = 0.95
gravity = "9.81 m/s^2"
polar_inertia = "0.04 kg m^2"
"""


@pytest.fixture
def machine_file(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(GENERAL)
    return str(path)


def test_drop_json_contract_matches_the_python_api(cli, machine_file, tmp_path):
    data = cli.json("drop", machine_file, "--speed", "12000rpm", "--t-end", "0.5s")
    assert set(data) == {"machine", "speed_rpm", "status", "message", "impacts", "contact_intervals", "summary"}
    assert data["speed_rpm"] == pytest.approx(12000.0, rel=1e-12)
    m = Machine(**{**reference_machine().as_dict(), "speed": 1759 * RPM, "gravity": 9.81, "polar_inertia": 0.04})
    assert data["machine"] == pytest.approx(m.as_dict(), rel=1e-15)
    api = drop(m, 12000 * RPM, 0.0, 0.5).to_dict()
    assert data["impacts"] == api["impacts"] and data["summary"] == api["summary"]
    first = data["impacts"][0]
    assert set(first) == {"t_s", "angle_rad", "normal_velocity_m_per_s", "normal_impulse_Ns",
                          "tangential_impulse_Ns", "spin_rpm_before", "spin_rpm_after", "race_rpm_after"}
    assert first["spin_rpm_before"] == pytest.approx(12000.0, rel=1e-12) and first["race_rpm_after"] is None
    code, out, err = cli.run("drop", machine_file, "--speed", "12000rpm", "--t-end", "0.5s",
                             "--plot", str(tmp_path / "d.png"))
    assert code == 0 and "regime:" in out and (tmp_path / "d.png").stat().st_size > 0


@pytest.mark.parametrize("argv, word", [
    (("--t-end=-1s",), "--t-end"), (("--speed", "3m"), "--speed"), (("--fail-at=-1s",), "--fail-at"),
    (("--t-end", "2 kg"), "--t-end"),
])
def test_drop_bad_input_exits_2_with_one_line(cli, machine_file, argv, word):
    code, out, err = cli.run("drop", machine_file, *argv)
    assert code == 2 and word in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_simulate_with_a_general_machine_runs_the_general_model_in_si(cli, machine_file):
    data = cli.json("simulate", "--machine", machine_file, "--t-end", "50")
    assert data["model"] == "general"
    m = Machine(**{**reference_machine().as_dict(), "speed": 1759 * RPM, "gravity": 9.81, "polar_inertia": 0.04})
    api = run_general(m, 0j, 0j, m.speed, math.inf, 50.0 / m.speed).to_dict()
    assert data["impacts"] == api["impacts"]
    # gravity balanced by the static force and the speed held: the paper's machine, so today's impacts (in s)
    paper = cli.json("simulate", "--machine", "reference", "--t-end", "50")
    ref_t = [row["t"] / reference_machine().speed for row in paper["impacts"]]
    m_ref = Machine(**{**reference_machine().as_dict(), "gravity": 9.81})
    gen = run_general(m_ref, 0j, 0j, m_ref.speed, math.inf, 50.0 / m_ref.speed)
    assert gen.column("t_s") == pytest.approx(ref_t, rel=1e-10)


def test_drop_map_json_figure_and_netcdf(cli, machine_file, tmp_path):
    out = tmp_path / "map"
    data = cli.json("drop-map", machine_file, "--speed", "3000:9000rpm", "--friction", "0.05:0.3", "--n", "2",
                    "--t-end", "0.01s", "--out", str(out))
    assert data["speeds_rpm"] == pytest.approx([3000.0, 9000.0], rel=1e-12)
    assert data["frictions"] == pytest.approx([0.05, 0.3], rel=1e-15)
    assert all(r in ("levitated", "bouncing", "contact", "backward-whirl") for row in data["regime"] for r in row)
    assert (out / "drop_map.nc").is_file() and (out / "drop_map.png").stat().st_size > 0
    code, _out, err = cli.run("drop-map", machine_file, "--speed", "3000rpm", "--out", str(out))
    assert code == 2 and "--speed" in err and len(err.strip().splitlines()) == 1


def test_drop_map_says_when_it_reads_a_finished_map_back_and_no_resume_computes_it_again(cli, machine_file,
                                                                                          tmp_path):
    argv = ("drop-map", machine_file, "--speed", "3000:9000rpm", "--n", "2", "--t-end", "0.01s", "--no-progress",
            "--out", str(tmp_path / "a"))
    code, first, err = cli.run(*argv)
    assert code == 0 and "read back" not in err
    code, again, err = cli.run(*argv)
    assert code == 0 and again == first and "already holds this finished study; it was read back" in err
    code, fresh, err = cli.run(*argv, "--no-resume")
    assert code == 0 and fresh == first and "read back" not in err


@pytest.mark.parametrize("stiffness, warned", [("1e10 N/m**1.5", True), ("1e13 N/m**1.5", False)])
def test_a_compliant_contact_deeper_than_a_clearance_is_warned_of(cli, tmp_path, stiffness, warned):
    # a soft contact at 12000 rpm presses the rotor several clearances in (the run's own max_penetration_m says
    # so): beyond the compliant law's range, said in one line on stderr; a stiff one stays shallow, unwarned
    path = tmp_path / "c.toml"
    path.write_text(GENERAL + f'contact = "compliant"\ncontact_stiffness = "{stiffness}"\n')
    code, out, err = cli.run("drop", str(path), "--speed", "12000rpm", "--t-end", "0.05s", "--json")
    assert code == 0
    deepest = max(i["max_penetration_m"] or 0.0 for i in cli.loads(out)["impacts"]) / 0.7e-3
    assert (deepest > 1.0) == warned
    assert ("warning: a contact pressed" in err) == warned and err.count("\n") == int(warned)


def test_drop_map_no_progress_hides_the_progress_bar(cli, machine_file, tmp_path):
    argv = ("drop-map", machine_file, "--speed", "3000:9000rpm", "--n", "2", "--t-end", "0.01s")
    code, out, err = cli.run(*argv, "--out", str(tmp_path / "a"))
    assert code == 0 and "drop-map: 100%|" in err  # the progress bar
    code, out, err = cli.run(*argv, "--out", str(tmp_path / "b"), "--no-progress")
    assert code == 0 and "%|" not in err and out.startswith("2 drops:")


def test_drop_with_a_compliant_bearing_matches_the_python_api(cli, tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(GENERAL + 'contact = "compliant"\ncontact_stiffness = "1e10 N/m**1.5"\n')
    data = cli.json("drop", str(path), "--speed", "12000rpm", "--t-end", "0.05s")
    m = Machine(**{**reference_machine().as_dict(), "speed": 1759 * RPM, "gravity": 9.81, "polar_inertia": 0.04,
                   "contact": "compliant", "contact_stiffness": 1e10})
    api = drop(m, 12000 * RPM, 0.0, 0.05).to_dict()
    assert data["machine"]["contact"] == "compliant"
    assert data["impacts"] == api["impacts"] and data["summary"] == api["summary"]
    first = data["impacts"][0]
    assert {"duration_s", "max_force_N", "max_penetration_m", "rebound_ratio"} <= set(first)
    assert first["max_force_N"] > 0.0 and 0.0 < first["rebound_ratio"] < 2.0
    code, out, err = cli.run("drop", str(path), "--speed", "12000rpm", "--t-end", "0.05s",
                             "--plot", str(tmp_path / "c.png"))
    assert code == 0 and "regime:" in out and (tmp_path / "c.png").stat().st_size > 0


def test_drop_refuses_a_compliant_bearing_without_stiffness(cli, tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(GENERAL + 'contact = "compliant"\n')
    code, out, err = cli.run("drop", str(path))
    assert code == 2 and "contact_stiffness" in err and "Traceback" not in err


def test_drop_to_rest_reports_the_time_and_stops_there(cli, tmp_path):
    path = tmp_path / "rest.toml"
    path.write_text(GENERAL.replace("eccentricity = 0.3e-3", "eccentricity = 0.0")
                    .replace("restitution = 0.95", "restitution = 0.5")
                    + "race_inertia = 2e-4\nrace_drag_torque = 0.0\nrace_drag_coefficient = 0.05\n")
    data = cli.json("drop", str(path), "--speed", "1000rpm", "--t-end", "20s")
    summary = data["summary"]
    assert data["status"] == "at-rest" and "came to rest" in data["message"]
    assert 0.0 < summary["time_to_rest_s"] < 20.0
    assert data["contact_intervals"][-1]["t_end_s"] == summary["time_to_rest_s"]
    # all the spin had and the fall to the bottom, dissipated (to the rest energy and the race's own)
    start = 0.5 * 0.04 * (1000 * RPM) ** 2 + 50.0 * 9.81 * 0.7e-3
    assert summary["energy_dissipated_J"] == pytest.approx(start, rel=1e-6)


def _file(tmp_path, name, *lines):
    path = tmp_path / name
    path.write_text(GENERAL + "\n".join(lines) + "\n")
    return str(path)


def test_drop_names_the_static_sag_not_the_speed(cli, tmp_path):
    """A static force whose sag (F_s - m g)/k_y passes the clearance is no fault of the speed."""
    code, out, err = cli.run("drop", _file(tmp_path, "sf.toml", "static_force = 1e4"))
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "static_force = 10000 N" in err and "speed =" not in err
    sag = (1e4 - 50.0 * 9.81) / 9.8e5
    assert f"{sag:.4g} m" in err and f"{9.8e5 * 0.7e-3:.4g} N" in err


def test_drop_whirl_outside_a_tiny_clearance_names_the_clearance(cli, tmp_path):
    path = _file(tmp_path, "nm.toml")
    text = open(path).read().replace('clearance = "0.7 mm"', "clearance = 1e-7")
    open(path, "w").write(text)
    code, _out, err = cli.run("drop", path)
    assert code == 2 and "clearance = 1e-07 m" in err and "speed = 1759 rpm" in err and "--speed" not in err
    code, _out, err = cli.run("drop", path, "--speed", "1000rpm")
    assert code == 2 and "--speed = 1000 rpm" in err


@pytest.mark.parametrize("lines, word", [
    (["gravity = 1e300"], "gravity = 1e+300"),
    (['contact = "compliant"', "contact_stiffness = 1e300"], "contact_stiffness = 1e+300"),
])
def test_drop_refuses_absurd_machine_values(cli, tmp_path, lines, word):
    text = GENERAL.replace('gravity = "9.81 m/s^2"\n', "")
    path = tmp_path / "bad.toml"
    path.write_text(text + "\n".join(lines) + "\n")
    code, out, err = cli.run("drop", str(path))
    assert code == 2 and out == "" and word in err and "allowed" in err and len(err.strip().splitlines()) == 1


def test_drop_echoes_a_speed_out_of_range_as_given(cli, machine_file):
    code, out, err = cli.run("drop", machine_file, "--speed=-12000rpm")
    assert code == 2 and out == "" and "--speed = '-12000rpm' (-1256.64 rad/s) is out of range" in err


def test_drop_refuses_an_absurd_speed(cli, machine_file):
    code, _out, err = cli.run("drop", machine_file, "--speed", "1e30rpm")
    assert code == 2 and "--speed = " in err and "allowed: (0, 1e+06]" in err


def test_simulate_overridden_general_machine_says_its_keys_are_ignored(cli, machine_file):
    code, out, err = cli.run("simulate", "--machine", machine_file, "--gamma", "0.1", "--t-end", "20", "--json")
    assert code == 0
    assert "gravity, polar_inertia are ignored" in err and "paper's dimensionless model" in err
    data = cli.loads(out)
    assert data["model"] == "paper" and data["ignored_machine_keys"] == ["gravity", "polar_inertia"]
    # the plain machine has nothing to ignore: no note, no new keys
    code, out, err = cli.run("simulate", "--machine", "reference", "--gamma", "0.1", "--t-end", "20", "--json")
    assert code == 0 and "ignored" not in err and "ignored_machine_keys" not in cli.loads(out)


def test_design_map_says_it_ignores_gravity_and_polar_inertia(cli, machine_file):
    code, out, err = cli.run("design-map", machine_file, "--speed", "5000:30000rpm", "--n", "3", "--json")
    assert code == 0 and "design-map computes on the paper's dimensionless model" in err
    data = cli.loads(out)
    assert data["model"] == "paper" and data["ignored_machine_keys"] == ["gravity", "polar_inertia"]
    code, _out, err = cli.run("design-map", machine_file, "--speed", "5000:30000rpm", "--n", "3")
    assert code == 0 and "gravity, polar_inertia are ignored" in err


@pytest.mark.parametrize("command, speed", [("drop", "1e30rpm"), ("drop-map", "10000:1e30rpm"),
                                            ("drop", "2e7rpm"), ("drop-map", "1000:2e7rpm")])
def test_a_speed_above_the_bound_is_refused_at_once(cli, machine_file, tmp_path, command, speed):
    out = tmp_path / "map"
    extra = ("--n", "2", "--out", str(out)) if command == "drop-map" else ()
    code, _out, err = cli.run(command, machine_file, "--speed", speed, "--t-end", "10ms", *extra)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert f"rotorcontact {command}: error: --speed = " in err and "allowed: (0, 1e+06]" in err
    assert not out.exists()  # refused before the output folder is made


@pytest.mark.parametrize("argv, words", [
    (("--t-end", "1e12s"), ("--t-end = '1e12s'", "(0, 10000] s")),
    (("--t-end", "10001"), ("--t-end = '10001'", "(0, 10000] s")),
    (("--t-end", "nan"), ("--t-end = 'nan'", "not finite", "(0, 10000] s")),
    (("--t-end", "0s"), ("--t-end = '0s'", "(0, 10000] s")),
    (("--fail-at=-1s",), ("--fail-at = '-1s'", "[0, inf) s")),
    (("--fail-at", "inf"), ("--fail-at = 'inf'", "not finite")),
    (("--fail-at", "1s", "--t-end", "0.1s"), ("--fail-at = 1.0 s is not before --t-end = 0.1 s",)),
])
@pytest.mark.parametrize("command", ["drop", "drop-map"])
def test_time_options_are_refused_by_their_option_names(cli, machine_file, tmp_path, command, argv, words):
    extra = ("--speed", "3000:9000rpm", "--n", "2", "--out", str(tmp_path / "map")) if command == "drop-map" else ()
    code, _out, err = cli.run(command, machine_file, *extra, *argv)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert all(w in err for w in words), err
    assert "t_end" not in err and "fail_at" not in err


@pytest.mark.parametrize("argv, words", [
    (("--speed", "3000:9000rpm", "--n", "1"), "--n = 1 would keep A of each range A:B alone; allowed: --n >= 2"),
    (("--speed", "3000:9000rpm", "--n", "2", "--friction", "0.1:0.1"), "--friction = '0.1:0.1': the range must "
                                                                       "increase"),
    (("--speed", "3000:9000rpm", "--n", "2", "--friction", "0.2:0.1"), "--friction = '0.2:0.1': the range must "
                                                                       "increase"),
])
def test_drop_map_ranges_must_span_an_interval(cli, machine_file, tmp_path, argv, words):
    code, _out, err = cli.run("drop-map", machine_file, *argv, "--t-end", "10ms", "--out", str(tmp_path / "map"))
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err
    assert not (tmp_path / "map").exists()


def test_drop_map_marks_failed_drops_and_exits_1(cli, machine_file, tmp_path, failing_drops):
    argv = ("--speed", "3000:9000rpm", "--n", "2", "--t-end", "10ms")
    code, _out, err = cli.run("drop", machine_file, "--speed", "9000rpm", *argv[4:], "--json")
    assert code == 1 and cli.loads(_out)["summary"]["regime"] == "failed"
    code, out, err = cli.run("drop-map", machine_file, *argv, "--out", str(tmp_path / "map"), "--json")
    assert code == 1 and "Traceback" not in err
    data = cli.loads(out)
    assert data["regime"] == [["failed", "failed"]]
    assert data["max_normal_impulse_Ns"] == [[None, None]] and data["energy_dissipated_J"] == [[None, None]]
    line = err.strip().splitlines()[-1]
    assert line.startswith("rotorcontact drop-map: failed: 2 of 2 drops failed") and "9000 rpm" in line
    assert (tmp_path / "map" / "drop_map.nc").is_file()
    code, out, err = cli.run("drop-map", machine_file, *argv, "--out", str(tmp_path / "map2"))
    assert code == 1 and "failed 2" in out and "levitated" not in out
