"""Design maps: the classification is the nondimensional analysis, seen in rpm and SI units."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError, Parameters, reference_machine
from rotorcontact.studies.design_map import (
    classify_machine,
    plane_map,
    rad_s_to_rpm,
    recovery_probability,
    rpm_to_rad_s,
    speed_map,
)
from rotorcontact.analysis.equilibria import equilibria
from rotorcontact.maps.impact_map import one_impact_orbits


def _analysis(p: Parameters):
    """Regime and coexisting motions straight from the nondimensional analysis."""
    eq = equilibria(p)
    whirl = eq.regular.admissible and eq.regular.stable
    contact = [o.label for o in one_impact_orbits(p) if o.admissible and o.plausible and o.stable]
    contact += [ps.name for ps in eq.pseudo if ps.exists and ps.admissible and ps.stable]
    regime = "contact-certain" if not whirl else ("bistable" if contact else "safe")
    return regime, tuple(contact)


def test_reference_speed_agrees_with_the_nondimensional_analysis():
    m = reference_machine()
    pt = classify_machine(m)
    # MODEL.md: the reference machine gives gamma ~ 0.152, omega ~ 0.76
    assert pt.gamma == pytest.approx(0.152, abs=5e-4) and pt.omega == pytest.approx(0.76, abs=5e-4)
    p = Parameters(gamma=1400 / (50 * 184.2), omega=math.sqrt(9.8e5 / (50 * 184.2**2)), rho=3 / 7, mu=0.15,
                   d=0.95, phi=0.21, r_ratio=0.04 / 0.7e-3)
    assert (pt.regime, pt.coexisting) == _analysis(p)
    assert pt.speed_rpm == pytest.approx(184.2 * 60 / (2 * math.pi), rel=1e-14)


def test_rpm_conversion_by_hand():
    assert rpm_to_rad_s(3000) == pytest.approx(100 * math.pi, rel=1e-15)
    assert rad_s_to_rpm(100 * math.pi) == pytest.approx(3000, rel=1e-15)
    np.testing.assert_allclose(rpm_to_rad_s([60.0, 120.0]), [2 * math.pi, 4 * math.pi], rtol=1e-15)


def test_physical_outputs_in_si():
    m = reference_machine()
    pt = classify_machine(m)
    p = m.parameters()
    by_name = {mo.name: mo for mo in pt.motions}
    # contact-free whirl amplitude |k| c_r in micrometres
    assert by_name["x_R"].amplitude_um == pytest.approx(abs(p.k) * 0.7e-3 * 1e6, rel=1e-12)
    for orbit in one_impact_orbits(p):
        if orbit.label in by_name:
            mo = by_name[orbit.label]
            # impulse (1 + d) rdot in units of m c_r Omega; one impact per period T / Omega
            assert mo.impulse_Ns == pytest.approx((1 + 0.95) * orbit.rdot * 50 * 0.7e-3 * 184.2, rel=1e-12)
            assert mo.impact_rate_hz == pytest.approx(184.2 / orbit.T, rel=1e-12)
    for ps in equilibria(p).pseudo:
        if ps.name in by_name:
            mo = by_name[ps.name]
            assert mo.contact_force_N == pytest.approx(ps.normal_force * 50 * 0.7e-3 * 184.2**2, rel=1e-12)
            # friction power mu N v_rel with v_rel = R Omega + c_r Omega (thetadot = 0)
            v_rel = 0.04 * 184.2 + 0.7e-3 * 184.2
            assert mo.friction_power_W == pytest.approx(0.15 * mo.contact_force_N * v_rel, rel=1e-12)
            # a rub of a pseudo-equilibrium is named as the simulator names it
            assert mo.kind == "forward-rub"


def test_each_speed_point_is_the_analysis_at_that_speed():
    m = reference_machine()
    dmap = speed_map(m, np.linspace(900, 4000, 12))
    for pt in dmap.points:
        assert (pt.regime, pt.coexisting) == _analysis(m.with_speed(rpm_to_rad_s(pt.speed_rpm)).parameters())


def test_two_resolutions_give_the_same_boundaries_within_one_grid_step():
    m = reference_machine()
    coarse = speed_map(m, np.linspace(1000, 6000, 51))
    fine = speed_map(m, np.linspace(1000, 6000, 401))
    step = 5000 / 50
    bc, bf = coarse.boundaries(), fine.boundaries()
    assert len(bc) == len(bf) >= 2
    for (sc, a, b), (sf, c, d) in zip(bc, bf):
        assert (a, b) == (c, d)
        assert abs(sc - sf) <= step


def test_plane_map_shapes_and_points():
    m = reference_machine()
    dmap = plane_map(m, ("stiffness", "damping"), np.linspace(5e5, 1.5e6, 4), np.linspace(500, 3000, 3))
    assert dmap.shape == (4, 3)
    assert dmap.regime_codes().shape == (4, 3)
    pt = dmap.points[1 * 3 + 2]
    assert pt.stiffness == pytest.approx(5e5 + 1e6 / 3) and pt.damping == pytest.approx(3000)
    ds = dmap.to_xarray()
    assert ds["regime"].dims == ("stiffness", "damping")
    assert ds["stiffness"].attrs["units"] == "N/m"
    # CF: every variable and coordinate named, flags as values of the variable's own type
    for name in list(ds.data_vars) + list(ds.coords):
        assert ds[name].attrs["long_name"], name
    flags = ds["regime"].attrs["flag_values"]
    assert flags.dtype == ds["regime"].dtype and list(flags) == list(range(len(ds["regime"].attrs["flag_meanings"]
                                                                                .split())))
    for text, pt in zip(ds["coexisting"].values.ravel(), dmap.points):  # labels hold commas: ';' between them
        assert (text.split(";") if text else []) == list(pt.coexisting)
    assert all(k[len("machine_"):-len("_units")] in m.as_dict() for k in ds.attrs if k.endswith("_units"))
    assert ds.attrs["source"].startswith("rotorcontact ")


def test_recovery_from_a_small_shock_is_certain():
    """A kick too small to reach the stator by the all-time bound |k| + |V| < 1 always recovers."""
    m = reference_machine().with_speed(rpm_to_rad_s(3000))
    p = m.parameters()
    assert abs(p.k) < 1
    nu = math.sqrt(p.omega**2 - p.gamma**2 / 4)
    # |V(t)| <= |V'(0)| / nu for V(0) = 0 in the inertial frame, so this kick never reaches r = 1
    kick = 0.5 * (1 - abs(p.k)) * nu
    shock = kick * m.clearance * m.speed
    assert recovery_probability(m, shock, directions=8) == 1.0


def test_recovery_needs_contact_free_whirl():
    m = reference_machine().with_speed(rpm_to_rad_s(1400))
    assert classify_machine(m).regime == "contact-certain"
    with pytest.raises(ParameterError):
        recovery_probability(m, 0.01)


def test_bad_grids_are_rejected():
    with pytest.raises(ParameterError):
        speed_map(reference_machine(), [1000, float("nan")])
    with pytest.raises(ParameterError):
        speed_map(reference_machine(), [-5.0, 100.0])
    with pytest.raises(ParameterError):
        plane_map(reference_machine(), ("damping", "speed_rpm"), [1.0], [1.0])


def test_design_map_draws_the_map_of_the_settings_given_ranges():
    from rotorcontact.studies.design_map import OUTCOMES, REGIMES, design_map

    machine = reference_machine()
    dmap = design_map(machine, {"speed": (2000.0, 4000.0)}, 5)
    assert dmap.axes == ("speed_rpm",) and dmap.shape == (5,)
    assert dmap.points == speed_map(machine, np.linspace(2000.0, 4000.0, 5)).points
    plane = design_map(machine, {"stiffness": (5e5, 1e6), "damping": (500.0, 1500.0)}, 100)
    assert plane.axes == ("stiffness", "damping") and plane.shape == (60, 60)
    assert sum(plane.outcome_counts().values()) == 3600 and tuple(plane.outcome_counts()) == OUTCOMES
    assert REGIMES == OUTCOMES
    with pytest.raises(ParameterError, match="give no map"):
        design_map(machine, {"damping": (500.0, 1500.0)}, 5)
    from rotorcontact.studies.design_map import MAX_POINTS

    with pytest.raises(ParameterError, match=f"^n = {MAX_POINTS + 1} .*allowed"):
        design_map(machine, {"speed": (2000.0, 4000.0)}, MAX_POINTS + 1)


def test_recovery_of_a_map_is_one_study_equal_to_the_basins_of_each_point():
    """The recovery probabilities of a map (one chunked study) are the no-contact fractions that `basins`
    computes on each point's shock grid, whatever the executor and the chunking."""
    from rotorcontact.studies.basins import basins, shock_grid
    from rotorcontact.studies.design_map import recovery_probabilities

    m = reference_machine()
    shock = 5e-3
    dmap = speed_map(m, np.linspace(1800.0, 2600.0, 5), shock=shock)
    bistable = [pt for pt in dmap.points if pt.regime == "bistable"]
    assert len(bistable) >= 2
    assert all(pt.recovery_probability is None for pt in dmap.points if pt.regime != "bistable")
    machines = [m.with_speed(rpm_to_rad_s(pt.speed_rpm)) for pt in bistable]
    directions = 24
    step = 2.0 * math.pi / directions
    for pt, machine in zip(bistable, machines):
        kick = shock / (machine.clearance * machine.speed)
        grid = shock_grid((kick, kick, 1), (-math.pi, math.pi - step, directions))
        expected = basins(machine.parameters(), grid, progress=False, n_jobs=1).fractions.get("no-contact", 0.0)
        assert pt.recovery_probability == expected
    serial = recovery_probabilities(machines, shock, chunk_size=1)
    assert list(serial) == [pt.recovery_probability for pt in bistable]
    assert np.array_equal(recovery_probabilities(machines, shock, chunk_size=3, n_jobs=2), serial)
    with pytest.raises(ParameterError, match="chunk_size"):
        recovery_probabilities(machines, shock, chunk_size=0)


