"""Rolling on a fixed stator with a free speed, integrated in the whirl angle (MODEL.md §7).

Once the bearing has failed, a rotor rolling on a fixed stator has Omega = -(c_r/R) theta' and
psi = psi_0 - (c_r/R)(theta - theta_0), and w = theta'^2 obeys the linear equation

    dw/dtheta = P(theta) + Q(theta) w      (`machine_model.rolling_fixed_coefficients`),

so that w = Phi (w_0 + int P / Phi), Phi = exp(int Q), and the time is t = t_0 + int dtheta / |theta'|.
`rolling_fixed_phase` evaluates these integrals panel by panel (half a turn each) with Gauss-Legendre
quadrature and its spectral integration matrix: the error is that of a polynomial of degree `NODES` - 1
over half a turn of smooth coefficients, far below the contact integrator's tolerance, at a cost per turn
that does not depend on the whirl rate. A rotor whirling at 10 kHz makes 10^5 turns in 10 s: the time
integrator (`general_contact.contact_phase`) would follow each with tens of steps.

A panel in which the contact would end (n <= 0, |q| >= mu n), the rotor near rest or turning back (w
small), or t_end falls, is handed to `contact_phase` from its start, which locates the event.

Its functions are compiled kernels for the event loops and take their arguments unchecked (NaN gives NaN;
text is a numba typing error): `rotorcontact.simulate`, `drop` and `run_general` are the checked entry
points.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.polynomial import legendre

from ..model.machine_model import contact_accelerations, rolling_fixed_coefficients
from .general_contact import contact_phase
from .peaks import BEST, PEAK_SLOTS, PEAK_STEPS, may_exceed, peak_next, peak_record, peak_search, peak_search_end

__all__ = ["rolling_fixed_phase", "fast_rolling_applies", "NODES", "PANEL"]

#: Gauss-Legendre nodes per panel and the panel's length in theta (half a turn).
NODES = 16
PANEL = math.pi
#: Panels handed to the time integrator once w falls below this fraction of its value at the start.
W_FLOOR = 1e-2
MAX_PANELS = 100_000_000


def _integration_matrix(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes x, weights and matrix S on [-1, 1]: sum_i S[j, i] f(x_i) = int_{-1}^{x_j} f, exact for degree < n."""
    x, wts = legendre.leggauss(n)
    v = legendre.legvander(x, n - 1)  # v[j, k] = P_k(x_j)
    # int_{-1}^{x} P_k = (P_{k+1} - P_{k-1}) / (2k + 1) for k >= 1, and x + 1 for k = 0
    integral = np.empty((n, n))
    integral[:, 0] = x + 1.0
    for k in range(1, n):
        up = np.zeros(k + 2)
        up[k + 1] = 1.0
        down = np.zeros(k + 2)
        down[k - 1] = 1.0
        integral[:, k] = (legendre.legval(x, up) - legendre.legval(x, down)) / (2 * k + 1)
    return x, wts, integral @ np.linalg.inv(v)


_X, _W, _S = _integration_matrix(NODES)
# barycentric weights of the nodes: f(x) = sum_j B_j f_j / (x - x_j) / sum_j B_j / (x - x_j), the polynomial
# through the nodes' values (`_interpolated`)
_B = np.array([1.0 / np.prod(_X[j] - np.delete(_X, j)) for j in range(NODES)])


@njit(cache=True)
def _reduced(angle: float) -> float:
    """``angle`` less a whole number of turns, to within the rounding of ``angle`` itself."""
    return angle - 2.0 * math.pi * round(angle / (2.0 * math.pi))


@njit(cache=True)
def _interpolated(x: float, values) -> float:
    """The polynomial through ``values`` at the nodes, at x in [-1, 1] (barycentric form)."""
    num = 0.0
    den = 0.0
    for j in range(NODES):
        if x == _X[j]:
            return values[j]
        c = _B[j] / (x - _X[j])
        num += c * values[j]
        den += c
    return num / den


@njit(cache=True)
def _rolling_force(cos_th, sin_th, cd, sd, w, sgn, p):
    """(n, q, theta') of rolling on the fixed stator at cos/sin theta, cd, sd = cos/sin delta and w = theta'^2
    (``p`` as `general_contact.NP`; the race-free branch of `contact_accelerations`)."""
    mass, cr, ecc, radius, mu, f_y, inv_p = p[0], p[1], p[2], p[3], p[5], p[10], p[11]
    ratio = cr / radius
    thd = sgn * math.sqrt(w)
    unb = ecc * ratio * ratio * w  # e Omega^2, Omega = -(c_r/R) theta'
    f_n = f_y * sin_th + unb * cd
    f_t = f_y * cos_th + unb * sd
    _a, _b, _c, n, q = contact_accelerations(f_n, f_t, sd, cd, ecc, cr, thd, mu, 1.0, True, mass, radius, inv_p,
                                             radius + cr, 0.0, 0.0)
    return n, q, thd


