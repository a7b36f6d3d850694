"""The design-map command: files, JSON contract and clear errors."""

from __future__ import annotations

import pytest


def test_speed_map_writes_png_nc_and_table(tmp_path, cli):
    code, out, err = cli.run("design-map", "--machine", "reference", "--speed", "1000:3000rpm", "--n", "30",
                             "--out", tmp_path)
    assert code == 0, err
    assert "regime" in out and "boundary near" in out
    png = (tmp_path / "map.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    import xarray as xr

    ds = xr.load_dataset(tmp_path / "map.nc")
    assert ds.sizes["speed_rpm"] == 30 and ds["speed_rpm"].attrs["units"] == "rpm"


def test_json_contract(cli):
    data = cli.json("design-map", "--machine", "reference", "--speed", "1500:2500rpm", "--n", "5")
    assert len(data["points"]) == 5
    for pt in data["points"]:
        for key in ("speed_rpm", "gamma", "omega", "regime", "coexisting"):
            assert key in pt
        assert pt["regime"] in ("safe", "bistable", "contact-certain")
        assert isinstance(pt["coexisting"], list)
    assert data["points"][0]["speed_rpm"] == pytest.approx(1500.0)


def test_recovery_probabilities_are_the_same_on_worker_processes(cli):
    args = ("design-map", "--machine", "reference", "--speed", "1800:2600rpm", "--n", "3", "--shock", "5mm/s",
            "--no-progress")
    serial = cli.json(*args)
    assert any(pt["recovery_probability"] is not None for pt in serial["points"])
    assert cli.json(*args, "--n-jobs", "2") == serial


def test_machine_file_with_units_and_plane(tmp_path, cli):
    path = tmp_path / "rig.toml"
    path.write_text(
        'mass = "50 kg"\ndamping = 1400\nstiffness = "980 kN/m"\neccentricity = "0.3 mm"\n'
        'clearance = "0.7 mm"\nrotor_radius = "4 cm"\nunbalance_phase = 0.21\nspeed = "1759 rpm"\n'
        "friction = 0.15\nrestitution = 0.95\n",
        encoding="utf-8",
    )
    data = cli.json("design-map", path, "--stiffness", "0.5:1.5MN/m", "--damping", "0.5:3kN*s/m", "--n", "4")
    assert data["axes"] == ["stiffness", "damping"] and len(data["points"]) == 16
    assert data["points"][0]["stiffness"] == pytest.approx(5e5) and data["points"][0]["damping"] == pytest.approx(500)


def test_help_says_a_speed_needs_its_unit(cli):
    code, out, _err = cli.run("design-map", "--help")
    assert code == 0
    text = " ".join(out.split())
    assert "a speed must carry its unit" in text and "plain numbers are rpm" not in text


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["--machine", "reference", "--speed", "1000-6000"], "malformed"),
        (["--machine", "reference", "--speed", "6000:1000rpm"], "must increase"),
        (["--machine", "reference", "--speed", "1000:6000wombats"], "unknown unit"),
        (["--machine", "reference", "--speed", "1000:6000kg"], "units of"),
        (["--machine", "reference"], "choose the map"),
        (["--machine", "reference", "--speed", "1000:2000"], "--speed = '2000' has no unit"),
        (["--speed", "1000:2000rpm"], "no machine"),
        (["--machine", "nosuchfile.toml", "--speed", "1000:2000rpm"], "no such file"),
        (["--machine", "/dev/null", "--speed", "1000:2000rpm"], "not a regular file"),
        (["--machine", "reference", "--speed", "3000rpm"], "expected a range A:B with its unit after B"),
    ],
)
def test_bad_input_exits_2_without_traceback(args, fragment, cli):
    code, _, err = cli.exe("design-map", *args)
    assert code == 2
    assert fragment in err and "Traceback" not in err
