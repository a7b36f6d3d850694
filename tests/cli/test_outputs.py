"""Output files of the subcommands: checked before computing, folders created with a note, reruns reused."""

from __future__ import annotations

import json

import pytest
import xarray as xr

from rotorcontact.cli.main import main

SWEEP = ["sweep", "--param", "gamma", "--from", "0.1", "--to", "0.12", "--n", "4", "--mode", "up",
         "--transient", "40", "--record", "5", "--no-progress"]
BASINS = ["basins", "--gamma", "0.1", "--grid", "plane:3", "--transient", "40", "--record", "5", "--no-progress"]

PLOTTING = [
    ["simulate", "--t-end", "5"],
    ["equilibria", "--from", "0", "--to", "0.2"],
    ["branches", "--from", "0.1", "--to", "0.12"],
    ["codim2"],
    [*SWEEP, "--out", "OUT.nc"],
    [*BASINS, "--out", "OUT.nc"],
]
#: where each subcommand does its computation, replaced by a function that must not be called
COMPUTE = {
    "simulate": "rotorcontact.simulation.simulator.simulate",
    "equilibria": "rotorcontact.analysis.equilibria.equilibrium_branches",
    "branches": "rotorcontact.continuation.branches.orbit_branches",
    "codim2": "rotorcontact.continuation.codim2.codim2_diagram",
    "sweep": "rotorcontact.studies.sweep.sweep",
    "basins": "rotorcontact.studies.basins.basins",
}


def _args(args, tmp_path):
    return [str(tmp_path / "out.nc") if a == "OUT.nc" else a for a in args]


def _never(*args, **kwargs):
    raise AssertionError("the computation ran although the output was refused")


@pytest.mark.parametrize("args", PLOTTING, ids=lambda a: a[0])
def test_an_empty_plot_name_is_an_error(capsys, tmp_path, monkeypatch, args):
    monkeypatch.setattr(COMPUTE[args[0]], _never)
    assert main([*_args(args, tmp_path), "--plot", ""]) == 2
    err = capsys.readouterr().err
    assert "--plot = '' is empty" in err and ".png" in err and "Traceback" not in err


@pytest.mark.parametrize("args", PLOTTING, ids=lambda a: a[0])
def test_an_unwritable_plot_path_is_refused_before_computing(capsys, tmp_path, monkeypatch, args):
    monkeypatch.setattr(COMPUTE[args[0]], _never)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    assert main([*_args(args, tmp_path), "--plot", str(blocker / "fig.png")]) == 2
    err = capsys.readouterr().err
    assert "--plot" in err and "is a file, not a folder" in err and "Traceback" not in err
    folder = tmp_path / "folder.png"
    folder.mkdir()
    assert main([*_args(args, tmp_path), "--plot", str(folder)]) == 2
    assert "is a folder" in capsys.readouterr().err


@pytest.mark.parametrize("args", PLOTTING[:1], ids=lambda a: a[0])
def test_a_file_system_that_refuses_the_file_is_found_before_computing(capsys, tmp_path, monkeypatch, args):
    """Permissions do not tell everything (a read-only mount, /proc as root): the file is created and removed."""
    import os

    monkeypatch.setattr(COMPUTE[args[0]], _never)
    target = tmp_path / "fig.png"
    real_open = os.open

    def refusing(path, *a, **k):
        if os.fspath(path) == str(target):
            raise OSError(30, "Read-only file system")
        return real_open(path, *a, **k)

    monkeypatch.setattr(os, "open", refusing)
    assert main([*_args(args, tmp_path), "--plot", str(target)]) == 2
    err = capsys.readouterr().err
    assert "--plot = " in err and "cannot be written (Read-only file system)" in err and "Traceback" not in err


def test_the_check_of_an_output_file_leaves_no_trace(tmp_path):
    import os

    from rotorcontact.cli.outputs import check_plot_path

    new = tmp_path / "new.png"
    check_plot_path(str(new))
    assert not new.exists()
    old = tmp_path / "old.png"
    old.write_bytes(b"figure")
    before = old.stat().st_mtime_ns
    check_plot_path(str(old))
    assert old.read_bytes() == b"figure" and old.stat().st_mtime_ns == before
    # a link to a file not written yet stays a link, and its target is not created
    link = tmp_path / "link.png"
    link.symlink_to(tmp_path / "later" / "fig.png")
    check_plot_path(str(link))
    assert os.path.islink(link) and not (tmp_path / "later").exists()
    if hasattr(os, "mkfifo"):  # a named pipe is not opened (that would wait for a reader)
        pipe = tmp_path / "pipe.png"
        os.mkfifo(pipe)
        check_plot_path(str(pipe))
        assert pipe.is_fifo()


def test_a_missing_folder_of_a_figure_is_created_with_a_note(capsys, tmp_path):
    fig = tmp_path / "new" / "deeper" / "fig.png"
    assert main(["simulate", "--t-end", "5", "--plot", str(fig)]) == 0
    err = capsys.readouterr().err
    assert fig.is_file() and "note: --plot: created the folder" in err
    assert main(["simulate", "--t-end", "5", "--plot", str(fig)]) == 0
    assert "note" not in capsys.readouterr().err  # nothing to create the second time


