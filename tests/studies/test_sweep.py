"""Brute-force orbit diagrams: agreement with the fixed points, hysteresis, scale-out and resume.

Claims checked here:

* where the rotor settles on a stable one-impact orbit, the recorded impacts
  sit on the fixed point of the impact map (`one_impact_orbits`);
* sweeping up and down shows hysteresis: on B1,d the up sweep keeps impacting
  where the down sweep, coming from rub, keeps rubbing;
* the results do not depend on how they are computed: in this process,
  joblib workers, a Dask LocalCluster, any chunk size (bit for bit);
* an interrupted sweep resumes from its chunk files and writes the same file.
"""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rotorcontact import ParameterError, simulate
from rotorcontact.studies.batch import BatchSettings, simulate_batch
from rotorcontact.maps.impact_map import one_impact_orbits
from rotorcontact.simulation.motion import REGIMES
from rotorcontact.studies.execution import chunk_folder
from rotorcontact.studies.sweep import one_impact_overlay, start_state, sweep, sweep_values
from reference_parameters import REF


def _assert_bitwise(a: xr.Dataset, b: xr.Dataset) -> None:
    xr.testing.assert_identical(a, b)
    for name in a.data_vars:
        assert a[name].values.tobytes() == b[name].values.tobytes(), name


def test_recorded_impacts_sit_on_the_stable_one_impact_fixed_point():
    values = sweep_values(0.09, 0.14, 6)
    res = sweep(REF, "gamma", values, mode="up", n_transient=1500, n_record=20, progress=False)
    ds = res.dataset.sel(direction="up")
    for i, g in enumerate(values):
        stable = [o for o in one_impact_orbits(REF.replace(gamma=g)) if o.stable and o.plausible]
        assert [o.label for o in stable] == ["B1,d"]
        o = stable[0]
        assert int(ds.impacts_per_period[i]) == 1
        assert abs(float(ds.period[i]) - o.T) < 1e-9
        theta = ds.theta.values[i]
        assert np.all(np.abs(np.angle(np.exp(1j * (theta - o.theta)))) < 1e-9)
        assert np.all(np.abs(ds.rdot.values[i] - o.rdot) < 1e-9)
        assert np.all(np.abs(ds.thetadot.values[i] - o.thetadot) < 1e-9)


def test_up_and_down_sweeps_show_hysteresis():
    values = sweep_values(0.14, 0.19, 11)
    res = sweep(REF, "gamma", values, mode="both", n_transient=1500, n_record=50, progress=False)
    up, down = res.regimes("up"), res.regimes("down")
    # down from gamma = 0.19 (beyond the fold of B1,d) the rotor rubs all the way
    assert set(down) == {"forward-rub"}
    # up from rest at 0.14 it settles on B1,d and stays on it until its fold near 0.178
    fold_side = values < 0.175
    assert all(r == "periodic-impacting" for r, f in zip(up, fold_side) if f)
    assert up[-1] == "forward-rub"
    both = (np.array(up) == "periodic-impacting") & (np.array(down) == "forward-rub")
    assert both.sum() >= 5
    # the NetCDF flags name the regimes as a single simulation does
    meanings = res.dataset["regime"].attrs["flag_meanings"].split()
    assert meanings[:6] == list(REGIMES) and "rub" not in meanings and "rolling" not in meanings


def test_period_doubling_on_the_continued_branch_separates_one_and_two_impacts():
    """Coming down on B1,d, the brute-force orbit has two impacts per period exactly below the
    period doubling that the continuation of B1,d locates."""
    pytest.importorskip("rotorcontact.continuation.branches")
    from rotorcontact.studies.sweep import continued_branches

    values = np.array([0.0829, 0.0832, 0.0836, 0.0842])
    branches = continued_branches(REF, "gamma", values)
    pd = [e.value for e in branches.events if e.type == "period-doubling" and "B1,d" in e.orbits]
    assert len(pd) == 1 and values[1] < pd[0] < values[2]
    res = sweep(REF, "gamma", values, mode="down", start="B1,d", n_transient=4000, n_record=100, progress=False)
    p = res.dataset.impacts_per_period.sel(direction="down").values
    assert p.tolist() == [2, 2, 1, 1]