@njit(cache=True)
def _searched(panel, search):
    """Run the started ``search`` on the polynomials through the nodes' n (`_largest_force`); its largest n."""
    for _ in range(PEAK_STEPS):
        x = peak_next(search)
        if x != x:  # done
            break
        k = 1 if x < -1.0 else 0
        peak_record(search, x, _interpolated(x + 2.0 * k, panel[k]))
    return search[BEST]


@njit(cache=True)
def _largest_force(x1, f1, x2, f2, x3, f3, panel, search):
    """The largest n where the samples f1 < f2 >= f3 at x1 < x2 < x3 bracket a maximum (`peaks`), between
    samples from the polynomial through the nodes' n (as accurate as the quadrature's w).

    x is in the Legendre coordinate of the current panel, [-1, 1]; x < -1 reaches back into the panel before
    it, at x + 2. ``panel`` holds the nodes' n of the current panel (row 0) and of the one before (row 1);
    ``search``: the search's slots.
    """
    peak_search(search, x1, f1, x2, f2, x3, f3)
    return _searched(panel, search)


@njit(cache=True)
def _largest_force_at_end(xa, fa, xb, fb, panel, search):
    """The largest n within the gap (xa, xb) at the start or end of the samples, whose end sample is the larger
    (`peaks.peak_search_end`); coordinates as `_largest_force`."""
    peak_search_end(search, xa, fa, xb, fb)
    return _searched(panel, search)


@njit(cache=True)
def fast_rolling_applies(p) -> bool:
    """Rolling of parameters ``p`` (`general_contact.NP`) reduces to theta: free speed, fixed stator (no race,
    not even one held by its bearing, which could let it slip), no bearing stiffness or damping, and a rotor
    with a radius (its reduction divides by R)."""
    return (p[3] > 0.0 and p[11] > 0.0 and p[12] == 0.0 and p[13] == 0.0 and p[6] == 0.0 and p[7] == 0.0
            and p[8] == 0.0 and p[9] == 0.0)