def test_a_speed_too_low_to_search_names_the_lowest_speed_that_can_be_mapped():
    import re

    from rotorcontact.model.params import reference_machine
    from rotorcontact.studies.design_map import speed_map

    m = reference_machine()
    with pytest.raises(ParameterError) as err:
        speed_map(m, [1.0, 2.0])
    text = str(err.value)
    assert text.startswith("at speed = 1 rpm") and "to the period 12" in text
    lowest = float(re.search(r"speeds from ([0-9.e+-]+) rpm$", text).group(1))
    assert speed_map(m, [lowest]).points[0].regime == "safe"
    with pytest.raises(ParameterError, match=f"speeds from {lowest:.4g} rpm"):
        speed_map(m, [0.99 * lowest])


@pytest.mark.parametrize("t_max", [float("nan"), float("inf"), 0.0, "x"])
def test_a_bad_t_max_is_named_before_the_settings_are_checked(t_max):
    from rotorcontact.model.params import reference_machine
    from rotorcontact.studies.design_map import speed_map

    with pytest.raises(ParameterError, match="^t_max = "):
        speed_map(reference_machine(), [3000.0], t_max=t_max)


@pytest.mark.parametrize("ranges, match", [
    ({"speed": ("1000", "2000")}, r"^range of speed = '1000' is text"),
    ({"speed": (2000.0, 1000.0)}, r"^range of speed = \(2000.0, 1000.0\) is invalid; allowed: \(first, last\) "
                                  r"with first < last"),
    ({"speed": (1000.0, 1000.0)}, r"with first < last \(first = last for a single point\)"),
    ({"speed": np.array(1000.0)}, r"^range of speed = .* allowed: \(first, last\), two numbers"),
    ({"speed": (1000.0, 2000.0, 3000.0)}, r"^range of speed = .* allowed: \(first, last\), two numbers"),
    ({"speed": "1000:2000"}, r"^range of speed = '1000:2000' is invalid"),
    ({"speed": (1000.0, math.inf)}, r"^range of speed = inf is not finite"),
    ([("speed", (1000.0, 2000.0))], r"^ranges = .* allowed: a dict of \(first, last\) by setting"),
    ({"speed": (1000.0, 2000.0), "mass": (1.0, 2.0)}, r"^ranges of mass, speed give no map"),
])
def test_design_map_refuses_malformed_ranges_by_name(ranges, match):
    from rotorcontact.studies.design_map import design_map

    with pytest.raises(ParameterError, match=match):
        design_map(reference_machine(), ranges, 3)


