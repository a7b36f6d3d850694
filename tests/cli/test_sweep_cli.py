"""``rotorcontact sweep``: files, figure, JSON summary, and bad input (exit 2, no traceback)."""

from __future__ import annotations

import pytest
import xarray as xr

SMALL = ["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "5", "--transient", "100", "--record", "10",
         "--no-progress"]


def test_writes_netcdf_and_figure_and_prints_a_summary(tmp_path, cli):
    out, png = tmp_path / "s.nc", tmp_path / "s.png"
    data = cli.json("sweep", *SMALL, "--out", out, "--plot", png)
    assert data["out"] == str(out) and data["values"] == 5 and data["directions"] == ["up", "down"]
    assert sum(data["regimes"]["up"].values()) == 5 and data["impacts"] > 0
    assert png.stat().st_size > 0
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.sizes["gamma"] == 5 and ds.sizes["direction"] == 2 and ds.sizes["impact"] == 10
    assert ds.attrs["swept_parameter"] == "gamma" and ds.attrs["n_transient"] == 100
    assert ds.attrs["omega_units"] == "1" and ds.theta.attrs["units"] == "rad"


def test_text_output_and_options(tmp_path, cli):
    out = tmp_path / "w.nc"
    code, text, err = cli.run("sweep", "--param", "omega", "--from", "0.74", "--to", "0.78", "--n", "3",
                              "--gamma", "0.1", "--mode", "up", "--start", "B1,d", "--transient", "50", "--record",
                              "8", "--chunk-size", "2", "--no-progress", "--out", out)
    assert code == 0, err
    assert f"wrote {out}" in text and "up:" in text and "impacts/s" in text
    ds = xr.load_dataset(out, engine="scipy")
    assert ds.attrs["start_state"] == "B1,d" and ds.attrs["gamma"] == 0.1


def test_progress_bar_on_stderr(tmp_path, cli):
    code, _, err = cli.exe("sweep", *SMALL[:-1], "--out", tmp_path / "p.nc")
    assert code == 0
    assert "sweep gamma" in err and "100%" in err


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
        # options that would be ignored are refused
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "1"], "--n = 1 is a single value"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--start", "B1,d", "--u0", "0.1,0"],
         "--start = 'B1,d' and --u0/--du0"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--overlay-doublings", "2"],
         "--overlay-doublings"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--section", "rdot"],
         "--section sets the figure; allowed: with --plot"),
        (["--param", "gamma", "--from", "0.1", "--to", "0.2", "--n", "3", "--no-overlay"],
         "--no-overlay sets the figure; allowed: with --plot"),
    ],
)
def test_bad_input_exits_2(tmp_path, cli, extra, message):
    code, _, err = cli.run("sweep", *extra, "--out", tmp_path / "x.nc", "--no-progress")
    assert code == 2
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "x.nc").exists()


def test_bad_input_from_the_shell_has_no_traceback(tmp_path, cli):
    code, _, err = cli.exe("sweep", "--param", "gamma", "--from", "0.2", "--to", "0.1", "--n", "3",
                           "--out", tmp_path / "x.nc")
    assert code == 2 and "smaller" in err and "Traceback" not in err


def test_output_must_be_netcdf(tmp_path, cli):
    code, _, err = cli.exe("sweep", *SMALL, "--out", tmp_path / "x.csv")
    assert code == 2 and ".nc" in err and "Traceback" not in err


@pytest.mark.parametrize("command", ["sweep", "basins"])
def test_chunk_size_help_states_how_the_default_is_fitted_to_the_workers(cli, command):
    from rotorcontact.studies.execution import CHUNKS_PER_WORKER, MIN_FITTED_CHUNK

    code, out, _ = cli.run(command, "--help")
    text = " ".join(out.split())
    assert code == 0
    assert f"fewer, down to {MIN_FITTED_CHUNK}, so that each worker gets {CHUNKS_PER_WORKER} chunks or more" in text
