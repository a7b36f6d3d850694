"""The batch kernel on an NVIDIA GPU: one GPU thread per lane, through numba-cuda.

Every thread runs its lane with `rotorcontact.studies.compact_batch`: the simulator's own closed-form
flights, guaranteed impact location (`rotorcontact.simulation.roots`), resets, test for accumulating
impacts, contact phases (sliding, rolling, lift-off), and the batch kernel's transient, window and
classification. A step whose window's summary that form cannot give exactly (`compact_batch.compact_item`:
contact phases that end out of order or after the window's stop, by rounding) is *deferred*: the GPU stops
the lane there, and the CPU batch kernel (`rotorcontact.studies.batch.run_lanes`) computes that step and
the lane's later ones, from the state the GPU reached at the start of the step. So every item gets the
CPU kernel's algorithm and rules, and a deferred item the CPU kernel's numbers.

The GPU evaluates ``sin``, ``cos`` and ``exp`` with its own library (libdevice), and fuses multiplies
and adds, so its last bits can differ from the CPU's: the numbers of a finished item agree with the
CPU's to rounding rather than bit for bit, and chaotic windows drift apart as they do between two
processors. The impact search keeps its tolerances (`rotorcontact.simulation.roots`), far above such
differences; on the 285,000 points of the two 400 x 400 basins of ``benchmarks/cuda_basins.py`` every
point the GPU finished had the CPU's number of impacts and every point the CPU's attractor.

numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) runs this module without a GPU, on the CPU's
arithmetic.

numba-cuda is optional: nothing here is imported until a study asks for ``backend="cuda"``.
"""

from __future__ import annotations

import numpy as np

from .batch import NSUM, BatchSettings, check_lanes, run_lanes

__all__ = ["THREADS_PER_BLOCK", "complete_deferred", "cuda_unavailable", "launch_lanes", "require_cuda",
           "restore_numpy_names", "run_lanes_cuda"]

#: Threads per block of the kernel.
THREADS_PER_BLOCK = 128


def restore_numpy_names() -> None:
    """Give numpy back ``row_stack`` (an alias of ``np.vstack``, removed in numpy 2.5) where it lacks it.

    numba-cuda registers its implementation of ``np.row_stack`` when it first compiles, and fails to compile
    anything without it.
    """
    if not hasattr(np, "row_stack"):
        np.row_stack = np.vstack


def cuda_unavailable() -> str | None:
    """Why the GPU backend cannot run here, or None when it can (a GPU, its driver, and NVVM to compile for it)."""
    restore_numpy_names()
    try:
        from numba import config, cuda
    except Exception as exc:  # numba-cuda missing or broken: its own words
        return f"numba.cuda cannot be imported ({type(exc).__name__}: {exc})"
    try:
        if not cuda.is_available():
            return "numba.cuda finds no usable CUDA GPU and driver"
    except Exception as exc:
        return f"numba.cuda cannot reach a GPU ({type(exc).__name__}: {exc})"
    if not config.ENABLE_CUDASIM:
        try:
            from numba.cuda.cudadrv import nvvm

            compiler = nvvm.is_available()
        except Exception:
            compiler = False
        if not compiler:
            return ("numba.cuda finds no NVVM, the CUDA toolkit's compiler library (numba-cuda's extra brings "
                    "one: pip install 'numba-cuda[cu12]')")
    return None


def require_cuda(name: str = "backend = 'cuda'") -> None:
    """Raise `ParameterError` naming the reason when the GPU backend cannot run here.

    ``name`` is how the message names the choice (``"--backend cuda"`` on the command line).
    """
    from ..errors import ParameterError

    reason = cuda_unavailable()
    if reason is not None:
        raise ParameterError(
            f"{name} cannot run here: {reason}; allowed: 'cpu', or 'cuda' on a machine with an NVIDIA GPU, "
            "its driver and numba-cuda (pip install 'rotorcontact[cuda]')"
        )


