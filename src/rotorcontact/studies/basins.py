"""Basins of attraction: which initial states end where.

A grid of initial states is simulated (`rotorcontact.studies.batch`) through a
transient and a window, and the attractor reached is classified:

* ``"no-contact"``: no impact and no contact in the last third of the window;
  the rotor settles on the contact-free synchronous whirl x_R;
* a named one-impact orbit, ``"B1,d"`` etc.: periodic with one impact per
  period, the impact state matching a fixed point of the impact map
  (`rotorcontact.maps.impact_map.one_impact_orbits`) to ``match_tol``;
  ``"one-impact"`` when periodic with one impact but no fixed point matches;
* ``"multi-impact"``: periodic with p >= 2 impacts per period;
* ``"forward-rub"``: continuous contact sliding forward only (settling on a
  pseudo-equilibrium);
* ``"backward-whirl"``: the window ends rolling round the stator;
* ``"mixed"``: impacts and contact phases, or contact with backward sliding;
* ``"irregular"``: impacting with no period of up to
  `rotorcontact.simulation.motion.MAX_PERIOD_IMPACTS` impacts;
* ``"undetermined"``: too few impacts to tell; ``"failed"``: the simulation
  could not continue; ``"outside"``: the grid point lies outside the
  clearance and was not simulated.

Two grids are provided (`BasinGrid`, `parse_grid`):

* ``displacement``: U(0) = x + i y on a rectangle, at zero velocity;
* ``shock``: from the contact-free whirl x_R (U = k, U' = 0), a velocity kick
  U'(0) = A e^{i (arg k + beta)} of amplitude A and direction beta measured
  from the outward radial direction of x_R (beta = 0 points at the stator,
  beta = pi/2 is a forward tangential kick). At t = 0 a kick in the
  co-rotating frame is the same kick in the inertial frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..simulation.motion import IRREGULAR, MIXED, NO_CONTACT, PERIODIC, ROLL, RUB, UNDETERMINED
from .batch import NSUM, BatchResult, BatchSettings, check_batch_settings, parameter_array
from ..errors import ParameterError
from ..model.angles import angle_difference
from ..model.params import Machine, Parameters, check_finite
from ..model.validation import check_int, check_machine, check_machine_params, check_params
from .attributes import RATE_UNITS, REGIME_COMMENT, parameter_attrs, settings_attrs, summary_variables
from .driver import run_study
from .execution import ChunkTask, backend_manifest, check_chunk_size, study_digest
from .grids import (  # noqa: F401  (offered here too, where they were first defined)
    AXIS_ATTRS,
    GRID_KINDS,
    GRID_SYNTAX,
    MAX_GRID_POINTS,
    BasinGrid,
    displacement_grid,
    parse_grid,
    shock_grid,
)

__all__ = [
    "GRID_KINDS",
    "BasinGrid",
    "BasinResult",
    "basins",
    "displacement_grid",
    "shock_grid",
    "parse_grid",
    "GRID_SYNTAX",
    "class_names",
]

#: Classes before and after the named orbits, in code order.
CLASSES_BEFORE = ("outside", "no-contact")
#: The contact regimes are named as in `rotorcontact.simulation.motion.REGIMES`; their former names ``"rub"`` and
#: ``"rolling"`` are accepted by `BasinResult.fraction` (`rotorcontact.simulation.motion.REGIME_ALIASES`).
CLASSES_AFTER = ("one-impact", "multi-impact", "forward-rub", "backward-whirl", "mixed", "irregular", "undetermined",
                 "failed")
DEFAULT_CHUNK = 2048


def class_names(orbit_labels: tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """All class names, in code order, for the given orbit labels.

    Raises
    ------
    ParameterError
        Unless ``orbit_labels`` is a list or tuple of labels (text alone would be read letter by letter).
    """
    if not isinstance(orbit_labels, (list, tuple)) or not all(isinstance(v, str) and v for v in orbit_labels):
        raise ParameterError(f"orbit_labels = {orbit_labels!r} is invalid; allowed: a list or tuple of orbit labels "
                             "such as ['B1,d']")
    return CLASSES_BEFORE + tuple(orbit_labels) + CLASSES_AFTER


@dataclass(frozen=True)
class BasinResult:
    """Basins of attraction on a grid.

    Attributes
    ----------
    dataset : xarray.Dataset
        ``attractor`` (class code per grid point, rows = second axis), the
        regime, impacts per period, period and last impact of each point, the
        initial states, the class table with ``count`` and ``fraction``, and
        the one-impact orbits used for naming.
    classes : tuple of str
        Class names in code order.
    fractions : dict
        Fraction of the simulated grid points (those inside the clearance)
        in each class that occurs.
    path : pathlib.Path or None
        The NetCDF file written, if any.
    chunks_computed, chunks_reused : int
        Chunks computed by this call, and found from an interrupted one (or
        all chunks, when `reused_file`).
    impacts_simulated : int
        Impacts computed.
    reused_file : bool
        The output file already held this finished study and was returned as it is.
    handed_to_cpu : int
        With ``backend="cuda"``: simulations of this call computed on the CPU because the GPU's summary of
        their window could not be exact (`rotorcontact.studies.compact_batch.compact_item`; in a carried
        chain, that step and the chain's later ones).
    """

    dataset: Any = field(repr=False)
    classes: tuple[str, ...]
    fractions: dict[str, float]
    path: Path | None
    chunks_computed: int
    chunks_reused: int
    impacts_simulated: int
    reused_file: bool = False
    handed_to_cpu: int = 0

    @property
    def image(self) -> np.ndarray:
        """Class codes, shape (rows, columns)."""
        return self.dataset["attractor"].values

    def class_of(self, i: int, j: int) -> str:
        """Class name at row ``i``, column ``j``.

        Raises
        ------
        ParameterError
            Unless ``i`` and ``j`` are whole numbers within the grid's rows and columns (from 0).
        """
        rows, cols = self.image.shape
        i = check_int("i", i, 0, rows - 1)
        j = check_int("j", j, 0, cols - 1)
        return self.classes[int(self.image[i, j])]

    def fraction(self, name: str) -> float:
        """Fraction of the simulated grid points in the class ``name`` (0 where it does not occur).

        Former regime names (``"rub"``, ``"rolling"``; `rotorcontact.simulation.motion.REGIME_ALIASES`) are accepted.

        Raises
        ------
        ParameterError
            If ``name`` is not a class of this result.
        """
        from ..simulation.motion import canonical_regime

        key = canonical_regime(name) if isinstance(name, str) else name
        if key not in self.classes or key == "outside":
            allowed = ", ".join(c for c in self.classes if c != "outside")
            raise ParameterError(f"name = {name!r} is not a class of these basins; allowed: {allowed}")
        return self.fractions.get(key, 0.0)


def classify(result: BatchResult, orbits, match_tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Class codes (for `class_names` of the orbits' labels) and the index of the matched orbit (-1: none).

    ``result`` must keep at least the last impact of each window.
    """
    labels = [o.label for o in orbits]
    names = class_names(labels)
    code = {name: i for i, name in enumerate(names)}
    reg = result.regime
    out = np.full(reg.shape, code["failed"], dtype=np.int32)
    matched = np.full(reg.shape, -1, dtype=np.int32)
    out[reg == NO_CONTACT] = code["no-contact"]
    out[reg == RUB] = code["forward-rub"]
    out[reg == ROLL] = code["backward-whirl"]
    out[reg == MIXED] = code["mixed"]
    out[reg == IRREGULAR] = code["irregular"]
    out[reg == UNDETERMINED] = code["undetermined"]
    periodic = reg == PERIODIC
    out[periodic & (result.impacts_per_period >= 2)] = code["multi-impact"]
    one = periodic & (result.impacts_per_period == 1)
    out[one] = code["one-impact"]
    if orbits and one.any():
        th = result.theta[..., -1]
        rd = result.rdot[..., -1]
        td = result.thetadot[..., -1]
        best = np.full(reg.shape, np.inf)
        for j, o in enumerate(orbits):
            dist = np.maximum.reduce([
                np.abs(angle_difference(th, o.theta)),
                np.abs(rd - o.rdot),
                np.abs(td - o.thetadot),
            ])
            better = one & (dist < match_tol) & (dist < best)
            best[better] = dist[better]
            matched[better] = j
        hit = matched >= 0
        out[hit] = len(CLASSES_BEFORE) + matched[hit]
    return out, matched


def basin_settings(n_transient: int = 300, n_record: int = 50, t_transient: float | None = None,
                   t_record: float | None = None, settle: int = 25) -> BatchSettings:
    """The batch settings of a basin study (`basins`): the last impact of each window is kept."""
    return BatchSettings(n_transient=n_transient, n_record=n_record, t_transient=t_transient,
                         t_record=t_record, n_keep=1, settle=settle)


def basins(
    params: Parameters,
    grid: BasinGrid | str,
    *,
    settings: BatchSettings | None = None,
    n_transient: int = 300,
    n_record: int = 50,
    t_transient: float | None = None,
    t_record: float | None = None,
    settle: int = 25,
    match_tol: float = 1e-3,
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
) -> BasinResult:
    """Basins of attraction of the attractors reached from a grid of initial states.

    Parameters
    ----------
    params : Parameters
        Model parameters.
    grid : BasinGrid or str
        The grid (`displacement_grid`, `shock_grid`, or a `parse_grid` string).
    settings : BatchSettings, optional
        Transient and window; otherwise from ``n_transient`` (300 events),
        ``n_record`` (50 events: enough to see periods of up to 16 impacts),
        the time limits (default 5 per event) and ``settle``.
    settle : int
        The transient runs in segments of this many events and ends once the
        motion repeats or can no longer touch the stator
        (`rotorcontact.studies.batch.BatchSettings`); 0 runs the whole transient.
    match_tol : float
        Largest difference in theta, rdot and thetadot between the last impact
        of a one-impact periodic window and the fixed point it is named after.
    chunk_size : int, optional
        Grid points per chunk (it sets where files are written, not the
        results; an interrupted run is resumed with the chunk size it was
        started with). Default `DEFAULT_CHUNK`, cut down on worker processes by
        `rotorcontact.studies.execution.fitted_chunk_size`.
    n_jobs, scheduler, processes, backend, out, resume, keep_chunks, progress, machine
        As for `rotorcontact.studies.sweep.sweep`.

    Returns
    -------
    BasinResult
    """
    check_machine(machine)
    check_params(params)
    check_machine_params(params, machine)
    if isinstance(grid, str):
        grid = parse_grid(grid)
    if not isinstance(grid, BasinGrid):
        raise ParameterError(f"grid = {grid!r} is not a BasinGrid or a grid string")
    match_tol = float(check_finite("match_tol", match_tol))
    if match_tol <= 0:
        raise ParameterError(f"match_tol = {match_tol!r} must be > 0")
    fit_chunks = chunk_size is None
    chunk_size = check_chunk_size(DEFAULT_CHUNK if fit_chunks else chunk_size)
    u0, du0, inside = grid.initial_states(params)
    settings = check_batch_settings(settings, int(inside.size), lambda: basin_settings(  # the sections span the grid
        n_transient=n_transient, n_record=n_record, t_transient=t_transient, t_record=t_record, settle=settle))
    if not inside.any():
        raise ParameterError("grid: no initial state lies inside the clearance (|U(0)| <= 1); nothing to simulate")
    row = parameter_array(params)
    flat = np.flatnonzero(inside.ravel())
    n_valid = flat.size
    from ..maps.impact_map import admissible_orbits

    admissible_orbits(params, 12.0)  # orbits that cannot be named are refused before the simulations run
    manifest = {
        "study": "basins",
        "params": params.as_dict(),
        "grid": {"kind": grid.kind, "axis0": grid.axis0, "axis1": grid.axis1},
        "settings": settings.as_dict(),
        **backend_manifest(backend),
    }
    # the finished file also depends on the naming of the orbits, the machine and the version
    digest = study_digest({**manifest, "match_tol": match_tol, "version": __version__,
                           "machine": None if machine is None else machine.as_dict()})
    u_flat, du_flat = u0.ravel(), du0.ravel()

    def keys(size: int) -> list[str]:
        return [f"basin-{c:06d}" for c in range(math.ceil(n_valid / size))]

    def waves(size: int, sink: dict[str, dict[str, np.ndarray]]):
        tasks = []
        for c, key in enumerate(keys(size)):
            idx = flat[c * size : (c + 1) * size]
            m = idx.size
            tasks.append(ChunkTask(
                key=key,
                params=np.broadcast_to(row, (m, 1, row.size)).copy(),
                u0=u_flat[idx].reshape(m, 1).copy(),
                du0=du_flat[idx].reshape(m, 1).copy(),
                carry=False,
                settings=settings,
            ))
        yield tasks

    def batch_result(size: int, load) -> BatchResult:
        n_all = inside.size
        sections = np.full((n_all, settings.keep, 4), np.nan)
        summary = np.zeros((n_all, NSUM))
        for c, key in enumerate(keys(size)):
            res = load(key)
            idx = flat[c * size : (c + 1) * size]
            sections[idx] = res["sections"][:, 0]
            summary[idx] = res["summary"][:, 0]
        shape = grid.shape
        # the result copies what it needs of the summary, which is let go on return
        return BatchResult.from_arrays(sections.reshape(shape + (settings.keep, 4)),
                                       summary.reshape(shape + (NSUM,)), settings)

    def assemble(size: int, load):
        result = batch_result(size, load)
        return _classified(result, params, grid, inside, u0, du0, match_tol, size, machine), result.impacts_simulated

    run = run_study(manifest, digest, keys=keys, waves=waves, assemble=assemble, n_items=n_valid, desc="basins",
                    chunk_size=chunk_size, out=out, resume=resume, keep_chunks=keep_chunks, n_jobs=n_jobs,
                    scheduler=scheduler, processes=processes, progress=progress,
                    backend=backend, fit_chunks=fit_chunks)
    ds = run.dataset
    names = tuple(str(n) for n in ds["class_name"].values)
    return BasinResult(
        dataset=ds,
        classes=names,
        fractions=_fractions(names, ds["count"].values, ds["fraction"].values),
        path=run.path,
        chunks_computed=run.chunks_computed,
        chunks_reused=run.chunks_reused,
        impacts_simulated=run.impacts_simulated,
        reused_file=run.reused_file,
        handed_to_cpu=run.handed_to_cpu,
    )


def _classified(result: BatchResult, params: Parameters, grid: BasinGrid, inside: np.ndarray, u0: np.ndarray,
                du0: np.ndarray, match_tol: float, chunk_size: int, machine: Machine | None):
    """The basins dataset: the attractor of every grid point, named after the one-impact orbits it matches."""
    codes, orbits = name_points(result, params, inside, match_tol)
    names = class_names([o.label for o in orbits])
    counts = np.bincount(codes[inside].ravel(), minlength=len(names)).astype(np.int32)
    fractions = counts / max(int(inside.sum()), 1)
    return _dataset(result, codes, inside, u0, du0, grid, params, names, counts, fractions, orbits, match_tol,
                    chunk_size, machine)


def name_points(result: BatchResult, params: Parameters, inside: np.ndarray, match_tol: float):
    """Class codes of the points of a batch (0, ``"outside"``, where not ``inside``) and the orbits named.

    The one-impact orbits are those of the impact map at ``params`` with periods up to 1.25 times the
    longest period found (at least 12), as far as they can be searched
    (`rotorcontact.maps.impact_map.admissible_orbits`); codes index
    `class_names` of their labels.
    """
    one = (result.regime == PERIODIC) & (result.impacts_per_period == 1) & inside
    t_max = 12.0
    if one.any():
        t_max = max(t_max, 1.25 * float(np.nanmax(result.period[one])))
    from ..maps.impact_map import admissible_orbits

    orbits = admissible_orbits(params, t_max)
    codes, _matched = classify(result, orbits, match_tol)
    codes[~inside] = 0
    return codes, orbits


def _fractions(names, counts, fractions) -> dict[str, float]:
    """The fraction of each class that occurs among the simulated points (``"outside"`` left out)."""
    return {str(names[i]): float(fractions[i]) for i in range(len(names)) if counts[i] > 0 and i > 0}


def _dataset(result, codes, inside, u0, du0, grid, params, names, counts, fractions, orbits, match_tol, chunk_size,
             machine=None):
    import xarray as xr

    a0, a1 = grid.names
    dims = (a1, a0)
    data: dict[str, Any] = {
        "attractor": (dims, codes.astype(np.int32), dict(
            long_name="attractor reached",
            flag_values=np.arange(len(names), dtype=np.int32),
            flag_meanings=" ".join(names),
            comment=REGIME_COMMENT,
        )),
        "inside": (dims, inside.astype(np.int8), dict(long_name="initial state inside the clearance (simulated)")),
        "theta": (dims, result.theta[..., -1], dict(long_name="angle of the last impact of the window", units="rad")),
        "rdot": (dims, result.rdot[..., -1], dict(long_name="rdot just before the last impact", units="1")),
        "thetadot": (dims, result.thetadot[..., -1],
                     dict(long_name="thetadot just before the last impact", **RATE_UNITS)),
        "u0_re": (dims, u0.real.copy(), dict(long_name="initial U, real part", units="1")),
        "u0_im": (dims, u0.imag.copy(), dict(long_name="initial U, imaginary part", units="1")),
        "du0_re": (dims, du0.real.copy(), dict(long_name="initial U', real part", units="1")),
        "du0_im": (dims, du0.imag.copy(), dict(long_name="initial U', imaginary part", units="1")),
        "count": (("class",), counts, dict(long_name="grid points in each class")),
        "fraction": (("class",), fractions, dict(long_name="fraction of the simulated grid points in each class",
                                                 units="1")),
        "orbit_T": (("orbit",), np.array([o.T for o in orbits], dtype=float), dict(long_name="period", units="1")),
        "orbit_theta": (("orbit",), np.array([o.theta for o in orbits], dtype=float),
                        dict(long_name="impact angle", units="rad")),
        "orbit_rdot": (("orbit",), np.array([o.rdot for o in orbits], dtype=float), dict(units="1")),
        "orbit_thetadot": (("orbit",), np.array([o.thetadot for o in orbits], dtype=float), dict(**RATE_UNITS)),
        "orbit_stable": (("orbit",), np.array([bool(o.stable) for o in orbits], dtype=np.int8), {}),
        "orbit_plausible": (("orbit",), np.array([o.plausible for o in orbits], dtype=np.int8), {}),
    }
    data.update(summary_variables(result, dims))
    coords = {
        a0: (a0, grid.axis0, AXIS_ATTRS[a0]),
        a1: (a1, grid.axis1, AXIS_ATTRS[a1]),
        "class": ("class", np.arange(len(names), dtype=np.int32)),
        "class_name": ("class", np.array(names, dtype=str)),
        "orbit": ("orbit", np.array([o.label for o in orbits], dtype=str)),
    }
    attrs: dict[str, Any] = {
        "title": "basins of attraction",
        "source": f"rotorcontact {__version__}",
        "grid_kind": grid.kind,
        "grid": grid.describe(),
        "match_tol": float(match_tol),
        "chunk_size": np.int32(chunk_size),
        "orbits_source": "one-impact fixed points of the impact map at these parameters",
    }
    attrs.update(parameter_attrs(params, machine=machine))
    attrs.update(settings_attrs(result.settings))
    if grid.kind == "shock":
        attrs["x_R_re"] = float(params.k.real)
        attrs["x_R_im"] = float(params.k.imag)
    return xr.Dataset(data, coords=coords, attrs=attrs)
