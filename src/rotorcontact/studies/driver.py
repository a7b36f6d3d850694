"""The driver of a chunked study: resume, run, assemble, write.

A study (a brute-force diagram, a basin of attraction) describes itself by

* a *manifest*, everything that defines its chunks (the chunk folder of an
  interrupted run is resumed only for the same manifest), and a *digest* of
  everything that defines its finished file (`rotorcontact.studies.execution.study_digest`);
* its chunk keys and its waves of `rotorcontact.studies.execution.ChunkTask`
  for a chunk size;
* an *assemble* function that builds its xarray Dataset from the finished chunks.

`run_study` does the rest, the same way for every study: it returns an output
file that already holds the finished study as it is, resumes the chunks of an
interrupted run with the chunk size they were cut with, runs the waves on the
executor asked for with a progress bar, assembles the result from the chunk
files (so that a resumed run is identical to an uninterrupted one), writes the
NetCDF file and removes the chunk folder.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

import numpy as np

from ..errors import ParameterError
from ..model.validation import check_bool, check_int, check_type, quoted
from .netcdf import check_output_path, read_finished, write_netcdf
from .execution import (ChunkStore, ChunkTask, StoredChunks, check_chunk_size, chunk_folder, fitted_chunk_size,
                        make_executor, progress_bar, run_waves)

__all__ = ["StudyRun", "run_study"]

#: The chunks of a study as a function of the chunk size: their keys, in order.
Keys = Callable[[int], list[str]]
#: The waves of chunks for a chunk size; a wave may read the finished chunks of earlier waves in ``sink``.
Waves = Callable[[int, dict[str, dict[str, np.ndarray]]], Iterable[list[ChunkTask]]]
#: The dataset of the study and the impacts it simulated, from the chunk size and a loader of finished chunks.
Assemble = Callable[[int, Callable[[str], dict[str, np.ndarray]]], tuple[Any, int]]


@dataclass(frozen=True)
class StudyRun:
    """What `run_study` did.

    Attributes
    ----------
    dataset : xarray.Dataset
        The study, with its digest as the attribute ``study_digest``.
    path : pathlib.Path or None
        The NetCDF file written (or read back), if any.
    chunk_size : int
        The chunk size used (that of an interrupted run when one was resumed).
    chunks_computed, chunks_reused : int
        Chunks computed by this call, and finished chunks found from an
        earlier, interrupted call (or all chunks, when `reused_file`).
    impacts_simulated : int
        Impacts computed (transients and windows, including reused chunks).
    reused_file : bool
        The output file already held this finished study and was returned as it is.
    handed_to_cpu : int
        With ``backend="cuda"``: simulations of this call computed on the CPU because the GPU's summary of
        their window could not be exact (`rotorcontact.studies.compact_batch.compact_item`; in a lane of
        several steps, that step and the lane's later ones).
    """

    dataset: Any = field(repr=False)
    path: Path | None
    chunk_size: int
    chunks_computed: int
    chunks_reused: int
    impacts_simulated: int
    reused_file: bool = False
    handed_to_cpu: int = 0


def dataset_impacts(ds) -> int:
    """Impacts simulated for a study's dataset: its windows' and its transients' (``n_impacts``, and
    ``transient_impacts`` where a study has transients)."""
    transient = ds["transient_impacts"].values.sum() if "transient_impacts" in ds else 0
    return int(ds["n_impacts"].values.sum() + transient)


def run_study(
    manifest: dict[str, Any],
    digest: str,
    *,
    keys: Keys,
    waves: Waves,
    assemble: Assemble,
    n_items: int,
    desc: str,
    chunk_size: int,
    out: str | Path | None = None,
    resume: bool = True,
    keep_chunks: bool = False,
    n_jobs: int | None = None,
    scheduler: Any = None,
    processes: bool = True,
    progress: bool = True,
    backend: str = "cpu",
    fit_chunks: bool = False,
) -> StudyRun:
    """Run a chunked study (see the module docstring).

    Parameters
    ----------
    manifest : dict
        Everything that defines the chunks (`rotorcontact.studies.execution.ChunkStore`).
    digest : str
        `rotorcontact.studies.execution.study_digest` of everything that defines the finished file.
    keys : callable
        ``keys(chunk_size)``: the keys of all chunks.
    waves : callable
        ``waves(chunk_size, sink)``: the waves of chunk tasks (`rotorcontact.studies.execution.run_waves`).
    assemble : callable
        ``assemble(chunk_size, load)``: the dataset and the impacts simulated, where ``load(key)``
        gives the arrays of a finished chunk, once for each key (without ``out`` the chunk held in memory is
        let go as it is loaded).
    n_items : int
        Simulations of the study (the length of the progress bar).
    desc : str
        Label of the progress bar.
    chunk_size : int
        Chunk size asked for; an interrupted run is resumed with its own.
    fit_chunks : bool
        ``chunk_size`` is the study's default rather than the user's: on worker processes it is cut
        down to give each worker several chunks (`rotorcontact.studies.execution.fitted_chunk_size`).
    out : path, optional
        NetCDF file to write; chunks go to ``out + ".chunks"`` meanwhile.
    resume : bool
        Continue from the chunks of an interrupted run with the same manifest,
        and return ``out`` as it is when it already holds this finished study;
        False computes afresh.
    keep_chunks : bool
        Keep the chunk folder after the merge.
    n_jobs, scheduler, processes, backend
        The executor (`rotorcontact.studies.execution.make_executor`).
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    StudyRun

    Raises
    ------
    ParameterError
        For a manifest that is not a dict, a digest that is not text, ``keys``, ``waves`` or ``assemble``
        not callable, or a count, label or chunk size of the wrong kind (and as the executor and the
        output path are checked).
    """
    check_type("manifest", manifest, dict, "a dict of everything that defines the chunks")
    check_type("digest", digest, str, "the study's digest (study_digest)")
    for name, value in (("keys", keys), ("waves", waves), ("assemble", assemble)):
        if not callable(value):
            raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: a function (see run_study)")
    check_int("n_items", n_items, 0)
    check_type("desc", desc, str, "the progress bar's label")
    chunk_size = check_chunk_size(chunk_size)
    fit_chunks = check_bool("fit_chunks", fit_chunks)
    resume, keep_chunks, progress = (check_bool(n, v) for n, v in
                                     (("resume", resume), ("keep_chunks", keep_chunks), ("progress", progress)))
    store = None
    if out is not None:
        out = check_output_path(out)
        finished = read_finished(out, digest) if resume else None
        if finished is not None:
            used = int(finished.attrs["chunk_size"])
            return StudyRun(dataset=finished, path=out, chunk_size=used, chunks_computed=0,
                            chunks_reused=len(keys(used)), impacts_simulated=dataset_impacts(finished),
                            reused_file=True)
    # the executor first: a cluster that cannot be used leaves no chunk folder behind
    with make_executor(n_jobs, scheduler, processes=processes, backend=backend) as executor:
        if fit_chunks:
            chunk_size = fitted_chunk_size(n_items, chunk_size, executor.workers)
        if out is not None:
            # the chunks of an interrupted run are resumed as they were cut (the results do not depend on it)
            store = ChunkStore(chunk_folder(out), manifest, resume=resume, layout={"chunk_size": chunk_size})
            chunk_size = int(store.layout["chunk_size"])
        reused = sum(store.done(k) for k in keys(chunk_size)) if store is not None else 0
        # results held in memory only without a store; with one, each wave is built from the stored chunks
        sink = {} if store is None else StoredChunks(store, keys(chunk_size))
        with progress_bar(n_items, desc, progress) as bar:
            computed = run_waves(executor, waves(chunk_size, sink), store, bar, sink)
    # assemble from the chunk files when there are any, so that a resumed run is identical; held in memory, each
    # chunk is let go as it is assembled (each is loaded once), so the study is not held twice
    ds, impacts = assemble(chunk_size, store.load if store is not None else sink.pop)
    ds.attrs["study_digest"] = digest
    if backend != "cpu":
        ds.attrs["backend"] = backend  # the GPU's results differ from the CPU's in rounding
    if out is not None:
        write_netcdf(ds, out)
        if not keep_chunks:
            store.remove()
    return StudyRun(dataset=ds, path=out, chunk_size=chunk_size, chunks_computed=computed, chunks_reused=reused,
                    impacts_simulated=int(impacts), handed_to_cpu=int(getattr(executor, "handed_to_cpu", 0)))
