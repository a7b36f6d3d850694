"""The check that a Dataset is a given study's result, for the functions and figures that read one.

It imports no compiled kernel: a figure of a study's file needs none.
"""

from __future__ import annotations

from typing import Any, Sequence

from ..errors import ParameterError
from ..model.validation import check_type, quoted

__all__ = ["check_dataset", "study_dataset"]


def study_dataset(ds: Any) -> Any:
    """The Dataset of a study's result (`basins`, `sweep`, `attractors` and `drop_map` return an object
    whose ``dataset`` it is), or ``ds`` itself, for `check_dataset`: a figure, or a reader of the
    results such as `rotorcontact.studies.drop_map.failed_points`, takes either."""
    import xarray as xr

    inner = getattr(ds, "dataset", None)
    return inner if not isinstance(ds, xr.Dataset) and isinstance(inner, xr.Dataset) else ds


def check_dataset(ds: Any, needs: Sequence[str], made_by: str, *, attrs: Sequence[str] = (), name: str = "ds"):
    """Return ``ds`` if it is an `xarray.Dataset` with the variables (or coordinates) ``needs`` and the
    attributes ``attrs`` that a figure reads, as the function ``made_by`` writes them.

    Raises
    ------
    ParameterError
        Naming ``name`` and the value: for an object that is not a Dataset, and for a Dataset that lacks
        one of them (the result of another study), saying which study's result is expected.
    """
    import xarray as xr

    check_type(name, ds, xr.Dataset, f"a {made_by} result or its Dataset")
    missing = [f"variable {v!r}" for v in needs if v not in ds.variables]
    missing += [f"attribute {a!r}" for a in attrs if a not in ds.attrs]
    if missing:
        wanted = [f"variables {', '.join(map(repr, needs))}"] if needs else []
        wanted += [f"attributes {', '.join(map(repr, attrs))}"] if attrs else []
        raise ParameterError(f"{name} = {quoted(ds)} is not a result of {made_by}; allowed: a {made_by} "
                             f"result or its Dataset (it needs {' and '.join(wanted)}; this one lacks "
                             f"{', '.join(missing)})")
    return ds
