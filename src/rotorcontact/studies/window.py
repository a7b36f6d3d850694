"""The window of a batch item: the columns of its summary, its classification and its state where it stopped.

Shared by the simulator's tables in the batch kernel (`rotorcontact.studies.batch`) and the table-free
form of its items (`rotorcontact.studies.compact_batch`), which the batch kernel and the GPU run.
"""

from __future__ import annotations

import math

from numba import njit

from ..model.flow import equilibrium_point, half_discriminant, propagate
from ..model.impact_law import polar_velocity
from ..simulation.motion import FAILED_REGIME, IRREGULAR, MIXED, NO_CONTACT, PERIODIC, ROLL, RUB, UNDETERMINED
from ..simulation.contact import ROLLING
from ..simulation.simulator import FAILED

CERTIFICATE_MARGIN = 1e-9

#: Columns of the per-item summary array of the kernel (`rotorcontact.studies.batch.run_lanes`), ``NSUM`` of them.
S_STATUS = 0
S_TRANSIENT_STATUS = 1
S_REGIME = 2
S_P = 3
S_PERIOD = 4
S_N_IMPACTS = 5
S_N_CONTACTS = 6
S_CONTACT_TIME = 7
S_FINAL_KIND = 8
S_U_RE = 9
S_U_IM = 10
S_DU_RE = 11
S_DU_IM = 12
S_T_TRANSIENT = 13
S_T_WINDOW = 14
S_TRANSIENT_IMPACTS = 15
NSUM = 16


@njit(cache=True)
def flight_final_state(t_fl, u_f, du_f, t_stop, gamma, omega, rho, phi):
    """State at ``t_stop`` of the free flight that started at ``t_fl`` from (u_f, du_f), kept inside |U| <= 1."""
    dt = t_stop - t_fl
    if dt <= 0.0:
        return u_f, du_f
    k = equilibrium_point(gamma, omega, rho, phi)
    v, dv = propagate(u_f - k, du_f, dt, gamma, omega)
    u = k + v
    r = abs(u)
    if r > 1.0:
        u = u / r
    return u, dv


@njit(cache=True)
def ends_in_contact(n_fl, t_fl, c_start, c_end):
    """Whether a run's last phase is its last contact phase (c_start to c_end), not the flight from t_fl.

    A contact phase is the last phase unless a flight (lift-off) started after it.
    """
    return n_fl == 0 or c_start > t_fl or (c_start == t_fl and c_end > t_fl)


@njit(cache=True)
def contact_end_state(theta, thetadot):
    """(U, U') at the end of a contact phase at angle theta moving at thetadot, ready for a restart.

    The simulator restarts from u / |u|; any outward radial velocity left by rounding there is removed,
    so that a restart continues in contact rather than recording a spurious impact at zero speed.
    """
    e = complex(math.cos(theta), math.sin(theta))
    du = complex(0.0, thetadot) * e
    en = e / abs(e)
    for _ in range(8):
        rd = polar_velocity(en, du)[0]
        if rd <= 0.0:
            break
        du = du - 2.0 * rd * en
    return e, du


@njit(cache=True)
def _angle_gap(a, b):
    x = a - b
    return abs(math.atan2(math.sin(x), math.cos(x)))


@njit(cache=True)
def detect_period_rows(imp, n, max_p, tol):
    """`rotorcontact.simulation.motion.detect_period` on the first ``n`` rows of an impact table.

    Returns (p, period), or (0, nan) when the rows do not repeat.
    """
    for p in range(1, max_p + 1):
        m = max(2 * p, 6)
        if n < m + p + 1:
            break
        ok = True
        pmin = math.inf
        pmax = -math.inf
        for i in range(n - m, n):
            j = i - p
            if (
                not (_angle_gap(imp[i, 1], imp[j, 1]) < tol)
                or not (abs(imp[i, 2] - imp[j, 2]) < tol)
                or not (abs(imp[i, 3] - imp[j, 3]) < tol)
            ):
                ok = False
                break
            dt = imp[i, 0] - imp[j, 0]
            pmin = min(pmin, dt)
            pmax = max(pmax, dt)
        if ok and (pmax - pmin) < tol * max(1.0, pmax):
            return p, imp[n - 1, 0] - imp[n - 1 - p, 0]
    return 0, math.nan


