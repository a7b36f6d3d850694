"""JSON data: the plain form of results printed by ``--json`` and written to reports."""

from __future__ import annotations

import json
import math
from typing import IO, Any

import numpy as np

from ..errors import ParameterError
from ..model.validation import quoted

__all__ = ["jsonable", "dump_json"]


def jsonable(obj: Any) -> Any:
    """Plain JSON data: complex as [re, im], non-finite numbers as null.

    Parameters
    ----------
    obj : Any
        Dicts, lists, tuples, numpy arrays and scalars, nested.

    Returns
    -------
    Any
        The same data made of dicts, lists, str, int, float, bool and None.

    Raises
    ------
    ParameterError
        For an object JSON cannot hold (a set, a `Parameters`, bytes ...), naming its type.
    """
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [jsonable(v) for v in obj.tolist()]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (complex, np.complexfloating)):
        return [jsonable(float(obj.real)), jsonable(float(obj.imag))]
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if obj is None or isinstance(obj, str):
        return obj
    raise ParameterError(f"data holds a {type(obj).__name__} ({quoted(obj)}), which JSON cannot hold; allowed: "
                         "dicts, lists, tuples, numpy arrays, numbers, text and None")


def dump_json(data: Any, stream: IO[str]) -> None:
    """Write ``data`` (made `jsonable`) to ``stream``, indented, then a newline; NaN is never written."""
    json.dump(jsonable(data), stream, indent=2, allow_nan=False)
    stream.write("\n")