@njit(cache=True)
def rolling_fixed_phase(y0, t0, t_end, p, rest_energy):
    """Rolling from y0 = (theta, theta', psi, Omega, Omega_b, E_d) at t0 until an event or t_end.

    Requires `fast_rolling_applies` (p) and y0 on the rolling manifold c_r theta' + R Omega = 0. Returns
    what `general_contact.contact_phase` returns for rolling; the panels where something happens are
    passed to it. The largest normal force is that of the samples (the nodes and the panels' ends) and of
    each maximum between them that may exceed the largest so far (`_largest_force`).
    """
    mass, cr, ecc, radius, f_y, inv_p = p[0], p[1], p[2], p[3], p[10], p[11]
    ratio = cr / radius
    th, psi, e_d = y0[0], y0[2], y0[5]
    w = y0[1] * y0[1]
    sgn = 1.0 if y0[1] > 0.0 else -1.0
    # kinetic energy m c_r^2 w / 2 + I_p (c_r/R)^2 w / 2 = energy_per_w * w
    energy_per_w = 0.5 * mass * cr * cr + 0.5 * ratio * ratio / inv_p
    w_floor = max(W_FLOOR * w, 2.0 * rest_energy / energy_per_w if rest_energy > 0.0 else 0.0)
    t = t0
    h = 0.5 * sgn * PANEL
    nodes = _X.shape[0]
    # the nodes' offsets from the panel's start, in theta and in delta = psi - theta (rate -(1 + c_r/R))
    c_off = np.empty(nodes)
    s_off = np.empty(nodes)
    c_doff = np.empty(nodes)
    s_doff = np.empty(nodes)
    for j in range(nodes):
        off = h * (1.0 + _X[j])
        c_off[j], s_off[j] = math.cos(off), math.sin(off)
        c_doff[j], s_doff[j] = math.cos((1.0 + ratio) * off), -math.sin((1.0 + ratio) * off)
    q_nodes = np.empty(nodes)
    p_nodes = np.empty(nodes)
    g_nodes = np.empty(nodes)
    phi = np.empty(nodes)
    ct = np.empty(nodes)
    st = np.empty(nodes)
    cd = np.empty(nodes)
    sd = np.empty(nodes)
    # the nodes' n of this panel (row 0) and the one before (`_largest_force`)
    panel = np.zeros((2, nodes))
    n_nodes = panel[0]
    search = np.empty(PEAK_SLOTS)
    th_r = _reduced(th)
    d_r = _reduced(psi - th)
    n_start = _rolling_force(math.cos(th_r), math.sin(th_r), math.cos(d_r), math.sin(d_r), w, sgn, p)[0]
    n_max = max(n_start, 0.0)
    n_before = math.inf  # the last node of the panel before (none yet: no maximum is bracketed across the start)
    for _ in range(MAX_PANELS):
        if w <= w_floor:
            break
        # reduced first: after 10^5 turns the library's sine takes its slow path for large arguments
        th_r = _reduced(th)
        d_r = _reduced(psi - th)
        c0, s0 = math.cos(th_r), math.sin(th_r)
        cd0, sd0 = math.cos(d_r), math.sin(d_r)
        for j in range(nodes):
            ct[j] = c0 * c_off[j] - s0 * s_off[j]
            st[j] = s0 * c_off[j] + c0 * s_off[j]
            cd[j] = cd0 * c_doff[j] - sd0 * s_doff[j]
            sd[j] = sd0 * c_doff[j] + cd0 * s_doff[j]
            p_nodes[j], q_nodes[j] = rolling_fixed_coefficients(ct[j], sd[j], cd[j], f_y, ecc, cr, mass, radius, inv_p)
        for j in range(nodes):
            acc = 0.0
            for i in range(nodes):
                acc += _S[j, i] * q_nodes[i]
            phi[j] = math.exp(h * acc)
            g_nodes[j] = p_nodes[j] / phi[j]
        ok = True
        dt = 0.0
        for j in range(nodes):
            acc = 0.0
            for i in range(nodes):
                acc += _S[j, i] * g_nodes[i]
            wj = phi[j] * (w + h * acc)
            if wj <= w_floor:
                ok = False
                break
            n, q, thd = _rolling_force(ct[j], st[j], cd[j], sd[j], wj, sgn, p)
            if n <= 0.0 or abs(q) >= p[5] * n:
                ok = False
                break
            n_nodes[j] = n
            dt += _W[j] / abs(thd)
        dt *= abs(h)
        if not ok or t + dt >= t_end:
            break
        sq = 0.0
        sg = 0.0
        for j in range(nodes):
            sq += _W[j] * q_nodes[j]
            sg += _W[j] * g_nodes[j]
        w = math.exp(h * sq) * (w + h * sg)
        th += 2.0 * h
        psi -= ratio * 2.0 * h
        t += dt
        th_e = th_r + 2.0 * h
        d_e = d_r - (1.0 + ratio) * 2.0 * h
        n_end = _rolling_force(math.cos(th_e), math.sin(th_e), math.cos(d_e), math.sin(d_e), w, sgn, p)[0]
        # the samples, in the panel's coordinate: the panel before's last node, the start, the nodes, the end
        n_max = max(n_max, n_end)
        xb = _X[nodes - 1] - 2.0  # the panel before's last node
        if n_before < n_start and n_start >= n_nodes[0]:
            if may_exceed(xb, n_before, -1.0, n_start, _X[0], n_nodes[0], n_max):
                n_max = max(n_max, _largest_force(xb, n_before, -1.0, n_start, _X[0], n_nodes[0], panel, search))
        for j in range(nodes):
            n_max = max(n_max, n_nodes[j])
        if n_before == math.inf and n_start >= n_nodes[0]:  # the phase's start, above its first node
            n_max = max(n_max, _largest_force_at_end(-1.0, n_start, _X[0], n_nodes[0], panel, search))
        for j in range(nodes):
            x1, f1 = (_X[j - 1], n_nodes[j - 1]) if j > 0 else (-1.0, n_start)
            x3, f3 = (_X[j + 1], n_nodes[j + 1]) if j < nodes - 1 else (1.0, n_end)
            if f1 < n_nodes[j] and n_nodes[j] >= f3 and may_exceed(x1, f1, _X[j], n_nodes[j], x3, f3, n_max):
                n_max = max(n_max, _largest_force(x1, f1, _X[j], n_nodes[j], x3, f3, panel, search))
        panel[1, :] = n_nodes
        n_before = n_nodes[nodes - 1]
        n_start = n_end
    if n_before < math.inf and n_start >= n_before:
        # the last whole panel's end, above its last node: the time integrator goes on from that end
        xb = _X[nodes - 1] - 2.0
        n_max = max(n_max, _largest_force_at_end(xb, n_before, -1.0, n_start, panel, search))
    thd = sgn * math.sqrt(w)
    y = np.array([th, thd, psi, -ratio * thd, 0.0, e_d])
    code, t1, y1, n_rest = contact_phase(y, t, t_end, p, True, 1.0, rest_energy)
    return code, t1, y1, max(n_max, n_rest)
