"""Compile the kernels ahead of use: ``rotorcontact warmup``.

Kernels are compiled by numba on their first call and cached on disk next to their modules (``cache=True``),
where every later process, worker processes included, loads them. `warm_up` makes those first calls on
tiny problems, group by group, so that a machine's first real command, or a cluster's workers, start
from the cache.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from ..errors import ParameterError

__all__ = ["WARMUP_GROUPS", "warm_up"]


def _simulate() -> None:
    from ..model.params import Parameters
    from ..simulation.simulator import simulate

    simulate(Parameters.reference(), 0.0, 0.0, 20.0)


def _studies() -> None:
    import numpy as np

    from ..model.angles import angle_difference
    from ..model.params import Parameters
    from ..studies.basins import basins
    from ..studies.batch import BatchSettings, parameter_array, run_lanes
    from ..studies.sweep import sweep

    p = Parameters.reference()
    # the batch kernel, which a study's threads and its worker processes (joblib, Dask) all run
    rows = parameter_array([p, p]).reshape(2, 1, -1)
    u0 = np.array([[0j], [0.5 + 0j]])
    run_lanes(rows, u0, np.zeros_like(u0), BatchSettings(n_transient=5, n_record=5), carry=False, parallel=False)
    # the classification compares the angles of all of a study's points in one call (basins of periodic
    # orbits, attractors): interpreted, that call takes about 0.4 s per 250,000 points
    angle_difference(np.zeros(2), np.zeros(2))
    sweep(p, "omega", [0.79, 0.8], n_transient=5, n_record=5, progress=False)
    basins(p, "x=-0.5:0.5:2,y=-0.5:0.5:2", n_transient=5, n_record=5, settle=2, progress=False)


def _orbits() -> None:
    from ..maps.impact_map import one_impact_orbits
    from ..model.params import Parameters

    one_impact_orbits(Parameters.reference(), 12.0)


def _drop() -> None:
    from ..model.params import Machine, reference_machine
    from ..simulation.drop_run import drop

    m = Machine(**{**reference_machine().as_dict(), "gravity": 9.81, "polar_inertia": 0.04})
    drop(m, t_end=0.02)


#: The groups of kernels `warm_up` compiles, by the commands that use them.
WARMUP_GROUPS: dict[str, tuple[str, Callable[[], None]]] = {
    "simulate": ("simulate, lyapunov", _simulate),
    "studies": ("sweep, basins, attractors, design-map", _studies),
    "orbits": ("orbits, branches, cascade, codim2, local, reproduce", _orbits),
    "drop": ("drop, drop-map, simulate --machine with the general keys", _drop),
}


def warm_up(groups: Iterable[str] | None = None) -> dict[str, float]:
    """Compile (or load from the cache) the kernels of ``groups`` (default: all of `WARMUP_GROUPS`); one group
    may be given by its name alone.

    Returns
    -------
    dict
        Seconds each group took, by group name: its compile time on a cold cache, its load time on a warm one.

    Raises
    ------
    ParameterError
        For a group not in `WARMUP_GROUPS`, or ``groups`` that is neither a name nor a list of names.
    """
    if isinstance(groups, str):
        groups = [groups]
    if groups is not None and not isinstance(groups, (list, tuple, set, frozenset)):
        raise ParameterError(f"groups = {groups!r} is invalid; allowed: a group name, a list of them, or None (all: "
                             f"{', '.join(WARMUP_GROUPS)})")
    names = list(WARMUP_GROUPS) if groups is None else list(groups)
    for name in names:
        if not isinstance(name, str) or name not in WARMUP_GROUPS:
            raise ParameterError(f"group = {name!r} is not a kernel group; allowed: {', '.join(WARMUP_GROUPS)}")
    from ..interpreted import compiled_only

    seconds = {}
    for name in names:
        start = time.perf_counter()
        with compiled_only():
            WARMUP_GROUPS[name][1]()
        seconds[name] = time.perf_counter() - start
    return seconds