def test_chunk_size_does_not_change_the_results():
    values = sweep_values(0.1, 0.2, 9)
    kw = dict(mode="both", n_transient=200, n_record=30, progress=False)
    a = sweep(REF, "gamma", values, chunk_size=2, **kw).dataset
    b = sweep(REF, "gamma", values, chunk_size=100, **kw).dataset
    a.attrs.pop("chunk_size")
    b.attrs.pop("chunk_size")
    _assert_bitwise(a, b)


def test_independent_mode_is_the_batch_kernel_from_one_start():
    values = sweep_values(0.08, 0.2, 7)
    st = BatchSettings(n_transient=300, n_record=25)
    ds = sweep(REF, "gamma", values, mode="independent", settings=st, progress=False, chunk_size=3).dataset
    direct = simulate_batch([REF.replace(gamma=g) for g in values], 0j, 0j, settings=st)
    assert ds.theta.values[0].tobytes() == direct.theta.tobytes()
    assert ds.regime.values[0].tolist() == direct.regime.tolist()


def test_sweep_over_another_parameter_and_named_start():
    values = sweep_values(0.74, 0.78, 3)
    res = sweep(REF.replace(gamma=0.1), "omega", values, mode="up", start="B1,d", n_transient=100, n_record=10,
                progress=False)
    ds = res.dataset
    assert "omega" in ds.dims and ds.attrs["swept_parameter"] == "omega" and "omega" not in ds.attrs
    assert ds.attrs["gamma"] == 0.1 and ds.attrs["start_state"] == "B1,d"
    u0, du0 = start_state(REF.replace(gamma=0.1, omega=0.74), "B1,d")
    assert ds.attrs["start_u0_re"][0] == u0.real and ds.attrs["start_du0_im"][0] == du0.imag
    assert set(res.regimes("up")) == {"periodic-impacting"}


def test_dask_local_cluster_equals_joblib_bit_for_bit(tmp_path):
    from distributed import Client

    from rotorcontact.studies.execution import local_cluster

    values = sweep_values(0.08, 0.2, 10)
    kw = dict(mode="both", n_transient=300, n_record=30, chunk_size=3, progress=False)
    ref = sweep(REF, "gamma", values, out=tmp_path / "inproc.nc", **kw)
    jl = sweep(REF, "gamma", values, n_jobs=2, out=tmp_path / "joblib.nc", **kw)
    cluster = local_cluster(2, processes=False)
    client = Client(cluster)
    try:
        assert len(client.scheduler_info()["workers"]) == 2
        dk = sweep(REF, "gamma", values, scheduler=client, out=tmp_path / "dask.nc", **kw)
    finally:
        client.close()
        cluster.close()
    _assert_bitwise(jl.dataset, dk.dataset)
    _assert_bitwise(ref.dataset, dk.dataset)
    data = (tmp_path / "joblib.nc").read_bytes()
    assert data == (tmp_path / "dask.nc").read_bytes() == (tmp_path / "inproc.nc").read_bytes()
    # the file holds the dataset, parameters and units included
    back = xr.load_dataset(tmp_path / "dask.nc", engine="scipy")
    _assert_bitwise(back, dk.dataset)
    assert back.attrs["omega"] == REF.omega and back.attrs["phi_units"] == "rad"
    assert back.theta.attrs["units"] == "rad" and back.gamma.attrs["units"] == "1"
    assert not chunk_folder(tmp_path / "dask.nc").exists()


def _sweep_command(out: Path) -> list[str]:
    # a sweep of 12 chunks of one value each
    return [
        "sweep", "--param", "gamma", "--from", "0.09", "--to", "0.13", "--n", "12", "--mode", "up",
        "--transient", "2000", "--record", "20", "--chunk-size", "1", "--out", str(out), "--no-progress",
    ]