def complete_deferred(params: np.ndarray, u0: np.ndarray, du0: np.ndarray, settings: BatchSettings, carry: bool,
                      sections: np.ndarray, summary: np.ndarray, deferred: np.ndarray, start_u: np.ndarray,
                      start_du: np.ndarray) -> None:
    """Compute the deferred steps of each lane with the CPU kernel, in place.

    A lane deferred at step s is run from s on: with ``carry`` from the state where step s - 1 ended
    (``start_u``, ``start_du``), else from each step's own initial state.
    """
    for step in np.unique(deferred[deferred >= 0]):
        lanes = np.flatnonzero(deferred == step)
        u = np.ascontiguousarray(u0[lanes, step:])
        du = np.ascontiguousarray(du0[lanes, step:])
        if carry:
            u[:, 0] = start_u[lanes]
            du[:, 0] = start_du[lanes]
        sec, summ = run_lanes(np.ascontiguousarray(params[lanes, step:]), u, du, settings, carry=carry,
                              parallel=True)
        sections[lanes, step:] = sec
        summary[lanes, step:] = summ


def launch_lanes(params: np.ndarray, u0: np.ndarray, du0: np.ndarray, settings: BatchSettings, *,
                 carry: bool) -> tuple[np.ndarray, ...]:
    """The GPU's part of `run_lanes_cuda`: every lane up to its first deferred step, if any.

    Returns
    -------
    sections, summary : numpy.ndarray
        As `rotorcontact.studies.batch.run_lanes`, for the steps finished on the GPU.
    deferred : numpy.ndarray of int
        Per lane, its first step left to the CPU, or -1.
    start_u, start_du : numpy.ndarray of complex
        Per lane, the state at the start of that step.
    """
    params, u0, du0 = check_lanes(params, u0, du0, settings)
    restore_numpy_names()
    from numba import cuda

    from .cuda_kernel import lanes_kernel

    n_lanes, n_steps = params.shape[:2]
    blocks = max(1, -(-n_lanes // THREADS_PER_BLOCK))
    c_tol, c_rdot, c_height, c_dt = settings.chatter_values
    try:
        d_sections = cuda.device_array((n_lanes, n_steps, settings.keep, 4), dtype=np.float64)
        d_summary = cuda.device_array((n_lanes, n_steps, NSUM), dtype=np.float64)
        d_deferred = cuda.device_array(n_lanes, dtype=np.int64)
        d_start_u = cuda.device_array(n_lanes, dtype=np.complex128)
        d_start_du = cuda.device_array(n_lanes, dtype=np.complex128)
        lanes_kernel[blocks, THREADS_PER_BLOCK](
            cuda.to_device(np.require(params, dtype=np.float64, requirements=["C"])),
            cuda.to_device(np.require(u0, dtype=np.complex128, requirements=["C"])),
            cuda.to_device(np.require(du0, dtype=np.complex128, requirements=["C"])), bool(carry),
            settings.n_transient, settings.n_record, settings.transient_time, settings.record_time,
            settings.settle, c_tol, c_rdot, c_height, c_dt, d_sections, d_summary, d_deferred, d_start_u,
            d_start_du,
        )
    except Exception as exc:  # compiling, memory or launch: numba-cuda's own words, on one line
        raise RuntimeError(
            f"the GPU kernel could not be compiled or launched ({type(exc).__name__}: {' '.join(str(exc).split())})"
        ) from exc
    return (d_sections.copy_to_host(), d_summary.copy_to_host(), d_deferred.copy_to_host(),
            d_start_u.copy_to_host(), d_start_du.copy_to_host())


def run_lanes_cuda(params: np.ndarray, u0: np.ndarray, du0: np.ndarray, settings: BatchSettings, *,
                   carry: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """`rotorcontact.studies.batch.run_lanes` with the lanes on the GPU (see the module docstring).

    Returns
    -------
    sections, summary : numpy.ndarray
        As `rotorcontact.studies.batch.run_lanes`.
    deferred : numpy.ndarray of int
        Per lane, the first step computed on the CPU (that step and the lane's later ones were; see the
        module docstring), or -1.
    """
    sections, summary, deferred, start_u, start_du = launch_lanes(params, u0, du0, settings, carry=carry)
    complete_deferred(params, u0, du0, settings, carry, sections, summary, deferred, start_u, start_du)
    return sections, summary, deferred