@njit(cache=True)
def regime_of(status, late_impacts, n_late, last_kind, forward_only, last_impacts, n_rows, n_impacts, max_p, tol,
              min_irregular):
    """The rules of `rotorcontact.studies.batch._classify_window` from what they read of a window.

    ``late_impacts``: an impact lies in the window's classified tail; ``n_late``, ``last_kind`` and
    ``forward_only``: its contact phases; ``last_impacts``: the window's last ``n_rows`` impacts (at least
    3 `MAX_PERIOD_IMPACTS` of them, or all), of ``n_impacts`` in all.
    """
    if status == FAILED:
        return FAILED_REGIME, 0, math.nan
    if not late_impacts and n_late == 0:
        return NO_CONTACT, 0, math.nan
    if not late_impacts:
        if last_kind == ROLLING:
            return ROLL, 0, math.nan
        if forward_only:
            return RUB, 0, math.nan
        return MIXED, 0, math.nan
    if n_late > 0:
        return MIXED, 0, math.nan
    p, period = detect_period_rows(last_impacts, n_rows, max_p, tol)
    if p > 0:
        return PERIODIC, p, period
    if n_impacts >= min_irregular:
        return IRREGULAR, 0, math.nan
    return UNDETERMINED, 0, math.nan


@njit(cache=True)
def never_touches(u, du, gamma, omega, rho, phi):
    """True when free flight from (u, du) provably never reaches |U| = 1 (for all t >= 0).

    U(t) = k + c+ e^{l+ t} + c- e^{l- t} with Re l+- <= 0 for gamma >= 0, so
    |U(t)| <= |k| + |c+| + |c-|; a margin covers rounding. Not used near
    critical damping, where the two exponentials merge.
    """
    if gamma < 0.0:
        return False
    r = abs(u)
    if r >= 1.0 - CERTIFICATE_MARGIN:
        return False
    k = equilibrium_point(gamma, omega, rho, phi)
    h2 = half_discriminant(gamma, omega)
    if abs(h2) < 1e-8:
        return False
    h = complex(math.sqrt(h2), 0.0) if h2 > 0.0 else complex(0.0, math.sqrt(-h2))
    m = complex(-0.5 * gamma, -1.0)
    lp = m + h
    lm = m - h
    v = u - k
    cp = (du - lm * v) / (lp - lm)
    cm = v - cp
    return abs(k) + abs(cp) + abs(cm) < 1.0 - CERTIFICATE_MARGIN


@njit(cache=True)
def fill_summary(summ, status, tr_status, regime, per_p, period, n_imp, n_contacts, contact_time, final_kind, u, du,
                 t_transient, t_window, tr_impacts):
    """Write an item's summary row, every one of its ``NSUM`` columns."""
    summ[S_STATUS] = status
    summ[S_TRANSIENT_STATUS] = tr_status
    summ[S_REGIME] = regime
    summ[S_P] = per_p
    summ[S_PERIOD] = period
    summ[S_N_IMPACTS] = n_imp
    summ[S_N_CONTACTS] = n_contacts
    summ[S_CONTACT_TIME] = contact_time
    summ[S_FINAL_KIND] = final_kind
    summ[S_U_RE] = u.real
    summ[S_U_IM] = u.imag
    summ[S_DU_RE] = du.real
    summ[S_DU_IM] = du.imag
    summ[S_T_TRANSIENT] = t_transient
    summ[S_T_WINDOW] = t_window
    summ[S_TRANSIENT_IMPACTS] = tr_impacts
