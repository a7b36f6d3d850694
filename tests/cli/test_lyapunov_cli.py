"""``rotorcontact lyapunov``: JSON contract, -inf as null, text output, and bad input."""

from __future__ import annotations

import math

import pytest

from rotorcontact.analysis.lyapunov import lyapunov_spectrum
from reference_parameters import REF


def test_json_contract_on_the_stable_one_impact_orbit(cli):
    data = cli.json("lyapunov", "--gamma", "0.1", "--u0", "0,0", "--du0", "0,0", "--t-end", "1200")
    assert set(data) == {"parameters", "exponents", "errors", "regime_change"}
    assert data["regime_change"] is False and len(data["errors"]) == 4
    ex = data["exponents"]
    assert len(ex) == 4 and all(isinstance(x, float) for x in ex)
    assert ex == sorted(ex, reverse=True)
    lib = lyapunov_spectrum(REF.replace(gamma=0.1), 0j, 0j, 1200.0)
    assert ex == list(lib.exponents)
    assert ex[0] == pytest.approx(0.0, abs=1e-6) and ex[1] < 0.0


def test_annihilated_directions_are_null(cli):
    args = ("--gamma", "0.065", "--t-end", "300", "--t-transient", "150")
    ex = cli.json("lyapunov", *args)["exponents"]
    assert ex[0] == pytest.approx(0.0, abs=1e-12) and ex[1:] == [None, None, None]
    details = cli.json("lyapunov", *args, "--details")
    assert details["exponents"] == ex
    assert details["collapsed"] == 3 and details["coordinates"] == ["Re U", "Im U", "Re U'", "Im U'"]
    assert details["t_start"] == 150.0 and details["t_stop"] == 300.0 and details["status"] == "completed"


def test_options_reach_the_library(cli):
    p = REF.replace(gamma=0.15, omega=0.7)
    ex = cli.json("lyapunov", "--gamma", "0.15", "--omega", "0.7", "--u0", "0.2,-0.1", "--du0", "0.3,0.4",
                  "--t-end", "300", "--t-transient", "100", "--qr-interval", "0.5")["exponents"]
    lib = lyapunov_spectrum(p, 0.2 - 0.1j, 0.3 + 0.4j, 300.0, t_transient=100.0, qr_interval=0.5)
    assert ex == [x if math.isfinite(x) else None for x in lib.exponents]


def test_text_output(cli):
    code, out, err = cli.run("lyapunov", "--gamma", "0.065", "--t-end", "200")
    assert code == 0, err
    assert "largest first" in out and out.count("-inf") == 3


@pytest.mark.parametrize(
    "args",
    [
        ["--u0", "0.1"],
        ["--u0", "2,0"],
        ["--t-end", "-5"],
        ["--t-end", "100", "--t-transient", "100"],
        ["--qr-interval", "0"],
        ["--gamma", "nan"],
        ["--mu", "-1"],
    ],
)
def test_bad_input_exits_2_without_traceback(cli, args):
    code, out, err = cli.run("lyapunov", "--json", *args)
    assert code == 2
    assert out == ""
    assert "error" in err and "Traceback" not in err


def test_details_without_json_is_refused(cli):
    code, out, err = cli.run("lyapunov", "--details", "--t-end", "10")
    assert code == 2 and out == "" and "--details adds fields to the JSON output; allowed: with --json" in err


@pytest.mark.parametrize("args, words", [
    (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "1"], "--n = 1 is a single value"),
    (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "2", "--details"],
     "--details adds the fields of one spectrum"),
    (["--machine", "reference", "--param", "gravity", "--from", "0", "--to", "10", "--n", "2"],
     "--param = 'gravity' is a key of the general model"),
    (["--n-jobs", "2"], "--n-jobs need --param"),
    (["--no-resume", "--chunk-size", "3"], "--chunk-size, --no-resume need --param"),
])
def test_options_that_would_be_ignored_are_refused(cli, args, words):
    code, out, err = cli.run("lyapunov", "--t-end", "20", "--json", *args)
    assert code == 2 and out == "" and words in err and "Traceback" not in err


