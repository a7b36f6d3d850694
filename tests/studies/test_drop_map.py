"""The drop map on the chunked study driver: each point is a drop; identical across executors; resumable."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from rotorcontact import Machine, ParameterError, reference_machine
from rotorcontact.simulation.drop_run import MAX_T_END, RPM, drop
from rotorcontact.studies.drop_map import FAILED, REGIMES, drop_map, failed_points

M = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
SPEEDS = np.array([3000.0, 9000.0, 15000.0]) * RPM
FRICTIONS = [0.05, 0.3]
T_END = 0.02


def test_each_point_is_a_drop_and_executors_agree(tmp_path):
    base = drop_map(M, SPEEDS, FRICTIONS, t_end=T_END, chunk_size=2)
    ds = base.dataset
    for i, mu in enumerate(FRICTIONS):
        for j, speed in enumerate(SPEEDS):
            r = drop(Machine(**{**M.as_dict(), "friction": mu}), speed, 0.0, T_END)
            s = r.to_dict()["summary"]
            assert REGIMES[int(ds["regime"].values[i, j])] == s["regime"]
            assert ds["max_normal_impulse_Ns"].values[i, j] == s["max_normal_impulse_Ns"]
            assert ds["energy_dissipated_J"].values[i, j] == s["energy_dissipated_J"]
            assert ds["n_impacts"].values[i, j] == len(r.impacts)
    joblib = drop_map(M, SPEEDS, FRICTIONS, t_end=T_END, chunk_size=4, n_jobs=2)
    for name in ds.data_vars:
        xr.testing.assert_identical(ds[name], joblib.dataset[name])
    out = tmp_path / "map.nc"
    first = drop_map(M, SPEEDS, FRICTIONS, t_end=T_END, chunk_size=3, out=out)
    again = drop_map(M, SPEEDS, FRICTIONS, t_end=T_END, chunk_size=3, out=out)
    assert again.reused_file and not first.reused_file
    for name in ds.data_vars:
        np.testing.assert_array_equal(ds[name].values, again.dataset[name].values)


def test_a_finished_map_of_another_version_is_computed_again(tmp_path, monkeypatch):
    import rotorcontact.studies.drop_map as module

    out = tmp_path / "map.nc"
    drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, out=out)
    assert drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, out=out).reused_file
    monkeypatch.setattr(module, "__version__", module.__version__ + ".other")
    again = drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, out=out)
    assert not again.reused_file and again.chunks_computed > 0


def test_the_file_s_variables_have_units_and_the_counts_are_integers(tmp_path):
    ds = drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, out=tmp_path / "map.nc").dataset
    units = {"regime": "1", "backward_whirl_onset_s": "s", "max_normal_impulse_Ns": "N s", "energy_dissipated_J": "J",
             "final_spin_rpm": "rpm", "n_impacts": "1", "speed_rpm": "rpm", "friction": "1"}
    with xr.open_dataset(tmp_path / "map.nc") as back:
        for name, unit in units.items():
            assert back[name].attrs["units"] == unit and back[name].attrs["long_name"]
        assert back["regime"].dtype == np.int32 and back["n_impacts"].dtype == np.int32
        assert set(back.data_vars) == set(units) - {"speed_rpm", "friction"}  # nothing else, nothing unlabelled
        np.testing.assert_array_equal(back["regime"].values, ds["regime"].values)


def test_dask_executor_agrees():
    pytest.importorskip("dask.distributed")
    base = drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, chunk_size=1)
    dask = drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, chunk_size=1, scheduler="local", processes=False)
    for name in base.dataset.data_vars:
        xr.testing.assert_identical(base.dataset[name], dask.dataset[name])


def test_a_failed_drop_is_marked_failed_with_no_outcome(failing_drops):
    ds = drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END).dataset
    assert [REGIMES[c] for c in ds["regime"].values[0].astype(int)] == ["failed", "failed"]
    assert (ds["regime"].values == FAILED).all()
    for name in ("backward_whirl_onset_s", "max_normal_impulse_Ns", "energy_dissipated_J", "final_spin_rpm"):
        assert np.isnan(ds[name].values).all(), name
    # the impacts before the failure are counted
    impacts = [len(drop(Machine(**{**M.as_dict(), "friction": FRICTIONS[0]}), v, 0.0, T_END).impacts)
               for v in SPEEDS[:2]]
    np.testing.assert_array_equal(ds["n_impacts"].values[0], impacts)
    assert np.array(failed_points(ds)) == pytest.approx(np.array([[3000.0, 0.05], [9000.0, 0.05]]), rel=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    (dict(speeds=[3000.0 * RPM, 1e30 * RPM]), r"speeds\[1\] = .*allowed: \(0, 1e\+06\]"),
    (dict(speeds=[3000.0 * RPM, np.nan]), r"speeds\[1\] = nan"),
    (dict(t_end=1e12), r"t_end = 1000000000000.0 .*\(0, 10000\]"),
    (dict(t_end=MAX_T_END * (1.0 + 1e-9)), r"t_end = .*\(0, 10000\]"),
    (dict(t_end=np.nan), "t_end = nan"),
    (dict(fail_at=-1.0), r"fail_at = -1.0 .*\[0, inf\)"),
    (dict(frictions=[0.1, -0.2]), r"frictions\[1\] = -0.2"),
])
def test_bad_arguments_are_refused_before_any_drop(kwargs, match):
    args = {"speeds": SPEEDS, **kwargs}
    with pytest.raises(ParameterError, match=match):
        drop_map(M, **args)


@pytest.mark.parametrize("machine", [None, "x"])
def test_what_is_not_a_machine_is_refused(machine):
    with pytest.raises(ParameterError, match=r"^machine = .* is not a Machine object"):
        drop_map(machine, [3000.0 * RPM])


def test_lists_of_speeds_or_frictions_beyond_the_bound_are_refused_before_numpy_reads_them():
    from rotorcontact import ParameterError, reference_machine
    from rotorcontact.studies.drop_map import MAX_DROP_POINTS, drop_map

    for kw, name in ((dict(speeds=range(10**12)), "speeds"), (dict(speeds=[100.0], frictions=range(10**12)),
                                                              "frictions")):
        with pytest.raises(ParameterError, match=rf"^{name} = range\(0, 1000000000000\) holds 1000000000000 values; "
                                                 rf"allowed: at most {MAX_DROP_POINTS}$"):
            drop_map(reference_machine(), **kw)


def test_failed_points_need_a_drop_maps_dataset():
    import xarray as xr

    from rotorcontact import ParameterError
    from rotorcontact.studies.drop_map import failed_points

    for bad in (None, "x"):
        with pytest.raises(ParameterError, match=r"^ds = .* is not an? Dataset object; allowed: a drop_map result "
                                                 r"or its Dataset$"):
            failed_points(bad)
    with pytest.raises(ParameterError, match=r"^ds = .* is not a result of drop_map; .* lacks variable 'regime'"):
        failed_points(xr.Dataset())
