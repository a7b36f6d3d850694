"""NetCDF files of the studies: checked paths, atomic writes, finished files read back.

The layers above the studies take these from `rotorcontact.io.netcdf`.

A file is written through a temporary file in the same folder and renamed into
place, so that an interrupted write never leaves a partial file under the
final name; it gets the permissions of an ordinary new file (0666 less the
umask). A study records its `rotorcontact.studies.execution.study_digest` as
the attribute ``study_digest``, by which `read_finished` recognises it.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from ..errors import ParameterError

__all__ = ["write_netcdf", "read_finished", "check_output_path", "check_output_folder", "umask_permissions"]


def umask_permissions(path: str | Path) -> None:
    """Give a file made by `tempfile.mkstemp` (mode 0600) the permissions of an ordinary new file (0666 & ~umask),
    or a folder made by `tempfile.mkdtemp` (mode 0700) those of an ordinary new folder (0777 & ~umask)."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(path, (0o777 if os.path.isdir(path) else 0o666) & ~mask)


def write_netcdf(ds, out: str | Path) -> Path:
    """Write an xarray Dataset to NetCDF (netCDF3 64-bit offset through scipy), atomically.

    The folder must exist (`ParameterError` otherwise). The file gets the
    permissions of an ordinary new file (0666 less the umask, usually 0644).

    Parameters
    ----------
    ds : xarray.Dataset
        The data.
    out : path
        The ``.nc`` file.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    ParameterError
        For ``ds`` that is not an xarray Dataset, or an ``out`` that `check_output_path` refuses.
    """
    import xarray as xr

    from ..model.validation import check_type

    check_type("ds", ds, xr.Dataset, "an xarray.Dataset")
    out = check_output_path(out)
    fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".part", dir=out.parent)
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="scipy", format="NETCDF3_64BIT")
        umask_permissions(tmp)
        os.replace(tmp, out)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return out


def read_finished(out: str | Path, digest: str):
    """The dataset in the NetCDF file ``out`` when it is the finished result of the study ``digest``.

    A study writes its `rotorcontact.studies.execution.study_digest` into its
    file as the attribute ``study_digest``; running the same study again can
    then return the file instead of computing it afresh.

    Parameters
    ----------
    out : path
        The file.
    digest : str
        The study's digest.

    Returns
    -------
    xarray.Dataset or None
        None when the file is missing, unreadable or of another study.

    Raises
    ------
    ParameterError
        For an ``out`` that is not a path, or a ``digest`` that is not text.
    """
    from ..model.validation import check_path

    out = check_path("out", out)
    if not isinstance(digest, str) or not digest:
        raise ParameterError(f"digest = {digest!r} is invalid; allowed: a study's digest (text, study_digest)")
    if not out.is_file():
        return None
    import xarray as xr

    try:
        ds = xr.load_dataset(out, engine="scipy")
    except (OSError, ValueError, TypeError):
        return None
    return ds if ds.attrs.get("study_digest") == digest else None


def check_output_path(out: str | Path) -> Path:
    """Check that ``out`` is a ``.nc`` path in an existing folder.

    Raises
    ------
    ParameterError
        For another suffix, a folder in its place, or a folder that is missing
        or is a file (folders are not created: make them first).
    """
    from ..model.validation import check_path  # here: the command line's --help does not import numpy

    out = check_path("out", out)
    if out.suffix.lower() != ".nc":
        raise ParameterError(f"out = {str(out)!r} is invalid: the output file must end in .nc; allowed: a NetCDF "
                             "file name, such as 'result.nc'")
    if out.exists() and out.is_dir():
        raise ParameterError(f"out = {str(out)!r} is a folder; allowed: a file in an existing folder")
    check_output_folder(out, "out")
    return out


def check_output_folder(path: str | Path, name: str = "path") -> None:
    """Check that the folder of the output file ``path`` exists (`ParameterError` naming ``name`` otherwise)."""
    from ..model.validation import check_path  # here: the command line's --help does not import numpy

    parent = check_path(name, path).parent
    if not parent.exists():
        raise ParameterError(f"{name} = {str(path)!r} is invalid: its folder {str(parent)!r} does not exist; "
                             "allowed: a file in an existing folder (create it first)")
    if not parent.is_dir():
        raise ParameterError(f"{name} = {str(path)!r} is invalid: {str(parent)!r} is not a folder; allowed: a file "
                             "in an existing folder")
