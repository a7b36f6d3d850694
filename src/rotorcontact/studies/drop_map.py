"""The drop map: drops of one machine over a grid of speeds (and friction coefficients), as a chunked study.

Each grid point is `rotorcontact.simulation.drop_run.drop` at that speed and friction; the map records
the regime after the drop, the onset of backward whirl, the peak normal impulse, the energy dissipated,
the final spin and the number of impacts; a drop that fails has the regime ``"failed"``, nan as its onset,
impulse, energy and final spin (what it reached is no outcome) and the impacts before the failure. It runs
on `rotorcontact.studies.driver.run_study` (in process, joblib or Dask; resumable NetCDF); every point is
independent, so the result does not depend on the executor or the chunk size.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.params import Machine, check_range
from ..model.units import RPM
from ..model.validation import check_length, check_machine
from ..simulation.drop_run import MAX_T_END, check_drop_speed, check_failure_before_end, drop
from .datasets import check_dataset, study_dataset
from .driver import StudyRun, run_study
from .. import __version__
from .execution import check_chunk_size, study_digest

__all__ = ["REGIMES", "FAILED", "DropTask", "drop_map", "failed_points"]

#: Most speeds, and most friction coefficients, of a drop map (as ``rotorcontact drop-map --n``): each
#: point is a whole drop.
MAX_DROP_POINTS = 10_000
#: Regime codes of the map, in the order of their codes 0, 1, 2, ... (`DropResult.regime`).
REGIMES = ("levitated", "bouncing", "contact", "backward-whirl", "failed")
#: Code of the drops that failed.
FAILED = REGIMES.index("failed")
_FIELDS = ("regime", "backward_whirl_onset_s", "max_normal_impulse_Ns", "energy_dissipated_J", "final_spin_rpm",
           "n_impacts")
#: Attributes of the map's variables in its file: (long_name, units).
_ATTRS = {
    "regime": ("regime after the drop (codes into the attribute regimes)", "1"),
    "backward_whirl_onset_s": ("onset of backward whirl (nan: none)", "s"),
    "max_normal_impulse_Ns": ("largest normal impulse of an impact (compliant: of a contact episode)", "N s"),
    "energy_dissipated_J": ("energy dissipated", "J"),
    "final_spin_rpm": ("spin speed at the end", "rpm"),
    "n_impacts": ("impacts", "1"),
}
#: Variables that are whole numbers at every point (a failed drop included).
_COUNTS = ("regime", "n_impacts")


@dataclass(frozen=True)
class DropTask:
    """A chunk of the drop map: the drops at a list of (speed, friction) points."""

    key: str
    machine: dict[str, float] = field(repr=False)
    speeds: np.ndarray = field(repr=False)
    frictions: np.ndarray = field(repr=False)
    fail_at: float
    t_end: float

    @property
    def n_items(self) -> int:
        return int(self.speeds.size)

    def compute(self, parallel: bool = False) -> dict[str, np.ndarray]:
        """The map's fields at each point (``parallel`` is unused: one drop is one sequential kernel call)."""
        out = {name: np.full(self.speeds.size, np.nan) for name in _FIELDS}
        for i, (speed, mu) in enumerate(zip(self.speeds, self.frictions)):
            r = drop(Machine(**{**self.machine, "friction": float(mu)}), float(speed), self.fail_at, self.t_end)
            s = r.to_dict()["summary"]
            out["regime"][i] = REGIMES.index(s["regime"])
            out["n_impacts"][i] = len(r.impacts)
            if s["regime"] == "failed":
                continue  # what it reached is no outcome: nan
            out["backward_whirl_onset_s"][i] = np.nan if s["backward_whirl_onset_s"] is None \
                else s["backward_whirl_onset_s"]
            out["max_normal_impulse_Ns"][i] = 0.0 if s["max_normal_impulse_Ns"] is None else s["max_normal_impulse_Ns"]
            out["energy_dissipated_J"][i] = s["energy_dissipated_J"]
            out["final_spin_rpm"][i] = s["final_spin_rpm"]
        return out