def test_one_point_over_a_range_of_two_ends_is_refused():
    from rotorcontact.studies.design_map import design_map

    with pytest.raises(ParameterError, match=r"^range of speed = \(1000.0, 6000.0\) has two ends, but n = 1 is a "
                                             r"single point; allowed: n >= 2, or first = last$"):
        design_map(reference_machine(), {"speed": (1000.0, 6000.0)}, 1)


@pytest.mark.parametrize("speeds", [["1000"], [True], [1000 + 1j], "1000"])
def test_speeds_that_are_not_real_numbers_are_refused(speeds):
    with pytest.raises(ParameterError, match=r"^speeds_rpm = .* allowed: finite values > 0"):
        speed_map(reference_machine(), speeds)


def test_a_range_of_one_point_may_be_a_single_value():
    from rotorcontact.studies.design_map import design_map

    one = design_map(reference_machine(), {"speed": (12000.0, 12000.0)}, 1)
    assert one.axes == ("speed_rpm",) and list(one.values[0]) == [12000.0]
    assert one.points == speed_map(reference_machine(), [12000.0]).points


def test_a_shock_beyond_the_simulators_velocity_bound_is_refused_in_metres_per_second(monkeypatch):
    import rotorcontact.studies.design_map as dm
    from rotorcontact.model.params import MAX_VELOCITY

    m = reference_machine()
    limit = MAX_VELOCITY * m.clearance * m.speed  # the kick shock / (c Omega) is a dimensionless velocity
    match = rf"^shock = .* m/s is too large at .* rpm: .* allowed: shock <= {limit:.6g} m/s"
    with pytest.raises(ParameterError, match=match):
        recovery_probability(m, limit * (1 + 1e-9))
    # a map refuses it before classifying any setting
    monkeypatch.setattr(dm, "classify_machine", lambda *a, **k: pytest.fail("classified before the check"))
    with pytest.raises(ParameterError, match=match):
        speed_map(m, [m.speed / dm.RPM], shock=limit * (1 + 1e-9))


