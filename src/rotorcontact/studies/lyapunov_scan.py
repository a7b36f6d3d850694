"""The Lyapunov spectrum against a parameter, on the chunked, resumable, parallel study driver.

At each value of one parameter (a model parameter, or with a machine a machine quantity in SI units;
`rotorcontact.studies.attractors.parameter_path`) the rotor is simulated from the same initial state and
`rotorcontact.analysis.lyapunov.lyapunov_spectrum` computes the spectrum with its error estimates and the
final regime of the run (a change of regime inside the averaging window is flagged). The values are cut
into chunks of `SpectrumTask` run by `rotorcontact.studies.driver.run_study`: in this process, in joblib
workers or on Dask, with identical results, written chunk by chunk so that an interrupted scan resumes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..errors import ParameterError
from ..model.params import Machine, Parameters, check_range
from ..model.validation import check_machine, check_params
from ..simulation.motion import REGIME_NAMES
from ..simulation.simulator import check_start
from .batch import PARAMETER_ORDER, parameter_array
from .driver import run_study
from .execution import check_chunk_size, study_digest
from .parameter_path import parameter_path, path_values

__all__ = ["FINAL_NAMES", "LyapunovScan", "SpectrumTask", "lyapunov_scan"]

#: Codes of the final regime stored in the dataset (-1: none, the run ends unsettled).
FINAL_NAMES = ("contact", "no-contact", "periodic")
DEFAULT_CHUNK = 4
DIM = 4


@dataclass(frozen=True)
class SpectrumTask:
    """A chunk of a Lyapunov scan: the spectra of a few parameter values.

    Attributes
    ----------
    key : str
        Name of the chunk.
    params : numpy.ndarray
        (n, 7) parameter rows (`rotorcontact.studies.batch.PARAMETER_ORDER`).
    u0, du0 : numpy.ndarray
        (n,) complex initial states, one per row.
    t_end, t_transient, qr_interval : float
        As for `rotorcontact.analysis.lyapunov.lyapunov_spectrum`.
    progress_items : int or None
        What the chunk counts for on a progress bar (default: its number of runs).
    """

    key: str
    params: np.ndarray = field(repr=False)
    u0: np.ndarray = field(repr=False)
    du0: np.ndarray = field(repr=False)
    t_end: float
    t_transient: float
    qr_interval: float
    progress_items: int | None = None

    @property
    def n_items(self) -> int:
        """What the chunk counts for on a progress bar: its number of runs unless ``progress_items`` is given."""
        return int(self.params.shape[0]) if self.progress_items is None else int(self.progress_items)

    def compute(self, parallel: bool = False) -> dict[str, np.ndarray]:
        """The spectra of the chunk as arrays (NaN rows and ``failed`` 1 where a run could not be made)."""
        from ..analysis.lyapunov import lyapunov_spectrum

        n = int(self.params.shape[0])
        out = {
            "exponents": np.full((n, DIM), np.nan), "errors": np.full((n, DIM), np.nan),
            "final_exponents": np.full((n, DIM), np.nan), "final_errors": np.full((n, DIM), np.nan),
            "regime_start": np.full(n, np.nan), "final_regime": np.full(n, -1, dtype=np.int32),
            "regime_change": np.zeros(n, dtype=np.int8), "regime": np.full(n, -1, dtype=np.int32),
            "failed": np.zeros(n, dtype=np.int8), "n_impacts": np.zeros(n, dtype=np.int64),
            "transient_impacts": np.zeros(n, dtype=np.int64), "collapsed": np.zeros(n, dtype=np.int32),
        }
        for i, row in enumerate(self.params):
            p = Parameters(**{name: float(v) for name, v in zip(PARAMETER_ORDER, row)})
            try:
                res = lyapunov_spectrum(p, complex(self.u0[i]), complex(self.du0[i]), self.t_end,
                                        t_transient=self.t_transient, qr_interval=self.qr_interval)
            except (RuntimeError, ParameterError):
                # a failed simulation, or an end state of a batch run just outside the clearance by rounding
                out["failed"][i] = 1
                continue
            out["exponents"][i] = res.exponents
            out["errors"][i] = res.errors
            out["collapsed"][i] = res.collapsed
            out["n_impacts"][i] = res.n_impacts
            out["transient_impacts"][i] = len(res.trajectory.impacts) - res.n_impacts
            regime = res.trajectory.summary.regime
            out["regime"][i] = REGIME_NAMES.index(regime) if regime in REGIME_NAMES else -1
            out["regime_change"][i] = int(res.regime_change)
            if res.final_regime is not None:
                out["final_regime"][i] = FINAL_NAMES.index(res.final_regime)
                out["regime_start"][i] = res.regime_start
            if res.final_exponents is not None:
                out["final_exponents"][i] = res.final_exponents
                out["final_errors"][i] = res.final_errors
        return out


@dataclass(frozen=True)
class LyapunovScan:
    """The Lyapunov spectrum against a parameter.

    Attributes
    ----------
    dataset : xarray.Dataset
        Per value: ``exponents`` and ``errors`` (value, index; -inf for annihilated directions),
        ``regime_change``, ``final_regime`` (code into `FINAL_NAMES`, -1 none), ``regime_start``,
        ``final_exponents``, ``final_errors``, ``regime`` (of the run, `rotorcontact.simulation.motion.REGIME_NAMES`),
        ``failed``.
    param : str
        The parameter.
    values : numpy.ndarray
        Its values.
    path : pathlib.Path or None
        The NetCDF file written.
    chunks_computed, chunks_reused, impacts_simulated, reused_file
        As for the other studies.
    """

    dataset: Any = field(repr=False)
    param: str
    values: np.ndarray = field(repr=False)
    path: Path | None
    chunks_computed: int
    chunks_reused: int
    impacts_simulated: int
    reused_file: bool = False

    @property
    def exponents(self) -> np.ndarray:
        """(values, 4) exponents, largest first."""
        return self.dataset["exponents"].values

    @property
    def errors(self) -> np.ndarray:
        """(values, 4) error estimates."""
        return self.dataset["errors"].values

    @property
    def regime_change(self) -> np.ndarray:
        """Where the run changed regime inside the averaging window."""
        return self.dataset["regime_change"].values.astype(bool)


def lyapunov_scan(
    params: Parameters,
    param: str,
    values: Any,
    *,
    u0: complex = 0j,
    du0: complex = 0j,
    t_end: float = 2000.0,
    t_transient: float | None = None,
    qr_interval: float = 1.0,
    chunk_size: int = DEFAULT_CHUNK,
    n_jobs: int | None = None,
    scheduler: Any = None,
    processes: bool = True,
    out: str | Path | None = None,
    resume: bool = True,
    keep_chunks: bool = False,
    progress: bool = True,
    machine: Machine | None = None,
) -> LyapunovScan:
    """The Lyapunov spectrum at each value of one parameter (module docstring).

    Parameters
    ----------
    params : Parameters
        The other parameters.
    param : str
        A model parameter, or with ``machine`` a machine quantity (values in SI units).
    values : array_like
        Its values.
    u0, du0 : complex
        Initial state of every run.
    t_end, t_transient, qr_interval
        As for `rotorcontact.analysis.lyapunov.lyapunov_spectrum` (``t_transient`` defaults to a
        quarter of ``t_end``).
    chunk_size : int
        Values per chunk.
    n_jobs, scheduler, processes, out, resume, keep_chunks, progress, machine
        As for `rotorcontact.studies.basins.basins`.

    Returns
    -------
    LyapunovScan
    """
    check_machine(machine)
    from ..analysis.lyapunov import MAX_T_END, _check_options

    check_params(params)
    vals = path_values(param, values)
    path = parameter_path(params, param, vals, machine)
    t_end = check_range("t_end", t_end, low=0.0, high=MAX_T_END, low_open=True)
    if t_transient is None:
        t_transient = 0.25 * t_end
    t_transient, qr_interval = _check_options(t_transient, qr_interval, t_end)
    if t_transient >= t_end:
        raise ParameterError(f"t_transient = {t_transient!r} is not below t_end = {t_end!r}; allowed: [0, t_end)")
    u0, du0 = check_start(u0, du0)
    chunk_size = check_chunk_size(chunk_size)
    rows = parameter_array(path)
    manifest = {"study": "lyapunov-scan", "param": param, "values": vals, "rows": rows,
                "u0": [u0.real, u0.imag], "du0": [du0.real, du0.imag], "t_end": t_end,
                "t_transient": t_transient, "qr_interval": qr_interval}
    digest = study_digest({**manifest, "version": __version__,
                           "machine": None if machine is None else machine.as_dict()})
    n = vals.size

    def keys(size: int) -> list[str]:
        return [f"spectra-{c:06d}" for c in range(math.ceil(n / size))]

    def waves(size: int, sink):
        tasks = []
        for c, key in enumerate(keys(size)):
            block = rows[c * size : (c + 1) * size].copy()
            m = block.shape[0]
            tasks.append(SpectrumTask(key=key, params=block, u0=np.full(m, u0), du0=np.full(m, du0), t_end=t_end,
                                      t_transient=t_transient, qr_interval=qr_interval))
        yield tasks

    def assemble(size: int, load):
        parts = [load(key) for key in keys(size)]
        arrays = {name: np.concatenate([p[name] for p in parts]) for name in parts[0]}
        ds = _dataset(arrays, param, vals, path, params, machine, size, u0, du0, t_end, t_transient, qr_interval)
        return ds, int(arrays["n_impacts"].sum() + arrays["transient_impacts"].sum())

    run = run_study(manifest, digest, keys=keys, waves=waves, assemble=assemble, n_items=n, desc="lyapunov",
                    chunk_size=chunk_size, out=out, resume=resume, keep_chunks=keep_chunks, n_jobs=n_jobs,
                    scheduler=scheduler, processes=processes, progress=progress)
    return LyapunovScan(dataset=run.dataset, param=param, values=vals, path=run.path,
                        chunks_computed=run.chunks_computed, chunks_reused=run.chunks_reused,
                        impacts_simulated=run.impacts_simulated, reused_file=run.reused_file)


def _dataset(a, param, vals, path, params, machine, chunk_size, u0, du0, t_end, t_transient, qr_interval):
    import xarray as xr

    from .attributes import parameter_attrs

    two = ("value", "index")
    data = {
        "exponents": (two, a["exponents"], {"long_name": "Lyapunov exponents, largest first (-inf: annihilated)",
                                            "units": "1"}),
        "errors": (two, a["errors"], {"long_name": "error estimates of the exponents (spread over sub-windows)",
                                      "units": "1"}),
        "final_exponents": (two, a["final_exponents"],
                            {"long_name": "exponents of the final regime alone (NaN: unsettled run)", "units": "1"}),
        "final_errors": (two, a["final_errors"], {"long_name": "error estimates of the final regime's exponents",
                                                  "units": "1"}),
        "regime_change": (("value",), a["regime_change"],
                          {"long_name": "the run settled on its final regime inside the averaging window"}),
        "final_regime": (("value",), a["final_regime"], {
            "long_name": "final regime of the run", "flag_values": np.arange(-1, len(FINAL_NAMES), dtype=np.int32),
            "flag_meanings": " ".join(("unsettled",) + tuple(FINAL_NAMES))}),
        "regime_start": (("value",), a["regime_start"],
                         {"long_name": "time at which the final regime began (NaN: unsettled)", "units": "1"}),
        "regime": (("value",), a["regime"], {
            "long_name": "regime of the run", "flag_values": np.arange(len(REGIME_NAMES), dtype=np.int32),
            "flag_meanings": " ".join(REGIME_NAMES)}),
        "collapsed": (("value",), a["collapsed"], {"long_name": "annihilated directions"}),
        "failed": (("value",), a["failed"], {"long_name": "the simulation failed (exponents NaN)"}),
        "n_impacts": (("value",), a["n_impacts"].astype(np.int32), {"long_name": "impacts in the averaging window"}),
        "transient_impacts": (("value",), a["transient_impacts"].astype(np.int32),
                              {"long_name": "impacts before the averaging window"}),
    }
    for name in PARAMETER_ORDER:
        data[f"param_{name}"] = (("value",), np.array([getattr(p, name) for p in path]),
                                 {"long_name": f"model parameter {name} at each value"})
    unit = "1" if param in PARAMETER_ORDER or machine is None else Machine.units()[param]
    coords = {"value": ("value", vals, {"long_name": param, "units": unit}), "index": ("index", np.arange(DIM))}
    attrs: dict[str, Any] = {
        "title": "Lyapunov spectrum against a parameter",
        "source": f"rotorcontact {__version__}",
        "param": param,
        "coordinates_of_state": "Re U, Im U, Re U', Im U'",
        "u0_re": u0.real, "u0_im": u0.imag, "du0_re": du0.real, "du0_im": du0.imag,
        "t_end": float(t_end), "t_transient": float(t_transient), "qr_interval": float(qr_interval),
        "chunk_size": np.int32(chunk_size),
    }
    attrs.update(parameter_attrs(params, skip=param if param in PARAMETER_ORDER else None, machine=machine))
    return xr.Dataset(data, coords=coords, attrs=attrs)