def test_bad_input_from_the_shell(cli):
    code, _, err = cli.exe("lyapunov", "--du0", "x,1")
    assert code == 2
    assert "--du0" in err and "Traceback" not in err


def test_a_change_of_regime_inside_the_window_is_warned_and_reported(cli):
    """From rest with no transient discarded, the window holds the approach to B1,d."""
    args = ("lyapunov", "--gamma", "0.1", "--t-end", "600", "--t-transient", "0")
    code, out, err = cli.run(*args, "--json")
    assert code == 0 and "warning: the motion changed regime" in err and "periodic" in err
    data = cli.json(*args)
    lib = lyapunov_spectrum(REF.replace(gamma=0.1), 0j, 0j, 600.0, t_transient=0.0)
    assert data["regime_change"] is True and data["final_regime"] == "periodic"
    assert data["regime_start"] == lib.regime_start > 0.0
    assert data["final_exponents"] == list(lib.final_exponents)
    assert data["final_errors"] == list(lib.final_errors)
    code, out, err = cli.run(*args)
    assert code == 0 and "final regime (periodic" in out and "warning" in err


def test_scan_against_a_parameter(cli, tmp_path):
    from rotorcontact.studies.lyapunov_scan import lyapunov_scan

    args = ("lyapunov", "--param", "gamma", "--from", "0.09", "--to", "0.11", "--n", "2", "--t-end", "400",
            "--no-progress", "--out", tmp_path / "l.nc")
    code, out, err = cli.run(*args, "--json")
    assert code == 0
    data = cli.loads(out)
    lib = lyapunov_scan(REF, "gamma", [0.09, 0.11], t_end=400.0, progress=False)
    assert data["values"] == [0.09, 0.11] and data["param"] == "gamma"
    assert data["exponents"] == [[x if math.isfinite(x) else None for x in row] for row in lib.exponents.tolist()]
    assert data["regime_change"] == lib.regime_change.tolist()
    assert ("warning: the motion changed regime" in err) == any(data["regime_change"])
    assert {"errors", "final_regime", "regime_start", "final_exponents", "final_errors", "failed"} <= set(data)
    code, _out, err = cli.run("lyapunov", "--from", "0.1", "--json")
    assert code == 2 and "--param" in err
    code, _out, err = cli.run("lyapunov", "--param", "gamma", "--from", "0.1", "--json")
    assert code == 2 and "--to" in err


@pytest.mark.parametrize("param, start, stop", [("speed", "1500rpm", "3000rpm"), ("stiffness", "9e5", "1.1e6")])
def test_a_machine_scan_gives_each_value_its_own_time_scale(cli, param, start, stop):
    # exponents per second are the dimensionless ones times Omega (time in units of 1 / Omega, MODEL.md §2): the
    # Omega of each value along the speed, the machine's own along the stiffness
    from rotorcontact import reference_machine

    data = cli.json("lyapunov", "--machine", "reference", "--param", param, "--from", start, "--to", stop,
                    "--n", "2", "--t-end", "300", "--no-progress")
    speeds = data["values"] if param == "speed" else [reference_machine().speed] * 2
    for row, per_s, omega in zip(data["exponents"], data["exponents_per_s"], speeds):
        assert per_s == [None if x is None else pytest.approx(x * omega, rel=1e-14) for x in row]
    if param == "speed":
        assert data["values_rpm"] == pytest.approx([1500.0, 3000.0], rel=1e-12)
    else:
        assert "values_rpm" not in data


def test_a_scan_of_one_value_with_equal_ends(cli):
    data = cli.json("lyapunov", "--param", "gamma", "--from", "0.1", "--to", "0.1", "--n", "1", "--t-end", "300",
                    "--no-progress")
    assert data["values"] == [0.1] and len(data["exponents"]) == 1
