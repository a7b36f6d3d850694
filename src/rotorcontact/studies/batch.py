"""Batch simulation: many (parameters, initial state) pairs in one compiled call.

Every item is run by the simulator's loop (`rotorcontact.simulation.simulator.simulate_into`, the loop of
`rotorcontact.simulation.simulator.simulate_kernel`): the same closed-form flight, guaranteed impact
location, reset and continuous contact, so a batch is exactly as exact as single runs. It runs in the
loop's form without tables (`rotorcontact.studies.compact_batch`), which keeps only what the batch reads and
gives the simulator's results bit for bit; a step it hands back (`rotorcontact.studies.compact_batch.compact_item`)
and the lane's later ones run through the simulator's own kernel, into tables grown as they need. An item is
two runs of that loop:

1. the *transient*: from the initial state for ``n_transient`` events (flights
   and contact phases; each flight ends in one impact, so in impacting motion
   these are impacts) or up to the time ``t_transient``, whichever comes first
   (optionally in segments, ended early once the motion has settled: see
   `BatchSettings.settle`);
2. the *window*: from the state where the transient stopped, for ``n_record``
   events or up to the time ``t_record``.

The impacts of the window are the recorded impact section, and the window is
classified into a regime (no contact, periodic impacting with p impacts per
period, irregular impacting, forward rub, backward whirl, mixed) with the rules of
`rotorcontact.simulation.motion.classify`, applied to the window.

Items are laid out as *lanes* of *steps*. Lanes are independent and run in
parallel over cores: threads claim blocks of lanes as they finish the last
(`rotorcontact.studies.guided`), each block through the single-core kernel.
Within a lane the steps run in order; with ``carry=True`` each step starts from the state where the previous step
ended (a sweep with the state carried along), otherwise every step starts from
its own initial state.

The state where a run ended (`final_state`) is read from the kernel's output:
after an impact, the state just after it; in free flight, the exact flight at
the stop time; in contact, the point on the stator with its angular velocity.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, fields
from typing import Any, Sequence

import numba
import numpy as np
from numba import njit

from ..errors import ParameterError
from .window import (
    NSUM,
    S_CONTACT_TIME,
    S_DU_IM,
    S_DU_RE,
    S_FINAL_KIND,
    S_N_CONTACTS,
    S_N_IMPACTS,
    S_P,
    S_PERIOD,
    S_REGIME,
    S_STATUS,
    S_T_TRANSIENT,
    S_T_WINDOW,
    S_TRANSIENT_IMPACTS,
    S_TRANSIENT_STATUS,
    S_U_IM,
    S_U_RE,
    contact_end_state,
    detect_period_rows,
    ends_in_contact,
    fill_summary,
    flight_final_state,
    never_touches,
    regime_of,
)
# the regimes of the window: the codes and names of `rotorcontact.simulation.motion` (``"forward-rub"`` and
# ``"backward-whirl"`` were formerly ``"rub"`` and ``"rolling"``, `rotorcontact.simulation.motion.REGIME_ALIASES`)
from ..simulation.motion import (
    FAILED_REGIME,
    MAX_PERIOD_IMPACTS,
    MIN_IRREGULAR,
    NO_CONTACT,
    REGIME_NAMES,
    REPEAT_TOL,
    WINDOW,
)
from ..model.params import (MAX_T_END, MAX_VELOCITY, Parameters, check_parameter_rows, check_range,
                            check_velocity)
from ..model.validation import (check_bool, check_int, check_type, complex_array, finite_array, quoted,
                                settings_or_default)
from ..simulation.simulator import (
    BOUNDARY_TOL,
    CHATTER_DEFAULTS,
    COMPLETED,
    FAILED,
    MAX_EVENTS,
    STATUS_NAMES,
    check_forced_response,
    check_forced_response_of,
    new_tables,
    simulate_into,
)
from .compact_batch import compact_lane, ring_buffer
from .guided import GuidedLanes
from ..simulation.contact import ACCUMULATION, KIND_NAMES, SLIDE_FORWARD

__all__ = [
    "PARAMETER_ORDER",
    "SECTION_COLUMNS",
    "REGIME_NAMES",
    "FINAL_KIND_NAMES",
    "BatchSettings",
    "BatchResult",
    "CHATTER_DEFAULTS",
    "check_batch_settings",
    "simulate_batch",
    "final_state",
    "parameter_array",
]

#: Order of the parameters in the rows of a parameter array.
PARAMETER_ORDER = ("gamma", "omega", "rho", "mu", "d", "phi", "r_ratio")
#: The columns of a parameter row that the forced response depends on (`check_forced_response_of`'s arguments).
_FORCING_COLUMNS = [PARAMETER_ORDER.index(name) for name in ("gamma", "omega", "rho", "phi")]
#: Columns of the recorded impact section: time since the start of the window,
#: impact angle, and the polar velocities just before the impact.
SECTION_COLUMNS = ("t", "theta", "rdot", "thetadot")

#: Names of the final-kind codes: -1 free flight, then the contact kinds of `rotorcontact.simulation.contact`.
FINAL_KIND_NAMES = {-1: "flight", **{i: name for i, name in enumerate(KIND_NAMES)}}



DEFAULT_TIME_PER_EVENT = 5.0
#: Most events of a transient or a window: at a few million impacts a second, about a minute per simulation.
MAX_BATCH_EVENTS = 10**8


# ---------------------------------------------------------------------------
# compiled core
# ---------------------------------------------------------------------------


@njit(cache=True)
def _final_state(flights, contacts, path, t_stop, gamma, omega, rho, phi):
    """State (U, U') where a run of `simulate_into` stopped, and what it was doing (-1 flight, else contact kind).

    The simulator records the state at the start of every flight (the start of
    the run, after each impact, touch and lift-off) and every contact phase
    with its path on r = 1; the last row of a phase (an accumulation of
    impacts included) is the state at its end.
    """
    n_fl = flights.shape[0]
    n_ct = contacts.shape[0]
    t_fl = flights[n_fl - 1, 0] if n_fl > 0 else -math.inf
    if n_ct > 0 and ends_in_contact(n_fl, t_fl, contacts[n_ct - 1, 0], contacts[n_ct - 1, 1]):
        row = int(contacts[n_ct - 1, 4])
        e, du = contact_end_state(path[row, 1], path[row, 2])
        return e, du, int(contacts[n_ct - 1, 2])
    u_f = complex(flights[n_fl - 1, 1], flights[n_fl - 1, 2])
    du_f = complex(flights[n_fl - 1, 3], flights[n_fl - 1, 4])
    u, du = flight_final_state(t_fl, u_f, du_f, t_stop, gamma, omega, rho, phi)
    return u, du, -1


@njit(cache=True)
def _classify_window(impacts, contacts, t_stop, status, window, max_p, tol, min_irregular):
    """Regime code (`rotorcontact.simulation.motion.REGIME_NAMES`), impacts per period and period of a window.

    The rules are those of `rotorcontact.simulation.motion.classify` (`rotorcontact.simulation.motion.regime_code`
    of its summary is this code; the tests check the two on the same runs).
    """
    n = impacts.shape[0]
    t_win = t_stop * (1.0 - window)
    late_impacts = False
    for i in range(n):
        if impacts[i, 0] >= t_win:
            late_impacts = True
    n_late = 0
    forward_only = True
    last_kind = -1
    for j in range(contacts.shape[0]):
        if contacts[j, 1] > t_win and int(contacts[j, 2]) != ACCUMULATION:
            n_late += 1
            kind = int(contacts[j, 2])
            last_kind = kind
            if kind != SLIDE_FORWARD:
                forward_only = False
    return regime_of(status, late_impacts, n_late, last_kind, forward_only, impacts, n, n, max_p, tol, min_irregular)


@njit(cache=True)
def _simulate(p, u, du, t_end, max_events, chatter, tables):
    """`simulate_into` for a parameter row, into ``tables`` (`new_tables`).

    Returns the tables (grown where they filled), views of their rows used (impacts, flights, contacts,
    path), status and t_stop.
    """
    imp, fl, ct, path = tables
    imp, fl, ct, path, n_imp, n_fl, n_ct, n_path, status, reason, t_stop = simulate_into(
        p[0], p[1], p[2], p[3], p[4], p[5], p[6], u, du, t_end, max_events, *chatter, False, imp, fl, ct, path
    )
    return (imp, fl, ct, path), imp[:n_imp], fl[:n_fl], ct[:n_ct], path[:n_path], status, t_stop


@njit(cache=True)
def _transient(p, u, du, n_transient, t_transient, settle, chatter, tables):
    """Run the transient; returns (u, du, status, duration, impacts, tables)."""
    gamma, omega, rho, phi = p[0], p[1], p[2], p[5]
    if n_transient <= 0:
        return u, du, COMPLETED, 0.0, 0, tables
    if settle <= 0:
        tables, imp, fl, ct, path, status, t_stop = _simulate(p, u, du, t_transient, n_transient, chatter, tables)
        u, du, kind = _final_state(fl, ct, path, t_stop, gamma, omega, rho, phi)
        return u, du, status, t_stop, imp.shape[0], tables
    # in segments of ``settle`` events, ending early once the motion repeats
    # (periodic impacts) or provably never touches the stator again
    events_left = n_transient
    time_left = t_transient
    t_total = 0.0
    n_imp = 0
    status = COMPLETED
    while events_left > 0 and time_left > 0.0:
        if never_touches(u, du, gamma, omega, rho, phi):
            break
        tables, imp, fl, ct, path, status, t_stop = _simulate(p, u, du, time_left, min(settle, events_left),
                                                              chatter, tables)
        u, du, kind = _final_state(fl, ct, path, t_stop, gamma, omega, rho, phi)
        events_left -= max(1, fl.shape[0] + ct.shape[0])
        time_left -= t_stop
        t_total += t_stop
        n_imp += imp.shape[0]
        if status != MAX_EVENTS:
            break
        per_p, period = detect_period_rows(imp, imp.shape[0], MAX_PERIOD_IMPACTS, REPEAT_TOL)
        if per_p > 0:
            break
    return u, du, status, t_total, n_imp, tables


@njit(cache=True, nogil=True)
def _run_item(p, u0, du0, n_transient, n_record, t_transient, t_record, settle, chatter, sec, summ, tables):
    """Transient and window of one item; fills ``sec`` (n_keep, 4) and ``summ`` (NSUM,).

    Its simulations write into ``tables`` (`new_tables`). Returns the final state and the tables.
    """
    gamma, omega, rho, phi = p[0], p[1], p[2], p[5]
    u, du, tr_status, t_tr, tr_impacts, tables = _transient(p, u0, du0, n_transient, t_transient, settle, chatter,
                                                            tables)
    sec[:, :] = math.nan
    if tr_status == FAILED:
        fill_summary(summ, FAILED, tr_status, FAILED_REGIME, 0, math.nan, 0, 0, 0.0, -1, u, du, t_tr, 0.0, tr_impacts)
        return u, du, tables
    if settle > 0 and never_touches(u, du, gamma, omega, rho, phi):
        # the window is one free flight to t_record: the simulator's own result,
        # evaluated directly (the same closed-form flow from the same state)
        u, du = flight_final_state(0.0, u, du, t_record, gamma, omega, rho, phi)
        status = COMPLETED
        t_stop = t_record
        regime, per_p, period = NO_CONTACT, 0, math.nan
        n_imp = 0
        n_ct = 0
        contact_time = 0.0
        kind = -1
    else:
        tables, imp, fl, ct, path, status, t_stop = _simulate(p, u, du, t_record, n_record, chatter, tables)
        u, du, kind = _final_state(fl, ct, path, t_stop, gamma, omega, rho, phi)
        regime, per_p, period = _classify_window(imp, ct, t_stop, status, WINDOW, MAX_PERIOD_IMPACTS, REPEAT_TOL,
                                                 MIN_IRREGULAR)
        n_imp = imp.shape[0]
        n_ct = 0
        n_keep = sec.shape[0]
        first = max(0, n_imp - n_keep)
        for i in range(first, n_imp):
            for c in range(4):
                sec[i - first, c] = imp[i, c]
        contact_time = 0.0
        for j in range(ct.shape[0]):
            if int(ct[j, 2]) != ACCUMULATION:  # the tail of a chatter sequence is not a contact phase
                n_ct += 1
                contact_time += min(ct[j, 1], t_stop) - ct[j, 0]
    fill_summary(summ, status, tr_status, regime, per_p, period, n_imp, n_ct, contact_time, kind, u, du, t_tr, t_stop,
                 tr_impacts)
    return u, du, tables


@njit(cache=True, nogil=True)
def _run_steps(lane, first, u, du, params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle,
               chatter, sections, summary, tables):
    """Steps ``first`` on of one lane, in order, through the simulator's tables (``tables``, `new_tables`), from
    the state (u, du) where step ``first`` starts; returns the tables, grown."""
    for s in range(first, params.shape[1]):
        if not carry:
            u = u0[lane, s]
            du = du0[lane, s]
        u, du, tables = _run_item(params[lane, s], u, du, n_transient, n_record, t_transient, t_record, settle,
                                  chatter, sections[lane, s], summary[lane, s], tables)
    return tables


@njit(cache=True, nogil=True)
def _batch_serial(params, u0, du0, carry, n_transient, n_record, t_transient, t_record, settle, chatter,
                  sections, summary):
    """The batch kernel on one core, releasing the GIL (for worker threads and processes); the lanes share one
    set of buffers."""
    ring = ring_buffer()
    tables = new_tables()
    for lane in range(params.shape[0]):
        first, u, du = compact_lane(lane, params, u0, du0, carry, n_transient, n_record, t_transient, t_record,
                                    settle, *chatter, sections, summary, ring)
        if first >= 0:
            tables = _run_steps(lane, first, u, du, params, u0, du0, carry, n_transient, n_record, t_transient,
                                t_record, settle, chatter, sections, summary, tables)


# ---------------------------------------------------------------------------
# Python front end
# ---------------------------------------------------------------------------


def _time_limit(given: float | None, events: int) -> float:
    """``given``, or by default 5 per event, at least 100 and at most `MAX_T_END`."""
    if given is not None:
        return float(given)
    return min(MAX_T_END, max(100.0, DEFAULT_TIME_PER_EVENT * events))


@dataclass(frozen=True)
class BatchSettings:
    """How long each item runs and what is kept.

    Attributes
    ----------
    n_transient : int
        Events (flights and contact phases; impacts in impacting motion) of
        the transient, from 0 to `MAX_BATCH_EVENTS`.
    n_record : int
        Events of the recorded window, from 1 to `MAX_BATCH_EVENTS`.
    t_transient, t_record : float or None
        Time limits of the transient and of the window, at most
        `rotorcontact.model.params.MAX_T_END` as in `rotorcontact.simulate`; None gives
        ``5 * n_transient`` and ``5 * n_record``, at least 100 and at most `MAX_T_END`.
    n_keep : int or None
        Number of impacts of the window kept in the section (the last ones);
        None keeps ``n_record``.
    settle : int
        0 (default): the transient is one run of ``n_transient`` events. A
        positive value runs the transient in segments of ``settle`` events and
        ends it early, after the first segment whose impacts repeat
        periodically (`rotorcontact.simulation.motion.detect_period`), or as soon as the
        free flight provably never reaches the stator again (|k| + |c+| + |c-|
        < 1 for U = k + c+ e^{l+ t} + c- e^{l- t}). Each segment restarts the
        simulator exactly where the previous one stopped. A window that starts
        with that certificate is contact-free and is evaluated in closed form.
    chatter : mapping or None
        Criteria for an accumulation of impacts by name (``chatter_rdot`` ...),
        as in `rotorcontact.simulation.simulator`; those not given keep the simulator's
        defaults (`CHATTER_DEFAULTS`). Stored as (name, value) pairs.
    """

    n_transient: int = 4000
    n_record: int = 1000
    t_transient: float | None = None
    t_record: float | None = None
    n_keep: int | None = None
    settle: int = 0
    chatter: Any = None

    def __post_init__(self) -> None:
        check_int("n_transient", self.n_transient, 0, MAX_BATCH_EVENTS)
        check_int("n_record", self.n_record, 1, MAX_BATCH_EVENTS)
        if self.n_keep is not None:
            check_int("n_keep", self.n_keep, 1, MAX_BATCH_EVENTS)
        check_int("settle", self.settle, 0, MAX_BATCH_EVENTS)
        for name in ("t_transient", "t_record"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, check_range(name, value, low=0.0, high=MAX_T_END, low_open=True))
        try:
            given = dict(self.chatter or {})
        except (TypeError, ValueError):
            raise ParameterError(f"chatter = {self.chatter!r} is invalid; allowed: a dict of criteria by name "
                                 f"({', '.join(CHATTER_DEFAULTS)}), or None") from None
        unknown = sorted(set(given) - set(CHATTER_DEFAULTS))
        if unknown:
            raise ParameterError(
                f"chatter criterion {unknown[0]!r} is unknown; allowed: {', '.join(CHATTER_DEFAULTS)}"
            )
        pairs = tuple(
            (name, check_range(name, given.get(name, default), low=0.0)) for name, default in CHATTER_DEFAULTS.items()
        )
        object.__setattr__(self, "chatter", pairs)

    @property
    def chatter_values(self) -> tuple[float, ...]:
        """The chatter criteria in the simulator kernel's order."""
        return tuple(float(v) for _, v in self.chatter)

    @property
    def transient_time(self) -> float:
        """Time limit of the transient."""
        return _time_limit(self.t_transient, self.n_transient)

    @property
    def record_time(self) -> float:
        """Time limit of the window."""
        return _time_limit(self.t_record, self.n_record)

    @property
    def keep(self) -> int:
        """Number of impacts kept in the section."""
        return self.n_record if self.n_keep is None else min(self.n_keep, self.n_record)

    def as_dict(self) -> dict[str, Any]:
        """Plain data, with the time limits resolved."""
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "chatter"}
        out.update(dict(self.chatter))
        out["t_transient"] = self.transient_time
        out["t_record"] = self.record_time
        out["n_keep"] = self.keep
        return out