# the CLI in a process that kills itself (SIGKILL: no clean-up runs) right after its
# third chunk file is saved, wherever the scheduler is at that moment
_KILLED_AFTER_THREE_CHUNKS = """
import os, signal, sys
from rotorcontact.studies import execution as scaleout
from rotorcontact.cli.main import main

save = scaleout.ChunkStore.save
saved = []

def save_then_die(self, key, arrays):
    save(self, key, arrays)
    saved.append(key)
    if len(saved) == 3:
        os.kill(os.getpid(), signal.SIGKILL)

scaleout.ChunkStore.save = save_then_die
sys.exit(main(sys.argv[1:]))
"""


def test_an_interrupted_sweep_resumes_and_writes_the_same_file(tmp_path):
    out = tmp_path / "resumed.nc"
    folder = chunk_folder(out)
    proc = subprocess.run([sys.executable, "-c", _KILLED_AFTER_THREE_CHUNKS, *_sweep_command(out)],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=300)
    assert proc.returncode == -signal.SIGKILL, proc.stderr.decode()
    assert len(list(folder.glob("*.npz"))) == 3 and not out.exists()
    # run again: it continues from the chunk files
    from rotorcontact.cli.main import main

    assert main(_sweep_command(out)) == 0
    assert out.exists() and not folder.exists()
    # the same sweep uninterrupted
    fresh = tmp_path / "fresh.nc"
    assert main(_sweep_command(fresh)) == 0
    assert out.read_bytes() == fresh.read_bytes()


def test_resume_reports_reused_chunks_and_refuses_a_different_study(tmp_path):
    out = tmp_path / "s.nc"
    values = sweep_values(0.1, 0.12, 4)
    kw = dict(mode="up", n_transient=50, n_record=5, chunk_size=1, progress=False, out=out, keep_chunks=True)
    first = sweep(REF, "gamma", values, **kw)
    assert first.chunks_computed == 4 and first.chunks_reused == 0
    out.unlink()  # the chunk files are kept: a second run assembles them again
    again = sweep(REF, "gamma", values, **kw)
    assert again.chunks_computed == 0 and again.chunks_reused == 4 and not again.reused_file
    _assert_bitwise(first.dataset, again.dataset)
    with pytest.raises(ParameterError, match="different study"):
        sweep(REF, "gamma", values, **{**kw, "n_record": 6})
    fresh = sweep(REF, "gamma", values, **{**kw, "n_record": 6, "resume": False})
    assert fresh.chunks_computed == 4


def test_a_finished_sweep_is_not_computed_again(tmp_path):
    out = tmp_path / "s.nc"
    values = sweep_values(0.1, 0.12, 4)
    kw = dict(mode="up", n_transient=50, n_record=5, chunk_size=2, progress=False, out=out)
    first = sweep(REF, "gamma", values, **kw)
    assert first.chunks_computed == 2 and not first.reused_file and not chunk_folder(out).exists()
    stamp = out.stat().st_mtime_ns
    again = sweep(REF, "gamma", values, **kw)
    assert again.reused_file and again.chunks_computed == 0 and again.chunks_reused == 2
    assert out.stat().st_mtime_ns == stamp  # the file was read, not written
    assert again.impacts_simulated == first.impacts_simulated
    assert again.regimes("up") == first.regimes("up")
    for name in ("theta", "rdot", "thetadot", "regime"):
        assert again.dataset[name].values.tobytes() == first.dataset[name].values.tobytes()
    # another study, or --no-resume, computes afresh
    other = sweep(REF, "gamma", values, **{**kw, "n_record": 6})
    assert not other.reused_file and other.chunks_computed == 2
    fresh = sweep(REF, "gamma", values, **{**kw, "n_record": 6, "resume": False})
    assert not fresh.reused_file and fresh.chunks_computed == 2


