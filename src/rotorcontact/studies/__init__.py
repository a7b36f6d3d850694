"""Studies of many simulations: the compiled batch kernel, chunked and resumable execution (in
process, joblib, Dask), brute-force sweeps, basins of attraction and design maps."""