#: Bytes of one kept impact of a section: (t, theta, rdot, thetadot) as float64.
SECTION_BYTES = len(SECTION_COLUMNS) * 8


def physical_memory() -> int | None:
    """This machine's physical memory in bytes, or None where the system does not tell."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return None


def check_batch_settings(settings: Any, simulations: int, default: Any = BatchSettings) -> BatchSettings:
    """``settings`` (``default()`` where None) as `BatchSettings` whose sections fit in this machine's memory.

    The sections of every simulation are held together (``simulations`` x ``keep`` impacts of
    `SECTION_BYTES`), so a study that needs more than the machine's physical memory is refused before it
    runs, rather than failing with a `MemoryError` part way.

    Raises
    ------
    ParameterError
        For settings that are not `BatchSettings`, or sections beyond the machine's memory.
    """
    settings = settings_or_default(settings, BatchSettings, default)
    simulations = check_int("simulations", simulations, 1)
    need = simulations * settings.keep * SECTION_BYTES
    have = physical_memory()
    if have is not None and need > have:
        raise ParameterError(
            f"n_record = {settings.n_record}, n_keep = {settings.n_keep}: {simulations} "
            f"simulation{'' if simulations == 1 else 's'} keeping "
            f"{settings.keep} impacts each need {need / 2**30:.3g} GiB of sections; allowed: at most this "
            f"machine's memory, {have / 2**30:.3g} GiB; keep fewer impacts (n_keep), run fewer simulations "
            "or split the study"
        )
    return settings


@dataclass(frozen=True)
class BatchResult:
    """Results of a batch, each array shaped like the batch (``shape``), sections with one more axis.

    Attributes
    ----------
    shape : tuple of int
        Shape of the batch.
    t, theta, rdot, thetadot : numpy.ndarray
        The recorded impact section, shape ``shape + (n_keep,)``: time since
        the start of the window, impact angle in (-pi, pi], and rdot-,
        thetadot- just before each impact; NaN where the window had fewer
        impacts.
    status, transient_status : numpy.ndarray of int
        How the window and the transient ended (`rotorcontact.simulation.simulator.STATUS_NAMES`).
    regime : numpy.ndarray of int
        Regime of the window (`REGIME_NAMES`).
    impacts_per_period : numpy.ndarray of int
        p of a periodic impacting window, else 0.
    period : numpy.ndarray of float
        Its period, else NaN.
    n_impacts, n_contacts : numpy.ndarray of int
        Impacts and contact phases in the window (the accumulation tail of a
        chatter sequence is not counted as a contact phase).
    transient_impacts : numpy.ndarray of int
        Impacts in the transient.
    contact_time : numpy.ndarray of float
        Time spent in contact during the window.
    final_kind : numpy.ndarray of int
        What the rotor was doing at the end (`FINAL_KIND_NAMES`).
    final_u, final_du : numpy.ndarray of complex
        State where the window ended.
    t_transient, t_window : numpy.ndarray of float
        Durations of the transient and of the window.
    settings : BatchSettings
        The settings of the run.
    """

    shape: tuple[int, ...]
    t: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    rdot: np.ndarray = field(repr=False)
    thetadot: np.ndarray = field(repr=False)
    status: np.ndarray = field(repr=False)
    transient_status: np.ndarray = field(repr=False)
    regime: np.ndarray = field(repr=False)
    impacts_per_period: np.ndarray = field(repr=False)
    period: np.ndarray = field(repr=False)
    n_impacts: np.ndarray = field(repr=False)
    n_contacts: np.ndarray = field(repr=False)
    transient_impacts: np.ndarray = field(repr=False)
    contact_time: np.ndarray = field(repr=False)
    final_kind: np.ndarray = field(repr=False)
    final_u: np.ndarray = field(repr=False)
    final_du: np.ndarray = field(repr=False)
    t_transient: np.ndarray = field(repr=False)
    t_window: np.ndarray = field(repr=False)
    settings: BatchSettings = field(default_factory=BatchSettings)

    @property
    def regime_names(self) -> np.ndarray:
        """The regimes as strings."""
        return np.asarray(REGIME_NAMES, dtype=object)[self.regime]

    @property
    def status_names(self) -> np.ndarray:
        """How each window ended, as strings."""
        return np.vectorize(STATUS_NAMES.get, otypes=[object])(self.status)

    @property
    def impacts_simulated(self) -> int:
        """Total number of impacts computed (transients and windows)."""
        return int(self.n_impacts.sum() + self.transient_impacts.sum())

    @classmethod
    def from_arrays(cls, sections: np.ndarray, summary: np.ndarray, settings: BatchSettings) -> "BatchResult":
        """Build the result from the kernel's raw arrays (shape ``batch + (n_keep, 4)`` and ``batch + (NSUM,)``);
        a `ParameterError` for other arrays, or ``settings`` that are not a `BatchSettings`."""
        check_type("settings", settings, BatchSettings, "a BatchSettings")
        shapes = (isinstance(sections, np.ndarray) and isinstance(summary, np.ndarray) and sections.ndim >= 2
                  and sections.dtype.kind == "f" and summary.dtype.kind == "f" and sections.shape[-1] == 4
                  and summary.shape == sections.shape[:-2] + (NSUM,))
        if not shapes:
            raise ParameterError(f"sections, summary = {quoted(sections)}, {quoted(summary)} are invalid; allowed: "
                                 f"the kernel's float arrays of shapes batch + (n_keep, 4) and batch + ({NSUM},)")
        s = summary
        as_int = lambda j: s[..., j].astype(np.int64)  # noqa: E731
        return cls(
            shape=tuple(summary.shape[:-1]),
            t=sections[..., 0],
            theta=sections[..., 1],
            rdot=sections[..., 2],
            thetadot=sections[..., 3],
            status=as_int(S_STATUS),
            transient_status=as_int(S_TRANSIENT_STATUS),
            regime=as_int(S_REGIME),
            impacts_per_period=as_int(S_P),
            period=s[..., S_PERIOD].copy(),
            n_impacts=as_int(S_N_IMPACTS),
            n_contacts=as_int(S_N_CONTACTS),
            transient_impacts=as_int(S_TRANSIENT_IMPACTS),
            contact_time=s[..., S_CONTACT_TIME].copy(),
            final_kind=as_int(S_FINAL_KIND),
            final_u=s[..., S_U_RE] + 1j * s[..., S_U_IM],
            final_du=s[..., S_DU_RE] + 1j * s[..., S_DU_IM],
            t_transient=s[..., S_T_TRANSIENT].copy(),
            t_window=s[..., S_T_WINDOW].copy(),
            settings=settings,
        )


def parameter_array(params: Parameters | Sequence[Parameters] | np.ndarray) -> np.ndarray:
    """Parameters as a float array with last axis `PARAMETER_ORDER`, validated.

    Parameters
    ----------
    params : Parameters, (nested) sequence of Parameters, or array_like (..., 7)
        One set of parameters, several, or an array of rows in `PARAMETER_ORDER`.

    Raises
    ------
    ParameterError
        If any row is not a valid set of parameters.
    """
    if isinstance(params, Parameters):
        check_forced_response(params)  # as every row of an array below
        return np.array([getattr(params, n) for n in PARAMETER_ORDER], dtype=float)

    def rows(obj):
        if isinstance(obj, Parameters):
            return [getattr(obj, n) for n in PARAMETER_ORDER]
        if isinstance(obj, (list, tuple)):
            return [rows(x) for x in obj]
        return obj

    try:
        arr = np.array(rows(params), dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"params = {params!r} is not Parameters or an array of parameter rows") from None
    if arr.ndim == 0 or arr.shape[-1] != len(PARAMETER_ORDER):
        raise ParameterError(
            f"params has shape {arr.shape}; expected rows of {len(PARAMETER_ORDER)} values "
            f"({', '.join(PARAMETER_ORDER)})"
        )
    _validate_rows(arr.reshape(-1, len(PARAMETER_ORDER)))
    return arr


def _validate_rows(rows: np.ndarray) -> None:
    bad = ~np.all(np.isfinite(rows), axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ParameterError(f"parameter row {i} = {rows[i].tolist()} is not finite")
    # the ranges of the Parameters constructor as arrays, then the simulator's bound on the forced response
    # once per distinct row (gamma, omega, rho, phi)
    check_parameter_rows(rows)
    for gamma, omega, rho, phi in np.unique(rows[:, _FORCING_COLUMNS], axis=0).tolist():
        check_forced_response_of(gamma, omega, rho, phi)


def _complex_values(name: str, value: Any) -> np.ndarray:
    arr = complex_array(value)
    if arr is None:
        raise ParameterError(f"{name} = {value!r} is not a complex number or an array of them (not text or bools)")
    return arr


def _complex_array(name: str, value: Any, shape: tuple[int, ...]) -> np.ndarray:
    arr = _complex_values(name, value)
    try:
        arr = np.broadcast_to(arr, shape)
    except ValueError:
        raise ParameterError(f"{name} has shape {arr.shape}, which does not fit the batch shape {shape}") from None
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} has values that are not finite")
    return np.ascontiguousarray(arr, dtype=np.complex128)


def check_initial_states(u0: np.ndarray, du0: np.ndarray) -> None:
    """Raise `ParameterError` unless every |u0| <= 1 (the rotor starts inside the clearance) and every
    |du0| is at most `rotorcontact.model.params.MAX_VELOCITY` (as `simulate` requires)."""
    fast = np.abs(du0) > MAX_VELOCITY
    if fast.any():
        check_velocity("du0", du0.ravel()[int(np.flatnonzero(fast.ravel())[0])])  # raises, with its message
    outside = np.abs(u0) > 1.0 + BOUNDARY_TOL
    if outside.any():
        i = int(np.flatnonzero(outside.ravel())[0])
        z = u0.ravel()[i]
        raise ParameterError(
            f"u0 = {z.real:g},{z.imag:g} (item {i}) lies outside the clearance (|u0| = {abs(z):.6g}); "
            "allowed: |u0| <= 1"
        )


def check_lanes(params: Any, u0: Any, du0: Any, settings: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The lanes `run_lanes` takes, as arrays: ``params`` finite and real, of shape (n_lanes, n_steps, 7) in
    `PARAMETER_ORDER`, ``u0`` and ``du0`` finite and complex, of shape (n_lanes, n_steps), and ``settings`` a
    `BatchSettings`; a `ParameterError` naming the first that is not. The values themselves are checked
    where the lanes are built (`parameter_array`, `simulate_batch`)."""
    check_type("settings", settings, BatchSettings, "a BatchSettings")
    lanes = f"a finite real array of shape (n_lanes, n_steps, {len(PARAMETER_ORDER)}), one row per step in " \
            "PARAMETER_ORDER (parameter_array)"
    params = finite_array("params", params, lanes, ndims=(3,))
    if params.shape[1] < 1 or params.shape[2] != len(PARAMETER_ORDER):
        raise ParameterError(f"params = {quoted(params)} is invalid; allowed: {lanes}")
    out = [params]
    for name, value in (("u0", u0), ("du0", du0)):
        arr = complex_array(value)
        if arr is None or arr.shape != params.shape[:2] or not np.all(np.isfinite(arr)):
            raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: a finite complex array of the "
                                 f"lanes' shape (n_lanes, n_steps) = {params.shape[:2]}")
        out.append(arr)
    return out[0], out[1], out[2]


