"""The compliant law with a stator on springs (MODEL.md §8): the coupled equations against solve_ivp, the
guaranteed impact search against a moving stator, the energy balance and the reduced mass of an impact
(dry whip: tests/analysis/test_dry_whip.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

from rotorcontact import Machine, ParameterError, reference_machine
from rotorcontact.model.machine_model import restitution_damping
from rotorcontact.simulation.drop import IMPACT_FIELDS
from rotorcontact.simulation.drop_run import DAMPING_VELOCITY_FRACTION, RPM, run_general
from rotorcontact.simulation.general_flight import flight_state, make_flight, make_stator_flight, next_impact
from rotorcontact.simulation.roots import CROSSING, NO_CROSSING

COL = {name: i for i, name in enumerate(IMPACT_FIELDS)}
KC = 1e10  # N/m^1.5
STATOR = dict(stator_mass=20.0, stator_stiffness=4e6, stator_damping=400.0)


def machine(**changes):
    base = {**reference_machine().as_dict(), "contact": "compliant", "contact_stiffness": KC, **STATOR}
    return Machine(**{**base, **changes})


# ---- an episode against a stator on springs, against solve_ivp -------------------------------------------------

def _coupled_rates(m, speed, chi_over_v0):
    """The rates of (z, z', z_s, z_s') in sliding contact (F_t = -mu F_n sgn v_rel), bearing failed, no
    gravity or unbalance, speed held: the equations of MODEL.md §8 written out again for the test."""
    kx, ky, cx, cy = m.stator_support()

    def rates(_t, s):
        x, y, vx, vy, xs, ys, vxs, vys = s
        dx, dy = x - xs, y - ys
        dist = math.hypot(dx, dy)
        nx, ny = dx / dist, dy / dist
        vn = (vx - vxs) * nx + (vy - vys) * ny
        vt = (vy - vys) * nx - (vx - vxs) * ny
        delta = dist - m.clearance
        fn = max(0.0, m.contact_stiffness * max(delta, 0.0) ** m.exponent * (1.0 + chi_over_v0 * vn))
        ft = -m.friction * fn * math.copysign(1.0, vt + m.rotor_radius * speed)
        fx, fy = -fn * nx - ft * ny, -fn * ny + ft * nx  # on the rotor; the stator takes -F
        return [vx, vy, fx / m.mass, fy / m.mass, vxs, vys,
                (-kx * xs - cx * vxs - fx) / m.stator_mass, (-ky * ys - cy * vys - fy) / m.stator_mass]

    return rates


def test_an_episode_against_a_moving_stator_matches_solve_ivp():
    m = machine(eccentricity=0.0, restitution=0.7)
    speed = 3000 * RPM
    v0 = complex(0.4, 0.15)
    zb0, vb0 = complex(-2e-5, 1e-5), complex(-0.03, 0.01)  # the stator moving towards the rotor
    res = run_general(m, 0j, v0, speed, 0.0, 5e-3, stator_start=(zb0, vb0))
    row = res.impacts[0]
    # the flight to the wall, from the closed-form flights, to the crossing found by brentq
    t_hit = brentq(lambda t: abs(v0 * t - (zb0 + vb0 * t)) - m.clearance, 0.0, 1.0, xtol=1e-16)
    # (the stator's support moves it during the flight: follow it by solve_ivp as well)
    kx, _ky, cx, _cy = m.stator_support()
    free = solve_ivp(lambda _t, s: [s[2], s[3], (-kx * s[0] - cx * s[2]) / m.stator_mass,
                                    (-kx * s[1] - cx * s[3]) / m.stator_mass],
                     (0.0, 5e-3), [zb0.real, zb0.imag, vb0.real, vb0.imag], method="DOP853", rtol=1e-13,
                     atol=1e-20, dense_output=True)
    t_hit = brentq(lambda t: abs(v0 * t - complex(*free.sol(t)[:2])) - m.clearance, 0.5 * t_hit, 1.5 * t_hit,
                   xtol=1e-16)
    assert row[COL["t_s"]] == pytest.approx(t_hit, rel=1e-10)
    xs, ys, vxs, vys = free.sol(t_hit)
    zs_hit = complex(xs, ys)
    normal = (v0 * t_hit - zs_hit) / abs(v0 * t_hit - zs_hit)
    v_n = (normal.conjugate() * (v0 - complex(vxs, vys))).real
    assert row[COL["normal_velocity_m_per_s"]] == pytest.approx(v_n, rel=1e-9)
    # the episode
    chi = restitution_damping(m.restitution, m.exponent) / max(v_n, DAMPING_VELOCITY_FRACTION * m.clearance * speed)

    def parted(_t, s):
        return math.hypot(s[0] - s[4], s[1] - s[5]) - m.clearance

    parted.terminal = True
    parted.direction = -1.0
    start = [(v0 * t_hit).real, (v0 * t_hit).imag, v0.real, v0.imag, xs, ys, vxs, vys]
    # leave the wall first: the event must see delta > 0 before it can fall back through 0
    ref = solve_ivp(_coupled_rates(m, speed, chi), (t_hit, t_hit + 4e-3), start, method="DOP853", rtol=1e-12,
                    atol=1e-18, events=parted, first_step=1e-9)
    (t_out,) = ref.t_events[0]
    assert row[COL["duration_s"]] == pytest.approx(t_out - t_hit, rel=1e-7)
    state = ref.y_events[0][0]
    assert complex(row[COL["vx_plus"]], row[COL["vy_plus"]]) == pytest.approx(complex(state[2], state[3]), rel=1e-7)
    # after the episode the stator rings on its support in closed form, the rotor flies straight on
    assert len(res.impacts) == 1
    after = solve_ivp(_coupled_rates(m, speed, chi), (t_out, res.t_stop), state, method="DOP853", rtol=1e-12,
                      atol=1e-18)
    np.testing.assert_allclose(res.final_state[8:10], after.y[4:6, -1], rtol=0, atol=1e-7 * m.clearance)
    np.testing.assert_allclose(res.final_state[10:12], after.y[6:8, -1], rtol=1e-7)
    np.testing.assert_allclose(res.final_state[1:3], after.y[0:2, -1], rtol=0, atol=1e-7 * m.clearance)


@pytest.mark.parametrize("d", [0.3, 0.6, 0.95])
def test_an_impact_on_a_free_stator_rebounds_with_the_restitution_at_the_reduced_mass(d):
    # a support too soft to act within the episode: the relative motion is the isolated impact with the
    # reduced mass m m_s / (m + m_s), and chi(d, n) does not depend on the mass
    m = machine(eccentricity=0.0, friction=0.0, restitution=d, stator_stiffness=1e-6, stator_damping=0.0)
    v0 = 0.3
    r = run_general(m, 0j, complex(v0, 0.0), m.speed, 0.0, m.clearance / v0 + 3e-3)
    row = r.impacts[0]
    reduced = m.mass * m.stator_mass / (m.mass + m.stator_mass)
    assert row[COL["rebound_ratio"]] == pytest.approx(d, rel=1e-8)
    assert row[COL["normal_impulse_Ns"]] == pytest.approx((1.0 + d) * reduced * v0, rel=1e-8)
    assert row[COL["energy_lost_J"]] == pytest.approx((1.0 - d * d) * reduced * v0 * v0 / 2.0, rel=1e-7)


# ---- energy ---------------------------------------------------------------------------------------------------

def _energy(m: Machine, state) -> float:
    """Rotor: m |v|^2/2 + I_p Omega^2/2 + m g y; contact: K_c delta^(n+1)/(n+1); stator: m_s |v_s|^2/2 and the
    energy of its springs (its weight is carried by their preload: z_s is measured from its rest); race:
    I_b Omega_b^2/2."""
    x, y, vx, vy, spin, race = state[1:7]
    xs, ys, vxs, vys = state[8:12]
    kx, ky, _cx, _cy = m.stator_support()
    delta = max(math.hypot(x - xs, y - ys) - m.clearance, 0.0)
    return (0.5 * m.mass * (vx * vx + vy * vy) + 0.5 * m.polar_inertia * spin**2 + m.mass * m.g * y
            + m.contact_stiffness * delta ** (m.exponent + 1.0) / (m.exponent + 1.0)
            + 0.5 * m.stator_mass * (vxs * vxs + vys * vys) + 0.5 * (kx * xs * xs + ky * ys * ys)
            + (0.5 * m.race_inertia * race**2 if m.has_race else 0.0))


@pytest.mark.parametrize("t_end", [0.03, 0.2])
@pytest.mark.parametrize("support", [
    dict(stator_damping=400.0),
    dict(stator_stiffness_x=2e6, stator_damping_x=50.0, stator_damping_y=900.0),
    # a race turning in the stator on springs: friction spins it up, its drag dissipates
    dict(stator_damping=400.0, race_inertia=2e-4, race_drag_torque=0.1, race_drag_coefficient=1e-4),
])
def test_dissipated_energy_is_the_fall_of_the_energy_of_rotor_and_stator(t_end, support):
    # the support's damping dissipates in flight (the stator rings between episodes) and during episodes
    m = machine(eccentricity=0.0, gravity=9.81, polar_inertia=0.04, restitution=0.9, **support)
    speed = 3000 * RPM
    r = run_general(m, 0j, 0j, speed, 0.0, t_end)
    assert len(r.impacts) >= 2
    assert (r.final_state[6] != 0.0) == m.has_race
    start = np.zeros(12)
    start[5] = speed
    assert r.energy_dissipated > 0.0
    assert r.energy_dissipated == pytest.approx(_energy(m, start) - _energy(m, r.final_state), rel=1e-8)


def test_an_elastic_frictionless_undamped_stator_keeps_the_energy():
    m = machine(eccentricity=0.0, gravity=9.81, polar_inertia=0.04, restitution=1.0, friction=0.0,
                stator_damping=0.0)
    speed = 3000 * RPM
    r = run_general(m, 0j, 0j, speed, 0.0, 0.1, tol=1e-12)
    assert len(r.impacts) >= 5 and r.energy_dissipated == 0.0
    start = np.zeros(12)
    start[5] = speed
    # to the episodes' integration error, against the kinetic energy of the first impact
    scale = m.mass * r.column("normal_velocity_m_per_s")[0] ** 2 / 2.0
    assert _energy(m, r.final_state) == pytest.approx(_energy(m, start), abs=1e-9 * scale)


# ---- the guaranteed impact search against a moving stator ------------------------------------------------------

def _graze(peak: float):
    """A rotor flight and a ringing stator whose relative distance |z - z_s| peaks at ``peak`` clearances."""
    # the rotor drifts slowly; the stator swings out from its centre and back (first swing near s = 4 ms)
    rotor = (complex(0.02, -0.01), complex(1.0, 0.5))
    stator = (0j, complex(-300.0, 200.0))
    gamma, w2 = 30.0, 2.0e5

    def build(scale):
        fl = make_flight(rotor[0] * scale, rotor[1] * scale, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        st = make_stator_flight(stator[0] * scale, stator[1] * scale, gamma, w2, gamma, 0.7 * w2)
        return fl, st

    fl, st = build(1.0)

    def gap(s):
        return -abs(flight_state(fl, 0.0, s)[0] - flight_state(st, 0.0, s)[0])

    grid = np.linspace(0.0, 0.006, 4001)
    i = int(np.argmin([gap(s) for s in grid]))
    assert 0 < i < len(grid) - 1
    res = minimize_scalar(gap, bounds=(grid[max(i - 1, 0)], grid[i + 1]), method="bounded",
                          options={"xatol": 1e-14})
    # the motions are linear: scaling both starts scales z - z_s
    fl, st = build(peak / -res.fun)
    return fl, st, res.x


@pytest.mark.parametrize("eps", [1e-6, 1e-9])
def test_near_tangent_flights_against_a_moving_stator(eps):
    fl, st, t_peak = _graze(1.0 + eps)
    code, s = next_impact(fl, 0.0, 1.5 * t_peak, False, False, st)
    assert code == CROSSING and s <= t_peak * (1.0 + 1e-9)
    assert abs(abs(flight_state(fl, 0.0, s)[0] - flight_state(st, 0.0, s)[0]) - 1.0) <= 1e-13
    fl, st, t_peak = _graze(1.0 - eps)
    code, s = next_impact(fl, 0.0, 1.5 * t_peak, False, False, st)
    assert code == NO_CROSSING and s == 1.5 * t_peak


def test_the_first_crossing_against_a_moving_stator_is_the_first_root():
    # a stator ringing fast against a slow rotor: the gap closes and opens several times before contact
    fl = make_flight(0.3 + 0.0j, 0.5 + 0.0j, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    st = make_stator_flight(-0.45 + 0.0j, 0j, 5.0, 4.0e4, 5.0, 4.0e4)

    def gap(s):
        return abs(flight_state(fl, 0.0, s)[0] - flight_state(st, 0.0, s)[0]) - 1.0

    grid = np.linspace(0.0, 2.0, 200_001)
    values = np.array([gap(s) for s in grid])
    i = int(np.flatnonzero(values > 0.0)[0])
    swings = np.flatnonzero((values[1:-1] > values[:-2]) & (values[1:-1] > values[2:]))
    assert np.count_nonzero(swings < i) >= 10  # the gap's maxima that stay short of the wall
    first = brentq(gap, grid[i - 1], grid[i], xtol=1e-15)
    code, s = next_impact(fl, 0.0, 2.0, False, False, st)
    assert code == CROSSING and s == pytest.approx(first, rel=1e-12)


# ---- inputs ---------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("changes,match", [
    (dict(stator_mass=None), "stator_stiffness = 4000000.0 with stator_mass = None"),
    (dict(contact=None, contact_stiffness=None), "stator_mass = 20.0 with contact = None"),
    (dict(stator_stiffness=None), "stator_stiffness_x = None with stator_stiffness = None"),
    (dict(stator_stiffness=None, stator_stiffness_x=1e6), "stator_stiffness_y = None"),
    (dict(stator_mass=0.0), "stator_mass = 0.0"),
    (dict(stator_stiffness=-1.0), "stator_stiffness = -1.0"),
    (dict(stator_damping_y=-2.0), "stator_damping_y = -2.0"),
])
def test_bad_stator_keys_are_refused(changes, match):
    with pytest.raises(ParameterError, match=match):
        machine(**changes)


def test_stator_support_per_axis_and_start_refused_for_a_fixed_stator():
    m = machine(stator_stiffness_y=3e6, stator_damping_x=10.0)
    assert m.has_stator and m.stator_support() == (4e6, 3e6, 10.0, 400.0)
    fixed = Machine(**{**reference_machine().as_dict(), "contact": "compliant", "contact_stiffness": KC})
    assert not fixed.has_stator and fixed.stator_support() == (0.0, 0.0, 0.0, 0.0)
    with pytest.raises(ParameterError, match="stator_start"):
        run_general(fixed, 0j, 0j, 100.0, 0.0, 0.01, stator_start=(1e-5, 0j))


def test_stator_keys_with_units_and_the_json_contract(tmp_path):
    from rotorcontact import load_machine
    from tests.reference_parameters import REF_MACHINE_TOML

    path = tmp_path / "m.toml"
    path.write_text(REF_MACHINE_TOML + 'contact = "compliant"\ncontact_stiffness = "1 kN/mm**1.5"\n'
                    'stator_mass = "20 kg"\nstator_stiffness = "4 kN/mm"\nstator_damping = "0.4 kN*s/m"\n')
    m = load_machine(path)
    assert m.stator_mass == 20.0 and m.stator_stiffness == pytest.approx(4e6, rel=1e-14)
    assert m.stator_damping == pytest.approx(400.0, rel=1e-14)
    r = run_general(m, 0j, complex(0.3, 0.0), m.speed, 0.0, 0.01)
    summary = r.to_dict()["summary"]
    assert summary["stator_final"] == {"x_m": r.final_state[8], "y_m": r.final_state[9],
                                       "vx_m_per_s": r.final_state[10], "vy_m_per_s": r.final_state[11]}
    assert summary["stator_final"]["vx_m_per_s"] != 0.0
    rigid = load_machine("reference")
    rigid_run = run_general(rigid, 0j, complex(0.3, 0.0), rigid.speed, 0.0, 0.01)
    assert rigid_run.to_dict()["summary"]["stator_final"] is None


def test_runs_with_a_stator_on_springs_do_not_depend_on_the_tolerance():
    from tests.simulation.test_compliant import tolerance_pair

    loose, tight = tolerance_pair(machine(gravity=9.81, polar_inertia=0.04), 12000 * RPM, 3)
    # the stator's end state, after a lasting backward whirl at MN forces: to 1e-6 of its excursion
    excursion = abs(complex(*tight.final_state[8:10]))
    np.testing.assert_allclose(loose.final_state[8:10], tight.final_state[8:10], rtol=0, atol=1e-6 * excursion)
