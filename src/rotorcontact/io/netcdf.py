"""NetCDF files: checked output paths, atomic writes with ordinary permissions, finished studies read back.

The studies write their files themselves, so these helpers are defined in the
studies layer (`rotorcontact.studies.netcdf`); this is where the layers above
it (figures, reports, the command line) take them from.
"""

from __future__ import annotations

from ..studies.netcdf import check_output_folder, check_output_path, read_finished, umask_permissions, write_netcdf

__all__ = ["write_netcdf", "read_finished", "check_output_path", "check_output_folder", "umask_permissions"]