def run_lanes(
    params: np.ndarray,
    u0: np.ndarray,
    du0: np.ndarray,
    settings: BatchSettings,
    *,
    carry: bool,
    parallel: bool = True,
    workers: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Run validated lanes through the kernel and return the raw (sections, summary) arrays.

    Parameters
    ----------
    params : numpy.ndarray, shape (n_lanes, n_steps, 7)
    u0, du0 : numpy.ndarray of complex, shape (n_lanes, n_steps)
        Initial states (only the first step of each lane is used with ``carry``).
    settings : BatchSettings
    carry : bool
        Carry the state along each lane.
    parallel : bool
        Lanes shared out among threads in blocks (`rotorcontact.studies.guided`), each block on one core
        with the GIL released; otherwise all on one core. The results are the same bit for bit.
    workers : int, optional
        With ``parallel``, the threads that share out the lanes (default: as many as numba's,
        `numba.get_num_threads`); at most one per lane is started.
    """
    args = lane_arguments(params, u0, du0, settings, carry=carry)
    n_lanes = args[0].shape[0]
    if workers is None:
        workers = int(numba.get_num_threads())
    workers = min(check_int("workers", workers, 1), n_lanes)
    if parallel and workers > 1:
        for _ in GuidedLanes([(n_lanes, lambda: args)], run_lane_block, workers).run():
            pass
    elif n_lanes:
        _batch_serial(*args)
    return args[-2], args[-1]


def lane_arguments(params: np.ndarray, u0: np.ndarray, du0: np.ndarray, settings: BatchSettings, *,
                   carry: bool) -> tuple:
    """The batch kernel's arguments for lanes (checked by `check_lanes`), with fresh result arrays
    (``sections`` and ``summary``, the last two), for `run_lanes` or for blocks of lanes (`run_lane_block`)."""
    params, u0, du0 = check_lanes(params, u0, du0, settings)
    n_lanes, n_steps = params.shape[:2]
    keep = settings.keep
    # writable C-contiguous copies where needed: one compiled signature for every call
    return (
        np.require(params, dtype=np.float64, requirements=["C", "W"]),
        np.require(u0, dtype=np.complex128, requirements=["C", "W"]),
        np.require(du0, dtype=np.complex128, requirements=["C", "W"]),
        bool(carry),
        settings.n_transient,
        settings.n_record,
        settings.transient_time,
        settings.record_time,
        settings.settle,
        settings.chatter_values,
        np.empty((n_lanes, n_steps, keep, 4)),
        np.empty((n_lanes, n_steps, NSUM)),
    )


def run_lane_block(args: tuple, start: int, stop: int) -> None:
    """Lanes ``start`` to ``stop`` (excluded) of `lane_arguments`'s ``args`` on one core with the GIL released,
    into their rows of its result arrays: the same numbers, bit for bit, as the lanes run in one call.

    Raises
    ------
    ParameterError
        Unless 0 <= start < stop <= the number of lanes.
    """
    n_lanes = args[0].shape[0]
    check_int("start", start, 0, n_lanes - 1)
    check_int("stop", stop, start + 1, n_lanes)
    # slices along the first axis of C-contiguous arrays stay C-contiguous: the same compiled signature
    block = slice(start, stop)
    _batch_serial(args[0][block], args[1][block], args[2][block], *args[3:10], args[10][block], args[11][block])


def simulate_batch(
    params: Parameters | Sequence[Parameters] | np.ndarray,
    u0: Any = 0j,
    du0: Any = 0j,
    *,
    settings: BatchSettings | None = None,
    carry: bool = False,
    parallel: bool = True,
    **kwargs: Any,
) -> BatchResult:
    """Simulate many (parameters, initial state) pairs through the compiled batch kernel, in parallel.

    Parameters
    ----------
    params : Parameters, sequence of Parameters, or array_like (..., 7)
        The parameters of each item (rows in `PARAMETER_ORDER`). A single
        Parameters object is shared by all items (the batch shape then comes
        from ``u0`` and ``du0``).
    u0, du0 : complex or array_like of complex
        Initial positions (|u0| <= 1) and velocities, broadcast to the batch shape.
    settings : BatchSettings, optional
        Transient and window lengths; keyword arguments (``n_transient=...``)
        build one instead.
    carry : bool
        With True, the last axis of the batch is a chain: each item starts
        where the previous one ended (a sweep with the state carried along);
        ``u0`` and ``du0`` give one state per chain (or one per item, of
        which the first of each chain is used). Chains run in parallel.
    parallel : bool
        Run over numba's threads (`numba.get_num_threads`, all cores by default), which share out the
        lanes (`rotorcontact.studies.guided`); False runs on one core. Both give the same results bit for
        bit.

    Returns
    -------
    BatchResult

    Examples
    --------
    >>> p = Parameters.reference().replace(gamma=0.1)
    >>> res = simulate_batch(p, u0=[0j, 0.5 + 0j], n_transient=300, n_record=50)
    >>> res.regime_names.tolist()  # doctest: +SKIP
    ['periodic-impacting', 'periodic-impacting']
    """
    carry = check_bool("carry", carry)
    if settings is None:
        unknown = sorted(set(kwargs) - {f.name for f in fields(BatchSettings)})
        if unknown:
            raise ParameterError(f"{unknown[0]} = {kwargs[unknown[0]]!r} is not a setting (unknown setting "
                                 f"{unknown[0]!r}); allowed: {', '.join(f.name for f in fields(BatchSettings))}")
        settings = BatchSettings(**kwargs)
    elif kwargs:
        raise ParameterError(f"give either settings or keyword settings, not both ({', '.join(kwargs)})")
    parr = parameter_array(params)
    single = parr.ndim == 1
    u0a = _complex_values("u0", u0)
    du0a = _complex_values("du0", du0)
    squeeze = False
    if carry:
        if single:
            raise ParameterError("carry=True needs a chain of parameters (params with shape (..., n_steps, 7))")
        shape = tuple(parr.shape[:-1])
        # one initial state per chain (or one per item, of which the first of each chain is used)
        full = u0a.ndim == len(shape) and du0a.ndim <= len(shape) or du0a.ndim == len(shape)
        if full:
            u0c = _complex_array("u0", u0, shape)
            du0c = _complex_array("du0", du0, shape)
        else:
            u0c = np.repeat(_complex_array("u0", u0, shape[:-1])[..., None], shape[-1], axis=-1)
            du0c = np.repeat(_complex_array("du0", du0, shape[:-1])[..., None], shape[-1], axis=-1)
    else:
        try:
            shape = np.broadcast_shapes(u0a.shape, du0a.shape) if single else np.broadcast_shapes(
                parr.shape[:-1], u0a.shape, du0a.shape)
        except ValueError:
            raise ParameterError(
                f"the shapes of params {parr.shape[:-1]}, u0 {u0a.shape} and du0 {du0a.shape} do not broadcast"
            ) from None
        if shape == ():
            shape = (1,)
            squeeze = True
        u0c = _complex_array("u0", u0, shape)
        du0c = _complex_array("du0", du0, shape)
    if 0 in shape:
        raise ParameterError(f"the batch is empty (shape {shape}); allowed: at least one item")
    parr = np.broadcast_to(parr, shape + (len(PARAMETER_ORDER),))
    check_initial_states(u0c, du0c)
    check_batch_settings(settings, int(np.prod(shape, dtype=np.int64)))
    if carry:
        lanes = int(np.prod(shape[:-1], dtype=np.int64))
        steps = shape[-1]
    else:
        lanes = int(np.prod(shape, dtype=np.int64))
        steps = 1
    sections, summary = run_lanes(
        parr.reshape(lanes, steps, -1),
        u0c.reshape(lanes, steps),
        du0c.reshape(lanes, steps),
        settings,
        carry=carry,
        parallel=check_bool("parallel", parallel),
    )
    out_shape = (1,) if squeeze else shape
    return BatchResult.from_arrays(
        sections.reshape(out_shape + sections.shape[-2:]), summary.reshape(out_shape + (NSUM,)), settings
    )


def final_state(traj) -> tuple[complex, complex, str]:
    """State (U, U') where a `Trajectory` stopped, and what the rotor was doing there.

    After an impact it is the state just after the impact; in free flight the
    exact flight at ``t_stop``; in contact the point on the stator with its
    angular velocity. This is the state from which the batch kernel continues.

    Returns
    -------
    u, du : complex
    kind : str
        ``"flight"`` or a contact kind (`FINAL_KIND_NAMES`).

    Raises
    ------
    ParameterError
        If ``traj`` is not a `rotorcontact.Trajectory`.
    """
    from ..simulation.trajectory import Trajectory

    check_type("traj", traj, Trajectory, "a Trajectory (rotorcontact.simulate)")
    p = traj.params
    fl = traj.flights if traj.flights.size else np.empty((0, 5))
    u, du, kind = _final_state(
        np.ascontiguousarray(fl, dtype=float).reshape(-1, 5),
        np.ascontiguousarray(traj.contacts, dtype=float).reshape(-1, 5),
        np.ascontiguousarray(traj.path, dtype=float).reshape(-1, 4),
        float(traj.t_stop),
        p.gamma,
        p.omega,
        p.rho,
        p.phi,
    )
    return complex(u), complex(du), FINAL_KIND_NAMES[int(kind)]