@pytest.mark.parametrize("base", [SWEEP, BASINS], ids=lambda a: a[0])
def test_an_unwritable_netcdf_file_is_refused_before_computing(capsys, tmp_path, monkeypatch, base):
    monkeypatch.setattr(COMPUTE[base[0]], _never)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    assert main([*base, "--out", str(blocker / "x.nc")]) == 2
    assert "--out" in capsys.readouterr().err
    assert main([*base, "--out", ""]) == 2
    assert "--out = '' is empty" in capsys.readouterr().err


def test_a_finished_sweep_is_read_back_and_chunks_resume_with_their_size(capsys, tmp_path):
    out = tmp_path / "new" / "s.nc"
    args = [*SWEEP, "--out", str(out), "--json"]
    assert main([*args, "--chunk-size", "1", "--keep-chunks"]) == 0
    first = json.loads(capsys.readouterr().out)
    assert first["chunks_computed"] == 4 and out.parent.is_dir()
    # the rotor's angular velocity is a rate, not an angle
    assert xr.load_dataset(out, engine="scipy")["thetadot"].attrs["units"] == "1"
    # run again: the finished file is read back, not computed
    assert main(args) == 0
    captured = capsys.readouterr()
    again = json.loads(captured.out)
    assert again["chunks_computed"] == 0 and again["regimes"] == first["regimes"]
    assert "already holds this finished study" in captured.err
    # an interrupted run (chunk files, no file yet) resumes with its own chunk size
    out.unlink()
    (out.parent / "s.nc.chunks" / "up-000003.npz").unlink()
    assert main([*args, "--chunk-size", "2"]) == 0
    captured = capsys.readouterr()
    resumed = json.loads(captured.out)
    assert resumed["chunks_computed"] == 1 and resumed["chunks_reused"] == 3
    assert resumed["regimes"] == first["regimes"]
    assert "resumed with --chunk-size 1" in captured.err


def test_basin_netcdf_thetadot_is_a_rate(capsys, tmp_path):
    assert main([*BASINS, "--out", str(tmp_path / "b.nc")]) == 0
    ds = xr.load_dataset(tmp_path / "b.nc", engine="scipy")
    assert ds["thetadot"].attrs["units"] == "1" and ds["orbit_thetadot"].attrs["units"] == "1"
    assert ds["theta"].attrs["units"] == "rad"


def test_branches_range_too_far_names_the_range_not_t_max(capsys, monkeypatch):
    monkeypatch.setattr(COMPUTE["branches"], _never)
    assert main(["branches", "--to", "1e5"]) == 2
    err = capsys.readouterr().err
    assert "--to = 100000 is out of reach" in err and "--t-max = 12" in err and "Traceback" not in err
    assert not err.split("error: ")[1].startswith("--t-max")
    # --t-max is named where it is what was given: at gamma = 10 flights grow like e^{5 T}
    assert main(["branches", "--gamma", "10", "--param", "omega", "--t-max", "80"]) == 2
    assert "error: --t-max = 80 is too large at omega = 1.25, the default --to" in capsys.readouterr().err


def test_design_map_shock_needs_a_unit_and_shows_progress(capsys, tmp_path, monkeypatch):
    base = ["design-map", "--machine", "reference", "--speed", "1500:2500rpm", "--n", "3"]
    assert main([*base, "--shock", "5"]) == 2
    err = capsys.readouterr().err
    assert "--shock = '5' has no unit" in err and "5mm/s" in err
    assert main([*base, "--shock", "5mm/s", "--out", str(tmp_path / "new")]) == 0
    err = capsys.readouterr().err
    assert "design map" in err and "3/3" in err  # the progress bar
    assert "note: --out" in err and (tmp_path / "new" / "map.png").is_file()
    # an output folder that is a file is refused before the map is computed
    monkeypatch.setattr("rotorcontact.cli.design_map.build_map", _never)
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    assert main([*base, "--out", str(blocker)]) == 2
    assert "--out" in capsys.readouterr().err


def test_design_map_figure_shows_the_recovery_probabilities():
    import matplotlib.pyplot as plt

    from rotorcontact import reference_machine
    from rotorcontact.studies.design_map import plane_map, speed_map
    from rotorcontact.plotting.design import plot_design_map

    m = reference_machine()
    dmap = speed_map(m, [1800.0, 2200.0], shock=5e-3)
    fig, axes = plot_design_map(dmap)
    lines = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_gid() == "recovery"]
    assert len(lines) == 1
    probs = [100 * pt.recovery_probability for pt in dmap.points]
    assert list(lines[0].get_ydata()) == probs
    plt.close(fig)
    plane = plane_map(m, ("speed_rpm", "stiffness"), [1800.0, 2200.0], [9e5, 1e6], shock=5e-3)
    fig, axes = plot_design_map(plane)
    assert len(axes) == 2 and [c for c in axes[1].collections if c.get_gid() == "recovery"]
    plt.close(fig)
    # without a shock the figure is as before
    fig, axes = plot_design_map(speed_map(m, [1800.0, 2200.0]))
    assert not [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_gid() == "recovery"]
    plt.close(fig)


def test_reproduce_checks_its_output_folder_before_computing(capsys, tmp_path, monkeypatch):
    monkeypatch.setattr("rotorcontact.report.reproduce.reproduce", _never)
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    assert main(["reproduce", "--out", str(blocker)]) == 2
    assert "--out" in capsys.readouterr().err
    assert main(["reproduce", "--out", str(blocker / "sub")]) == 2
    assert "is a file, not a folder" in capsys.readouterr().err
