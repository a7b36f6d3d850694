"""Failures the command line reports without a traceback, whatever the subcommand."""

from __future__ import annotations

import pytest

from rotorcontact.cli.main import main


@pytest.mark.parametrize(
    "args",
    [
        ("simulate", "--t-end", "5", "--plot", "/dev/null/x.png"),
        ("equilibria", "--plot", "/dev/null/x.png", "--from", "0", "--to", "0.2"),
    ],
)
def test_an_unwritable_output_is_bad_input(args, cli):
    code, _, err = cli.exe(*args, timeout=300)
    assert code == 2
    # refused before the computation, naming the option and why
    assert "--plot = '/dev/null/x.png': '/dev/null' is a file, not a folder" in err
    assert "Traceback" not in err


@pytest.mark.parametrize(
    "args, fragment",
    [
        (("lyapunov", "--qr-interval", "1e-9", "--t-end", "100"), "qr_interval"),
        (("lyapunov", "--t-end", "1e9"), "--t-end"),
        (("branches", "--seeds", "1000000"), "--seeds"),
        (("branches", "--rdot-max", "0"), "--rdot-max = 0.0"),
        (("basins", "--grid", "plane:100000", "--out", "/tmp/never.nc"), "too large"),
        (("basins", "--grid", "x=2:3:5,y=2:3:5", "--out", "/tmp/never.nc"), "inside the clearance"),
        (("design-map", "--machine", "reference", "--speed", "nan:6000rpm"), "not finite"),
        (("design-map", "--machine", "reference", "--speed=-1000:6000rpm"), "--speed"),
    ],
)
def test_unbounded_or_empty_work_is_refused_at_once(args, fragment, cli):
    code, _, err = cli.exe(*args, timeout=300)
    assert code == 2, err
    assert fragment in err and "Traceback" not in err


def test_a_failed_computation_exits_1_with_one_line(cli):
    code, _, err = cli.exe("lyapunov", "--gamma=-1e6", "--t-end", "10", timeout=300)
    assert code == 1
    assert "failed" in err and "Traceback" not in err


# ---------------------------------------------------------------------------
# extreme inputs: refused up front, naming the option, the value and the limit
# ---------------------------------------------------------------------------

SWEEP = ("sweep", "--param", "gamma", "--from", "0.1", "--to", "0.2", "--out", "/tmp/never.nc")
BASINS = ("basins", "--grid", "plane:3", "--out", "/tmp/never.nc")