def test_an_interrupted_sweep_resumes_with_its_own_chunk_size(tmp_path):
    out = tmp_path / "s.nc"
    values = sweep_values(0.1, 0.12, 4)
    kw = dict(mode="up", n_transient=50, n_record=5, progress=False, out=out, keep_chunks=True)
    first = sweep(REF, "gamma", values, chunk_size=1, **kw)
    out.unlink()
    (chunk_folder(out) / "up-000003.npz").unlink()  # as if interrupted before the last chunk
    resumed = sweep(REF, "gamma", values, chunk_size=3, **kw)
    assert resumed.chunks_reused == 3 and resumed.chunks_computed == 1
    assert int(resumed.dataset.attrs["chunk_size"]) == 1
    _assert_bitwise(first.dataset, resumed.dataset)


def test_netcdf_files_get_the_permissions_of_ordinary_files(tmp_path):
    import os

    mask = os.umask(0o022)
    try:
        out = tmp_path / "s.nc"
        sweep(REF, "gamma", sweep_values(0.1, 0.11, 2), mode="up", n_transient=20, n_record=5, progress=False,
              out=out)
        assert out.stat().st_mode & 0o777 == 0o644
    finally:
        os.umask(mask)


def test_overlay_holds_the_fixed_points():
    values = sweep_values(0.09, 0.12, 4)
    ov = one_impact_overlay(REF, "gamma", values)
    assert list(ov.orbit.values) == ["B1,a", "B1,b", "B1,c", "B1,d"]
    g = float(values[1])
    o = [x for x in one_impact_orbits(REF.replace(gamma=g)) if x.label == "B1,d"][0]
    assert ov.theta.isel(gamma=1).sel(orbit="B1,d").item() == o.theta
    assert ov.stable.isel(gamma=1).sel(orbit="B1,d").item() == 1


def test_invalid_input():
    values = sweep_values(0.1, 0.2, 3)
    with pytest.raises(ParameterError, match="param"):
        sweep(REF, "speed", values)
    with pytest.raises(ParameterError, match="increase"):
        sweep(REF, "gamma", [0.2, 0.1])
    for mode in ("sideways", ["both"], None):
        with pytest.raises(ParameterError, match=r"^mode = .* is invalid; allowed: "):
            sweep(REF, "gamma", values, mode=mode)
    with pytest.raises(ParameterError, match="d = 2"):
        sweep(REF, "d", [0.5, 2.0])
    with pytest.raises(ParameterError, match="B1,d"):
        sweep(REF, "gamma", [0.19, 0.2], start="B1,d")
    with pytest.raises(ParameterError, match=".nc"):
        sweep(REF, "gamma", values, out="x.txt")
    with pytest.raises(ParameterError, match="n_jobs"):
        sweep(REF, "gamma", values, n_jobs=0, n_transient=1, n_record=1)
    with pytest.raises(ParameterError, match="scheduler"):
        sweep(REF, "gamma", values, scheduler="nowhere", n_transient=1, n_record=1)
    with pytest.raises(ParameterError, match="smaller"):
        sweep_values(0.2, 0.1, 3)
    with pytest.raises(ParameterError, match="^n = 1 is a single value"):
        sweep_values(0.1, 0.2, 1)
    assert sweep_values(0.1, 0.1, 1).tolist() == [0.1]
    with pytest.raises(ParameterError, match="^start = 'B1,d' and an explicit u0/du0"):
        sweep(REF, "gamma", values, start="B1,d", du0=0.1j, n_transient=1, n_record=1)


def test_a_chunk_folder_without_chunks_does_not_block_another_study(tmp_path):
    """A study that stopped before its first chunk leaves nothing to resume; one with chunks is protected."""
    import numpy as np

    from rotorcontact.errors import ParameterError
    from rotorcontact.studies.execution import ChunkStore

    folder = tmp_path / "x.nc.chunks"
    ChunkStore(folder, {"study": "a"})
    store = ChunkStore(folder, {"study": "b"})  # replaces the empty study a
    store.save("c0", {"v": np.zeros(2)})
    with pytest.raises(ParameterError):
        ChunkStore(folder, {"study": "c"})


