"""``rotorcontact basins``: files, figure, fractions, the documented grid syntax, bad input."""

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


def test_writes_netcdf_and_figure_and_prints_fractions(tmp_path, capsys):
    out, png = tmp_path / "b.nc", tmp_path / "b.png"
    args = ["basins", "--gamma", "0.1", "--grid", "plane:7", "--out", str(out), "--plot", str(png), "--json",
            "--no-progress"]
    assert main(args) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["kind"] == "displacement" and data["shape"] == [7, 7]
    assert abs(sum(data["fractions"].values()) - 1.0) < 1e-12 and "B1,d" in data["fractions"]
    assert png.stat().st_size > 0
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.attractor.shape == (7, 7) and ds.attrs["grid_kind"] == "displacement"
    assert data["simulated"] == int(ds.inside.sum())


def test_shock_grid_text_output(tmp_path, capsys):
    out = tmp_path / "s.nc"
    args = ["basins", "--gamma", "0.2", "--grid", "amplitude=0:0.02:2,direction=-pi:pi:3", "--out", str(out),
            "--no-progress"]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "shock grid 2 x 3" in text and "no-contact" in text and "100.00 %" in text


def test_machine_in_si_units_is_stored(tmp_path, capsys):
    out = tmp_path / "m.nc"
    assert main(["basins", "--machine", "reference", "--grid", "plane:3", "--out", str(out), "--no-progress"]) == 0
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.attrs["machine_mass"] == 50.0 and ds.attrs["machine_mass_units"] == "kg"
    assert ds.attrs["machine_speed_units"] == "rad/s"


def test_help_documents_the_grid_syntax():
    proc = subprocess.run([str(EXE), "basins", "--help"], capture_output=True, text=True)
    assert proc.returncode == 0
    for piece in ("x=X0:X1:NX,y=Y0:Y1:NY", "amplitude=A0:A1:NA,direction=B0:B1:NB", "plane:N", "shock:N", "pi/2"):
        assert piece in proc.stdout


@pytest.mark.parametrize(
    "grid, message",
    [
        ("x=0:1:3", "both x and y"),
        ("nonsense", "NAME=START:STOP:COUNT"),
        ("plane:0", ">= 1"),
        ("x=-1:1:3,y=-1:1:two", "integer"),
    ],
)
def test_bad_grid_exits_2(tmp_path, capsys, grid, message):
    assert run_main(["basins", "--grid", grid, "--out", str(tmp_path / "x.nc"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_bad_grid_from_the_shell_has_no_traceback(tmp_path):
    proc = subprocess.run([str(EXE), "basins", "--grid", "x=0:1:3", "--out", str(tmp_path / "x.nc")],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and "both x and y" in proc.stderr and "Traceback" not in proc.stderr


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--gamma", "0.05", "--grid", "shock:3"], "virtual"),
        (["--grid", "plane:3", "--match-tol", "-1"], "match_tol"),
        (["--grid", "plane:3", "--transient", "-5"], "--transient"),
        (["--grid", "plane:3", "--n-jobs", "zero"], "--n-jobs"),
        (["--grid", "plane:3", "--gamma", "nan"], "--gamma"),
    ],
)
def test_bad_options_exit_2(tmp_path, capsys, extra, message):
    assert run_main(["basins", *extra, "--out", str(tmp_path / "x.nc"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