@pytest.mark.parametrize(
    "args, fragment",
    [
        (("simulate", "--gamma", "1e308"), "--gamma = 1e+308"),
        (("simulate", "--omega", "1e308"), "--omega = 1e+308"),
        (("simulate", "--r-ratio", "1e300"), "--r-ratio = 1e+300"),
        (("simulate", "--du0=1e308,0"), "--du0"),
        (("simulate", "--du0=1e7,0"), "--du0"),
        (("simulate", "--t-end", "1e300"), "--t-end"),
        (("simulate", "--max-events", "1e12"), "--max-events"),
        (("lyapunov", "--du0=1e308,0"), "--du0"),
        (("branches", "--from", "0", "--to", "1e308"), "--to = 1e+308"),
        (("branches", "--t-max", "1e4"), "--t-max"),
        (("branches", "--rdot-max", "1e300"), "--rdot-max"),
        (("codim2", "--t-max", "1e4"), "--t-max"),
        (("codim2", "--folds", "1,1000000"), "--folds"),
        (("codim2", "--from", "0,0.6", "--to", "1e300,1.25"), "--to = 1e+300"),
        (("orbits", "--t-max", "1e6"), "--t-max"),
        (("orbits", "--impacts", "100000000"), "--impacts"),
        (("local", "--t-max", "1e6"), "--t-max"),
        (("equilibria", "--from", "0", "--to", "1", "--points", "100000000"), "--points"),
        (("equilibria", "--from", "0", "--to", "1e308"), "--to = 1e+308"),
        ((*SWEEP, "--n", "10000000"), "--n = 10000000"),
        ((*SWEEP, "--n", "10", "--transient", "1000000000"), "--transient"),
        ((*SWEEP, "--n", "10", "--record", "100000000"), "--record"),
        ((*SWEEP, "--n", "10", "--t-record", "1e300"), "--t-record"),
        ((*SWEEP, "--n", "10", "--settle", "1e12"), "--settle"),
        ((*SWEEP, "--n", "10", "--chunk-size", "1e12"), "--chunk-size"),
        ((*SWEEP, "--n", "100000", "--transient", "1000000"), "events per study"),
        ((*SWEEP, "--n", "50000", "--record", "1000", "--transient", "0"), "kept events"),
        ((*SWEEP, "--n", "10", "--du0=1e308,0"), "--du0"),
        (("sweep", "--param", "gamma", "--from", "0", "--to", "1e308", "--n", "3", "--out", "/tmp/never.nc"),
         "--to = 1e+308"),
        ((*BASINS, "--transient", "1000000000"), "--transient"),
        ((*BASINS, "--record", "1e9"), "--record"),
        (("basins", "--grid", "amplitude=0:1e308:3,direction=0:1:3", "--out", "/tmp/never.nc"), "amplitude"),
        (("design-map", "--machine", "reference", "--speed", "1000:6000rpm", "--n", "1e9"), "--n"),
        (("design-map", "--machine", "reference", "--speed", "1000:6000rpm", "--shock", "5mm/s", "--n", "1e5"),
         "--n"),
        (("design-map", "--machine", "reference", "--speed", "1000:6000rpm", "--shock", "1e300m/s"), "--shock"),
        (("design-map", "--machine", "reference", "--speed", "1e-6:6000rpm"), "--speed"),
    ],
)
def test_extreme_inputs_are_refused_up_front(args, fragment, capsys):
    code = main(list(args))
    err = capsys.readouterr().err
    assert code == 2, err
    assert fragment in err and "allowed" in err
    assert len(err.strip().splitlines()) == 1


def test_every_size_option_names_its_limit(capsys):
    assert main([*SWEEP, "--n", "1e9"]) == 2
    assert "an integer from 1 to 100000" in capsys.readouterr().err
    assert main(["equilibria", "--from", "0", "--to", "1", "--points", "1e9"]) == 2
    assert "an integer from 2 to 10000" in capsys.readouterr().err
    assert main(["simulate", "--max-events", "0"]) == 2
    assert "an integer from 1 to 10000000" in capsys.readouterr().err


def test_too_many_local_workers_are_capped_with_a_note(capsys):
    from rotorcontact.cli.main import build_parser
    from rotorcontact.cli.scale import scale_kwargs
    from rotorcontact.studies.execution import available_cores

    args = build_parser().parse_args([*SWEEP, "--n", "3", "--n-jobs", "1000000"])
    kw = scale_kwargs(args)
    assert kw["n_jobs"] == available_cores()
    assert "note: --n-jobs 1000000 is more than" in capsys.readouterr().err
    # a remote scheduler's workers are not this machine's: nothing to cap
    args = build_parser().parse_args([*SWEEP, "--n", "3", "--n-jobs", "1000", "--scheduler", "tcp://h:8786"])
    assert scale_kwargs(args)["n_jobs"] == 1000
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("value", ["-2", "0", "1.5", "x"])
def test_every_refused_worker_count_says_the_same_thing_is_allowed(value, capsys):
    from rotorcontact.cli.main import build_parser
    from rotorcontact.cli.scale import scale_kwargs
    from rotorcontact.errors import ParameterError

    args = build_parser().parse_args([*SWEEP, "--n", "3", "--n-jobs", value])
    with pytest.raises(ParameterError, match=r"; allowed: an integer from 1 to 1000000, or -1 for one per core$"):
        scale_kwargs(args)


@pytest.mark.parametrize("value", ["0", "-3", "1.5", "four", ""])
def test_a_numba_thread_count_that_is_not_a_whole_number_of_at_least_one_is_bad_input(value, monkeypatch, capsys):
    monkeypatch.setenv("NUMBA_NUM_THREADS", value)
    assert main(["simulate", "--t-end", "1"]) == 2
    err = capsys.readouterr().err
    assert err == (f"rotorcontact simulate: error: NUMBA_NUM_THREADS = {value!r} is invalid; allowed: a whole "
                   "number >= 1 (the threads of numba and of the studies in this process), or unset for one "
                   "per core\n")