def test_a_missing_output_folder_is_refused_before_any_computation(tmp_path, monkeypatch):
    import rotorcontact.studies.driver as driver_module

    def no_computation(*args, **kwargs):  # pragma: no cover - must not be reached
        raise AssertionError("computed before the output was checked")

    monkeypatch.setattr(driver_module, "run_waves", no_computation)
    with pytest.raises(ParameterError, match="does not exist"):
        sweep(REF, "gamma", sweep_values(0.1, 0.11, 2), mode="up", n_transient=20, n_record=5, progress=False,
              out=tmp_path / "missing" / "s.nc")
    assert not (tmp_path / "missing").exists()


@pytest.mark.parametrize("values", [np.array([0.1, 0.2]) + 0j, [[0.1, 0.2]], ["0.1", "0.2"], [True, False]])
def test_sweep_values_must_be_a_list_of_real_numbers(values):
    with pytest.raises(ParameterError, match="are not a list of real numbers"):
        sweep(REF, "gamma", values, n_transient=1, n_record=1)
    with pytest.raises(ParameterError, match="^machine = 'x' is not a Machine object"):
        sweep(REF, "gamma", [0.1, 0.2], n_transient=1, n_record=1, machine="x")


@pytest.mark.parametrize("param, value", [("rho", 1e6), ("omega", 1.0)])
def test_a_value_beyond_the_simulators_accurate_range_is_refused(param, value):
    """The batch refuses what `simulate` refuses: a forced response |k| beyond 1000 clearances."""
    base = REF.replace(gamma=1e-6) if param == "omega" else REF
    with pytest.raises(ParameterError, match=r"^rho = .*allowed: rho <= 1000 \|omega\^2 - 1 \+ i gamma\|"):
        sweep(base, param, [0.5, value], n_transient=20, n_record=10, progress=False)
    with pytest.raises(ParameterError, match=r"^rho = "):
        simulate(base.replace(**{param: value}), 0j, 0j, 1.0)


@pytest.mark.parametrize("args, match", [
    ((0.0, 1.0, 10**12), r"^n = 1000000000000 is invalid; allowed: an integer from 1 to 16000000$"),
    ((-1e308, 1e308, 3), r"^start = -1e\+308 to stop = 1e\+308 spans more than"),
])
def test_sweep_values_refuses_what_it_cannot_build(args, match):
    with pytest.raises(ParameterError, match=match):
        sweep_values(*args)


def test_a_machine_whose_parameters_are_not_params_is_refused_and_so_are_too_many_values():
    from rotorcontact import reference_machine
    from rotorcontact.studies.grids import MAX_GRID_POINTS

    m = reference_machine()
    other = m.with_speed(0.5 * m.speed)  # the same machine at half speed: other omega, gamma, ...
    with pytest.raises(ParameterError, match=r"^params are not the machine's \(omega = .*; allowed: machine"):
        sweep(m.parameters(), "gamma", [0.1], machine=other, progress=False)
    # the swept parameter itself may differ from the machine's
    res = sweep(m.parameters().replace(gamma=0.3), "gamma", [0.2], machine=m, n_transient=10, n_record=5,
                progress=False)
    assert res.dataset.attrs["swept_parameter"] == "gamma"
    with pytest.raises(ParameterError, match=rf"^values of 'gamma' = range\(0, 1000000000000\) holds 1000000000000 "
                                             rf"values; allowed: at most {MAX_GRID_POINTS}$"):
        sweep(REF, "gamma", range(10**12), progress=False)


def test_the_regimes_of_a_direction_the_sweep_does_not_have_are_refused():
    res = sweep(REF, "gamma", [0.1], mode="up", n_transient=10, n_record=5, progress=False)
    assert len(res.regimes("up")) == 1
    for bad in ("down", "UP", None):
        with pytest.raises(ParameterError, match=r"^direction = .* is invalid; allowed: 'up'$"):
            res.regimes(bad)


def test_the_overlay_checks_its_parameters_and_count():
    for kw, name in ((dict(max_values=0), "max_values"), (dict(max_values=None), "max_values"),
                     (dict(max_values=1.5), "max_values")):
        with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid"):
            one_impact_overlay(REF, "gamma", [0.1, 0.2], **kw)
    with pytest.raises(ParameterError, match=r"^params = None is not a Parameters object"):
        one_impact_overlay(None, "gamma", [0.1])
