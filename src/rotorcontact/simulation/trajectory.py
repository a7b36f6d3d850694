"""The result of a simulation: impacts, exact dense output, status and a summary."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numba import njit

from .contact import ACCUMULATION, KIND_NAMES, ROLLING, SLIDE_BACKWARD, SLIDE_FORWARD
from .phase_sampling import PhaseForces, peak_of_samples, phase_grids

from ..errors import ParameterError
from ..interpreted import call_kernel
from ..model.flow import propagate, to_inertial
from ..model.impact_law import relative_velocity
from ..model.validation import check_int, check_machine, quoted, real_array
from ..model.params import Machine, Parameters, check_range

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
#: Most uniform sample times `Trajectory.sample` gives (800 MB of them).
MAX_SAMPLE_TIMES = 100_000_000
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
        if not (isinstance(records, np.ndarray) and records.ndim == 2 and records.shape[1] == len(COLUMNS)
                and records.dtype.kind == "f"):
            raise ParameterError(f"records = {quoted(records)} is invalid; allowed: the (n, {len(COLUMNS)}) float "
                                 "array of a simulation's impact records (Trajectory.records)")
        self._records = records
        for i, name in enumerate(COLUMNS):
            setattr(self, name, records[:, i])
        self.point = records[:, 9] + 1j * records[:, 10]
        self.du_plus = records[:, 11] + 1j * records[:, 12]

    def __len__(self) -> int:
        return self._records.shape[0]

    def to_dicts(self, machine: Machine | None = None) -> list[dict[str, float]]:
        """One plain dict per impact (the JSON form)."""
        check_machine(machine)
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
def _evaluate_flights(t, starts, u_start, du_start, k, gamma, omega):
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
class ContactInterval:
    """A phase of continuous contact.

    Attributes
    ----------
    t_start, t_end : float
        Its time span.
    kind : str
        ``"sliding-forward"`` (v_rel > 0), ``"rolling"`` (v_rel = 0) or
        ``"sliding-backward"`` (v_rel < 0).
    """

    t_start: float
    t_end: float
    kind: str

    def to_dict(self) -> dict[str, Any]:
        return {"t_start": self.t_start, "t_end": self.t_end, "kind": self.kind}


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
        ``"completed"``, ``"chatter"`` (impacts accumulate and the run was
        asked to stop there), ``"max-events"`` or ``"failed"``.
    records : numpy.ndarray
        Raw impact records, columns `COLUMNS`.
    flights : numpy.ndarray
        Start time and (U, U') (as re, im pairs) of each free flight.
    contacts : numpy.ndarray
        t_start, t_end, kind code, first and last row in ``path`` of each contact phase.
    path : numpy.ndarray
        (t, theta, thetadot, thetadot') along the contact phases.
    machine : Machine or None
        The machine the parameters come from, for SI outputs.
    failure : str or None
        Why the run stopped, when ``status == "failed"``.
    """

    params: Parameters
    u0: complex
    du0: complex
    t_end: float
    t_stop: float
    status: str
    records: np.ndarray = field(repr=False)
    flights: np.ndarray = field(repr=False)
    contacts: np.ndarray = field(repr=False)
    path: np.ndarray = field(repr=False)
    machine: Machine | None = None
    failure: str | None = None

    @cached_property
    def impacts(self) -> ImpactTable:
        """The table of impacts."""
        return ImpactTable(self.records)

    @cached_property
    def contact_intervals(self) -> list[ContactInterval]:
        """The phases of continuous contact, in time order."""
        return [
            ContactInterval(float(c[0]), float(c[1]), KIND_NAMES[int(c[2])])
            for c in self.contacts
            if int(c[2]) != ACCUMULATION
        ]

    @property
    def success(self) -> bool:
        """True when the run reached ``t_end``."""
        return self.status == "completed"

    @property
    def message(self) -> str:
        """A sentence describing how the run ended."""
        n = len(self.impacts)
        c = len(self.contact_intervals)
        if self.status == "completed":
            return f"Reached t_end = {self.t_end:g} after {n} impacts and {c} contact phases."
        if self.status == "chatter":
            th = self.impacts.theta[-1] if n else float(np.angle(self.u0))
            return (
                f"Impacts accumulate (chatter) at t = {self.t_stop:.12g}, theta = {th:.6g}, "
                f"after {n} impacts; the run stops there (on_chatter='stop')."
            )
        if self.status == "max-events":
            return f"Stopped after the maximum number of events at t = {self.t_stop:.12g} ({n} impacts)."
        return f"The simulation could not continue at t = {self.t_stop:.12g}: {self.failure}."

    @cached_property
    def _flight_table(self):
        fl = self.flights
        return fl[:, 0].copy(), fl[:, 1] + 1j * fl[:, 2], fl[:, 3] + 1j * fl[:, 4]

    @cached_property
    def _contact_splines(self) -> list:
        from scipy.interpolate import BPoly  # here, not at import: a batch worker never needs scipy

        out = []
        for c in self.contacts:
            rows = self._held_rows(self.path[int(c[3]) : int(c[4]) + 1])[0]
            if int(c[2]) == ROLLING or rows.shape[0] < 2:
                out.append(None)
                continue
            # quintic Hermite through theta, thetadot, thetadot' at the integrator's steps (at the two
            # ends of an accumulation of impacts, whose bounces it smooths over)
            t, keep = np.unique(rows[:, 0], return_index=True)
            out.append(BPoly.from_derivatives(t, rows[keep, 1:4]) if t.size >= 2 else None)
        return out

    @staticmethod
    def _held_rows(rows: np.ndarray) -> tuple[np.ndarray, float]:
        """The rows of a sliding phase up to where it comes to rest, and the time it does (inf if it does not).

        A slide that reaches a stable pseudo-equilibrium to the integrator's tolerance is held there until
        its end (`rotorcontact.simulation.contact.slide`): its last row repeats the state of the one before
        at the later time. Over that hold the state is constant, not the Hermite curve through the two rows,
        whose tiny derivatives times a long hold would swing it far from the rest point.
        """
        if rows.shape[0] >= 3 and rows[-1, 0] > rows[-2, 0] and np.array_equal(rows[-1, 1:], rows[-2, 1:]):
            return rows[:-1], float(rows[-2, 0])
        return rows, math.inf

    def _contact_state(self, j: int, t: np.ndarray):
        c = self.contacts[j]
        rows, t_rest = self._held_rows(self.path[int(c[3]) : int(c[4]) + 1])
        spline = self._contact_splines[j]
        if spline is None:
            theta = rows[0, 1] + rows[0, 2] * (t - rows[0, 0])
            thetadot = np.full_like(t, rows[0, 2])
        else:
            held = t > t_rest
            moving = np.where(held, t_rest, t)
            theta = np.where(held, rows[-1, 1], spline(moving))
            thetadot = np.where(held, rows[-1, 2], spline(moving, 1))
        e = np.exp(1j * theta)
        return e, 1j * thetadot * e

    def in_contact(self, t) -> np.ndarray:
        """Index of the contact phase holding each time, or -1 in free flight."""
        return self._phase_of(self._times(t))

    def _phase_of(self, tt: np.ndarray) -> np.ndarray:
        """`in_contact` of times already checked (`_times`)."""
        out = np.full(tt.shape, -1, dtype=int)
        if len(self.contacts) == 0:
            return out
        c_start, c_end = self.contacts[:, 0], self.contacts[:, 1]
        j = np.searchsorted(c_start, tt, side="right") - 1
        f_start = self._flight_table[0]
        i = np.searchsorted(f_start, tt, side="right") - 1
        last_flight = np.where(i >= 0, f_start[np.clip(i, 0, None)], -np.inf)
        jj = np.clip(j, 0, None)
        inside = (j >= 0) & (tt <= c_end[jj]) & (c_start[jj] >= last_flight)
        out[inside] = j[inside]
        return out

    def _times(self, t) -> np.ndarray:
        """``t`` as an array of floats in [0, t_stop]; a `ParameterError` naming it otherwise."""
        tt = real_array(t)
        if tt is None:
            raise ParameterError(f"t = {t!r} is invalid; allowed: real numbers in [0, t_stop] = [0, {self.t_stop:g}]")
        flat = tt.ravel()
        if flat.size and (
            not np.all(np.isfinite(flat)) or flat.min() < 0.0 or flat.max() > self.t_stop * (1 + 1e-14)
        ):
            raise ParameterError(
                f"t must lie in [0, t_stop] = [0, {self.t_stop:g}]; got values in [{flat.min():g}, {flat.max():g}]"
            )
        return tt

    def state(self, t) -> tuple[np.ndarray, np.ndarray]:
        """Exact (U, U') in the co-rotating frame at times ``t`` in [0, t_stop].

        In free flight the closed form is evaluated; in contact phases the
        rolling motion is exact and sliding is the integrator's solution,
        interpolated by quintic Hermite polynomials (constant where a slide
        comes to rest on a stable pseudo-equilibrium and is held there). At an
        impact time the state just after the impact is returned.
        """
        tt = self._times(t)
        flat = tt.ravel()
        p = self.params
        k = p.k
        starts, u_start, du_start = self._flight_table
        u, du = call_kernel(_evaluate_flights, flat, starts, u_start, du_start, k, p.gamma, p.omega)
        phase = self._phase_of(flat)
        for j in np.unique(phase[phase >= 0]):
            sel = phase == j
            u[sel], du[sel] = self._contact_state(int(j), flat[sel])
        return u.reshape(tt.shape), du.reshape(tt.shape)

    def contact_forces(self, t) -> tuple[np.ndarray, np.ndarray]:
        """Normal force N and tangential contact force per unit mass (dimensionless) at times ``t``.

        Both are zero in free flight. The tangential force is along +theta:
        -mu N sgn(v_rel) when sliding, and the force that holds v_rel = 0 when
        rolling (MODEL.md §4). At the time where a phase gives way to the next
        phase, or to flight, the later one's forces are given.
        """
        tt = self._times(t)
        _r, theta, _rdot, thetadot = self.polar(tt)
        phase = self._phase_of(tt)
        n = np.zeros(tt.shape)
        ft = np.zeros(tt.shape)
        for j in np.unique(phase[phase >= 0]):
            sel = phase == j
            n[sel], ft[sel] = self._phase_law(theta[sel], thetadot[sel], int(self.contacts[j, 2]))
        return n, ft

    def _phase_law(self, theta: np.ndarray, thetadot: np.ndarray, kind: int) -> tuple[np.ndarray, np.ndarray]:
        """(N, F_t) of a contact phase of kind ``kind`` (a code of `KIND_NAMES`) at the polar states given."""
        from ..model.contact_law import forces_along

        p = self.params
        n, f_free = call_kernel(forces_along, np.ascontiguousarray(theta), np.ascontiguousarray(thetadot),
                                p.gamma, p.omega, p.rho, p.phi)
        if kind == ROLLING:
            return n, -f_free
        if kind == SLIDE_FORWARD:
            return n, -p.mu * n
        if kind == SLIDE_BACKWARD:
            return n, p.mu * n
        # accumulation of impacts: friction opposes the slip
        return n, -p.mu * n * np.sign(relative_velocity(p.r_ratio, thetadot))

    def friction_power(self, t) -> np.ndarray:
        """Power dissipated by friction per unit mass (dimensionless), |F_t v_rel|, at times ``t``."""
        tt = self._times(t)
        _n, ft = self.contact_forces(tt)
        thetadot = self.polar(tt)[3]
        return np.abs(ft * relative_velocity(self.params.r_ratio, thetadot))

    def phase_forces(self, t_start: float, t_end: float, kind: str) -> PhaseForces:
        """The largest forces and the mean friction power of the contact phase of ``kind`` on [t_start, t_end].

        Every time of the closed span is taken in this phase (at its end, `contact_forces` gives the next
        phase's forces). The sample times (`phase_sampling.phase_grids`) are at most 0.05 apart, and close
        enough that theta turns at most pi/16 between neighbours (up to a whirl of about a million turns);
        the largest values are refined about the largest sample (`phase_sampling.peak_of_samples`), and the
        mean power is Romberg's rule on the samples.

        Parameters
        ----------
        t_start, t_end : float
            The phase's span, within [0, t_stop].
        kind : str
            Its kind, one of `KIND_NAMES`.

        Returns
        -------
        PhaseForces
            Dimensionless (per unit mass): the largest N, the largest |F_t| and the mean of |F_t v_rel|.

        Raises
        ------
        ParameterError
            For a ``kind`` not in `KIND_NAMES`, or a span not within [0, t_stop] with t_start <= t_end.
        """
        from scipy.integrate import romb

        if kind not in KIND_NAMES:
            raise ParameterError(f"kind = {kind!r} is invalid; allowed: {', '.join(map(repr, KIND_NAMES))}")
        t_start = check_range("t_start", t_start, low=0.0, high=self.t_stop)
        t_end = check_range("t_end", t_end, low=t_start, high=self.t_stop)
        code = KIND_NAMES.index(kind)
        r_ratio = self.params.r_ratio

        def law(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            _r, theta, _rdot, thetadot = self.polar(t)
            n, ft = self._phase_law(theta, thetadot, code)
            return n, np.abs(ft), np.abs(ft * relative_velocity(r_ratio, thetadot))

        grids = phase_grids(lambda x: np.abs(self.polar(x)[3]), t_start, t_end)
        max_normal = max_friction = -np.inf
        means = np.empty(len(grids))
        for i, t in enumerate(grids):
            n, ft, power = law(t)
            max_normal = max(max_normal, peak_of_samples(lambda x: law(x)[0], t, n))
            max_friction = max(max_friction, peak_of_samples(lambda x: law(x)[1], t, ft))
            # Romberg's rule with the step 1 / steps: the piece's mean, exact in its span down to none
            means[i] = romb(power, dx=1.0 / (t.size - 1)) if t.size > 1 else power[0]
        widths = np.array([t[-1] - t[0] for t in grids])
        mean_power = float(means[0]) if len(grids) == 1 else float(means @ widths / widths.sum())
        return PhaseForces(max_normal=max_normal, max_friction=max_friction, mean_power=mean_power)

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
        """(r, theta, rdot, thetadot) at times ``t``.

        At r = 0 the polar coordinates are singular; there theta is the
        direction of U' (0 when U' = 0 too), rdot = |U'| and thetadot = 0, the
        limits along the motion as it leaves the centre.
        """
        u, du = self.state(t)
        r = np.abs(u)
        at_centre = r == 0.0
        e = np.where(at_centre, np.exp(1j * np.angle(du)), u / np.where(at_centre, 1.0, r))
        w = np.conj(e) * du
        th = np.where(at_centre, np.angle(du), np.angle(u))
        thetadot = np.where(at_centre, 0.0, w.imag / np.where(at_centre, 1.0, r))
        return r, np.where(th <= -np.pi, th + 2 * np.pi, th), w.real, thetadot

    def sample(self, n: int = 2000) -> np.ndarray:
        """Uniform sample times over [0, t_stop] (``n`` of them, 2 to `MAX_SAMPLE_TIMES`) that include every
        impact time."""
        n = check_int("n", n, 2, MAX_SAMPLE_TIMES)
        base = np.linspace(0.0, self.t_stop, n)
        return np.unique(np.concatenate((base, self.impacts.t)))

    def contact_dicts(self, intervals: list[ContactInterval] | None = None) -> list[dict[str, Any]]:
        """Contact intervals as plain dicts; with a machine, also their largest forces and mean friction power in
        SI (`phase_forces`).

        Parameters
        ----------
        intervals : list of ContactInterval, optional
            The intervals to describe (default: all of `contact_intervals`).
        """
        if intervals is None:
            intervals = self.contact_intervals
        elif not isinstance(intervals, (list, tuple)) or not all(isinstance(c, ContactInterval) for c in intervals):
            raise ParameterError(f"intervals = {intervals!r} is invalid; allowed: a list of ContactInterval "
                                 "(from contact_intervals) or None")
        out = []
        m = self.machine
        for c in intervals:
            row = c.to_dict()
            if m is not None:
                f = self.phase_forces(c.t_start, min(c.t_end, self.t_stop), c.kind)
                row.update(
                    t_start_s=c.t_start * m.time_scale,
                    t_end_s=c.t_end * m.time_scale,
                    max_normal_force_N=f.max_normal * m.force_scale,
                    max_friction_force_N=f.max_friction * m.force_scale,
                    mean_friction_power_W=f.mean_power * m.force_scale * m.clearance * m.speed,
                )
            out.append(row)
        return out

    @cached_property
    def summary(self):
        """Classification of the long-run motion (`rotorcontact.simulation.motion.MotionSummary`)."""
        from .motion import classify

        return classify(self)

    def to_dict(self, max_rows: int | None = None) -> dict[str, Any]:
        """The whole result as plain JSON-ready data (the ``simulate --json`` contract).

        Parameters
        ----------
        max_rows : int, optional
            Largest number of impacts, and of contact intervals, listed (>= 2).
            A longer list keeps its first ``max_rows // 2`` and its last
            ``max_rows - max_rows // 2`` entries, and the result then also has
            ``"impacts_total"`` (the number of impacts) and
            ``"impacts_truncated": true`` (likewise ``"contact_intervals_total"``
            and ``"contact_intervals_truncated"``). None (default) lists all.

        Returns
        -------
        dict
            ``parameters``, ``status``, ``message``, ``t_end``, ``t_stop``,
            ``initial_state``, ``impacts``, ``contact_intervals``, ``summary``
            (and ``machine`` with a machine).
        """
        if max_rows is not None:
            max_rows = check_int("max_rows", max_rows, 2)
        n_imp = len(self.impacts)
        cut_impacts = max_rows is not None and n_imp > max_rows
        records = self.records
        if cut_impacts:
            head = max_rows // 2
            records = np.concatenate((records[:head], records[n_imp - (max_rows - head):]))
        intervals = self.contact_intervals
        n_int = len(intervals)
        cut_intervals = max_rows is not None and n_int > max_rows
        if cut_intervals:
            head = max_rows // 2
            intervals = intervals[:head] + intervals[n_int - (max_rows - head):]
        out: dict[str, Any] = {
            "parameters": self.params.as_dict(),
            "status": self.status,
            "message": self.message,
            "t_end": self.t_end,
            "t_stop": self.t_stop,
            "initial_state": {"u0": [self.u0.real, self.u0.imag], "du0": [self.du0.real, self.du0.imag]},
            "impacts": ImpactTable(records).to_dicts(self.machine),
            "contact_intervals": self.contact_dicts(intervals=intervals),
            "summary": self.summary.to_dict(),
        }
        if cut_impacts:
            out["impacts_total"] = n_imp
            out["impacts_truncated"] = True
        if cut_intervals:
            out["contact_intervals_total"] = n_int
            out["contact_intervals_truncated"] = True
        if self.machine is not None:
            out["machine"] = self.machine.as_dict()
        return out
