"""Attractors followed across a parameter: which exist, where they are born and die, their basins.

At each value of one parameter the same grid of initial states as `rotorcontact.studies.basins`
(`rotorcontact.studies.basins.parse_grid`) is simulated through a transient and a window with the
batch kernel, on the chunked, resumable, parallel study driver `rotorcontact.studies.driver.run_study`
(so the results are identical whichever executor runs them), and every point is classified exactly as
`basins` classifies it (`rotorcontact.studies.basins.name_points`). The classes are then turned into
*identities* that hold along the parameter:

* ``"x_R"``: the contact-free whirl (class ``"no-contact"``);
* the label of a one-impact orbit of the impact map (``"B1,d"`` ...), matched at each value to the fixed
  points of the impact map at that value, whose labels follow the orbits' branches;
* ``"P1"``, ``"P2"``: forward rub settled on a pseudo-equilibrium of `rotorcontact.analysis.equilibria.pseudo_equilibria`
  (the final contact angle within ``match_tol`` of it), else ``"forward-rub"``;
* ``"p-impact"`` for a periodic orbit with p >= 2 impacts per period (``"2-impact"`` ...);
* the other classes by name (``"backward-whirl"``, ``"one-impact"``, ``"mixed"``, ``"irregular"``,
  ``"undetermined"``, ``"failed"``).

For each identity and value: the count and fraction of the simulated initial states that reach it, and the
95 % Wilson confidence interval of the fraction (`scipy.stats.binomtest`); the largest Lyapunov exponent
of `rotorcontact.analysis.lyapunov.lyapunov_spectrum` from the end state of the first point that reached it,
with its error estimate; and a label:

* ``"periodic"``: x_R, one-impact and p-impact orbits;
* ``"contact"``: forward rub and backward whirl;
* ``"chaotic"``: irregular or mixed motion whose largest exponent exceeds `CHAOS_MIN` and three times its
  error estimate; ``"quasi-periodic"``: irregular or mixed motion whose largest exponent does not;
* ``"transient"``: irregular or mixed motion that, continued over the Lyapunov run, settles into a
  final regime (`rotorcontact.analysis.regime_change.final_regime`): a chaotic transient, not an attractor;
* ``"undetermined"``: too few impacts to tell, a failed run, or no exponent computed.

An identity *appears* at the first value where it is reached (when that is not the first value) and
*disappears* at the first value after the last one where it is reached (when that is not the last).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..errors import ParameterError
from ..model.params import Machine, Parameters, check_finite
from ..model.validation import (check_bool, check_float, check_int, check_machine, check_params, check_type, quoted,
                                real_array)
from .basins import DEFAULT_CHUNK, BasinGrid, class_names, name_points, parse_grid
from .batch import NSUM, PARAMETER_ORDER, BatchResult, BatchSettings, check_batch_settings, parameter_array
from .driver import run_study
from .execution import ChunkTask, backend_manifest, check_chunk_size, study_digest
from .lyapunov_scan import SpectrumTask
from .parameter_path import parameter_path, path_values

__all__ = [
    "CHAOS_MIN",
    "CONFIDENCE",
    "LABELS",
    "Attractor",
    "AttractorsResult",
    "attractor_label",
    "attractors",
    "identity_names",
    "parameter_path",
    "wilson_interval",
]

#: Labels of an attractor.
LABELS = ("periodic", "quasi-periodic", "chaotic", "contact", "undetermined", "transient")
#: Smallest largest exponent called chaotic (per unit of dimensionless time).
CHAOS_MIN = 1e-3
#: Confidence level of the intervals of the basin fractions.
CONFIDENCE = 0.95
#: Default length of the Lyapunov runs from each attractor (a quarter of it is left out as transient).
DEFAULT_T_LYAPUNOV = 400.0
_PERIODIC_CLASSES = ("no-contact", "one-impact", "multi-impact")
_CONTACT_CLASSES = ("forward-rub", "backward-whirl")
_LABELLED_BY_EXPONENT = ("irregular", "mixed")


@dataclass(frozen=True)
class Attractor:
    """One attractor followed along the parameter.

    Attributes
    ----------
    name : str
        Its identity (module docstring).
    label : str
        One of `LABELS`: the most frequent label over the values where it is reached.
    present : numpy.ndarray of bool
        Where it is reached from at least one initial state.
    count : numpy.ndarray of int
        Initial states that reach it, per value.
    fraction, ci_low, ci_high : numpy.ndarray
        Its basin fraction per value and the `CONFIDENCE` Wilson interval.
    exponent, exponent_error : numpy.ndarray
        Largest Lyapunov exponent and its error estimate per value (NaN where it is not reached or
        no exponent was computed).
    labels : tuple of str
        Label per value (``""`` where it is not reached).
    appears, disappears : float or None
        The value where it is first reached (None when at the first value), and the first value
        after the last one where it is reached (None when reached at the last value).
    """

    name: str
    label: str
    present: np.ndarray = field(repr=False)
    count: np.ndarray = field(repr=False)
    fraction: np.ndarray = field(repr=False)
    ci_low: np.ndarray = field(repr=False)
    ci_high: np.ndarray = field(repr=False)
    exponent: np.ndarray = field(repr=False)
    exponent_error: np.ndarray = field(repr=False)
    labels: tuple[str, ...] = field(repr=False)
    appears: float | None = None
    disappears: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data (NaN as None)."""
        clean = lambda a: [None if not math.isfinite(x) else float(x) for x in a]
        return {
            "name": self.name,
            "label": self.label,
            "appears": self.appears,
            "disappears": self.disappears,
            "present": [bool(x) for x in self.present],
            "count": [int(x) for x in self.count],
            "fraction": clean(self.fraction),
            "ci_low": clean(self.ci_low),
            "ci_high": clean(self.ci_high),
            "exponent": clean(self.exponent),
            "exponent_error": clean(self.exponent_error),
            "labels": [x or None for x in self.labels],
        }


