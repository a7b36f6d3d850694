"""The parameters at each value of one varied quantity: a model parameter, or a machine quantity in SI units."""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.params import Machine, Parameters
from .batch import PARAMETER_ORDER
from ..model.validation import check_length, check_machine, check_machine_params, check_params, real_array
from .grids import MAX_GRID_POINTS

__all__ = ["parameter_path", "path_values"]


def path_values(param: Any, values: Any) -> np.ndarray:
    """``values`` of ``param`` as a flat array of finite reals, at least one and at most `MAX_GRID_POINTS`;
    text, bools and complex numbers are refused (`rotorcontact.model.validation.real_array`)."""
    check_length(f"values of {param!r}", values, MAX_GRID_POINTS)
    vals = real_array(values)
    if vals is None:
        raise ParameterError(f"values of {param!r} = {values!r} are not real numbers; allowed: a list or array of "
                             "real numbers (not strings, bools or complex numbers)")
    vals = vals.reshape(-1)
    if vals.size == 0 or not np.all(np.isfinite(vals)):
        raise ParameterError(f"values of {param!r} must be finite and at least one")
    return vals


def parameter_path(params: Parameters, param: str, values: Any, machine: Machine | None = None) -> list[Parameters]:
    """The parameters at each value of ``param``: a model parameter, or with ``machine`` a machine quantity (SI).

    Raises
    ------
    ParameterError
        For an unknown parameter, a value that gives invalid parameters, a machine quantity without a
        machine, or ``params`` that are not the machine's (``param`` excepted when it is a model parameter).
    """
    check_params(params)
    check_machine(machine)
    machine_fields = tuple(f.name for f in fields(Machine))
    vals = path_values(param, values)
    check_machine_params(params, machine, skip=param if param in PARAMETER_ORDER else None)
    if param in PARAMETER_ORDER:
        return [params.replace(**{param: float(v)}) for v in vals]
    if param in machine_fields:
        if machine is None:
            raise ParameterError(f"param = {param!r} is a machine quantity; allowed with a machine only "
                                 f"(model parameters: {', '.join(PARAMETER_ORDER)})")
        return [replace(machine, **{param: float(v)}).parameters() for v in vals]
    raise ParameterError(f"param = {param!r} is invalid; allowed: {', '.join(PARAMETER_ORDER)}, or with a machine "
                         f"{', '.join(machine_fields)}")
