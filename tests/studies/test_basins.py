"""Basins of attraction: classification of known attractors, grids, fractions.

Claims checked here, at the reference machine:

* at gamma = 0.1 the rotor released from rest settles on B1,d, the stable
  one-impact orbit, and is named after it; at gamma = 0.15 from rest it rubs
  (forward sliding); at gamma = 0.05 it ends in backward whirl (rolling);
  at gamma = 0.2 a small kick from the contact-free whirl x_R dies away;
* just past the period doubling of B1,d (gamma = 0.083) the orbit that
  continues it has two impacts per period: "multi-impact";
* the fractions of the classes add up to one over the simulated points, and
  points outside the clearance are not simulated.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from rotorcontact import ParameterError
from rotorcontact.studies.basins import (
    BasinGrid,
    basins,
    class_names,
    classify,
    displacement_grid,
    parse_grid,
    shock_grid,
)
from rotorcontact.studies.batch import BatchSettings, simulate_batch
from rotorcontact.maps.impact_map import one_impact_orbits
from rotorcontact.studies.sweep import start_state
from reference_parameters import REF


ORIGIN = displacement_grid((0.0, 0.0, 1), (0.0, 0.0, 1))


@pytest.mark.parametrize(
    "gamma, expected",
    [(0.1, "B1,d"), (0.15, "forward-rub"), (0.05, "backward-whirl")],
)
def test_release_from_rest(gamma, expected):
    res = basins(REF.replace(gamma=gamma), ORIGIN, progress=False)
    assert res.class_of(0, 0) == expected
    assert res.fractions == {expected: 1.0}


def test_regimes_carry_the_simulator_names_and_accept_the_former_ones(tmp_path):
    # released from rest at gamma = 0.15 the rotor ends in a forward rub, as `simulate` says
    p = REF.replace(gamma=0.15)
    res = basins(p, ORIGIN, progress=False, out=tmp_path / "b.nc")
    from rotorcontact import simulate

    assert simulate(p, 0j, 0j, 500.0).summary.regime == "forward-rub" == res.class_of(0, 0)
    assert "rub" not in res.classes and "rolling" not in res.classes
    assert res.fraction("rub") == res.fraction("forward-rub") == 1.0
    assert res.fraction("rolling") == res.fraction("backward-whirl") == 0.0
    with pytest.raises(ParameterError, match="'sliding'.*allowed"):
        res.fraction("sliding")
    back = xr.load_dataset(tmp_path / "b.nc", engine="scipy")
    meanings = back["attractor"].attrs["flag_meanings"].split()
    assert {"forward-rub", "backward-whirl"} <= set(meanings) and "rub" not in meanings
    assert "formerly" in back["attractor"].attrs["comment"]


def test_named_orbit_is_the_fixed_point_it_is_named_after():
    p = REF.replace(gamma=0.1)
    res = basins(p, ORIGIN, progress=False)
    ds = res.dataset
    o = [x for x in one_impact_orbits(p) if x.label == "B1,d"][0]
    assert int(ds.impacts_per_period[0, 0]) == 1
    assert abs(float(ds.period[0, 0]) - o.T) < 1e-6
    assert abs(float(ds.rdot[0, 0]) - o.rdot) < 1e-5
    assert abs(float(ds.thetadot[0, 0]) - o.thetadot) < 1e-5
    # the orbit table of the file holds the fixed points used for naming
    j = list(ds.orbit.values).index("B1,d")
    assert ds.orbit_T.values[j] == o.T and ds.orbit_stable.values[j] == 1


@pytest.mark.parametrize("rho", [REF.rho, 300.0])
def test_strong_damping_names_the_orbits_it_can_search(rho):
    # at gamma = 100 the flight decays like e^{-50 T}: orbits are searched up to period_limit (3.0), not the
    # default 12, which f1_zeros refuses there; the study completes and names what that search finds
    from rotorcontact.maps.impact_map import period_limit

    p = REF.replace(gamma=100.0, rho=rho)
    limit = period_limit(p)
    assert limit == pytest.approx(300.0 / (50.0 + math.sqrt(50.0**2 - p.omega**2)), rel=1e-12) and limit < 12.0
    res = basins(p, "x=-0.5:0.5:3,y=-0.5:0.5:3", n_transient=20, n_record=5, progress=False)
    named = [o.label for o in one_impact_orbits(p, limit) if o.admissible]
    assert list(res.dataset.orbit.values) == named
    assert sum(res.fractions.values()) == pytest.approx(1.0, abs=1e-12)


def test_parameters_beyond_the_simulators_range_are_refused_before_anything_runs(tmp_path):
    # the forced response |k| = 2.2e6 clearances at rho = 1e6 (the simulator's bound: 1000), as for a sweep
    with pytest.raises(ParameterError, match=r"^rho = 1000000.0, .*forced response"):
        basins(REF.replace(rho=1e6), "plane:3", out=tmp_path / "b.nc", progress=False)
    assert list(tmp_path.iterdir()) == []


def test_small_kicks_from_the_contact_free_whirl_die_away():
    p = REF.replace(gamma=0.2)
    res = basins(p, shock_grid((0.0, 0.02, 3), (-math.pi, math.pi, 4)), progress=False)
    assert res.fractions == {"no-contact": 1.0}
    assert abs(res.dataset.attrs["x_R_re"] - p.k.real) == 0.0


def test_period_two_orbit_is_multi_impact():
    """From B1,d, which has flipped (multiplier -1.047) at gamma = 0.083, onto the period-two orbit. The start
    is turned by 1e-8 rad off B1,d: a departure left to rounding alone may never come, as the rounded map
    can cycle about a weakly unstable orbit."""
    p = REF.replace(gamma=0.083)
    u0, du0 = start_state(p, "B1,d")
    turn = complex(math.cos(1e-8), math.sin(1e-8))
    u0, du0 = u0 * turn, du0 * turn
    st = BatchSettings(n_transient=4000, n_record=200, n_keep=1)
    res = simulate_batch(p, u0, du0, settings=st)
    orbits = [o for o in one_impact_orbits(p) if o.admissible]
    codes, matched = classify(res, orbits, 1e-3)
    names = class_names([o.label for o in orbits])
    assert names[codes[0]] == "multi-impact"
    assert res.impacts_per_period[0] == 2 and matched[0] == -1


def test_displacement_plane_fractions_and_outside_points(tmp_path):
    p = REF.replace(gamma=0.1)
    grid = displacement_grid((-1.0, 1.0, 9), (-1.0, 1.0, 9))
    res = basins(p, grid, progress=False, out=tmp_path / "b.nc", chunk_size=10)
    ds = res.dataset
    inside = ds.inside.values.astype(bool)
    x, y = np.meshgrid(ds.x.values, ds.y.values)
    assert np.array_equal(inside, x**2 + y**2 <= 1.0)
    assert np.all(res.image[~inside] == res.classes.index("outside"))
    assert np.all(res.image[inside] != res.classes.index("outside"))
    assert math.isclose(sum(res.fractions.values()), 1.0, rel_tol=0, abs_tol=1e-12)
    assert int(ds["count"].sum()) == inside.sum()
    assert {"B1,d", "forward-rub"} <= set(res.fractions)
    # the file is the dataset, with parameters and units as attributes
    back = xr.load_dataset(tmp_path / "b.nc", engine="scipy")
    xr.testing.assert_identical(back, ds)
    assert back.attrs["gamma"] == 0.1 and back.attrs["gamma_units"] == "1"
    assert back.attractor.attrs["flag_meanings"].split() == list(res.classes)
    # another chunking, in worker processes, gives the same image
    again = basins(p, grid, progress=False, chunk_size=64, n_jobs=2)
    assert np.array_equal(again.image, res.image)
    assert again.dataset.theta.values.tobytes() == ds.theta.values.tobytes()


def test_parse_grid():
    g = parse_grid("x=-1:1:5,y=-0.5:0.5:3")
    assert g.kind == "displacement" and g.shape == (3, 5) and g.axis0[0] == -1 and g.axis1[-1] == 0.5
    g = parse_grid("amplitude=0:2:4, direction=-pi:pi/2:3")
    assert g.kind == "shock" and g.axis1[0] == -math.pi and g.axis1[-1] == math.pi / 2
    assert parse_grid("direction=0:2pi:3,amplitude=0:1:2").axis1[-1] == 2 * math.pi
    assert parse_grid("plane:7").shape == (7, 7)
    s = parse_grid("shock:5")
    assert s.kind == "shock" and s.axis0[-1] == 1.0 and s.axis1[0] == -math.pi
    assert parse_grid(g.describe()).axis1.tolist() == g.axis1.tolist()
    for bad, msg in [
        ("", "empty"),
        (5, r"^grid = 5 is not text"),
        (["plane:4"], r"^grid = \['plane:4'\] is not text"),
        ("x=0:1:3", "both x and y"),
        ("x=0:1:3,direction=0:1:3", "both"),
        ("x=0:1,y=0:1:3", "NAME=START:STOP:COUNT"),
        ("x=0:1:a,y=0:1:3", "integer"),
        ("x=0:1:0,y=0:1:3", "count"),
        ("x=1:0:3,y=0:1:3", "smaller"),
        ("z=0:1:3,y=0:1:3", "unknown axis"),
        ("x=0:q:3,y=0:1:3", "not a number"),
        ("amplitude=-1:1:3,direction=0:1:3", ">= 0"),
    ]:
        with pytest.raises(ParameterError, match=msg):
            parse_grid(bad)
    # in Python the grid is named as the argument it is, on the command line as the option
    with pytest.raises(ParameterError, match="^grid = 'plane:0': the count must be >= 1$"):
        parse_grid("plane:0")
    with pytest.raises(ParameterError, match="^--grid: x: 'nan' is not finite$"):
        parse_grid("x=nan:1:3,y=0:1:3", "--grid")


def test_shock_grid_needs_an_admissible_contact_free_whirl():
    p = REF.replace(gamma=0.05)  # |k| > 1: x_R is virtual
    with pytest.raises(ParameterError, match="virtual"):
        basins(p, "shock:3", progress=False)


def test_kick_directions_are_measured_from_the_radial():
    p = REF.replace(gamma=0.2)
    g = BasinGrid("shock", np.array([0.5]), np.array([0.0, math.pi / 2]))
    u0, du0, inside = g.initial_states(p)
    k = p.k
    radial = du0[0, 0] / (k / abs(k))
    tangential = du0[1, 0] / (k / abs(k))
    assert abs(radial - 0.5) < 1e-15 and abs(tangential - 0.5j) < 1e-15
    assert np.all(u0 == k) and inside.all()


def test_a_finished_basin_is_read_back_and_an_interrupted_one_resumes_with_its_chunk_size(tmp_path):
    p = REF.replace(gamma=0.1)
    grid = displacement_grid((-0.5, 0.5, 3), (-0.5, 0.5, 3))
    kw = dict(n_transient=40, n_record=5, progress=False, out=tmp_path / "b.nc")
    first = basins(p, grid, chunk_size=4, keep_chunks=True, **kw)
    again = basins(p, grid, chunk_size=4, **kw)
    assert again.reused_file and again.chunks_computed == 0 and again.chunks_reused == 3
    assert again.fractions == first.fractions and again.classes == first.classes
    assert np.array_equal(again.image, first.image) and again.impacts_simulated == first.impacts_simulated
    # chunks kept from an interrupted run are resumed as they were cut, whatever --chunk-size says now
    (tmp_path / "b.nc").unlink()
    (tmp_path / "b.nc.chunks" / "basin-000002.npz").unlink()
    resumed = basins(p, grid, chunk_size=2, **kw)
    assert not resumed.reused_file and resumed.chunks_reused == 2 and resumed.chunks_computed == 1
    assert int(resumed.dataset.attrs["chunk_size"]) == 4
    assert np.array_equal(resumed.image, first.image)


@pytest.mark.parametrize("x, match", [((0.0, 1.0), r"^x = \(0.0, 1.0\) is invalid; allowed: \(start, stop, count\)"),
                                      (None, r"^x = None is invalid"),
                                      ((0.0, 1.0, 10**9), r"^x count = 1000000000 is invalid; allowed: an integer "
                                                          r"from 1 to 16000000$")])
def test_a_malformed_or_huge_axis_is_refused_before_it_is_built(x, match):
    with pytest.raises(ParameterError, match=match):
        displacement_grid(x, (-1.0, 1.0, 2))


@pytest.mark.parametrize("axis", [["x", "y"], [True, False], [0.1 + 1j], []])
def test_grid_axes_hold_finite_real_values(axis):
    with pytest.raises(ParameterError, match=r"^grid axis0 = .* allowed: finite real values$"):
        BasinGrid("displacement", axis, [0.0])


def test_a_machine_whose_parameters_are_not_params_is_refused():
    from rotorcontact import reference_machine

    m = reference_machine()
    with pytest.raises(ParameterError, match=r"^params are not the machine's \(gamma = .*; allowed: machine"):
        basins(m.parameters().replace(gamma=0.1), "plane:3", machine=m, progress=False)


def test_result_lookups_and_class_names_refuse_what_is_not_in_them():
    from rotorcontact.studies.basins import class_names, displacement_grid

    res = basins(REF.replace(gamma=0.1), displacement_grid(np.array([-0.5, 0.5, 3]), (-0.5, 0.5, 2)), progress=False)
    assert res.image.shape == (2, 3)
    assert res.class_of(np.int64(1), 2) == res.classes[int(res.image[1, 2])]
    for i, j, name in ((2, 0, "i"), (-1, 0, "i"), (0, 3, "j"), (0.5, 0, "i"), (None, 0, "i"), (True, 0, "i")):
        with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: an integer from 0 to"):
            res.class_of(i, j)
    with pytest.raises(ParameterError, match=r"^name = 'nothing' is not a class of these basins"):
        res.fraction("nothing")
    from rotorcontact.studies.basins import CLASSES_AFTER, CLASSES_BEFORE

    assert class_names(["B1,d", "B1,a"]) == CLASSES_BEFORE + ("B1,d", "B1,a") + CLASSES_AFTER
    for bad in ("B1,d", None, [1], [""]):
        with pytest.raises(ParameterError, match=r"^orbit_labels = .* is invalid; allowed: a list or tuple"):
            class_names(bad)
