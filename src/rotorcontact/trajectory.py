"""The result of a simulation: impacts, exact dense output, status and a summary."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numba import njit

from .errors import ParameterError
from .flow import equilibrium_point, propagate, to_inertial
from .params import Machine, Parameters

__all__ = ["Trajectory", "ImpactTable", "COLUMNS"]

#: Columns of the impact records, in order. Velocities are just before (no
#: suffix) or just after (``_plus``) the impact; impulses are per unit mass.
COLUMNS = (
    "t",
    "theta",
    "rdot",
    "thetadot",
    "rdot_plus",
    "thetadot_plus",
    "v_rel",
    "normal_impulse",
    "tangential_impulse",
    "u_re",
    "u_im",
    "du_plus_re",
    "du_plus_im",
    "normal_force",
)
_PUBLIC = COLUMNS[:9]


class ImpactTable:
    """Impacts of a trajectory, one entry per impact, as named numpy arrays.

    Attributes
    ----------
    t, theta, rdot, thetadot, rdot_plus, thetadot_plus, v_rel,
    normal_impulse, tangential_impulse : numpy.ndarray
        Time; impact angle in (-pi, pi]; polar velocities before and after;
        relative surface velocity before; normal and tangential impulse per
        unit mass (dimensionless).
    point : numpy.ndarray
        Complex impact point U (on |U| = 1).
    """

    def __init__(self, records: np.ndarray):
        self._records = records
        for i, name in enumerate(COLUMNS):
            setattr(self, name, records[:, i])
        self.point = records[:, 9] + 1j * records[:, 10]
        self.du_plus = records[:, 11] + 1j * records[:, 12]

    def __len__(self) -> int:
        return self._records.shape[0]

    def to_dicts(self, machine: Machine | None = None) -> list[dict[str, float]]:
        """One plain dict per impact (the JSON form)."""
        rows = []
        for rec in self._records:
            row = {name: float(rec[i]) for i, name in enumerate(_PUBLIC)}
            if machine is not None:
                row["t_s"] = row["t"] * machine.time_scale
                row["normal_impulse_Ns"] = row["normal_impulse"] * machine.impulse_scale
                row["tangential_impulse_Ns"] = row["tangential_impulse"] * machine.impulse_scale
            rows.append(row)
        return rows


@njit(cache=True)
def _evaluate(t, starts, u_start, du_start, k, gamma, omega):
    n = t.shape[0]
    u = np.empty(n, dtype=np.complex128)
    du = np.empty(n, dtype=np.complex128)
    for i in range(n):
        j = np.searchsorted(starts, t[i], side="right") - 1
        if j < 0:
            j = 0
        v, dv = propagate(u_start[j] - k, du_start[j], t[i] - starts[j], gamma, omega)
        u[i] = k + v
        du[i] = dv
    return u, du


@dataclass(frozen=True)
class Trajectory:
    """A simulated motion of the rotor, in the style of scipy's ``OdeResult``.

    Attributes
    ----------
    params : Parameters
        Parameters of the run.
    u0, du0 : complex
        Initial state in the co-rotating frame.
    t_end : float
        Requested final time.
    t_stop : float
        Time the simulation reached (``t_end`` unless it stopped early).
    status : str
        ``"completed"``, ``"chatter"`` (impacts accumulate), ``"max-impacts"``
        or ``"failed"``.
    records : numpy.ndarray
        Raw impact records, columns `COLUMNS`.
    machine : Machine or None
        The machine the parameters come from, for SI outputs.
    """

    params: Parameters
    u0: complex
    du0: complex
    t_end: float
    t_stop: float
    status: str
    records: np.ndarray = field(repr=False)
    machine: Machine | None = None

    @cached_property
    def impacts(self) -> ImpactTable:
        """The table of impacts."""
        return ImpactTable(self.records)

    @property
    def success(self) -> bool:
        """True when the run reached ``t_end``."""
        return self.status == "completed"

    @property
    def message(self) -> str:
        """A sentence describing how the run ended."""
        n = len(self.impacts)
        if self.status == "completed":
            return f"Reached t_end = {self.t_end:g} after {n} impacts."
        if self.status == "chatter":
            th = self.impacts.theta[-1] if n else float(np.angle(self.u0))
            return (
                f"Impacts accumulate (chatter) at t = {self.t_stop:.12g}, theta = {th:.6g}, "
                f"after {n} impacts; continuous contact follows."
            )
        if self.status == "max-impacts":
            return f"Stopped after the maximum of {n} impacts at t = {self.t_stop:.12g}."
        return f"Impact location failed to converge at t = {self.t_stop:.12g}."

    @cached_property
    def _segments(self):
        rec = self.records
        starts = np.concatenate(([0.0], rec[:, 0]))
        u_start = np.concatenate(([self.u0], rec[:, 9] + 1j * rec[:, 10]))
        du_start = np.concatenate(([self.du0], rec[:, 11] + 1j * rec[:, 12]))
        return starts, u_start, du_start

    def state(self, t) -> tuple[np.ndarray, np.ndarray]:
        """Exact (U, U') in the co-rotating frame at times ``t`` in [0, t_stop].

        At an impact time the state just after the impact is returned.
        """
        tt = np.asarray(t, dtype=float)
        flat = tt.ravel()
        if flat.size and (not np.all(np.isfinite(flat)) or flat.min() < 0.0 or flat.max() > self.t_stop * (1 + 1e-14)):
            raise ParameterError(
                f"t must lie in [0, t_stop] = [0, {self.t_stop:g}]; got values in [{flat.min():g}, {flat.max():g}]"
            )
        p = self.params
        k = equilibrium_point(p.gamma, p.omega, p.rho, p.phi)
        starts, u_start, du_start = self._segments
        u, du = _evaluate(flat, starts, u_start, du_start, k, p.gamma, p.omega)
        return u.reshape(tt.shape), du.reshape(tt.shape)

    def U(self, t) -> np.ndarray:
        """Co-rotating position U(t)."""
        return self.state(t)[0]

    def dU(self, t) -> np.ndarray:
        """Co-rotating velocity U'(t)."""
        return self.state(t)[1]

    def Z(self, t) -> np.ndarray:
        """Inertial position Z(t) = U(t) e^{it}."""
        return to_inertial(self.U(t), t)

    def r(self, t) -> np.ndarray:
        """Radius |U(t)| (in units of the clearance)."""
        return np.abs(self.U(t))

    def theta(self, t) -> np.ndarray:
        """Co-rotating angle of U(t), in (-pi, pi]."""
        th = np.angle(self.U(t))
        return np.where(th <= -np.pi, th + 2 * np.pi, th)

    def polar(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(r, theta, rdot, thetadot) at times ``t``."""
        u, du = self.state(t)
        r = np.abs(u)
        w = np.conj(u / r) * du
        th = np.angle(u)
        return r, np.where(th <= -np.pi, th + 2 * np.pi, th), w.real, w.imag / r

    def sample(self, n: int = 2000) -> np.ndarray:
        """Uniform sample times over [0, t_stop] that include every impact time."""
        base = np.linspace(0.0, self.t_stop, n)
        return np.unique(np.concatenate((base, self.impacts.t)))

    @cached_property
    def summary(self):
        """Classification of the long-run motion (`rotorcontact.motion.MotionSummary`)."""
        from .motion import classify

        return classify(self)

    def to_dict(self) -> dict[str, Any]:
        """The whole result as plain JSON-ready data (the ``simulate --json`` contract)."""
        out: dict[str, Any] = {
            "parameters": self.params.as_dict(),
            "status": self.status,
            "message": self.message,
            "t_end": self.t_end,
            "t_stop": self.t_stop,
            "initial_state": {"u0": [self.u0.real, self.u0.imag], "du0": [self.du0.real, self.du0.imag]},
            "impacts": self.impacts.to_dicts(self.machine),
            "summary": self.summary.to_dict(),
        }
        if self.machine is not None:
            out["machine"] = self.machine.as_dict()
        return out
