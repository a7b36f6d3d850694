"""The parameters at each value of one varied quantity: a model parameter, or a machine quantity in SI units."""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.params import Machine, Parameters
from .batch import PARAMETER_ORDER

__all__ = ["parameter_path"]


def parameter_path(params: Parameters, param: str, values: Any, machine: Machine | None = None) -> list[Parameters]:
    """The parameters at each value of ``param``: a model parameter, or with ``machine`` a machine quantity (SI).

    Raises
    ------
    ParameterError
        For an unknown parameter, a value that gives invalid parameters, or a machine quantity without
        a machine.
    """
    machine_fields = tuple(f.name for f in fields(Machine))
    vals = np.asarray(values, dtype=float).reshape(-1)
    if vals.size == 0 or not np.all(np.isfinite(vals)):
        raise ParameterError(f"values of {param!r} must be finite and at least one")
    if param in PARAMETER_ORDER:
        return [params.replace(**{param: float(v)}) for v in vals]
    if param in machine_fields:
        if machine is None:
            raise ParameterError(f"param = {param!r} is a machine quantity; allowed with a machine only "
                                 f"(model parameters: {', '.join(PARAMETER_ORDER)})")
        return [replace(machine, **{param: float(v)}).parameters() for v in vals]
    raise ParameterError(f"param = {param!r} is invalid; allowed: {', '.join(PARAMETER_ORDER)}, or with a machine "
                         f"{', '.join(machine_fields)}")
