"""Reading and writing results: NetCDF files of the studies and JSON data."""
