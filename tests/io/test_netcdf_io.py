"""The io layer's NetCDF helpers are those the studies write their files with."""

from __future__ import annotations

import rotorcontact.io.netcdf as io_netcdf
import rotorcontact.studies.netcdf as studies_netcdf


def test_the_io_layer_offers_the_studies_netcdf_helpers():
    for name in io_netcdf.__all__:
        assert getattr(io_netcdf, name) is getattr(studies_netcdf, name)
