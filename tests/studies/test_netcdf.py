"""NetCDF helpers: atomic writes with ordinary permissions, finished files recognised by their digest."""

from __future__ import annotations

import os
import stat

import pytest
import xarray as xr

from rotorcontact.errors import ParameterError
from rotorcontact.studies.netcdf import check_output_folder, check_output_path, read_finished, write_netcdf


def test_a_written_file_is_read_back_only_for_its_own_study(tmp_path):
    ds = xr.Dataset({"a": ("x", [1.0, 2.0])}, attrs={"study_digest": "abc"})
    out = write_netcdf(ds, tmp_path / "f.nc")
    assert out == tmp_path / "f.nc"
    back = read_finished(out, "abc")
    assert back is not None and back["a"].values.tolist() == [1.0, 2.0]
    assert read_finished(out, "other") is None
    assert read_finished(tmp_path / "missing.nc", "abc") is None
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".part")]


def test_written_files_get_the_permissions_of_an_ordinary_new_file(tmp_path):
    mask = os.umask(0o022)
    try:
        out = write_netcdf(xr.Dataset({"a": ("x", [1.0])}), tmp_path / "f.nc")
    finally:
        os.umask(mask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o644


def test_an_unreadable_file_is_not_a_finished_study(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text("not netcdf")
    assert read_finished(bad, "abc") is None


def test_output_paths_are_checked(tmp_path):
    with pytest.raises(ParameterError, match=r"^out = .* must end in .nc"):
        check_output_path(tmp_path / "f.txt")
    (tmp_path / "d.nc").mkdir()
    with pytest.raises(ParameterError, match=r"^out = .* is a folder"):
        check_output_path(tmp_path / "d.nc")
    with pytest.raises(ParameterError, match=r"^path = .* does not exist"):
        check_output_folder(tmp_path / "missing" / "f.nc")
    (tmp_path / "file").write_text("")
    with pytest.raises(ParameterError, match=r"^path = .* is not a folder"):
        check_output_folder(tmp_path / "file" / "f.nc")
    for bad in (None, 5, "", "a\0b.nc"):
        with pytest.raises(ParameterError, match=r"^path = .* is not a path"):
            check_output_folder(bad)
        with pytest.raises(ParameterError, match=r"^out = .* is not a path"):
            write_netcdf(xr.Dataset(), bad)
    for bad in (None, {"a": 1}):
        with pytest.raises(ParameterError, match=r"^ds = .* is not a Dataset object"):
            write_netcdf(bad, tmp_path / "f.nc")
    with pytest.raises(ParameterError, match=r"^digest = None is invalid"):
        read_finished(tmp_path / "f.nc", None)


def test_a_folder_gets_the_permissions_of_an_ordinary_new_folder(tmp_path):
    import tempfile

    from rotorcontact.studies.netcdf import umask_permissions

    folder = tempfile.mkdtemp(dir=tmp_path)
    mask = os.umask(0o022)
    try:
        umask_permissions(folder)
    finally:
        os.umask(mask)
    assert stat.S_IMODE(os.stat(folder).st_mode) == 0o755  # searchable: the execute bits kept
