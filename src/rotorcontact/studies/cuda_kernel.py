"""The GPU kernel of `rotorcontact.studies.cuda_batch`: one thread per lane of `rotorcontact.studies.compact_batch`.

Importing this module imports numba.cuda; only `rotorcontact.studies.cuda_batch` does, when a study asks
for the GPU. Under numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) a thread's arrays are the
simulator's own objects, which compiled CPU code cannot take, so there the lane runs as the interpreted
twin of its kernel (`rotorcontact.interpreted`), the same operations in the same order.
"""

from __future__ import annotations

from numba import config, cuda, float64

from ..interpreted import interpreted
from .compact_batch import RING, compact_lane

RING_ROWS = 2 * RING
_lane = interpreted(compact_lane) if config.ENABLE_CUDASIM else compact_lane


@cuda.jit(cache=True)
def lanes_kernel(params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle, c_tol, c_rdot,
                 c_height, c_dt, sections, summary, deferred, start_u, start_du):
    """`rotorcontact.studies.compact_batch.compact_lanes`, lane ``cuda.grid(1)`` per thread."""
    lane = cuda.grid(1)
    if lane < params.shape[0]:
        ring = cuda.local.array((RING_ROWS, 4), float64)
        s, u, du = _lane(lane, params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle,
                         c_tol, c_rdot, c_height, c_dt, sections, summary, ring)
        deferred[lane] = s
        start_u[lane] = u
        start_du[lane] = du
