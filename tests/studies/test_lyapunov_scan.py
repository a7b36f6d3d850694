"""The Lyapunov spectrum against a parameter on the study driver."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from rotorcontact import ParameterError
from rotorcontact.analysis.lyapunov import lyapunov_spectrum
from rotorcontact.studies.execution import chunk_folder
from rotorcontact.studies.lyapunov_scan import FINAL_NAMES, lyapunov_scan
from reference_parameters import REF

VALUES = [0.065, 0.1, 0.15]


def test_each_value_is_the_spectrum_of_that_run_and_executors_agree(tmp_path):
    kw = {"t_end": 500.0, "t_transient": 200.0, "progress": False, "chunk_size": 2}
    a = lyapunov_scan(REF, "gamma", VALUES, out=tmp_path / "a.nc", **kw)
    for i, g in enumerate(VALUES):
        one = lyapunov_spectrum(REF.replace(gamma=g), 0j, 0j, 500.0, t_transient=200.0)
        assert tuple(a.exponents[i]) == one.exponents and tuple(a.errors[i]) == one.errors
        assert bool(a.regime_change[i]) == one.regime_change
        code = int(a.dataset["final_regime"].values[i])
        assert (FINAL_NAMES[code] if code >= 0 else None) == one.final_regime
        if one.final_exponents is not None:
            assert tuple(a.dataset["final_exponents"].values[i]) == one.final_exponents
    # backward whirl at 0.065, B1,d at 0.1, forward rub at 0.15
    assert a.exponents[0, 1:].tolist() == [-math.inf] * 3
    lyapunov_scan(REF, "gamma", VALUES, out=tmp_path / "b.nc", n_jobs=2, **kw)
    assert (tmp_path / "a.nc").read_bytes() == (tmp_path / "b.nc").read_bytes()
    xr.testing.assert_identical(xr.load_dataset(tmp_path / "a.nc", engine="scipy"), a.dataset)
    assert not chunk_folder(tmp_path / "a.nc").exists()
    again = lyapunov_scan(REF, "gamma", VALUES, out=tmp_path / "a.nc", **kw)
    assert again.reused_file and np.array_equal(again.exponents, a.exponents)


def test_bad_input():
    with pytest.raises(ParameterError):
        lyapunov_scan(REF, "gamma", [0.1], t_end=100.0, t_transient=100.0, progress=False)
    with pytest.raises(ParameterError):
        lyapunov_scan(REF, "nonsense", [0.1], t_end=100.0, progress=False)
    with pytest.raises(ParameterError):
        lyapunov_scan(REF, "gamma", [0.1], u0=complex(math.nan, 0), t_end=100.0, progress=False)


@pytest.mark.parametrize("start, match", [(dict(u0=3), "^u0 = .* lies outside the clearance"),
                                          (dict(du0=1e9), "^du0 = .* is too fast")])
def test_a_start_state_that_simulate_refuses_is_refused_before_any_run(start, match, tmp_path):
    with pytest.raises(ParameterError, match=match):
        lyapunov_scan(REF, "gamma", [0.1], t_end=30.0, progress=False, out=tmp_path / "l.nc", **start)
    assert not (tmp_path / "l.nc").exists() and not chunk_folder(tmp_path / "l.nc").exists()


def test_params_that_are_not_the_machines_are_refused():
    from rotorcontact import reference_machine

    m = reference_machine()
    with pytest.raises(ParameterError, match=r"^params are not the machine's \(omega = "):
        lyapunov_scan(m.parameters().replace(omega=0.5), "gamma", [0.1], machine=m, progress=False)


def test_the_final_regime_flags_cover_every_code_it_holds():
    # -1 (unsettled) is a code of the variable: CF flag_values name it too
    ds = lyapunov_scan(REF, "gamma", [0.1], t_end=200.0, progress=False).dataset
    attrs = ds["final_regime"].attrs
    flags = dict(zip(attrs["flag_values"].tolist(), attrs["flag_meanings"].split()))
    assert flags == {-1: "unsettled", **{i: name for i, name in enumerate(FINAL_NAMES)}}
    assert set(ds["final_regime"].values.tolist()) <= set(flags)
