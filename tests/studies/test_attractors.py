"""Attractors followed across a parameter: identities, basin fractions with intervals, births and deaths."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from scipy.optimize import brentq

from rotorcontact import ParameterError, simulate
from rotorcontact.analysis.equilibria import boundary_gamma, pseudo_equilibria
from rotorcontact.maps.impact_map import one_impact_orbits
from rotorcontact.model.params import reference_machine
from rotorcontact.studies.attractors import (
    attractor_label,
    attractors,
    parameter_path,
    wilson_interval,
)
from rotorcontact.studies.basins import basins, parse_grid
from reference_parameters import REF

SCAN = np.linspace(0.06, 0.22, 17)


@pytest.fixture(scope="module")
def scan():
    return attractors(REF, "gamma", SCAN, "plane:12", progress=False, t_lyapunov=200.0)


def _stable_b1d(gamma: float) -> bool:
    return any(o.label == "B1,d" and o.admissible and o.stable for o in one_impact_orbits(REF.replace(gamma=gamma)))


def _b1d_exists(gamma: float) -> bool:
    return any(o.label == "B1,d" for o in one_impact_orbits(REF.replace(gamma=gamma)))


def test_fractions_agree_with_basins_at_one_value():
    res = attractors(REF, "gamma", [0.09, 0.1, 0.11], "plane:15", progress=False, lyapunov=False)
    same = basins(REF.replace(gamma=0.1), "plane:15", progress=False)
    # the same grid: the same simulations, the same classes
    n = int(same.dataset["inside"].values.sum())
    assert res.attractor("B1,d").fraction[1] == same.fraction("B1,d")
    assert res.attractor("P2").fraction[1] == same.fraction("forward-rub")
    assert res.dataset.attrs["simulated_per_value"] == n
    # a finer grid: its fractions lie within the sampling error of the coarse one
    fine = basins(REF.replace(gamma=0.1), "plane:40", progress=False)
    for name, cls in (("B1,d", "B1,d"), ("P2", "forward-rub")):
        a = res.attractor(name)
        assert a.ci_low[1] <= fine.fraction(cls) <= a.ci_high[1]
    # the fractions of each value add up to one, and each interval holds its fraction
    total = sum(a.fraction for a in res.attractors)
    np.testing.assert_allclose(total, 1.0, rtol=0, atol=1e-12)
    for a in res.attractors:
        assert np.all((a.ci_low <= a.fraction) & (a.fraction <= a.ci_high))


def test_b1d_and_p2_keep_their_labels_and_b1d_dies_at_its_fold(scan):
    b1d = scan.attractor("B1,d")
    stable = np.array([_stable_b1d(g) for g in SCAN])
    # reached exactly where the impact map has it admissible and stable
    assert np.array_equal(b1d.present, stable)
    assert b1d.label == "periodic" and {lab for lab in b1d.labels if lab} == {"periodic"}
    # it disappears at the first value past its fold (where the fixed point ceases to exist)
    last = int(np.flatnonzero(b1d.present)[-1])
    fold = brentq(lambda g: 1.0 if _b1d_exists(g) else -1.0, SCAN[last], SCAN[last + 1], xtol=1e-6)
    assert _b1d_exists(SCAN[last]) and not _b1d_exists(SCAN[last + 1])
    assert SCAN[last] < fold < b1d.disappears == SCAN[last + 1]
    # along a periodic orbit the largest exponent is that of the flow direction, 0
    on = b1d.present
    assert np.all(np.abs(b1d.exponent[on]) < 5e-3)
    p2 = scan.attractor("P2")
    assert all(pe.admissible and pe.stable for g in SCAN for pe in pseudo_equilibria(REF.replace(gamma=g))
               if pe.name == "P2")
    assert p2.present.all() and p2.appears is None and p2.disappears is None
    assert set(p2.labels) == {"contact"}
    # at P2 the exponents are those of the pseudo-equilibrium, all negative
    assert np.all(p2.exponent < 0)


def test_irregular_motion_is_chaotic_or_a_transient(scan):
    """Irregular windows: chaotic where the motion stays irregular with a clearly positive exponent, transient
    where, continued, it settles (at gamma = 0.08 the chaotic set lies beyond the period doubling of B1,d)."""
    irr = scan.attractor("irregular")
    assert irr.present[np.isclose(SCAN, 0.08)].all() and np.isclose(SCAN, 0.08).sum() == 1
    for lab, lam, err in zip(irr.labels, irr.exponent, irr.exponent_error):
        if not lab:
            continue
        assert lab in ("chaotic", "transient", "quasi-periodic")
        if lab == "chaotic":
            assert lam > 3.0 * err and lam > 1e-3
    assert "chaotic" in irr.labels or "transient" in irr.labels


def test_x_r_is_reached_only_where_it_is_admissible():
    """x_R becomes virtual at gamma*: below it no initial state ends there."""
    values = np.linspace(0.06, 0.11, 11)
    grid = "x=-0.93:-0.85:9,y=-0.44:-0.34:9"
    res = attractors(REF, "gamma", values, grid, progress=False, lyapunov=False)
    x_r = res.attractor("x_R")
    g_star = boundary_gamma(REF)
    assert not x_r.present[values < g_star].any()
    assert x_r.appears > g_star and x_r.label == "periodic"
    # where it is admissible, it is reached wherever the simulator takes some grid point to it without contact
    g = parse_grid(grid)
    u0, _du0, inside = g.initial_states(REF)
    n_free = 0
    for v, present in zip(values, x_r.present):
        p = REF.replace(gamma=v)
        if abs(p.k) >= 1.0:
            continue
        runs = [simulate(p, complex(u), 0j, 200.0) for u in u0[inside]]
        if any(len(t.impacts) == 0 and not t.contact_intervals for t in runs):
            n_free += 1
            assert present
    assert n_free >= 3


def test_identical_results_across_executors(tmp_path):
    from distributed import Client

    from rotorcontact.studies.execution import local_cluster

    kw = {"grid": "plane:7", "progress": False, "chunk_size": 40, "t_lyapunov": 100.0}
    values = [0.08, 0.12, 0.16]
    a = attractors(REF, "gamma", values, out=tmp_path / "a.nc", **kw)
    b = attractors(REF, "gamma", values, out=tmp_path / "b.nc", n_jobs=2, **kw)
    cluster = local_cluster(2, processes=False)
    client = Client(cluster)
    try:
        c = attractors(REF, "gamma", values, out=tmp_path / "c.nc", scheduler=client, **kw)
    finally:
        client.close()
        cluster.close()
    data = (tmp_path / "a.nc").read_bytes()
    assert data == (tmp_path / "b.nc").read_bytes() == (tmp_path / "c.nc").read_bytes()
    xr.testing.assert_identical(xr.load_dataset(tmp_path / "a.nc", engine="scipy"), a.dataset)
    assert a.names == b.names == c.names
    # run again: the finished file is read back
    again = attractors(REF, "gamma", values, out=tmp_path / "a.nc", **kw)
    assert again.reused_file and again.names == a.names


def test_machine_speed_in_si_and_bad_input():
    m = reference_machine()
    rpm = 2.0 * math.pi / 60.0
    path = parameter_path(REF, "speed", [3000 * rpm, 4000 * rpm], m)
    assert path[0] == m.with_speed(3000 * rpm).parameters()
    with pytest.raises(ParameterError, match="machine"):
        parameter_path(REF, "speed", [1.0])
    with pytest.raises(ParameterError, match="param"):
        parameter_path(REF, "nonsense", [1.0])
    with pytest.raises(ParameterError, match=r"^gamma = 0\.01: shock grid: "):  # the value as a number, not a numpy repr
        attractors(REF, "gamma", [0.01, 0.1], "shock:3", progress=False)
    with pytest.raises(ParameterError):
        attractors(REF, "gamma", [0.1], "plane:3", t_lyapunov=0.0, progress=False)
    with pytest.raises(ParameterError, match=r"^lyapunov = 'False' is invalid; allowed: True or False$"):
        attractors(REF, "gamma", [0.1], "plane:3", lyapunov="False", progress=False)


@pytest.mark.parametrize("lyapunov", [False, True])
def test_a_study_held_in_memory_lets_its_chunks_go(monkeypatch, lyapunov):
    # without an output file the chunks are held in memory; each is let go once assembled, also where the
    # exponents' wave assembles the simulations first and the assembly reuses them
    import rotorcontact.studies.driver as driver

    sinks = []

    def recording(executor, waves, store, bar, sink):
        sinks.append(sink)
        return run_waves(executor, waves, store, bar, sink)

    run_waves = driver.run_waves
    monkeypatch.setattr(driver, "run_waves", recording)
    res = attractors(REF, "gamma", [0.1, 0.12], "plane:3", lyapunov=lyapunov, t_lyapunov=50.0, chunk_size=2,
                     progress=False)
    assert res.attractors and len(sinks) == 1 and len(sinks[0]) == 0


@pytest.mark.parametrize("match_tol", [4.0, 0.0, -1e-3, float("nan")])
def test_a_match_tolerance_outside_zero_to_pi_is_refused_before_anything_is_computed(match_tol, tmp_path):
    # a rubbing point is named by its angle alone: a tolerance beyond pi matches every angle
    with pytest.raises(ParameterError, match=r"^match_tol = "):
        attractors(REF, "gamma", [0.1, 0.12], "plane:3", match_tol=match_tol, out=tmp_path / "a.nc",
                   progress=False)
    assert list(tmp_path.iterdir()) == []


def test_labels_and_intervals():
    assert attractor_label("irregular", 0.1, 0.01) == "chaotic"
    assert attractor_label("irregular", 0.1, 0.01, settles=True) == "transient"
    assert attractor_label("B1,d", 0.0, 0.0, settles=True) == "periodic"
    assert attractor_label("irregular", 0.1, 0.05) == "quasi-periodic"
    assert attractor_label("mixed", 1e-4, 1e-5) == "quasi-periodic"
    assert attractor_label("irregular", None, None) == "undetermined"
    assert attractor_label("2-impact", None, None) == "periodic"
    assert attractor_label("backward-whirl", 0.0, 0.0) == "contact"
    low, high = wilson_interval(np.array([0, 5, 10]), 10)
    # the Wilson interval in closed form
    z = 1.959963984540054
    for k, lo, hi in zip((0, 5, 10), low, high):
        ph = k / 10
        centre = (ph + z * z / 20) / (1 + z * z / 10)
        half = z / (1 + z * z / 10) * math.sqrt(ph * (1 - ph) / 10 + z * z / 400)
        assert lo == pytest.approx(centre - half, abs=1e-12) and hi == pytest.approx(centre + half, abs=1e-12)
    for count, total, confidence, name in (([0, 11], 10, 0.95, "count"), ([0.5], 10, 0.95, "count"),
                                           ([-1], 10, 0.95, "count"), (["1"], 10, 0.95, "count"),
                                           ([[1]], 10, 0.95, "count"), ([1], 0, 0.95, "total"),
                                           ([1], 10.0, 0.95, "total"), ([1], 10, 1.0, "confidence"),
                                           ([1], 10, 0.0, "confidence"), ([1], 10, math.nan, "confidence")):
        with pytest.raises(ParameterError, match=rf"^{name} = .* is invalid; allowed: "):
            wilson_interval(count, total, confidence)


@pytest.mark.parametrize("values", [["0.1"], [True], [0.1, True], [0.1 + 1j], "0.1", [], [0.1, math.nan], None,
                                    [[0.1], [0.1, 0.2]]])
def test_values_that_are_not_real_numbers_are_refused_by_every_parameter_path(values, tmp_path):
    from rotorcontact.studies.lyapunov_scan import lyapunov_scan

    with pytest.raises(ParameterError, match=r"^values of 'gamma'"):
        parameter_path(REF, "gamma", values)
    with pytest.raises(ParameterError, match=r"^values of 'gamma'"):
        attractors(REF, "gamma", values, "plane:3", progress=False)
    with pytest.raises(ParameterError, match=r"^values of 'gamma'"):
        lyapunov_scan(REF, "gamma", values, t_end=100.0, progress=False, out=tmp_path / "l.nc")
    assert not any(tmp_path.iterdir())


def _study_calls(**kw):
    from rotorcontact.studies.lyapunov_scan import lyapunov_scan
    from rotorcontact.studies.sweep import sweep

    return [lambda: attractors(REF, "gamma", [0.1], "plane:3", progress=False, **kw),
            lambda: basins(REF, "plane:3", progress=False, **kw),
            lambda: (lyapunov_scan(REF, "gamma", [0.1], t_end=100.0, progress=False, **kw) if "machine" in kw
                     else sweep(REF, "gamma", [0.1, 0.2], progress=False, **kw))]


@pytest.mark.parametrize("machine", ["x", 3, REF])
def test_a_machine_that_is_not_a_machine_is_refused(machine):
    for call in _study_calls(machine=machine) + [lambda: parameter_path(REF, "gamma", [0.1], machine)]:
        with pytest.raises(ParameterError, match=r"^machine = .* is not a Machine object"):
            call()


@pytest.mark.parametrize("bad", ["x", {"n_record": 5}])
def test_settings_that_are_not_batch_settings_are_refused_by_the_studies(bad):
    for call in _study_calls(settings=bad):
        with pytest.raises(ParameterError, match=r"^settings = .* is not a BatchSettings"):
            call()


def test_a_study_whose_sections_exceed_the_machines_memory_is_refused_before_it_runs(monkeypatch, tmp_path):
    import rotorcontact.studies.batch as batch
    from rotorcontact.studies.sweep import sweep

    # a sweep up and down over 2 values is 4 simulations; 50 kept impacts each
    monkeypatch.setattr(batch, "physical_memory", lambda: 4 * 50 * batch.SECTION_BYTES - 1)
    with pytest.raises(ParameterError, match=r"^n_record = 50, n_keep = None: 4 simulations"):
        sweep(REF, "gamma", [0.1, 0.2], mode="both", n_transient=10, n_record=50, progress=False,
              out=tmp_path / "s.nc")
    assert not any(tmp_path.iterdir())
    # a basin keeps one impact per point of its grid (a point outside the clearance too): 9 on a 3 x 3 plane
    monkeypatch.setattr(batch, "physical_memory", lambda: 9 * batch.SECTION_BYTES - 1)
    with pytest.raises(ParameterError, match=r"n_keep = 1: 9 simulations keeping 1 impacts each"):
        basins(REF, "plane:3", progress=False)
    # attractors: values x points inside the clearance
    inside = int(parse_grid("plane:3").initial_states(REF)[2].sum())
    monkeypatch.setattr(batch, "physical_memory", lambda: 2 * inside * batch.SECTION_BYTES - 1)
    with pytest.raises(ParameterError, match=rf"n_keep = 1: {2 * inside} simulations keeping 1 impacts each"):
        attractors(REF, "gamma", [0.1, 0.2], "plane:3", progress=False)


def test_params_that_are_not_the_machines_are_refused_by_every_parameter_path():
    from rotorcontact import reference_machine
    from rotorcontact.studies.grids import MAX_GRID_POINTS
    from rotorcontact.studies.parameter_path import path_values

    m = reference_machine()
    p = m.parameters()
    # a model parameter may differ (it is the one varied), a machine quantity leaves none free
    assert parameter_path(p.replace(gamma=0.3), "gamma", [0.1], m)[0] == p.replace(gamma=0.1)
    with pytest.raises(ParameterError, match=r"^params are not the machine's \(rho = "):
        parameter_path(p.replace(rho=0.3), "gamma", [0.1], m)
    with pytest.raises(ParameterError, match=r"^params are not the machine's \(gamma = "):
        attractors(p.replace(gamma=0.3), "speed", [m.speed], "plane:3", machine=m, progress=False)
    with pytest.raises(ParameterError, match=rf"^values of 'gamma' = .* allowed: at most {MAX_GRID_POINTS}$"):
        path_values("gamma", range(MAX_GRID_POINTS + 1))



def test_attractor_labels_and_the_attributes_of_a_study_check_what_they_take():
    from rotorcontact.studies.attributes import parameter_attrs, settings_attrs, summary_variables

    assert attractor_label("irregular", np.float64(0.1), None) == attractor_label("irregular", 0.1, None)
    for args, name in (((None, 0.1, 0.01), "name"), (("irregular", "0.1", 0.01), "exponent"),
                       (("irregular", 0.1, True), "error"), (("irregular", 0.1, 0.01, "yes"), "settles")):
        with pytest.raises(ParameterError, match=rf"^{name} = "):
            attractor_label(*args)
    for call, name in ((lambda: parameter_attrs(None), "params"),
                       (lambda: parameter_attrs(REF, machine="m"), "machine"),
                       (lambda: settings_attrs(REF), "settings"),
                       (lambda: summary_variables(None, ("x",)), "result")):
        with pytest.raises(ParameterError, match=rf"^{name} = .* is not an? "):
            call()


def test_identity_names_takes_one_value_s_result_and_its_class_codes_only():
    from rotorcontact.studies.attractors import identity_names
    from rotorcontact.studies.basins import class_names, classify
    from rotorcontact.studies.batch import BatchSettings, simulate_batch

    p = REF.replace(gamma=0.1)
    res = simulate_batch(p, np.array([0j, 0.5 + 0j]), np.zeros(2, complex),
                         settings=BatchSettings(n_transient=200, n_record=20, n_keep=1))
    orbits = [o for o in one_impact_orbits(p) if o.admissible]
    labels = [o.label for o in orbits]
    codes, _ = classify(res, orbits, 1e-3)
    names = identity_names(res, codes, labels, p, 1e-2)
    assert names.shape == (2,) and all(n is None or isinstance(n, str) for n in names)
    n_classes = len(class_names(labels))
    cases = [
        ((None, codes, labels, p, 1e-2), "result = None"),
        ((res, codes[:1], labels, p, 1e-2), "codes = "),
        ((res, np.full(2, n_classes), labels, p, 1e-2), "codes = "),
        ((res, codes.astype(float), labels, p, 1e-2), "codes = "),
        ((res, codes, "B1,d", p, 1e-2), "orbit_labels = "),
        ((res, codes, labels, None, 1e-2), "params"),
        ((res, codes, labels, p, 0.0), "match_tol = "),
    ]
    for args, words in cases:
        with pytest.raises(ParameterError, match=words):
            identity_names(*args)


def test_every_variable_and_coordinate_of_the_file_has_a_long_name_and_the_numbers_units():
    ds = attractors(REF, "gamma", [0.1, 0.12], "plane:3", lyapunov=False, progress=False).dataset
    for name in list(ds.data_vars) + list(ds.coords):
        assert ds[name].attrs.get("long_name"), name
        if ds[name].dtype.kind == "f" and "flag_values" not in ds[name].attrs:
            assert "units" in ds[name].attrs, name
