"""``rotorcontact basins``: files, figure, fractions, the documented grid syntax, bad input."""

from __future__ import annotations

import pytest
import xarray as xr


def test_writes_netcdf_and_figure_and_prints_fractions(tmp_path, cli):
    out, png = tmp_path / "b.nc", tmp_path / "b.png"
    data = cli.json("basins", "--gamma", "0.1", "--grid", "plane:7", "--out", out, "--plot", png, "--no-progress")
    assert data["kind"] == "displacement" and data["shape"] == [7, 7]
    assert abs(sum(data["fractions"].values()) - 1.0) < 1e-12 and "B1,d" in data["fractions"]
    assert png.stat().st_size > 0
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.attractor.shape == (7, 7) and ds.attrs["grid_kind"] == "displacement"
    assert data["simulated"] == int(ds.inside.sum())


def test_shock_grid_text_output(tmp_path, cli):
    out = tmp_path / "s.nc"
    code, text, err = cli.run("basins", "--gamma", "0.2", "--grid", "amplitude=0:0.02:2,direction=-pi:pi:3",
                              "--out", out, "--no-progress")
    assert code == 0, err
    assert "shock grid 2 x 3" in text and "no-contact" in text and "100.00 %" in text


def test_machine_in_si_units_is_stored(tmp_path, cli):
    out = tmp_path / "m.nc"
    code, _, err = cli.run("basins", "--machine", "reference", "--grid", "plane:3", "--out", out, "--no-progress")
    assert code == 0, err
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.attrs["machine_mass"] == 50.0 and ds.attrs["machine_mass_units"] == "kg"
    assert ds.attrs["machine_speed_units"] == "rad/s"


def test_help_documents_the_grid_syntax(cli):
    code, out, _ = cli.exe("basins", "--help")
    assert code == 0
    for piece in ("x=X0:X1:NX,y=Y0:Y1:NY", "amplitude=A0:A1:NA,direction=B0:B1:NB", "plane:N", "shock:N", "pi/2"):
        assert piece in out


@pytest.mark.parametrize(
    "grid, message",
    [
        ("x=0:1:3", "both x and y"),
        ("nonsense", "NAME=START:STOP:COUNT"),
        ("plane:0", ">= 1"),
        ("plane:-3", "the count must be >= 1"),
        ("shock:many", "the count 'many' is not an integer"),
        ("x=-1:1:3,y=-1:1:two", "integer"),
        ("", "is empty"),
    ],
)
def test_bad_grid_exits_2(tmp_path, cli, grid, message):
    code, _, err = cli.run("basins", "--grid", grid, "--out", tmp_path / "x.nc", "--no-progress")
    assert code == 2
    assert message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_bad_grid_from_the_shell_has_no_traceback(tmp_path, cli):
    code, _, err = cli.exe("basins", "--grid", "x=0:1:3", "--out", tmp_path / "x.nc")
    assert code == 2 and "both x and y" in err and "Traceback" not in err


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--gamma", "0.05", "--grid", "shock:3"], "virtual"),
        (["--grid", "plane:3", "--match-tol", "-1"], "--match-tol"),
        (["--grid", "plane:3", "--transient", "-5"], "--transient"),
        (["--grid", "plane:3", "--n-jobs", "zero"], "--n-jobs"),
        (["--grid", "plane:3", "--gamma", "nan"], "--gamma"),
    ],
)
def test_bad_options_exit_2(tmp_path, cli, extra, message):
    code, _, err = cli.run("basins", *extra, "--out", tmp_path / "x.nc", "--no-progress")
    assert code == 2
    assert message in err and "Traceback" not in err