def test_a_zero_numba_thread_count_is_one_line_not_numbas_traceback(tmp_path):
    # numba itself cannot be imported with it: the command must say so before anything imports numba
    import os
    import subprocess
    import sys

    env = {**os.environ, "NUMBA_NUM_THREADS": "0"}
    out = subprocess.run([sys.executable, "-m", "rotorcontact.cli.main", "basins", "--grid", "plane:4",
                          "--no-progress", "--out", str(tmp_path / "b.nc")],
                         env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 2, out.stderr
    assert out.stderr.startswith("rotorcontact basins: error: NUMBA_NUM_THREADS = '0' is invalid")
    assert len(out.stderr.splitlines()) == 1 and out.stdout == ""


# ---------------------------------------------------------------------------
# a failed simulation: exit status 1, and nothing claims a regime
# ---------------------------------------------------------------------------


@pytest.fixture
def failing_simulate(monkeypatch):
    """The simulator, as the CLI finds it when it runs, made to fail at t = 1.5 after its impacts so far."""
    import dataclasses

    import rotorcontact.simulation.simulator as simulator
    from rotorcontact import simulate

    def fake(params, u0, du0, t_end, **kw):
        traj = simulate(params, u0, du0, min(t_end, 1.5), **kw)
        return dataclasses.replace(traj, status="failed", failure="the impact search exceeded its step limit")

    monkeypatch.setattr(simulator, "simulate", fake)


def test_a_failed_simulation_exits_1_and_says_so(failing_simulate, capsys):
    assert main(["simulate"]) == 1
    out, err = capsys.readouterr()
    assert "could not continue" in out
    assert "regime: none (the run failed" in out and "no-contact" not in out
    assert err.strip().startswith("rotorcontact simulate: failed:") and len(err.strip().splitlines()) == 1


def test_a_failed_simulation_in_json_is_marked_failed(failing_simulate, capsys):
    import json

    assert main(["simulate", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "failed"
    assert data["summary"]["motion"] == "failed"
    assert data["summary"]["regime"] is None and data["summary"]["contact_fraction"] is None


def test_a_simulation_that_fails_for_real_exits_1(capsys):
    # an absurd negative damping within the allowed range: the flight explodes at once
    assert main(["simulate", "--gamma=-1e6", "--t-end", "5"]) == 1
    out, err = capsys.readouterr()
    assert "regime: none" in out and "failed" in err


@pytest.mark.parametrize(
    "args, option, value",
    [
        (("drop", "reference", "--speed", "30000"), "--speed", "30000"),
        (("dry-whip", "reference", "--speed", "30000"), "--speed", "30000"),
        (("drop-map", "reference", "--speed", "10000:30000", "--out", "/tmp/never"), "--speed", "30000"),
        (("design-map", "--machine", "reference", "--speed", "1000:6000"), "--speed", "6000"),
        (("attractors", "--machine", "reference", "--param", "speed", "--from", "3000", "--to", "6000rpm", "--n", "3",
          "--grid", "shock:4", "--out", "/tmp/never.nc"), "--from", "3000"),
    ],
)
def test_a_bare_speed_is_refused_not_guessed(args, option, value, cli):
    """A bare 30000 could be rpm or rad/s, a factor of ten apart: every speed option asks for the unit."""
    code, _, err = cli.exe(*args, timeout=300)
    assert code == 2, err
    assert f"{option} = '{value}' has no unit; allowed: an angular speed with its unit" in err
    assert "Traceback" not in err


def test_a_dimensionless_option_with_units_says_it_takes_none(cli):
    code, _, err = cli.exe("simulate", "--t-end", "10s", timeout=300)
    assert code == 2 and "Traceback" not in err
    assert "--t-end = '10s' is not a number; allowed: a plain number without units" in err