@pytest.mark.parametrize("machines", [["x"], [None]])
def test_recovery_probabilities_refuses_what_is_not_a_machine(machines):
    from rotorcontact.studies.design_map import recovery_probabilities

    with pytest.raises(ParameterError, match=r"^machine = .* is not a Machine object"):
        recovery_probabilities(machines, 0.01)


@pytest.mark.parametrize("machine", [None, "x", Parameters.reference()])
def test_every_design_function_refuses_what_is_not_a_machine(machine):
    from rotorcontact.studies.design_map import design_map

    calls = [lambda: classify_machine(machine), lambda: recovery_probability(machine, 0.01),
             lambda: speed_map(machine, [1000.0]), lambda: plane_map(machine, ("speed_rpm", "stiffness"), [1.0], [1.0]),
             lambda: design_map(machine, {"speed": (1000.0, 2000.0)}, 2)]
    for call in calls:
        with pytest.raises(ParameterError,
                           match=r"^machine = .* is not a Machine object; allowed: rotorcontact.Machine$"):
            call()


def test_lists_of_speeds_beyond_the_bound_are_refused_before_numpy_reads_them():
    from rotorcontact import ParameterError, reference_machine
    from rotorcontact.studies.design_map import MAX_POINTS, speed_map

    with pytest.raises(ParameterError, match=rf"^speeds_rpm = range\(1, 1000000000001\) holds 1000000000000 values; "
                                             rf"allowed: at most {MAX_POINTS}$"):
        speed_map(reference_machine(), range(1, 10**12 + 1))


def test_speed_conversions_and_recovery_inputs_are_checked():
    import math

    import numpy as np

    from rotorcontact import ParameterError, reference_machine
    from rotorcontact.studies.design_map import rad_s_to_rpm, recovery_probabilities, rpm_to_rad_s

    assert rpm_to_rad_s(60.0) == 2.0 * math.pi and np.allclose(rad_s_to_rpm(np.array([2.0 * math.pi])), [60.0])
    assert rad_s_to_rpm(rpm_to_rad_s(np.float32(3000.0))) == pytest.approx(3000.0, rel=1e-15)
    for bad in (None, "1000 rpm", math.nan, [1.0, math.inf], True):
        with pytest.raises(ParameterError, match=r"^rpm = .* is invalid; allowed: finite real numbers$"):
            rpm_to_rad_s(bad)
        with pytest.raises(ParameterError, match=r"^rad_s = .* is invalid; allowed: finite real numbers$"):
            rad_s_to_rpm(bad)
    for bad in (None, reference_machine(), []):
        with pytest.raises(ParameterError, match=r"^machines = .* is invalid; allowed: a non-empty list of Machine$"):
            recovery_probabilities(bad, 0.1)


def test_a_speed_beyond_the_machines_bound_is_refused_in_rpm():
    from rotorcontact import ParameterError, reference_machine
    from rotorcontact.studies.design_map import speed_map

    with pytest.raises(ParameterError, match=r"^speeds_rpm = \[3000.0, 1e\+300\] holds 1e\+300 rpm; allowed: speeds up "
                                             r"to 9.5493e\+06 rpm"):
        speed_map(reference_machine(), [3000.0, 1e300])
