"""The parameters at each value of one varied quantity: a model parameter, or a machine quantity in SI units."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from ..errors import ParameterError
from ..model.params import OPTIONAL_MACHINE_KEYS, PAPER_MACHINE_KEYS, Machine, Parameters
from ..model.validation import check_length, check_machine, check_machine_params, check_params, quoted, real_array
from .batch import PARAMETER_ORDER
from .grids import MAX_GRID_POINTS

__all__ = ["check_path_param", "machine_at", "parameter_path", "path_values"]


def path_values(param: Any, values: Any) -> np.ndarray:
    """``values`` of ``param`` as a flat array of finite reals, strictly increasing, at least one and at most
    `MAX_GRID_POINTS`; text, bools and complex numbers are refused (`rotorcontact.model.validation.real_array`)."""
    check_length(f"values of {param!r}", values, MAX_GRID_POINTS)
    vals = real_array(values)
    if vals is None:
        raise ParameterError(f"values of {param!r} = {values!r} are not real numbers; allowed: a list or array of "
                             "real numbers (not strings, bools or complex numbers)")
    vals = vals.reshape(-1)
    if vals.size == 0 or not np.all(np.isfinite(vals)):
        raise ParameterError(f"values of {param!r} must be finite and at least one")
    if not np.all(np.diff(vals) > 0.0):
        raise ParameterError(f"values of {param!r} = {quoted(values)} must increase strictly (a path through the "
                             "values in order)")
    return vals


def check_path_param(param: Any, machine: Machine | None, name: str = "param", given: str = "a machine") -> str:
    """Return ``param`` if it can be varied: a model parameter, or with a machine one of the machine's keys
    that the paper's dimensionless model depends on (`PAPER_MACHINE_KEYS`).

    ``name`` and ``given`` name the parameter and the way to give a machine in the error (the command line's
    ``--param`` and ``--machine``).

    Raises
    ------
    ParameterError
        Naming ``name``: for an unknown parameter, a machine quantity without a machine, or a key of the general
        model (MODEL.md §7-8: gravity, anisotropy, spin inertia, race, compliant contact, stator on springs),
        which the studies on the paper's model leave out: every value would give the same result.
    """
    if param in PARAMETER_ORDER:
        return param
    allowed = f"{', '.join(PARAMETER_ORDER)}, or with {given} {', '.join(PAPER_MACHINE_KEYS)}"
    if param in PAPER_MACHINE_KEYS:
        if machine is None:
            raise ParameterError(f"{name} = {param!r} is a machine quantity; allowed with {given} only "
                                 f"(model parameters: {', '.join(PARAMETER_ORDER)})")
        return param
    if param in OPTIONAL_MACHINE_KEYS:
        raise ParameterError(f"{name} = {param!r} is a key of the general model (MODEL.md §7-8), which this study "
                             f"leaves out (it computes on the paper's model, MODEL.md §2: every value would give "
                             f"the same result); allowed: {allowed}")
    raise ParameterError(f"{name} = {param!r} is invalid; allowed: {allowed}")


def parameter_path(params: Parameters, param: str, values: Any, machine: Machine | None = None) -> list[Parameters]:
    """The parameters at each value of ``param``: a model parameter, or with ``machine`` a machine quantity (SI)
    of the paper's model (`check_path_param`).

    Raises
    ------
    ParameterError
        For a ``param`` that `check_path_param` refuses, a value that gives invalid parameters, or ``params``
        that are not the machine's (``param`` excepted when it is a model parameter).
    """
    check_params(params)
    check_machine(machine)
    check_path_param(param, machine)
    vals = path_values(param, values)
    check_machine_params(params, machine, skip=param if param in PARAMETER_ORDER else None)
    if param in PARAMETER_ORDER:
        return [params.replace(**{param: float(v)}) for v in vals]
    return [machine_at(machine, param, v).parameters() for v in vals]


def machine_at(machine: Machine, param: str, value: float) -> Machine:
    """The machine at one value of a path: ``param``, one of its keys, set to ``value`` (SI); a model parameter
    leaves the machine as it is. Its scales (`rotorcontact.model.si`) are those of that value: varying the
    speed changes the time scale 1 / Omega that turns rates and times into SI.

    Raises
    ------
    ParameterError
        For a ``machine`` that is not a Machine, a ``param`` that `check_path_param` refuses, or a value the
        machine refuses.
    """
    check_machine(machine, optional=False)
    check_path_param(param, machine)
    if param in PARAMETER_ORDER:
        return machine
    return replace(machine, **{param: float(value)})
