"""``rotorcontact simulate``: bad input gives exit status 2 and a message naming the
parameter and its value, never a traceback; the ``--name=value`` form; machine files;
and the stable JSON contract of ``--json``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import load_machine, simulate
from reference_parameters import REF, REF_MACHINE_TOML, replace_line


# ---------------------------------------------------------------------------
# bad input: exit status 2, message names parameter and value, no traceback
# ---------------------------------------------------------------------------

BAD_OPTIONS = [
    # argv, strings the message must contain
    (["--gamma", "nan"], ["--gamma", "nan"]),
    (["--gamma=inf"], ["--gamma", "inf"]),
    (["--gamma", "abc"], ["--gamma", "abc"]),
    (["--omega", "0"], ["omega", "0", "(0, 1e+06]"]),
    (["--omega=-0.5"], ["omega", "-0.5", "(0, 1e+06]"]),
    (["--rho=-0.1"], ["rho", "-0.1", "[0, 1e+06]"]),
    (["--mu=-0.2"], ["mu", "-0.2", "[0, 1e+06]"]),
    (["--d", "1.5"], ["d", "1.5", "[0, 1]"]),
    (["--d=-0.01"], ["d", "-0.01", "[0, 1]"]),
    (["--r-ratio=-1"], ["r-ratio", "-1", "[0, 1e+06]"]),
    (["--phi=-inf"], ["--phi", "-inf"]),
    (["--u0", "1.5,0"], ["u0", "1.5", "|u0| <= 1"]),
    (["--u0=0.9,-0.9"], ["u0", "0.9", "-0.9"]),
    (["--u0", "1,2,3"], ["u0", "1,2,3"]),
    (["--u0", "0.5"], ["u0", "0.5"]),
    (["--u0", "x,0"], ["u0", "x"]),
    (["--du0", "nan,0"], ["du0", "nan"]),
    (["--du0=0,inf"], ["du0", "inf"]),
    (["--t-end", "0"], ["t-end", "0"]),
    (["--t-end=-5"], ["t-end", "-5"]),
    (["--t-end", "nan"], ["t-end", "nan"]),
    (["--t-end", "soon"], ["t-end", "soon"]),
    (["--all-impacts"], ["--all-impacts", "allowed: with --json"]),  # it would change nothing
]


@pytest.mark.parametrize("argv,needles", BAD_OPTIONS, ids=[" ".join(a) for a, _ in BAD_OPTIONS])
def test_bad_options_in_process(argv, needles, cli):
    extra = [] if any(a.startswith("--t-end") for a in argv) else ["--t-end=1"]
    code, out, err = cli.run("simulate", *argv, *extra)
    assert code == 2, (code, err)
    assert "Traceback" not in err
    assert out == ""
    for needle in needles:
        assert needle in err, (needle, err)


def machine_file(tmp_path, text, name="machine.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


BAD_MACHINES = [
    # file text, strings the message must contain
    (REF_MACHINE_TOML + "colour = 1.0\n", ["colour", "unknown"]),
    ("\n".join(REF_MACHINE_TOML.splitlines()[1:]) + "\n", ["'mass'", "missing"]),
    ("mass = \n", ["malformed"]),
    ("[machine\n", ["malformed"]),
    (replace_line(REF_MACHINE_TOML, "mass", 'mass = "heavy"'), ["mass", "'heavy'"]),
    (replace_line(REF_MACHINE_TOML, "mass", "mass = 0.0"), ["mass", "0.0", "(0, inf)"]),
    (replace_line(REF_MACHINE_TOML, "mass", "mass = nan"), ["mass", "nan"]),
    (replace_line(REF_MACHINE_TOML, "stiffness", "stiffness = -1.0"), ["stiffness", "-1.0"]),
    (replace_line(REF_MACHINE_TOML, "clearance", "clearance = 0"), ["clearance", "0"]),
    (replace_line(REF_MACHINE_TOML, "speed", "speed = -184.2"), ["speed", "-184.2"]),
    (replace_line(REF_MACHINE_TOML, "restitution", "restitution = 1.2"), ["restitution", "1.2", "[0, 1]"]),
    (replace_line(REF_MACHINE_TOML, "friction", "friction = -0.1"), ["friction", "-0.1"]),
    (replace_line(REF_MACHINE_TOML, "eccentricity", "eccentricity = -1e-4"), ["eccentricity", "-0.0001"]),
    (replace_line(REF_MACHINE_TOML, "damping", "damping = inf"), ["damping", "inf"]),
]


@pytest.mark.parametrize("text,needles", BAD_MACHINES)
def test_bad_machine_files_in_process(tmp_path, text, needles, cli):
    path = machine_file(tmp_path, text)
    code, out, err = cli.run("simulate", "--machine", str(path), "--t-end=1")
    assert code == 2, (code, err)
    assert "Traceback" not in err and out == ""
    for needle in needles:
        assert needle in err, (needle, err)


def test_missing_machine_file(tmp_path, cli):
    code, out, err = cli.run("simulate", f"--machine={tmp_path / 'none.toml'}")
    assert code == 2 and "none.toml" in err and "Traceback" not in err


@pytest.mark.parametrize(
    "argv,needles",
    [
        (["simulate", "--d", "2"], ["d", "2"]),
        (["simulate", "--u0=1.1,0"], ["u0", "1.1"]),
        (["simulate", "--omega=-3"], ["omega", "-3"]),
        (["simulate", "--t-end", "-1"], ["t-end", "-1"]),
    ],
)
def test_bad_input_through_the_installed_command(argv, needles, cli):
    code, out, err = cli.exe(*argv)
    assert code == 2, (code, err)
    assert "Traceback" not in err
    assert out == ""
    for needle in needles:
        assert needle in err


def test_bad_machine_file_through_the_installed_command(tmp_path, cli):
    path = machine_file(tmp_path, replace_line(REF_MACHINE_TOML, "restitution", "restitution = -0.5"))
    code, out, err = cli.exe("simulate", "--machine", str(path))
    assert code == 2 and "restitution" in err and "-0.5" in err and "Traceback" not in err


def test_argparse_errors_exit_2_without_traceback(cli):
    for argv in (["simulate", "--bogus", "1"], ["simulate", "--gamma"], ["nosuchcommand"]):
        code, out, err = cli.run(*argv)
        assert code == 2 and "Traceback" not in err


@pytest.mark.parametrize("command, needed", [
    ("simulate", ()), ("basins", ("--grid", "shock:4", "--out", "b.nc")),
    ("drop-map", ("reference", "--speed", "1000:2000rpm", "--out", "m")),
])
def test_an_unknown_option_is_refused_by_its_subcommand(command, needed, cli):
    code, out, err = cli.run(command, *needed, "--bogus", "1")
    lines = err.strip().splitlines()
    assert code == 2 and out == ""
    assert lines[0].startswith(f"usage: rotorcontact {command} ")
    assert lines[-1] == f"rotorcontact {command}: error: unrecognized arguments: --bogus 1"


def test_undamped_resonance_is_not_a_traceback(cli):
    code, out, err = cli.exe("simulate", "--gamma", "0", "--omega", "1", "--t-end", "5")
    assert "Traceback" not in err
    assert code in (0, 2)


def test_machine_with_underflowing_groups_is_not_a_traceback(tmp_path, cli):
    path = machine_file(tmp_path, replace_line(REF_MACHINE_TOML, "speed", "speed = 1e-170"))
    code, out, err = cli.exe("simulate", "--machine", str(path), "--t-end", "1")
    assert "Traceback" not in err
    assert code == 2


# ---------------------------------------------------------------------------
# good input
# ---------------------------------------------------------------------------


def test_equals_form_with_negative_values(cli):
    code, out, err = cli.run("simulate", "--gamma=0.1", "--u0=-0.2,0.1", "--du0=-1.2,0.4", "--t-end=20", "--json")
    assert code == 0, err
    data = cli.loads(out)
    assert data["initial_state"]["du0"] == [-1.2, 0.4]
    assert data["initial_state"]["u0"] == [-0.2, 0.1]
    p = REF.replace(gamma=0.1)
    traj = simulate(p, -0.2 + 0.1j, -1.2 + 0.4j, 20.0)
    assert [row["t"] for row in data["impacts"]] == list(traj.impacts.t)


def test_equals_form_through_the_installed_command(cli):
    code, out, err = cli.exe("simulate", "--du0=-1.2,0.4", "--gamma=0.1", "--t-end=20", "--json")
    assert code == 0, err
    data = cli.loads(out)
    assert data["initial_state"]["du0"] == [-1.2, 0.4]
    assert data["parameters"]["gamma"] == 0.1


def test_default_parameters_are_the_reference_machine(cli):
    code, out, err = cli.run("simulate", "--t-end=5", "--json")
    assert code == 0
    assert cli.loads(out)["parameters"] == REF.as_dict()


def test_machine_file_and_overrides(tmp_path, cli):
    path = machine_file(tmp_path, REF_MACHINE_TOML.replace("damping = 1400.0", "damping = 921.0"))
    code, out, err = cli.run("simulate", "--machine", str(path), "--t-end=30", "--json")
    assert code == 0, err
    data = cli.loads(out)
    m = load_machine(path)
    assert data["parameters"] == m.parameters().as_dict()
    assert data["parameters"]["gamma"] == pytest.approx(921.0 / (50.0 * 184.2), rel=1e-15)
    assert data["machine"]["damping"] == 921.0
    for row in data["impacts"]:
        assert row["t_s"] == pytest.approx(row["t"] / 184.2, rel=1e-15)
    # an override replaces one parameter and keeps the machine's others
    code, out, err = cli.run("simulate", "--machine", str(path), "--mu=0.3", "--t-end=30", "--json")
    assert code == 0
    data2 = cli.loads(out)
    assert data2["parameters"]["mu"] == 0.3
    assert data2["parameters"]["gamma"] == data["parameters"]["gamma"]


def test_text_output(cli):
    code, out, err = cli.run("simulate", "--gamma=0.1", "--t-end=1000")
    assert code == 0
    assert "1000" in out and "periodic-impacting" in out
    assert "T = 2.86351" in out


def test_plot_option_writes_a_png(tmp_path, cli):
    path = tmp_path / "fig.png"
    code, out, err = cli.run("simulate", "--gamma=0.1", "--t-end=40", f"--plot={path}")
    assert code == 0, err
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------------------
# the JSON contract
# ---------------------------------------------------------------------------


def check_contract(data, traj):
    assert isinstance(data, dict)
    for key in ("parameters", "status", "impacts", "summary"):
        assert key in data
    assert set(data["parameters"]) >= {"gamma", "omega", "rho", "mu", "d", "phi", "r_ratio"}
    assert data["parameters"] == traj.params.as_dict()
    assert isinstance(data["status"], str) and data["status"] == traj.status
    assert isinstance(data["summary"], dict) and "motion" in data["summary"]
    assert isinstance(data["impacts"], list) and len(data["impacts"]) == len(traj.impacts)
    imp = traj.impacts
    for j, row in enumerate(data["impacts"]):
        for key in ("t", "theta", "rdot", "thetadot"):
            assert isinstance(row[key], float) and math.isfinite(row[key])
        assert -math.pi < row["theta"] <= math.pi
        assert row["rdot"] > 0
        # rdot and thetadot are the values just before the impact
        assert row["t"] == imp.t[j] and row["theta"] == imp.theta[j]
        assert row["rdot"] == imp.rdot[j] and row["thetadot"] == imp.thetadot[j]
    ts = [row["t"] for row in data["impacts"]]
    assert ts == sorted(ts)


@pytest.mark.parametrize(
    "argv,args",
    [
        (["--gamma=0.1", "--t-end=200"], (0.1, 0j, 0j, 200.0)),
        (["--gamma=0.12", "--u0=0.3,-0.7", "--du0=-0.5,1.5", "--t-end=80"], (0.12, 0.3 - 0.7j, -0.5 + 1.5j, 80.0)),
        (["--gamma=0.3", "--t-end=50", "--u0=0.1,0.1"], (0.3, 0.1 + 0.1j, 0j, 50.0)),
    ],
)
def test_json_contract_in_process(argv, args, cli):
    code, out, err = cli.run("simulate", *argv, "--json")
    assert code == 0, err
    data = cli.loads(out)
    gamma, u0, du0, t_end = args
    traj = simulate(REF.replace(gamma=gamma), u0, du0, t_end)
    check_contract(data, traj)


def test_json_contract_at_chatter(cli):
    code, out, err = cli.run("simulate", "--gamma=0.2", "--t-end=100", "--on-chatter=stop", "--json")
    assert code == 0, err
    data = cli.loads(out)
    assert data["status"] == "chatter"
    traj = simulate(REF.replace(gamma=0.2), 0j, 0j, 100.0, on_chatter="stop")
    check_contract(data, traj)


def test_json_contract_through_the_installed_command(tmp_path, cli):
    code, out, err = cli.exe("simulate", "--gamma", "0.1", "--t-end", "300", "--json", cwd=tmp_path)
    assert code == 0, err
    data = cli.loads(out)
    check_contract(data, simulate(REF.replace(gamma=0.1), 0j, 0j, 300.0))
    assert data["summary"]["motion"] == "periodic-impacting"
    assert data["summary"]["impacts_per_period"] == 1
    # theta is wrapped to (-pi, pi] over a long sequence
    th = np.array([row["theta"] for row in data["impacts"]])
    assert np.all(th > -math.pi) and np.all(th <= math.pi)


SMALL_RUN_KEYS = {"parameters", "status", "message", "t_end", "t_stop", "initial_state", "impacts",
                  "contact_intervals", "summary"}


def test_json_of_a_small_run_keeps_its_keys(cli):
    code, out, err = cli.run("simulate", "--gamma=0.1", "--t-end=200", "--json")
    assert code == 0, err
    assert set(cli.loads(out)) == SMALL_RUN_KEYS


def test_json_of_a_long_run_is_proportionate(cli):
    # about 1050 impacts: past the 1000 listed
    code, out, err = cli.run("simulate", "--gamma=0.1", "--t-end=3000", "--json")
    assert code == 0, err
    data = cli.loads(out)
    traj = simulate(REF.replace(gamma=0.1), 0j, 0j, 3000.0)
    n = len(traj.impacts)
    assert n > 1000
    assert set(data) == SMALL_RUN_KEYS | {"impacts_total", "impacts_truncated"}
    assert data["impacts_truncated"] is True and data["impacts_total"] == n == data["summary"]["n_impacts"]
    ts = [row["t"] for row in data["impacts"]]
    assert ts == list(traj.impacts.t[:500]) + list(traj.impacts.t[-500:])
    # --all-impacts: every impact, with the keys of a small run
    code, out, err = cli.run("simulate", "--gamma=0.1", "--t-end=3000", "--json", "--all-impacts")
    assert code == 0, err
    data = cli.loads(out)
    assert set(data) == SMALL_RUN_KEYS
    check_contract(data, traj)


def test_max_events_stops_the_run(cli):
    code, out, err = cli.run("simulate", "--gamma=0.1", "--t-end=3000", "--max-events=50", "--json")
    assert code == 0, err
    data = cli.loads(out)
    assert data["status"] == "max-events" and len(data["impacts"]) <= 50