@dataclass(frozen=True)
class AttractorsResult:
    """Attractors against a parameter.

    Attributes
    ----------
    dataset : xarray.Dataset
        Per (value, attractor): ``count``, ``fraction``, ``ci_low``, ``ci_high``, ``exponent``,
        ``exponent_error``, ``label``; per (value, point): ``identity`` (index into the attractor
        names, -1 outside the clearance) and the initial states.
    param : str
        The parameter varied.
    values : numpy.ndarray
        Its values (SI for a machine quantity).
    attractors : tuple of Attractor
        In order of first appearance.
    path : pathlib.Path or None
        The NetCDF file written.
    chunks_computed, chunks_reused, impacts_simulated, reused_file, handed_to_cpu
        As for `rotorcontact.studies.basins.BasinResult`.
    """

    dataset: Any = field(repr=False)
    param: str
    values: np.ndarray = field(repr=False)
    attractors: tuple[Attractor, ...]
    path: Path | None
    chunks_computed: int
    chunks_reused: int
    impacts_simulated: int
    reused_file: bool = False
    handed_to_cpu: int = 0

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the attractors."""
        return tuple(a.name for a in self.attractors)

    def attractor(self, name: str) -> Attractor:
        """The attractor of that name.

        Raises
        ------
        ParameterError
            If no attractor of that name was found.
        """
        for a in self.attractors:
            if a.name == name:
                return a
        raise ParameterError(f"attractor = {name!r} was not found; allowed: {', '.join(self.names)}")


def wilson_interval(count: np.ndarray, total: int, confidence: float = CONFIDENCE) -> tuple[np.ndarray, np.ndarray]:
    """Wilson score intervals of binomial proportions ``count / total`` (`scipy.stats.binomtest`).

    Raises
    ------
    ParameterError
        Unless ``total`` is a whole number >= 1, ``count`` whole numbers from 0 to ``total``, and
        ``confidence`` in (0, 1) (at 1 the interval would be the whole of [0, 1] with no information).
    """
    from scipy.stats import binomtest

    total = check_int("total", total, 1)
    confidence = check_float("confidence", confidence, 0.0, 1.0, low_open=True, high_open=True)
    counts = real_array(count)
    if counts is None or counts.ndim != 1 or not np.all((counts == np.round(counts)) & (counts >= 0)
                                                         & (counts <= total)):
        raise ParameterError(f"count = {quoted(count)} is invalid; allowed: a sequence of whole numbers from 0 "
                             f"to total = {total}")
    low = np.empty(len(counts))
    high = np.empty(len(counts))
    for i, k in enumerate(counts):
        ci = binomtest(int(k), total).proportion_ci(confidence_level=confidence, method="wilson")
        low[i], high[i] = ci.low, ci.high
    return low, high


def identity_names(result: BatchResult, codes: np.ndarray, orbit_labels, params: Parameters,
                   match_tol: float) -> np.ndarray:
    """The identity (module docstring) of every point of one value, as an object array (None outside).

    ``codes`` are `rotorcontact.studies.basins.classify`'s class codes of the points of ``result``, with the
    orbits ``orbit_labels`` of ``params``; rubbing points are named by the pseudo-equilibrium within
    ``match_tol`` (rad) of their final angle. A `ParameterError` for anything else.
    """
    from ..analysis.equilibria import pseudo_equilibria

    check_type("result", result, BatchResult, "a BatchResult (rotorcontact.studies.batch.simulate_batch)")
    check_params(params)
    match_tol = check_float("match_tol", match_tol, 0.0, math.pi, low_open=True)
    if not (isinstance(orbit_labels, (list, tuple)) and all(isinstance(x, str) for x in orbit_labels)):
        raise ParameterError(f"orbit_labels = {quoted(orbit_labels)} is invalid; allowed: a list of orbit labels")
    names = np.asarray(class_names(list(orbit_labels)), dtype=object)
    if not isinstance(codes, np.ndarray) or codes.dtype.kind not in "iu" or codes.shape != result.shape \
            or (codes.size and (codes.min() < 0 or codes.max() >= len(names))):
        raise ParameterError(f"codes = {quoted(codes)} is invalid; allowed: an integer array of the result's shape "
                             f"{result.shape} with class codes from 0 to {len(names) - 1}")

    out = names[codes].astype(object)
    out[codes == 0] = None
    out[out == "no-contact"] = "x_R"
    multi = out == "multi-impact"
    out[multi] = [f"{int(p)}-impact" for p in result.impacts_per_period[multi]]
    rub = out == "forward-rub"
    if rub.any():
        angle = np.angle(result.final_u[rub])
        named = np.full(angle.shape, "forward-rub", dtype=object)
        for pe in pseudo_equilibria(params):
            if pe.exists and pe.admissible:
                near = np.abs(np.angle(np.exp(1j * (angle - pe.theta)))) < match_tol
                named[near] = pe.name
        out[rub] = named
    return out


def attractor_label(name: str, exponent: float | None, error: float | None, settles: bool = False) -> str:
    """Label of an attractor (module docstring) from its identity, largest exponent, and whether its motion
    continued settles into a final regime.

    Raises
    ------
    ParameterError
        Unless ``name`` is text, ``exponent`` and ``error`` numbers or None, and ``settles`` a bool.
    """
    check_type("name", name, str, "an attractor's identity, such as 'B1,d' or 'irregular'")
    for label, value in (("exponent", exponent), ("error", error)):
        if value is not None and (isinstance(value, (bool, np.bool_))
                                  or not isinstance(value, (int, float, np.integer, np.floating))):
            raise ParameterError(f"{label} = {value!r} is invalid; allowed: a number or None")
    settles = check_bool("settles", settles)
    if name == "x_R" or name.endswith("-impact") or name.startswith("B") or name == "one-impact":
        return "periodic"
    if name in ("P1", "P2") or name in _CONTACT_CLASSES:
        return "contact"
    if name in _LABELLED_BY_EXPONENT:
        if settles:
            return "transient"
        if exponent is None or not math.isfinite(exponent):
            return "undetermined"
        err = error if error is not None and math.isfinite(error) else math.inf
        return "chaotic" if exponent > CHAOS_MIN and exponent > 3.0 * err else "quasi-periodic"
    return "undetermined"


def _identities(result: BatchResult, path: list[Parameters], match_tol: float) -> np.ndarray:
    """The identity of every point of a (values, points) batch result."""
    n_v, n_in = result.shape
    ident = np.empty((n_v, n_in), dtype=object)
    for i, p in enumerate(path):
        one = _value_result(result, i)
        codes, orbits = name_points(one, p, np.ones(n_in, dtype=bool), match_tol)
        ident[i] = identity_names(one, codes, [o.label for o in orbits], p, match_tol)
    return ident


def _representatives(names: np.ndarray) -> list[tuple[str, int]]:
    """(identity, index of its first point) in order of first occurrence; failed runs have none."""
    _uniq, first = np.unique(names.astype(str), return_index=True)
    return [(str(names[j]), int(j)) for j in sorted(first) if names[j] != "failed"]


def attractors(
    params: Parameters,
    param: str,
    values: Any,
    grid: BasinGrid | str,
    *,
    settings: BatchSettings | None = None,
    n_transient: int = 300,
    n_record: int = 50,
    settle: int = 25,
    match_tol: float = 1e-3,
    lyapunov: bool = True,
    t_lyapunov: float = DEFAULT_T_LYAPUNOV,
    chunk_size: int = DEFAULT_CHUNK,
    n_jobs: int | None = None,
    scheduler: Any = None,
    processes: bool = True,
    backend: str = "cpu",
    out: str | Path | None = None,
    resume: bool = True,
    keep_chunks: bool = False,
    progress: bool = True,
    machine: Machine | None = None,
) -> AttractorsResult:
    """Follow the attractors reached from a grid of initial states across the values of one parameter.

    Parameters
    ----------
    params : Parameters
        The other parameters.
    param : str
        A model parameter (gamma, omega, rho, mu, d, phi, r_ratio), or with ``machine`` a field of
        `rotorcontact.model.params.Machine` (speed, stiffness, ...), whose values are then in SI units.
    values : array_like
        Its values.
    grid : BasinGrid or str
        Initial states (`rotorcontact.studies.basins.parse_grid`); a shock grid needs x_R admissible at
        every value.
    settings, n_transient, n_record, settle, match_tol
        As for `rotorcontact.studies.basins.basins`.
    lyapunov : bool
        Compute the largest Lyapunov exponent of each attractor at each value.
    t_lyapunov : float
        Length of those runs.
    chunk_size, n_jobs, scheduler, processes, backend, out, resume, keep_chunks, progress, machine
        As for `rotorcontact.studies.basins.basins`.

    Returns
    -------
    AttractorsResult
    """
    check_machine(machine)
    check_params(params)
    if isinstance(grid, str):
        grid = parse_grid(grid)
    if not isinstance(grid, BasinGrid):
        raise ParameterError(f"grid = {grid!r} is not a BasinGrid or a grid string")
    if not isinstance(param, str):
        raise ParameterError(f"param = {param!r} is not a name")
    vals = path_values(param, values)
    path = parameter_path(params, param, vals, machine)
    # rubbing points are matched by their angle alone (`identity_names`): a tolerance up to pi
    match_tol = check_float("match_tol", match_tol, 0.0, math.pi, low_open=True)
    lyapunov = check_bool("lyapunov", lyapunov)
    t_lyapunov = float(check_finite("t_lyapunov", t_lyapunov))
    if not 0.0 < t_lyapunov <= 1e5:
        raise ParameterError(f"t_lyapunov = {t_lyapunov!r} is invalid; allowed: 0 < t_lyapunov <= 1e5")
    chunk_size = check_chunk_size(chunk_size)
    states = []
    from ..maps.impact_map import admissible_orbits

    for v, p in zip(vals, path):
        try:
            states.append(grid.initial_states(p))
            admissible_orbits(p, 12.0)  # orbits that cannot be named are refused before the simulations run
        except ParameterError as exc:
            raise ParameterError(f"{param} = {float(v)!r}: {exc}") from None
    inside = states[0][2]
    if not inside.any():
        raise ParameterError("grid: no initial state lies inside the clearance (|U(0)| <= 1); nothing to simulate")
    flat = np.flatnonzero(inside.ravel())
    n_in = flat.size
    n_items = vals.size * n_in
    settings = check_batch_settings(settings, n_items, lambda: BatchSettings(
        n_transient=n_transient, n_record=n_record, n_keep=1, settle=settle))
    rows = parameter_array(path)
    u_all = np.stack([s[0].ravel()[flat] for s in states])
    du_all = np.stack([s[1].ravel()[flat] for s in states])
    manifest = {
        "study": "attractors",
        "param": param,
        "values": vals,
        "rows": rows,
        "grid": {"kind": grid.kind, "axis0": grid.axis0, "axis1": grid.axis1},
        "settings": settings.as_dict(),
        **backend_manifest(backend),
    }
    digest = study_digest({**manifest, "match_tol": match_tol, "lyapunov": bool(lyapunov),
                           "t_lyapunov": t_lyapunov, "version": __version__,
                           "machine": None if machine is None else machine.as_dict()})

    def batch_keys(size: int) -> list[str]:
        return [f"attractors-{c:06d}" for c in range(math.ceil(n_items / size))]

    def keys(size: int) -> list[str]:
        spectra = [f"spectra-{i:06d}" for i in range(vals.size)] if lyapunov else []
        return batch_keys(size) + spectra

    named: dict[str, Any] = {}

    def classified(size: int, load) -> tuple[BatchResult, np.ndarray]:
        """The batch result and the identity of every point (computed once per call)."""
        if "ident" not in named:
            sections = np.full((n_items, settings.keep, 4), np.nan)
            summary = np.zeros((n_items, NSUM))
            for c, key in enumerate(batch_keys(size)):
                res = load(key)
                sl = slice(c * size, min((c + 1) * size, n_items))
                sections[sl] = res["sections"][:, 0]
                summary[sl] = res["summary"][:, 0]
            result = BatchResult.from_arrays(sections.reshape(vals.size, n_in, settings.keep, 4),
                                             summary.reshape(vals.size, n_in, NSUM), settings)
            named["result"], named["ident"] = result, _identities(result, path, match_tol)
        return named["result"], named["ident"]

    def waves(size: int, sink):
        tasks = []
        for c, key in enumerate(batch_keys(size)):
            idx = np.arange(c * size, min((c + 1) * size, n_items))
            m = idx.size
            tasks.append(ChunkTask(
                key=key,
                params=rows[idx // n_in].reshape(m, 1, rows.shape[1]).copy(),
                u0=u_all.ravel()[idx].reshape(m, 1).copy(),
                du0=du_all.ravel()[idx].reshape(m, 1).copy(),
                carry=False,
                settings=settings,
            ))
        yield tasks
        if not lyapunov:
            return
        # the largest exponent of each attractor at each value, from the end state of the first point reaching it;
        # chunks held in memory are let go once assembled (the assembly reuses the result), those of a store stay
        result, ident = classified(size, getattr(sink, "pop", None) or sink.__getitem__)
        spectra = []
        for i in range(vals.size):
            first = [j for _name, j in _representatives(ident[i])]
            spectra.append(SpectrumTask(
                key=f"spectra-{i:06d}", params=np.repeat(rows[i : i + 1], len(first), axis=0),
                u0=result.final_u[i, first].copy(), du0=result.final_du[i, first].copy(), t_end=t_lyapunov,
                t_transient=0.25 * t_lyapunov, qr_interval=1.0, progress_items=1,
            ))
        yield spectra

    def assemble(size: int, load):
        result, ident = classified(size, load)
        spectra = [load(f"spectra-{i:06d}") for i in range(vals.size)] if lyapunov else None
        ds = _dataset(result, ident, spectra, path, param, vals, grid, inside, flat, u_all, du_all, match_tol,
                      t_lyapunov, size, params, machine)
        return ds, result.impacts_simulated

    # the progress bar counts the simulations, then one unit per value for its exponents
    run = run_study(manifest, digest, keys=keys, waves=waves, assemble=assemble,
                    n_items=n_items + (vals.size if lyapunov else 0),
                    desc="attractors", chunk_size=chunk_size, out=out, resume=resume, keep_chunks=keep_chunks,
                    n_jobs=n_jobs, scheduler=scheduler, processes=processes, progress=progress,
                    backend=backend)
    ds = run.dataset
    return AttractorsResult(dataset=ds, param=param, values=vals, attractors=attractors_of(ds), path=run.path,
                            chunks_computed=run.chunks_computed, chunks_reused=run.chunks_reused,
                            impacts_simulated=run.impacts_simulated, reused_file=run.reused_file,
                            handed_to_cpu=run.handed_to_cpu)


def _value_result(result: BatchResult, i: int) -> BatchResult:
    """The points of the i-th value of a (values, points) batch result."""
    return replace(result, shape=result.shape[1:], **{
        f.name: getattr(result, f.name)[i] for f in fields(BatchResult) if f.name not in ("shape", "settings")
    })


def _dataset(result, ident, spectra, path, param, vals, grid, inside, flat, u_all, du_all, match_tol, t_lyapunov,
             chunk_size, params, machine):
    import xarray as xr

    n_v, n_in = result.shape
    # names in order of first appearance along the parameter, then along the grid
    names: list[str] = []
    for row in ident:
        _uniq, first = np.unique(row.astype(str), return_index=True)
        names.extend(str(row[j]) for j in sorted(first) if str(row[j]) not in names)
    index = {name: j for j, name in enumerate(names)}
    code = np.vectorize(index.__getitem__, otypes=[np.int32])(ident) if names else np.zeros((n_v, n_in), np.int32)
    n_a = len(names)
    count = np.zeros((n_v, n_a), dtype=np.int32)
    for j in range(n_a):
        count[:, j] = np.count_nonzero(code == j, axis=1)
    fraction = count / n_in
    ci_low = np.empty_like(fraction)
    ci_high = np.empty_like(fraction)
    for i in range(n_v):
        ci_low[i], ci_high[i] = wilson_interval(count[i], n_in)
    exponent = np.full((n_v, n_a), np.nan)
    error = np.full((n_v, n_a), np.nan)
    settles = np.zeros((n_v, n_a), dtype=bool)
    label = np.full((n_v, n_a), -1, dtype=np.int32)
    for i in range(n_v):
        if spectra is not None:
            for (name, _first), lam, err, fin in zip(_representatives(ident[i]), spectra[i]["exponents"][:, 0],
                                                     spectra[i]["errors"][:, 0], spectra[i]["final_regime"]):
                j = index[name]
                exponent[i, j], error[i, j], settles[i, j] = lam, err, fin >= 0
        for j in range(n_a):
            if count[i, j] > 0:
                lam = exponent[i, j] if math.isfinite(exponent[i, j]) else None
                label[i, j] = LABELS.index(attractor_label(names[j], lam, error[i, j], bool(settles[i, j])))
    image = np.full((n_v, inside.size), -1, dtype=np.int32)
    image[:, flat] = code
    rows_, cols_ = grid.shape
    a0, a1 = grid.names
    data = {
        "identity": (("value", a1, a0), image.reshape(n_v, rows_, cols_),
                     {"long_name": "attractor reached (index into attractor; -1: outside the clearance)"}),
        "count": (("value", "attractor"), count, {"long_name": "initial states that reach the attractor"}),
        "fraction": (("value", "attractor"), fraction, {"long_name": "basin fraction", "units": "1"}),
        "ci_low": (("value", "attractor"), ci_low,
                   {"long_name": f"lower end of the {CONFIDENCE:.0%} Wilson interval of the fraction", "units": "1"}),
        "ci_high": (("value", "attractor"), ci_high,
                    {"long_name": f"upper end of the {CONFIDENCE:.0%} Wilson interval of the fraction", "units": "1"}),
        "exponent": (("value", "attractor"), exponent,
                     {"long_name": "largest Lyapunov exponent (NaN: not reached or not computed)", "units": "1"}),
        "exponent_error": (("value", "attractor"), error,
                           {"long_name": "error estimate of the largest exponent (spread over sub-windows)",
                                "units": "1"}),
        "label": (("value", "attractor"), label, {"long_name": "label of the attractor at the value (-1: absent)",
                                                      "flag_values": np.arange(len(LABELS), dtype=np.int32),
                                                      "flag_meanings": " ".join(LABELS)}),
        "u0_re": (("value", "point"), u_all.real.copy(), {"long_name": "initial U, real part", "units": "1"}),
        "u0_im": (("value", "point"), u_all.imag.copy(), {"long_name": "initial U, imaginary part", "units": "1"}),
        "du0_re": (("value", "point"), du_all.real.copy(), {"long_name": "initial U', real part", "units": "1"}),
        "du0_im": (("value", "point"), du_all.imag.copy(), {"long_name": "initial U', imaginary part", "units": "1"}),
    }
    from .attributes import PARAMETER_UNITS, SUMMARY_ATTRS, parameter_attrs, settings_attrs
    from .grids import AXIS_ATTRS

    for name in PARAMETER_ORDER:
        data[f"param_{name}"] = (("value",), np.array([getattr(p, name) for p in path]),
                                 {"long_name": f"model parameter {name} at each value", "units": PARAMETER_UNITS[name]})
    unit = "1" if machine is None or param in PARAMETER_ORDER else Machine.units()[param]
    coords = {
        "value": ("value", vals, {"long_name": param, "units": unit}),
        "attractor": ("attractor", np.array(names if names else [""], dtype=str)[:n_a], {"long_name": "attractor"}),
        a0: (a0, grid.axis0, AXIS_ATTRS[a0]),
        a1: (a1, grid.axis1, AXIS_ATTRS[a1]),
    }

    attrs: dict[str, Any] = {
        "title": "attractors against a parameter",
        "source": f"rotorcontact {__version__}",
        "param": param,
        "grid_kind": grid.kind,
        "grid": grid.describe(),
        "match_tol": float(match_tol),
        "lyapunov": np.int8(spectra is not None),
        "t_lyapunov": float(t_lyapunov),
        "confidence": float(CONFIDENCE),
        "chunk_size": np.int32(chunk_size),
        "simulated_per_value": np.int32(n_in),
    }
    attrs.update(parameter_attrs(params, skip=param if param in PARAMETER_ORDER else None, machine=machine))
    attrs.update(settings_attrs(result.settings))
    ds = xr.Dataset(data, coords=coords, attrs=attrs)
    ds["n_impacts"] = (("value", "point"), result.n_impacts.astype(np.int32), SUMMARY_ATTRS["n_impacts"])
    ds["transient_impacts"] = (("value", "point"), result.transient_impacts.astype(np.int32),
                               SUMMARY_ATTRS["transient_impacts"])
    return ds


def attractors_of(ds) -> tuple[Attractor, ...]:
    """The `Attractor` records of an attractors dataset."""
    vals = ds["value"].values
    out = []
    for j, name in enumerate(str(n) for n in ds["attractor"].values):
        count = ds["count"].values[:, j]
        if not count.any():
            continue
        present = count > 0
        codes = ds["label"].values[:, j]
        labels = tuple(LABELS[c] if c >= 0 else "" for c in codes)
        seen = [lab for lab in labels if lab]
        label = max(LABELS, key=lambda lab: (seen.count(lab), -LABELS.index(lab)))
        on = np.flatnonzero(present)
        appears = float(vals[on[0]]) if on[0] > 0 else None
        disappears = float(vals[on[-1] + 1]) if on[-1] + 1 < vals.size else None
        out.append(Attractor(
            name=name, label=label, present=present, count=count.astype(int),
            fraction=ds["fraction"].values[:, j], ci_low=ds["ci_low"].values[:, j], ci_high=ds["ci_high"].values[:, j],
            exponent=ds["exponent"].values[:, j], exponent_error=ds["exponent_error"].values[:, j], labels=labels,
            appears=appears, disappears=disappears,
        ))
    return tuple(out)
