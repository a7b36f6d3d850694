"""Shared, independent reference computations for the tests.

Nothing here uses the package's flow, root finding or reset: the references are
written from MODEL.md directly.

* `MPFlight`: the closed-form free flight U(t) = k + c+ e^{l+ t} + c- e^{l- t}
  (MODEL.md §3) evaluated in mpmath, with its own eigenvalues and coefficients.
* `mp_first_crossing` / `mp_simulate`: impact times by dense sampling of
  |U|^2 - 1 and its derivative in mpmath, refined with ``mp.findroot``, and the
  impact law of MODEL.md §2 applied in mpmath.
* `ivp_simulate`: scipy ``solve_ivp`` integration of the Cartesian co-rotating
  ODE with a terminal event and a restart at each impact.
* `f1_expm`: F1(T) of MODEL.md §5 from ``scipy.linalg.expm``.

They are exposed through the session fixture ``ref``.
"""

from __future__ import annotations

import inspect
import math
import os
from types import SimpleNamespace

import mpmath as mp
import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import solve_ivp

# figures are drawn to files: no display, whatever the machine
os.environ.setdefault("MPLBACKEND", "Agg")

DPS = 40


# ---------------------------------------------------------------------------
# mpmath closed form
# ---------------------------------------------------------------------------


class MPFlight:
    """Free flight from (U, U') = (u0, du0) at local time 0, exactly, in mpmath.

    U'' + (gamma + 2i) U' + (omega^2 - 1 + i gamma) U = rho e^{i phi}.
    Characteristic roots l = (-(gamma + 2i) +- sqrt(gamma^2 - 4 omega^2)) / 2.
    Requires gamma != 2 omega (distinct roots); for the double root use
    `MPFlightCritical`.
    """

    def __init__(self, gamma, omega, rho, phi, u0, du0, dps=DPS):
        self.dps = dps
        with mp.workdps(dps):
            g, w, r, ph = (mp.mpf(gamma), mp.mpf(omega), mp.mpf(rho), mp.mpf(phi))
            self.k = r * mp.expj(ph) / mp.mpc(w**2 - 1, g)
            disc = mp.sqrt(mp.mpc(g**2 - 4 * w**2, 0))
            alpha = mp.mpc(g, 2)
            self.lp = (-alpha + disc) / 2
            self.lm = (-alpha - disc) / 2
            assert abs(self.lp - self.lm) > mp.mpf(10) ** (-dps // 3)
            v0 = mp.mpc(u0) - self.k
            dv0 = mp.mpc(du0)
            self.cp = (dv0 - self.lm * v0) / (self.lp - self.lm)
            self.cm = v0 - self.cp

    def derivs(self, t, n=2):
        """[U, U', ..., U^(n)] at local time t."""
        with mp.workdps(self.dps):
            t = mp.mpf(t)
            ep = self.cp * mp.exp(self.lp * t)
            em = self.cm * mp.exp(self.lm * t)
            out = [self.k + ep + em]
            for j in range(1, n + 1):
                out.append(self.lp**j * ep + self.lm**j * em)
            return out

    def U(self, t):
        return self.derivs(t, 1)[0]

    def state(self, t):
        u, du = self.derivs(t, 1)
        return u, du

    # f = |U|^2 - 1 and its derivatives
    def f(self, t):
        with mp.workdps(self.dps):
            u = self.U(t)
            return mp.re(u) ** 2 + mp.im(u) ** 2 - 1

    def fp(self, t):
        with mp.workdps(self.dps):
            u, du = self.derivs(t, 1)
            return 2 * mp.re(mp.conj(u) * du)

    def fpp(self, t):
        with mp.workdps(self.dps):
            u, du, ddu = self.derivs(t, 2)
            return 2 * abs(du) ** 2 + 2 * mp.re(mp.conj(u) * ddu)


class MPFlightCritical(MPFlight):
    """Free flight at critical damping gamma = 2 omega (double root l = -gamma/2 - i)."""

    def __init__(self, gamma, omega, rho, phi, u0, du0, dps=DPS):
        self.dps = dps
        with mp.workdps(dps):
            g, w, r, ph = (mp.mpf(gamma), mp.mpf(omega), mp.mpf(rho), mp.mpf(phi))
            self.k = r * mp.expj(ph) / mp.mpc(w**2 - 1, g)
            self.lam = mp.mpc(-g / 2, -1)
            v0 = mp.mpc(u0) - self.k
            # V = (c1 + c2 t) e^{l t}
            self.c1 = v0
            self.c2 = mp.mpc(du0) - self.lam * v0

    def derivs(self, t, n=2):
        with mp.workdps(self.dps):
            t = mp.mpf(t)
            e = mp.exp(self.lam * t)
            out = [self.k + (self.c1 + self.c2 * t) * e]
            for j in range(1, n + 1):
                # d^j/dt^j [(c1 + c2 t) e^{l t}] = (l^j (c1 + c2 t) + j l^{j-1} c2) e^{l t}
                out.append((self.lam**j * (self.c1 + self.c2 * t) + j * self.lam ** (j - 1) * self.c2) * e)
            return out


def make_flight(p, u0, du0, dps=DPS):
    """`MPFlight`, or `MPFlightCritical` where gamma = 2 omega exactly."""
    critical = mp.mpf(p.gamma) == 2 * mp.mpf(p.omega)
    return (MPFlightCritical if critical else MPFlight)(p.gamma, p.omega, p.rho, p.phi, u0, du0, dps)


def _bracket_root(fun, a, b, dps):
    """Root of fun in [a, b] (fun(a) < 0 < fun(b)): bisection down to a small bracket, then findroot."""
    with mp.workdps(dps):
        a, b = mp.mpf(a), mp.mpf(b)
        fa = fun(a)
        for _ in range(30):
            m = (a + b) / 2
            fm = fun(m)
            if (fm < 0) == (fa < 0):
                a, fa = m, fm
            else:
                b = m
        x = mp.findroot(fun, (a, b), solver="anderson")
        assert a - mp.mpf(10) ** (-dps // 2) <= x <= b + mp.mpf(10) ** (-dps // 2)
        return x


def mp_first_crossing(flight: MPFlight, t_max: float, dt: float = 0.01):
    """First t in (0, t_max] with |U(t)| = 1 and |U| increasing, or None.

    Dense sampling of f = |U|^2 - 1 and f' in mpmath: a sign change of f from - to +
    brackets a crossing; a sign change of f' from + to - brackets an interior
    maximum, which is located with findroot so that a crossing pair hidden
    between two samples (near grazing) is not missed.
    """
    dps = flight.dps
    n = int(math.ceil(t_max / dt))
    with mp.workdps(dps):
        ts = [mp.mpf(t_max) * j / n for j in range(n + 1)]
        f0 = flight.f(0)
        if abs(f0) < mp.mpf(10) ** -12:
            # starting on the boundary (just after an impact, or a point rounded onto
            # |U| = 1 in double precision): start just inside, where f < 0
            fp0 = flight.fp(0)
            assert fp0 < 0
            ts[0] = 10 * abs(f0) / abs(fp0) + mp.mpf(10) ** (-dps // 2)
            assert ts[0] < ts[1] and flight.f(ts[0]) < 0
        f_prev, fp_prev = flight.f(ts[0]), flight.fp(ts[0])
        assert f_prev < 0
        for j in range(1, n + 1):
            a, b = ts[j - 1], ts[j]
            f_b, fp_b = flight.f(b), flight.fp(b)
            if f_prev < 0 < f_b:
                return _bracket_root(flight.f, a, b, dps)
            if f_prev < 0 and f_b < 0 and fp_prev > 0 > fp_b:
                tm = _bracket_root(lambda s: -flight.fp(s), a, b, dps)
                if flight.f(tm) > 0:
                    return _bracket_root(flight.f, a, tm, dps)
            f_prev, fp_prev = f_b, fp_b
    return None


def mp_reset(u, du, d, mu, r_ratio):
    """Impact law of MODEL.md §2 in mpmath at a point u with |u| = 1.

    Returns (u, du_plus, rdot, thetadot, rdot_plus, thetadot_plus, v_rel).
    While the Coulomb impulse mu (1 + d) rdot does not reach |v_rel| the complex
    form U'+ = U'- - q rdot- U, q = (1 + d)(1 + i mu sgn v_rel) is used; otherwise the
    slip stops at v_rel = 0.
    """
    u = u / abs(u)
    w = mp.conj(u) * du
    rdot, thetadot = mp.re(w), mp.im(w)
    v_rel = r_ratio + 1 + thetadot
    slip = mu * (1 + d) * rdot
    if abs(v_rel) > slip:
        sgn = 1 if v_rel > 0 else -1
        q = (1 + d) * mp.mpc(1, sgn * mu)
        du_plus = du - q * rdot * u
    else:
        du_plus = u * mp.mpc(-d * rdot, -(r_ratio + 1))
    w2 = mp.conj(u) * du_plus
    return u, du_plus, rdot, thetadot, mp.re(w2), mp.im(w2), v_rel


def mp_simulate(p, u0, du0, n_impacts, seg_max=60.0, dt=0.01, dps=DPS):
    """Impacts of the hybrid system in mpmath: list of dicts (t, theta, rdot, thetadot, ...)."""
    out = []
    with mp.workdps(dps):
        t0 = mp.mpf(0)
        u, du = mp.mpc(u0), mp.mpc(du0)
        for _ in range(n_impacts):
            fl = make_flight(p, u, du, dps)
            tau = mp_first_crossing(fl, seg_max, dt)
            if tau is None:
                break
            ui, dui = fl.state(tau)
            ui, du, rd, td, rdp, tdp, vrel = mp_reset(ui, dui, mp.mpf(p.d), mp.mpf(p.mu), mp.mpf(p.r_ratio))
            t0 = t0 + tau
            u = ui
            out.append(
                dict(t=t0, theta=mp.arg(ui), rdot=rd, thetadot=td, rdot_plus=rdp, thetadot_plus=tdp,
                     v_rel=vrel, point=ui, du_plus=du)
            )
    return out


# ---------------------------------------------------------------------------
# scipy solve_ivp reference
# ---------------------------------------------------------------------------


def linear_rhs(force, damp, stiff):
    """Right-hand side of U'' = force - damp U' - stiff U (complex coefficients) as a real 4-system
    (x, y, x', y')."""

    def rhs(t, y):
        u = complex(y[0], y[1])
        du = complex(y[2], y[3])
        ddu = force - damp * du - stiff * u
        return [du.real, du.imag, ddu.real, ddu.imag]

    return rhs


def cartesian_rhs(p):
    """Right-hand side of the Cartesian co-rotating ODE as a real 4-system (x, y, x', y')."""
    force = p.rho * complex(math.cos(p.phi), math.sin(p.phi))
    return linear_rhs(force, complex(p.gamma, 2.0), complex(p.omega**2 - 1.0, p.gamma))


def np_reset(u, du, d, mu, r_ratio):
    """Impact law (MODEL.md §2) in double precision, polar form; returns du_plus and polar values."""
    e = u / abs(u)
    w = e.conjugate() * du
    rdot, thetadot = w.real, w.imag
    v_rel = r_ratio + 1.0 + thetadot
    slip = mu * (1.0 + d) * rdot
    if abs(v_rel) > slip:
        thetadot_plus = thetadot - math.copysign(slip, v_rel)
    else:
        thetadot_plus = -(r_ratio + 1.0)
    rdot_plus = -d * rdot
    return e, e * complex(rdot_plus, thetadot_plus), rdot, thetadot, rdot_plus, thetadot_plus


def ivp_next_impact(p, t0, u, du, t_end, rtol=1e-12, atol=1e-12, method="DOP853"):
    """The first impact after (t0, U, U') by solve_ivp with a terminal event |U|^2 - 1
    (direction +1): a row (t, theta, rdot, thetadot, rdot_plus, thetadot_plus) and the
    post-impact state (U, U'), or None if the flight reaches t_end."""
    def hit(t, y):
        return y[0] * y[0] + y[1] * y[1] - 1.0

    hit.terminal = True
    hit.direction = 1.0
    sol = solve_ivp(cartesian_rhs(p), (t0, t_end), [u.real, u.imag, du.real, du.imag], method=method,
                    rtol=rtol, atol=atol, events=hit)
    assert sol.status in (0, 1), sol.message
    if sol.status == 0:
        return None
    te = float(sol.t_events[0][0])
    ye = sol.y_events[0][0]
    e, du_plus, rd, td, rdp, tdp = np_reset(complex(ye[0], ye[1]), complex(ye[2], ye[3]),
                                            p.d, p.mu, p.r_ratio)
    return (te, math.atan2(e.imag, e.real), rd, td, rdp, tdp), e, du_plus


def ivp_simulate(p, u0, du0, n_impacts, t_end, rtol=1e-12, atol=1e-12, method="DOP853"):
    """Impacts by solve_ivp, restarted at each impact from its own post-impact state."""
    t0 = 0.0
    u, du = complex(u0), complex(du0)
    rows = []
    segments = []  # (t_start, u_start, du_start) of each flight segment
    while len(rows) < n_impacts and t0 < t_end:
        segments.append((t0, u, du))
        step = ivp_next_impact(p, t0, u, du, t_end, rtol, atol, method)
        if step is None:
            break
        row, u, du = step
        rows.append(row)
        t0 = row[0]
    return np.array(rows).reshape(-1, 6), segments


def ivp_state(p, t_start, u_start, du_start, times, rtol=1e-12, atol=1e-12):
    """(U, U') at ``times`` (>= t_start) of free flight from the given state, by solve_ivp."""
    times = np.atleast_1d(np.asarray(times, dtype=float))
    sol = solve_ivp(cartesian_rhs(p), (t_start, float(times.max())),
                    [u_start.real, u_start.imag, du_start.real, du_start.imag],
                    method="DOP853", rtol=rtol, atol=atol, t_eval=np.sort(times), dense_output=False)
    assert sol.success
    order = np.argsort(times)
    u = np.empty(times.shape, complex)
    du = np.empty(times.shape, complex)
    u[order] = sol.y[0] + 1j * sol.y[1]
    du[order] = sol.y[2] + 1j * sol.y[3]
    return u, du


# ---------------------------------------------------------------------------
# F1 of MODEL.md §5 with scipy.linalg.expm
# ---------------------------------------------------------------------------


def matrix_A(p):
    return np.array([[0.0, 1.0], [1.0 - p.omega**2 - 1j * p.gamma, -p.gamma - 2j]], dtype=complex)


def a_matrix(p, T):
    """[a_ij(T)] = (e^{-A T} - I)^{-1}."""
    return np.linalg.inv(scipy.linalg.expm(-matrix_A(p) * T) - np.eye(2))


def f1_expm(p, T):
    q = (1.0 + p.d) * complex(1.0, p.mu)
    return 1.0 + (q * a_matrix(p, T)[1, 1]).real


# ---------------------------------------------------------------------------
# calling the simulator
# ---------------------------------------------------------------------------

#: Statuses a run may end with. "max-events" is the name of the run-length cap
#: where the simulator counts flights and contact phases rather than impacts.
MAX_STATUSES = {"max-impacts", "max-events"}
STATUSES = {"completed", "chatter"} | MAX_STATUSES


def run_simulation(params, u0=0j, du0=0j, t_end=500.0, *, max_impacts=None, stop_on_chatter=True,
                   impacts_only=False, **kw):
    """Call `rotorcontact.simulation.simulator` with a cap on the number of impacts.

    Where the simulator can continue through continuous contact, it is asked to
    stop at an accumulation of impacts (status "chatter"), the behaviour these
    tests check. The cap is passed as ``max_impacts`` or, where the simulator
    counts events (flights and contact phases), as ``max_events``: without
    contact each flight ends in one impact, so both mean the same here.
    With ``impacts_only`` every chatter criterion other than ``chatter_rdot`` is
    switched off, so that sequences of fast bounces are resolved impact by impact.
    """
    from rotorcontact import simulate

    sig = inspect.signature(simulate).parameters
    if max_impacts is not None:
        kw["max_impacts" if "max_impacts" in sig else "max_events"] = max_impacts
    if "on_chatter" in sig and "on_chatter" not in kw:
        kw["on_chatter"] = "stop" if stop_on_chatter else "contact"
    if impacts_only and "chatter_dt" in sig:
        kw["chatter_dt"] = 0.0
    return simulate(params, u0, du0, t_end, **kw)


def angle_diff(a, b):
    """Signed difference a - b of angles, in (-pi, pi]."""
    return np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))


@pytest.fixture(scope="session")
def ref():
    """Independent reference implementations (see the module docstring)."""
    return SimpleNamespace(
        MPFlight=MPFlight,
        MPFlightCritical=MPFlightCritical,
        flight=make_flight,
        mp_first_crossing=mp_first_crossing,
        mp_reset=mp_reset,
        mp_simulate=mp_simulate,
        cartesian_rhs=cartesian_rhs,
        linear_rhs=linear_rhs,
        np_reset=np_reset,
        ivp_simulate=ivp_simulate,
        ivp_next_impact=ivp_next_impact,
        ivp_state=ivp_state,
        matrix_A=matrix_A,
        a_matrix=a_matrix,
        f1_expm=f1_expm,
        angle_diff=angle_diff,
        run=run_simulation,
        STATUSES=STATUSES,
        MAX_STATUSES=MAX_STATUSES,
        DPS=DPS,
    )


@pytest.fixture(scope="session")
def reference_params():
    """The reference machine's dimensionless parameters (MODEL.md §1-§2; tests/reference_parameters.py)."""
    from reference_parameters import REF

    return REF


@pytest.fixture(scope="session", autouse=True)
def compiled_kernels():
    """Compile the simulator's and the batch kernels once, before any test.

    numba caches them on disk, so the CLI tests' subprocesses and the study
    workers load them instead of compiling inside their own time limits.
    """
    from rotorcontact import Parameters, simulate
    from rotorcontact.studies.batch import simulate_batch

    p = Parameters.reference()
    simulate(p, 0j, 0j, 10.0)
    simulate_batch(p, np.array([0j, 0.1 + 0j]), 0j, n_transient=2, n_record=2)
    simulate_batch(p, np.array([0j, 0.1 + 0j]), 0j, n_transient=2, n_record=2, parallel=False)


@pytest.fixture
def failing_drops(monkeypatch):
    """Every drop's run reports the status ``failed`` (its impacts and state as computed), to test how a
    failure is reported wherever it comes from."""
    from rotorcontact.interpreted import call_kernel
    from rotorcontact.simulation import drop_run
    from rotorcontact.simulation.drop import FAILED

    real = drop_run.drop_kernel

    def failing(*args):
        impacts, contacts, _status, t_stop, state = call_kernel(real, *args)
        return impacts, contacts, FAILED, t_stop, state

    monkeypatch.setattr(drop_run, "drop_kernel", failing)
