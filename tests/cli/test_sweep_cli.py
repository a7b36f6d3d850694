"""``rotorcontact sweep``: files, figure, JSON summary, and bad input (exit 2, no traceback)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr

from rotorcontact.cli.main import main

EXE = Path(sys.executable).parent / "rotorcontact"


def run_main(argv: list[str]) -> int:
    """The exit status of the command line run in this process (argparse errors included)."""
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)
SMALL = ["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "5", "--transient", "100", "--record", "10",
         "--no-progress"]


def test_writes_netcdf_and_figure_and_prints_a_summary(tmp_path, capsys):
    out, png = tmp_path / "s.nc", tmp_path / "s.png"
    assert main(["sweep", *SMALL, "--out", str(out), "--plot", str(png), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["out"] == str(out) and data["values"] == 5 and data["directions"] == ["up", "down"]
    assert sum(data["regimes"]["up"].values()) == 5 and data["impacts"] > 0
    assert png.stat().st_size > 0
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.sizes["gamma"] == 5 and ds.sizes["direction"] == 2 and ds.sizes["impact"] == 10
    assert ds.attrs["swept_parameter"] == "gamma" and ds.attrs["n_transient"] == 100
    assert ds.attrs["omega_units"] == "1" and ds.theta.attrs["units"] == "rad"


def test_text_output_and_options(tmp_path, capsys):
    out = tmp_path / "w.nc"
    args = ["sweep", "--param", "omega", "--from", "0.74", "--to", "0.78", "--n", "3", "--gamma", "0.1",
            "--mode", "up", "--start", "B1,d", "--transient", "50", "--record", "8", "--chunk-size", "2",
            "--no-progress", "--out", str(out)]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert f"wrote {out}" in text and "up:" in text and "impacts/s" in text
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.attrs["start_state"] == "B1,d" and ds.attrs["gamma"] == 0.1


def test_progress_bar_on_stderr(tmp_path):
    out = tmp_path / "p.nc"
    proc = subprocess.run([str(EXE), "sweep", *SMALL[:-1], "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 0
    assert "sweep gamma" in proc.stderr and "100%" in proc.stderr


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--param", "speed", "--from", "0", "--to", "1", "--n", "3"], "--param"),
        (["--param", "gamma", "--from", "0.2", "--to", "0.1", "--n", "3"], "smaller"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "x"], "--n"),
        (["--param", "gamma", "--from", "a", "--to", "0.2", "--n", "3"], "--from"),
        (["--param", "d", "--from", "0.5", "--to", "1.5", "--n", "3"], "d = 1.5"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--n-jobs", "0"], "--n-jobs"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--scheduler", "nowhere"], "scheduler"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--plot", "x.gif"], "--plot"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--start", "B7,q"], "B7,q"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--u0", "2,0"], "outside"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--record", "0"], "--record"),
    ],
)
def test_bad_input_exits_2(tmp_path, capsys, extra, message):
    assert run_main(["sweep", *extra, "--out", str(tmp_path / "x.nc"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "x.nc").exists()


def test_bad_input_from_the_shell_has_no_traceback(tmp_path):
    proc = subprocess.run([str(EXE), "sweep", "--param", "gamma", "--from", "0.2", "--to", "0.1", "--n", "3",
                           "--out", str(tmp_path / "x.nc")], capture_output=True, text=True)
    assert proc.returncode == 2 and "smaller" in proc.stderr and "Traceback" not in proc.stderr


def test_output_must_be_netcdf(tmp_path):
    proc = subprocess.run([str(EXE), "sweep", *SMALL, "--out", str(tmp_path / "x.csv")], capture_output=True,
                          text=True)
    assert proc.returncode == 2 and ".nc" in proc.stderr and "Traceback" not in proc.stderr