def drop_map(machine: Machine, speeds, frictions=None, *, fail_at: float = 0.0, t_end: float = 2.0,
             chunk_size: int = 16, out: str | Path | None = None, resume: bool = True, n_jobs: int | None = None,
             scheduler: Any = None, processes: bool = True, progress: bool = False) -> StudyRun:
    """Drops of ``machine`` at each speed (rad/s) and friction coefficient: an xarray Dataset on (friction, speed).

    Parameters
    ----------
    machine : Machine
    speeds : array_like
        Spin speeds at the start: numbers in rad/s (> 0), or strings with units (``"12000 rpm"``).
    frictions : array_like, optional
        Friction coefficients (default: the machine's).
    fail_at, t_end : float
        Failure and final time of each drop, s (``fail_at >= 0``, ``0 < t_end <=`` `MAX_T_END`).
    chunk_size : int
        Drops per chunk.
    out, resume, n_jobs, scheduler, processes, progress
        As for `rotorcontact.studies.driver.run_study`.

    Returns
    -------
    StudyRun
        Its dataset has the variables ``regime`` (codes into `REGIMES`, listed in the attribute
        ``regimes``), ``backward_whirl_onset_s`` (nan: none), ``max_normal_impulse_Ns``,
        ``energy_dissipated_J``, ``final_spin_rpm`` and ``n_impacts``; at a drop that failed, the regime
        is ``"failed"`` (`failed_points`), ``n_impacts`` counts the impacts before the failure and the
        other variables are nan.

    Raises
    ------
    ParameterError
        For a bad argument, before any drop: each speed is checked by
        `rotorcontact.simulation.drop_run.check_drop_speed` (named ``speeds[i]``), each friction
        coefficient must be >= 0 (``frictions[i]``).
    """
    check_machine(machine, optional=False)
    check_length("speeds", speeds, MAX_DROP_POINTS)
    check_length("frictions", frictions, MAX_DROP_POINTS)
    speeds = np.atleast_1d(np.asarray(speeds, dtype=object))
    frictions = np.atleast_1d(np.asarray([machine.friction] if frictions is None else frictions, dtype=object))
    if speeds.ndim != 1 or speeds.size == 0 or frictions.ndim != 1 or frictions.size == 0:
        raise ParameterError("speeds and frictions must be non-empty lists of numbers")
    speeds = np.array([check_drop_speed(machine, v, f"speeds[{i}]") for i, v in enumerate(speeds)])
    frictions = np.array([check_range(f"frictions[{i}]", v, low=0.0) for i, v in enumerate(frictions)])
    fail_at = check_range("fail_at", fail_at, low=0.0)
    t_end = check_range("t_end", t_end, low=0.0, high=MAX_T_END, low_open=True)
    check_failure_before_end(fail_at, t_end)
    chunk_size = check_chunk_size(chunk_size)
    grid_mu, grid_speed = np.meshgrid(frictions, speeds, indexing="ij")
    flat_speed, flat_mu = grid_speed.ravel(), grid_mu.ravel()
    n = flat_speed.size
    manifest = {"study": "drop-map", "machine": machine.as_dict(), "speeds": speeds.tolist(),
                "frictions": frictions.tolist(), "fail_at": fail_at, "t_end": t_end, "regimes": list(REGIMES)}

    def keys(size: int) -> list[str]:
        return [f"drops-{i:06d}" for i in range(0, n, size)]

    def waves(size: int, _sink):
        yield [DropTask(key, machine.as_dict(), flat_speed[i:i + size], flat_mu[i:i + size], fail_at, t_end)
               for key, i in zip(keys(size), range(0, n, size))]

    def assemble(size: int, load):
        import xarray as xr

        parts = [load(k) for k in keys(size)]
        data = {name: np.concatenate([p[name] for p in parts]).reshape(grid_speed.shape) for name in _FIELDS}
        ds = xr.Dataset(
            {name: (("friction", "speed_rpm"), data[name].astype(np.int32) if name in _COUNTS else data[name],
                    {"long_name": _ATTRS[name][0], "units": _ATTRS[name][1]}) for name in _FIELDS},
            coords={"friction": frictions, "speed_rpm": speeds / RPM},
        )
        ds["speed_rpm"].attrs.update(long_name="spin speed at the start", units="rpm")
        ds["friction"].attrs.update(long_name="friction coefficient", units="1")
        ds.attrs.update({"regimes": ",".join(REGIMES), "fail_at_s": fail_at, "t_end_s": t_end,
                         "chunk_size": size})
        ds.attrs.update({f"machine_{k}": v for k, v in machine.as_dict().items()})
        return ds, int(data["n_impacts"].sum())

    # the finished file depends on the version too: a file of another version is computed again
    digest = study_digest({**manifest, "version": __version__})
    return run_study(manifest, digest, keys=keys, waves=waves, assemble=assemble, n_items=n,
                     desc="drop-map", chunk_size=chunk_size, out=out, resume=resume, n_jobs=n_jobs,
                     scheduler=scheduler, processes=processes, progress=progress)


def failed_points(ds) -> list[tuple[float, float]]:
    """The (speed in rpm, friction) of each drop of a drop map's dataset that failed, in grid order.

    Raises
    ------
    ParameterError
        For ``ds`` that is not a drop map's Dataset (or the `drop_map` result holding it).
    """
    ds = check_dataset(study_dataset(ds), ("regime", "speed_rpm", "friction"), "drop_map")
    rows, cols = np.nonzero(ds["regime"].values.astype(int) == FAILED)
    return [(float(ds["speed_rpm"].values[j]), float(ds["friction"].values[i])) for i, j in zip(rows, cols)]
