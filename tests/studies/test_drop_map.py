"""The drop map on the chunked study driver: each point is a drop; identical across executors; resumable."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from rotorcontact import Machine, reference_machine
from rotorcontact.simulation.drop_run import RPM, drop
from rotorcontact.studies.drop_map import REGIMES, drop_map

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


def test_dask_executor_agrees():
    pytest.importorskip("dask.distributed")
    base = drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, chunk_size=1)
    dask = drop_map(M, SPEEDS[:2], FRICTIONS[:1], t_end=T_END, chunk_size=1, scheduler="local", processes=False)
    for name in base.dataset.data_vars:
        xr.testing.assert_identical(base.dataset[name], dask.dataset[name])
