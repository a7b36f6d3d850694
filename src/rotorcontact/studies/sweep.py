"""Brute-force orbit diagrams: the impact section against a parameter, with hysteresis.

For each value of the swept parameter the rotor is simulated through a
transient and a recorded window (`rotorcontact.studies.batch`); the impacts of the
window (angle theta, rdot- and thetadot- just before each impact) make the
diagram. Sweeping *up* runs the values in increasing order and *down* in
decreasing order, each value starting from the state where the previous one
ended, so that coexisting attractors show as hysteresis between the two
directions. Mode ``"independent"`` starts every value afresh from the start
state (taken at that value) instead.

The work is cut into chunks of consecutive values (`rotorcontact.studies.execution`),
run in this process, by joblib or on a Dask cluster, with identical results.
With an output file every finished chunk is written at once to a folder beside
it (``FILE.nc.chunks``); an interrupted sweep started again with the same
arguments continues from the chunks found there, and the folder is merged
into the NetCDF file at the end.

The result is an xarray Dataset: the sections (``theta``, ``rdot``,
``thetadot``, ``t``) over (direction, parameter value, impact) and, per
direction and value, the regime of the window, the impacts per period and
period of periodic motion, counts, contact time and the final state. The
model parameters, the settings and the units are attributes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .. import __version__
from ..errors import ParameterError
from ..model.params import BRANCH_PARAMETERS, Machine, Parameters, check_finite
from ..model.validation import (check_choice, check_int, check_length, check_machine, check_machine_params,
                                check_params, real_array)
from .attributes import (
    PARAMETER_LONG_NAMES,
    PARAMETER_UNITS,
    RATE_UNITS,
    parameter_attrs,
    settings_attrs,
    summary_variables,
)
from .batch import (
    NSUM,
    PARAMETER_ORDER,
    REGIME_NAMES,
    S_DU_IM,
    S_DU_RE,
    S_U_IM,
    S_U_RE,
    BatchResult,
    BatchSettings,
    check_batch_settings,
    parameter_array,
)
from .driver import run_study
from .execution import ChunkTask, backend_manifest, check_chunk_size, study_digest
from .grids import MAX_GRID_POINTS

__all__ = [
    "SWEEP_PARAMETERS",
    "MODES",
    "SweepResult",
    "sweep",
    "sweep_values",
    "start_state",
    "one_impact_overlay",
    "continued_branches",
    "overlay_for",
    "PARAMETER_UNITS",
]

#: Parameters a sweep may vary.
SWEEP_PARAMETERS = PARAMETER_ORDER
#: Sweep modes and the directions they run.
MODES = {"both": ("up", "down"), "up": ("up",), "down": ("down",), "independent": ("independent",)}
DEFAULT_CHUNK_CARRY = 20
DEFAULT_CHUNK_INDEPENDENT = 64

SECTION_ATTRS = {
    "t": dict(long_name="time of the impact since the start of the recorded window", units="1",
              description="dimensionless time t = Omega tau"),
    "theta": dict(long_name="impact angle in the co-rotating frame", units="rad"),
    "rdot": dict(long_name="radial velocity just before the impact", units="1",
                 description="clearances per unit of dimensionless time"),
    "thetadot": dict(long_name="angular velocity just before the impact (co-rotating)", **RATE_UNITS),
}


def sweep_values(start: float, stop: float, n: int) -> np.ndarray:
    """``n`` equally spaced values from ``start`` to ``stop`` (both included; one value needs start = stop)."""
    start = check_finite("start", start)
    stop = check_finite("stop", stop)
    n = check_int("n", n, 1, MAX_GRID_POINTS)
    if not math.isfinite(stop - start):
        raise ParameterError(f"start = {start!r} to stop = {stop!r} spans more than the largest float")
    if n > 1 and not start < stop:
        raise ParameterError(f"start = {start!r} must be smaller than stop = {stop!r}")
    if n == 1 and start != stop:
        raise ParameterError(f"n = 1 is a single value, but start = {start!r} and stop = {stop!r} differ; allowed: "
                             "n >= 2, or start = stop")
    return np.linspace(start, stop, int(n))


def _check_values(param: str, values: Any) -> np.ndarray:
    check_length(f"values of {param!r}", values, MAX_GRID_POINTS)
    vals = real_array(values)
    if vals is None or vals.ndim > 1:
        raise ParameterError(f"values = {values!r} are not a list of real numbers; allowed: a 1-D list or array of "
                             "real numbers (not strings, bools or complex numbers)")
    vals = vals.reshape(-1)
    if vals.size == 0:
        raise ParameterError("values is empty; give at least one parameter value")
    if not np.all(np.isfinite(vals)):
        raise ParameterError(f"values of {param} must be finite")
    if vals.size > 1 and not np.all(np.diff(vals) > 0):
        raise ParameterError(f"values of {param} must increase strictly (the direction is set by mode)")
    return vals


def start_state(params: Parameters, start: str) -> tuple[complex, complex]:
    """Initial state named by ``start``.

    Parameters
    ----------
    params : Parameters
        Parameters at which the state is taken.
    start : str
        ``"rest"`` (U = U' = 0, the rotor centred and at rest), ``"equilibrium"``
        (the regular equilibrium x_R, U = k, U' = 0; it must be admissible) or
        the label of a one-impact orbit such as ``"B1,d"`` (the state just
        after its impact; it must exist and be admissible).

    Raises
    ------
    ParameterError
        If the state does not exist at these parameters.
    """
    if start == "rest":
        return 0j, 0j
    if start == "equilibrium":
        k = params.k
        if abs(k) >= 1.0:
            raise ParameterError(
                "start = 'equilibrium': the regular equilibrium is virtual at these parameters "
                f"(|k| = {abs(k):.6g} >= 1)"
            )
        return complex(k), 0j
    from ..maps.impact_map import admissible_orbits

    orbits = admissible_orbits(params, 12.0)
    for o in orbits:
        if o.label == start:
            u0, du0 = o.initial_condition()
            return complex(u0), complex(du0)
    avail = ", ".join(o.label for o in orbits) or "none"
    raise ParameterError(
        f"start = {start!r} is not available at {params}; allowed: 'rest', 'equilibrium' or an admissible "
        f"one-impact orbit ({avail})"
    )


@dataclass(frozen=True)
class SweepResult:
    """A brute-force diagram.

    Attributes
    ----------
    dataset : xarray.Dataset
        The diagram (see the module docstring).
    param : str
        The swept parameter.
    path : pathlib.Path or None
        The NetCDF file written, if any.
    chunks_computed, chunks_reused : int
        Chunks computed by this call, and finished chunks found from an
        earlier, interrupted call (or all chunks, when `reused_file`).
    impacts_simulated : int
        Impacts computed (transients and windows, including reused chunks).
    reused_file : bool
        The output file already held this finished study and was returned as it is.
    handed_to_cpu : int
        With ``backend="cuda"``: simulations of this call computed on the CPU because the GPU's summary of
        their window could not be exact (`rotorcontact.studies.compact_batch.compact_item`; in a carried
        chain, that step and the chain's later ones).
    """

    dataset: Any = field(repr=False)
    param: str
    path: Path | None
    chunks_computed: int
    chunks_reused: int
    impacts_simulated: int
    reused_file: bool = False
    handed_to_cpu: int = 0

    def regimes(self, direction: str) -> list[str]:
        """The regime at each value for one direction, as strings.

        Raises
        ------
        ParameterError
            If ``direction`` is not one of the sweep's directions.
        """
        check_choice("direction", direction, tuple(str(d) for d in self.dataset.direction.values))
        codes = self.dataset["regime"].sel(direction=direction).values
        return [REGIME_NAMES[int(c)] for c in codes]

    def regime_counts(self) -> dict[str, dict[str, int]]:
        """How many values end in each regime, per direction: ``{direction: {regime: count}}``, regimes sorted."""
        counts = {}
        for d in self.dataset.direction.values:
            names = self.regimes(str(d))
            counts[str(d)] = {name: names.count(name) for name in sorted(set(names))}
        return counts


def _lane_orders(directions: tuple[str, ...], n: int) -> list[np.ndarray]:
    return [np.arange(n)[::-1] if d == "down" else np.arange(n) for d in directions]


def sweep(
    params: Parameters,
    param: str,
    values: Any,
    *,
    mode: str = "both",
    start: str | None = None,
    u0: complex | None = None,
    du0: complex | None = None,
    settings: BatchSettings | None = None,
    n_transient: int = 4000,
    n_record: int = 1000,
    t_transient: float | None = None,
    t_record: float | None = None,
    chunk_size: int | None = None,
    n_jobs: int | None = None,
    scheduler: Any = None,
    processes: bool = True,
    backend: str = "cpu",
    out: str | Path | None = None,
    resume: bool = True,
    keep_chunks: bool = False,
    progress: bool = True,
    machine: Machine | None = None,
) -> SweepResult:
    """Brute-force orbit diagram of the impact section against one parameter.

    Parameters
    ----------
    params : Parameters
        The other parameters (the swept one is replaced by each value).
    param : str
        The swept parameter, one of `SWEEP_PARAMETERS` (gamma, omega, rho, mu, d, phi, r_ratio).
    values : array_like
        Strictly increasing values (see `sweep_values`).
    mode : {"both", "up", "down", "independent"}
        Directions with the state carried along from value to value, or
        every value from the start state.
    start : str, optional
        Initial state at the first value of each direction (`start_state`):
        ``"rest"`` (default), ``"equilibrium"`` or an orbit label such as ``"B1,d"``.
    u0, du0 : complex, optional
        An explicit initial state instead of ``start`` (not both).
    settings : BatchSettings, optional
        Transient and window; otherwise built from ``n_transient``,
        ``n_record``, ``t_transient`` and ``t_record`` (defaults: 4000 and
        1000 events, time limits 5 per event).
    chunk_size : int, optional
        Values per chunk (default 20 with the state carried, 64 otherwise, cut down on worker processes by
        `rotorcontact.studies.execution.fitted_chunk_size`).
        It sets where files are written, not the results; an interrupted run
        is resumed with the chunk size it was started with.
    n_jobs : int, optional
        Worker processes for joblib; None runs in this process over all
        cores; -1 uses one worker per core.
    scheduler : str or distributed.Client, optional
        Run on Dask: ``"local"`` (a LocalCluster of ``n_jobs`` workers, default
        one per core) or a scheduler address ``"tcp://host:port"``.
    processes : bool
        With ``scheduler="local"``: workers as processes (True) or threads.
    backend : {"cpu", "cuda"}
        ``"cuda"`` runs the simulations on this machine's NVIDIA GPU
        (`rotorcontact.studies.cuda_batch`; with neither ``n_jobs`` nor ``scheduler``).
    out : path, optional
        NetCDF file to write; chunks go to ``out + ".chunks"`` meanwhile.
    resume : bool
        Continue from the chunks of an interrupted run with the same
        arguments, and return ``out`` as it is when it already holds this
        finished sweep (default); False computes afresh.
    keep_chunks : bool
        Keep the chunk folder after the merge.
    progress : bool
        Show a progress bar on stderr.
    machine : Machine, optional
        The machine the parameters come from; its SI values and units are
        stored as attributes too.

    Returns
    -------
    SweepResult

    Raises
    ------
    ParameterError
        On invalid input.
    """
    check_params(params)
    check_machine(machine)
    if param not in SWEEP_PARAMETERS:
        raise ParameterError(f"param = {param!r} is invalid; allowed: {', '.join(SWEEP_PARAMETERS)}")
    check_machine_params(params, machine, skip=param)
    if not isinstance(mode, str) or mode not in MODES:
        raise ParameterError(f"mode = {mode!r} is invalid; allowed: {', '.join(MODES)}")
    vals = _check_values(param, values)
    settings = check_batch_settings(settings, vals.size * len(MODES[mode]), lambda: BatchSettings(
        n_transient=n_transient, n_record=n_record, t_transient=t_transient, t_record=t_record))
    carry = mode != "independent"
    fit_chunks = chunk_size is None and not carry  # a carried sweep's chunks of a direction run in turn
    if chunk_size is None:
        chunk_size = DEFAULT_CHUNK_CARRY if carry else DEFAULT_CHUNK_INDEPENDENT
    chunk_size = check_chunk_size(chunk_size)
    n = vals.size
    rows = parameter_array([params.replace(**{param: float(v)}) for v in vals])  # validates every value
    directions = MODES[mode]
    orders = _lane_orders(directions, n)

    # initial states: explicit, or named, at the first value of each direction
    if start is not None and (u0 is not None or du0 is not None):
        raise ParameterError(f"start = {start!r} and an explicit u0/du0 were both given; allowed: one of them")
    if u0 is not None or du0 is not None:
        from ..simulation.simulator import check_start

        z0, dz0 = check_start(0j if u0 is None else u0, 0j if du0 is None else du0)
        starts = [(z0, dz0)] * (len(directions) if carry else n)
        start_name = "explicit"
    else:
        start = "rest" if start is None else start
        if not isinstance(start, str):
            raise ParameterError(f"start = {start!r} is invalid; allowed: 'rest', 'equilibrium' or an orbit label")
        if carry:
            starts = [start_state(params.replace(**{param: float(vals[o[0]])}), start) for o in orders]
        elif start == "rest":
            starts = [(0j, 0j)] * n
        else:
            starts = [start_state(params.replace(**{param: float(v)}), start) for v in vals]
        start_name = start

    manifest = {
        "study": "sweep",
        "param": param,
        "values": vals,
        "params": params.as_dict(),
        "mode": mode,
        "starts": [list(s) for s in starts],
        "settings": settings.as_dict(),
        **backend_manifest(backend),
    }
    # the finished file also records how the start was given and the machine, and depends on the version
    digest = study_digest({**manifest, "start": start_name, "version": __version__,
                           "machine": None if machine is None else machine.as_dict()})

    # chunks: (direction, block of consecutive steps)
    def keys(size: int) -> list[str]:
        return [key for ks in _sweep_keys(directions, n, size) for key in ks]

    def waves(size: int, sink: dict[str, dict[str, np.ndarray]]):
        return _sweep_waves(rows, starts, orders, directions, carry, settings, size, sink)

    def assemble(size: int, load):
        result = _assemble(load, orders, directions, carry, settings, size)
        ds = _dataset(result, params, param, vals, directions, mode, start_name, starts, size, machine)
        return ds, result.impacts_simulated

    run = run_study(manifest, digest, keys=keys, waves=waves, assemble=assemble, n_items=n * len(directions),
                    desc=f"sweep {param}", chunk_size=chunk_size, out=out, resume=resume, keep_chunks=keep_chunks,
                    n_jobs=n_jobs, scheduler=scheduler, processes=processes, progress=progress,
                    backend=backend, fit_chunks=fit_chunks)
    return SweepResult(dataset=run.dataset, param=param, path=run.path, chunks_computed=run.chunks_computed,
                       chunks_reused=run.chunks_reused, impacts_simulated=run.impacts_simulated,
                       reused_file=run.reused_file, handed_to_cpu=run.handed_to_cpu)


def _blocks(n: int, chunk_size: int) -> list[slice]:
    """The steps of each chunk of a direction: consecutive blocks of ``chunk_size``."""
    return [slice(b * chunk_size, min(n, (b + 1) * chunk_size)) for b in range(math.ceil(n / chunk_size))]


def _sweep_keys(directions: Sequence[str], n: int, chunk_size: int) -> list[list[str]]:
    """Chunk keys per direction: ``"up-000000"``, ``"up-000001"``, ..."""
    n_blocks = math.ceil(n / chunk_size)
    return [[f"{d}-{b:06d}" for b in range(n_blocks)] for d in directions]


def _sweep_waves(rows, starts, orders, directions, carry: bool, settings: BatchSettings, chunk_size: int,
                 sink: dict[str, dict[str, np.ndarray]]):
    """The waves of a sweep: one wave of every chunk, or, with the state carried, a wave per block of steps.

    With the state carried, the chunk of block b of a direction starts where the chunk of block b - 1
    ended (read from ``sink``).
    """
    n = rows.shape[0]
    blocks = _blocks(n, chunk_size)
    keys = _sweep_keys(directions, n, chunk_size)
    if not carry:
        tasks = []
        z0 = np.array([s[0] for s in starts], dtype=complex)
        dz0 = np.array([s[1] for s in starts], dtype=complex)
        for b, block in enumerate(blocks):
            steps = orders[0][block]
            m = steps.size
            tasks.append(ChunkTask(
                key=keys[0][b],
                params=rows[steps].reshape(m, 1, -1),
                u0=z0[steps].reshape(m, 1),
                du0=dz0[steps].reshape(m, 1),
                carry=False,
                settings=settings,
            ))
        yield tasks
        return
    state = list(starts)
    for b, block in enumerate(blocks):
        tasks = []
        for li in range(len(directions)):
            if b > 0:
                last = sink[keys[li][b - 1]]["summary"][0, -1]
                state[li] = (complex(last[S_U_RE], last[S_U_IM]), complex(last[S_DU_RE], last[S_DU_IM]))
            steps = orders[li][block]
            m = steps.size
            z0, dz0 = state[li]
            tasks.append(ChunkTask(
                key=keys[li][b],
                params=rows[steps].reshape(1, m, -1),
                u0=np.full((1, m), z0, dtype=complex),
                du0=np.full((1, m), dz0, dtype=complex),
                carry=True,
                settings=settings,
            ))
        yield tasks


def _assemble(load, orders, directions, carry: bool, settings: BatchSettings, chunk_size: int) -> BatchResult:
    """The batch result of a sweep from its finished chunks (``load(key)``), in the order of the values."""
    n = orders[0].size
    keys = _sweep_keys(directions, n, chunk_size)
    sections = np.empty((len(directions), n, settings.keep, 4))  # every step is written below
    summary = np.empty((len(directions), n, NSUM))
    for li in range(len(directions)):
        for b, block in enumerate(_blocks(n, chunk_size)):
            res = load(keys[li][b])
            steps = orders[li][block]
            if carry:
                sections[li, steps] = res["sections"][0]
                summary[li, steps] = res["summary"][0]
            else:
                sections[li, steps] = res["sections"][:, 0]
                summary[li, steps] = res["summary"][:, 0]
    return BatchResult.from_arrays(sections, summary, settings)


def _dataset(result: BatchResult, params: Parameters, param: str, vals: np.ndarray, directions, mode: str,
             start_name: str, starts, chunk_size: int, machine: Machine | None = None):
    import xarray as xr

    dims = ("direction", param)
    sec_dims = dims + ("impact",)
    data = {name: (sec_dims, getattr(result, name), SECTION_ATTRS[name]) for name in ("t", "theta", "rdot", "thetadot")}
    data.update(summary_variables(result, dims))
    coords = {
        "direction": ("direction", np.array(directions, dtype=str)),
        param: (param, vals, dict(long_name=PARAMETER_LONG_NAMES[param], units=PARAMETER_UNITS[param])),
        "impact": ("impact", np.arange(result.t.shape[-1], dtype=np.int32),
                   dict(long_name="index of the impact in the kept part of the window")),
    }
    attrs: dict[str, Any] = {
        "title": f"brute-force orbit diagram against {param}",
        "source": f"rotorcontact {__version__}",
        "swept_parameter": param,
        "sweep_mode": mode,
        "start_state": start_name,
        "start_u0_re": np.array([s[0].real for s in starts]),
        "start_u0_im": np.array([s[0].imag for s in starts]),
        "start_du0_re": np.array([s[1].real for s in starts]),
        "start_du0_im": np.array([s[1].imag for s in starts]),
        "chunk_size": np.int32(chunk_size),
    }
    attrs.update(parameter_attrs(params, skip=param, machine=machine))
    attrs.update(settings_attrs(result.settings))
    return xr.Dataset(data, coords=coords, attrs=attrs)


def one_impact_overlay(params: Parameters, param: str, values: Any, *, max_values: int = 200, t_max: float = 12.0):
    """The one-impact fixed points B_n,m at parameter values, for overlaying on a diagram.

    Every fixed point of the impact map (`rotorcontact.maps.impact_map.one_impact_orbits`) with period up to
    ``t_max``, or as far as it can be searched there (`rotorcontact.maps.impact_map.searchable_t_max`), is
    computed at up to ``max_values`` of the values (evenly subsampled).

    Returns
    -------
    xarray.Dataset
        Over (value, orbit label): ``theta``, ``rdot``, ``thetadot``, ``T``
        (NaN where the orbit does not exist), and ``admissible``, ``stable``,
        ``plausible`` (0/1).
    """
    import xarray as xr

    from ..maps.impact_map import one_impact_orbits, searchable_t_max

    check_params(params)
    if param not in SWEEP_PARAMETERS:
        raise ParameterError(f"param = {param!r} is invalid; allowed: {', '.join(SWEEP_PARAMETERS)}")
    vals = _check_values(param, values)
    max_values = check_int("max_values", max_values, 1, MAX_GRID_POINTS)
    if vals.size > max_values:
        vals = vals[np.unique(np.linspace(0, vals.size - 1, max_values).round().astype(int))]
    found: dict[str, dict[int, Any]] = {}
    for i, v in enumerate(vals):
        at = params.replace(**{param: float(v)})
        for o in one_impact_orbits(at, t_max=searchable_t_max(at, t_max)):
            found.setdefault(o.label, {})[i] = o
    labels = sorted(found, key=lambda s: (int(s[1:].split(",")[0]), s.split(",")[1]))
    shape = (vals.size, len(labels))
    arrays = {name: np.full(shape, np.nan) for name in ("theta", "rdot", "thetadot", "T")}
    flags = {name: np.zeros(shape, dtype=np.int8) for name in ("admissible", "stable", "plausible")}
    for j, lab in enumerate(labels):
        for i, o in found[lab].items():
            arrays["theta"][i, j] = o.theta
            arrays["rdot"][i, j] = o.rdot
            arrays["thetadot"][i, j] = o.thetadot
            arrays["T"][i, j] = o.T
            flags["admissible"][i, j] = o.admissible
            flags["stable"][i, j] = bool(o.stable)
            flags["plausible"][i, j] = o.plausible
    data = {k: ((param, "orbit"), v) for k, v in {**arrays, **flags}.items()}
    return xr.Dataset(data, coords={param: vals, "orbit": np.array(labels, dtype=str)},
                      attrs={"source": "one-impact fixed points of the impact map at each value"})


def continued_branches(params: Parameters, param: str, values: Any, *, t_max: float = 12.0):
    """The continued branches of one-impact orbits over the range of ``values``, for overlaying.

    Uses `rotorcontact.continuation.branches.orbit_branches` (pseudo-arclength continuation
    with located bifurcations) from the first to the last value.

    Returns
    -------
    rotorcontact.continuation.branches.OrbitBranches

    Raises
    ------
    ParameterError
        If ``param`` cannot be continued (phi, r_ratio) or the range is a single value.
    """
    if param not in BRANCH_PARAMETERS:
        raise ParameterError(f"param = {param!r} cannot be continued; allowed: {', '.join(BRANCH_PARAMETERS)}")
    vals = _check_values(param, values)
    if vals.size < 2:
        raise ParameterError("continued branches need a range of at least two values")
    from ..continuation.branches import orbit_branches

    return orbit_branches(params, param, float(vals[0]), float(vals[-1]), t_max=t_max)


def overlay_for(params: Parameters, param: str, values: Any):
    """The best overlay available: continued branches where possible, else the fixed points at the values.

    Returns
    -------
    overlay : OrbitBranches or xarray.Dataset
    kind : str
        ``"branches"`` or ``"fixed-points"``.
    """
    try:
        return continued_branches(params, param, values), "branches"
    except (ImportError, ParameterError):
        return one_impact_overlay(params, param, values), "fixed-points"
