"""Variables and attributes of the NetCDF files of the studies (brute-force diagrams, basins).

The model parameters with their units, the machine in SI units, the transient
and window settings, and the per-item results of a batch (regime flags,
counts, contact time, final state), named and described as in the files of
`rotorcontact.studies.sweep` and `rotorcontact.studies.basins`.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..model.params import Machine, Parameters
from ..model.validation import check_machine, check_params, check_type
from ..simulation.simulator import STATUS_NAMES
from .batch import FINAL_KIND_NAMES, PARAMETER_ORDER, REGIME_NAMES, BatchResult, BatchSettings

__all__ = [
    "PARAMETER_UNITS",
    "PARAMETER_LONG_NAMES",
    "RATE_UNITS",
    "REGIME_COMMENT",
    "SUMMARY_ATTRS",
    "parameter_attrs",
    "settings_attrs",
    "summary_variables",
]

#: Units of the dimensionless parameters.
PARAMETER_UNITS = {
    "gamma": "1",
    "omega": "1",
    "rho": "1",
    "mu": "1",
    "d": "1",
    "phi": "rad",
    "r_ratio": "1",
}
PARAMETER_LONG_NAMES = {
    "gamma": "damping c / (m Omega)",
    "omega": "stiffness ratio sqrt(k / (m Omega^2))",
    "rho": "eccentricity over clearance e_c / c_r",
    "mu": "Coulomb friction coefficient",
    "d": "Newton restitution coefficient",
    "phi": "unbalance phase",
    "r_ratio": "rotor radius over clearance R / c_r",
}

#: Units of an angular velocity in dimensionless time (thetadot): a rate, not an angle.
RATE_UNITS = dict(units="1", description="radians per unit of dimensionless time t = Omega tau")


#: Note on the regime names stored with the flags (files of earlier versions used the former names).
REGIME_COMMENT = "forward-rub and backward-whirl were formerly named rub and rolling"


def _flag_attrs(names: Sequence[str], values: Sequence[int] | None = None, **extra: str) -> dict[str, Any]:
    """CF flag attributes: ``flag_values`` (int32, default 0, 1, ...) and ``flag_meanings`` for ``names``."""
    vals = list(range(len(names))) if values is None else list(values)
    return dict(flag_values=np.asarray(vals, dtype=np.int32), flag_meanings=" ".join(names), **extra)


SUMMARY_ATTRS: dict[str, dict[str, Any]] = {
    "regime": _flag_attrs(REGIME_NAMES, long_name="regime of the recorded window", comment=REGIME_COMMENT),
    "impacts_per_period": dict(long_name="impacts per period of a periodic impacting window (0: none)", units="1"),
    "period": dict(long_name="period of a periodic impacting window", units="1"),
    "n_impacts": dict(long_name="impacts in the recorded window", units="1"),
    "n_contacts": dict(long_name="contact phases in the recorded window", units="1"),
    "transient_impacts": dict(long_name="impacts in the transient", units="1"),
    "contact_time": dict(long_name="time in continuous contact during the recorded window", units="1"),
    "final_kind": _flag_attrs(list(FINAL_KIND_NAMES.values()), list(FINAL_KIND_NAMES.keys()),
                              long_name="motion at the end of the window"),
    "status": _flag_attrs(list(STATUS_NAMES.values()), list(STATUS_NAMES.keys()),
                          long_name="how the recorded window ended"),
    "transient_status": _flag_attrs(list(STATUS_NAMES.values()), list(STATUS_NAMES.keys()),
                                    long_name="how the transient ended"),
    "t_transient": dict(long_name="duration of the transient", units="1"),
    "t_window": dict(long_name="duration of the recorded window", units="1"),
    "final_u_re": dict(long_name="real part of U at the end of the window", units="1"),
    "final_u_im": dict(long_name="imaginary part of U at the end of the window", units="1"),
    "final_du_re": dict(long_name="real part of U' at the end of the window", units="1"),
    "final_du_im": dict(long_name="imaginary part of U' at the end of the window", units="1"),
}
_INT_FIELDS = ("regime", "impacts_per_period", "n_impacts", "n_contacts", "transient_impacts", "final_kind", "status",
               "transient_status")



def parameter_attrs(params: Parameters, skip: str | None = None, machine: Machine | None = None) -> dict[str, Any]:
    """Attributes holding the model parameters and their units, and the machine in SI units if given (a
    `ParameterError` for what is not `Parameters`, or not a `Machine` or None)."""
    check_params(params)
    check_machine(machine)
    attrs: dict[str, Any] = {}
    for name in PARAMETER_ORDER:
        if name == skip:
            continue
        attrs[name] = float(getattr(params, name))
        attrs[f"{name}_units"] = PARAMETER_UNITS[name]
    if machine is not None:
        units = machine.units()
        for name, value in machine.as_dict().items():
            attrs[f"machine_{name}"] = value if isinstance(value, str) else float(value)
            attrs[f"machine_{name}_units"] = units[name]
    return attrs


def settings_attrs(settings: BatchSettings) -> dict[str, Any]:
    """Attributes holding the transient and window settings (a `ParameterError` for what is not
    `BatchSettings`)."""
    check_type("settings", settings, BatchSettings, "a BatchSettings")
    s = settings.as_dict()
    return {
        "n_transient": np.int32(s["n_transient"]),
        "n_record": np.int32(s["n_record"]),
        "t_transient": float(s["t_transient"]),
        "t_record": float(s["t_record"]),
        "n_keep": np.int32(s["n_keep"]),
        "settle": np.int32(s["settle"]),
        "transient_definition": "events (flights and contact phases) or time, whichever ends first",
        **{name: float(value) for name, value in settings.chatter},
    }


def summary_variables(result: BatchResult, dims: tuple[str, ...]) -> dict[str, Any]:
    """Per-item variables of a batch result for an xarray Dataset (netCDF3 types); a `ParameterError` for
    what is not a `BatchResult`."""
    check_type("result", result, BatchResult, "a BatchResult (simulate_batch)")
    out: dict[str, Any] = {}
    for name in ("regime", "impacts_per_period", "period", "n_impacts", "n_contacts", "transient_impacts",
                 "contact_time", "final_kind", "status", "transient_status", "t_transient", "t_window"):
        arr = getattr(result, name)
        arr = arr.astype(np.int32) if name in _INT_FIELDS else arr.astype(float)
        out[name] = (dims, arr, SUMMARY_ATTRS[name])
    out["final_u_re"] = (dims, result.final_u.real.copy(), SUMMARY_ATTRS["final_u_re"])
    out["final_u_im"] = (dims, result.final_u.imag.copy(), SUMMARY_ATTRS["final_u_im"])
    out["final_du_re"] = (dims, result.final_du.real.copy(), SUMMARY_ATTRS["final_du_re"])
    out["final_du_im"] = (dims, result.final_du.imag.copy(), SUMMARY_ATTRS["final_du_im"])
    return out
