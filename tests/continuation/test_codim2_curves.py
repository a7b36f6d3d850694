"""Two-parameter curves: a-c and b-d coalescences (and the regions R1-R4 that follow them), and the
period-doubling, fold and Neimark-Sacker curves of one- and multi-impact orbits.

References: the discriminant of the quadratic in rdot and the zeros of F1 (the guaranteed search), the
number of one-impact orbits on either side of a curve, the reference Newton on P_I^p with finite
differences (a multiplier -1 on a period-doubling curve, a complex pair on the unit circle on a
Neimark-Sacker curve) and the folds of F1.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorcontact import ParameterError, Parameters
from rotorcontact.continuation.codim2 import (
    coalescence_curve,
    coalescence_curves,
    region,
)
from rotorcontact.continuation.codim2_orbits import orbit_by_label, orbit_curve
from rotorcontact.continuation.multi_impact_families import seed_orbits
from rotorcontact.maps.impact_map import f1_zeros, one_impact_orbits, rdot_roots
from reference_parameters import REF

SET = Parameters(gamma=0.33, omega=0.8, rho=0.4, mu=0.3, d=0.9, phi=0.5, r_ratio=57.1)
BOX = ((0.0, 0.5), (0.6, 1.25))


@pytest.fixture(scope="module")
def coalescences():
    return coalescence_curves(SET, ("gamma", "omega"), BOX)


def _pair_count(p):
    return len([o for o in one_impact_orbits(p) if o.n == 1])


def test_regions_follow_the_coalescences():
    # only B1,b and B1,d exist here: not R4
    assert sorted(o.label for o in one_impact_orbits(SET)) == ["B1,b", "B1,d"]
    assert region(SET) is None
    inside = SET.replace(gamma=0.15, omega=0.7)
    assert _pair_count(inside) == 4 and region(inside) == "R4"


@pytest.mark.parametrize("pair, kind", [("ac", "a"), ("bd", "b")])
def test_coalescence_curve_is_where_the_two_roots_merge(coalescences, pair, kind):
    curve = coalescences[0 if pair == "ac" else 1]
    assert curve.name == f"coalescence_{pair}_1" and curve.kind == "coalescence" and curve.pieces
    pts = np.vstack(curve.pieces)
    assert len(pts) >= 10
    for T, rdot, g, w in pts[:: max(1, len(pts) // 5)]:
        p = SET.replace(gamma=g, omega=w)
        zero = min(f1_zeros(p), key=lambda z: abs(z.T - T))
        assert zero.T == pytest.approx(T, abs=1e-7) and zero.kind == kind and zero.n == 1
        disc, _ = rdot_roots(p, zero.T)
        scale = rdot_roots(p, zero.T + 1e-3)[0] - disc
        assert abs(disc) < 1e-6 * max(1.0, abs(scale) * 1e3)
        # on either side (gamma -+ 1e-3 at this omega) two orbits of the pair appear or vanish
        counts = {_pair_count(SET.replace(gamma=g + s, omega=w)) for s in (-1e-3, 1e-3)}
        assert len(counts) == 2 and max(counts) - min(counts) == 2


def test_coalescence_curve_bad_pair():
    with pytest.raises(ParameterError, match="pair"):
        coalescence_curve(SET, pair="ab")


@pytest.fixture(scope="module")
def b1d():
    return orbit_by_label(SET.replace(gamma=0.15), "B1,d")


def test_period_doubling_curve_of_a_one_impact_orbit(b1d, power_newton):
    curve = orbit_curve(b1d, "period-doubling", ("gamma", "omega"), ((0.05, 0.25), (0.7, 0.9)))
    assert curve.name == "pd_B1d" and len(curve.pieces) == 1 and len(curve.pieces[0]) >= 10
    piece = curve.pieces[0]
    for y in piece[:: max(1, len(piece) // 4)]:
        p = SET.replace(gamma=y[-2], omega=y[-1])
        _x, z = power_newton(p, y[:3], 1)
        assert np.min(np.abs(z + 1.0)) < 1e-5


def test_fold_curve_of_a_one_impact_orbit_is_where_two_orbits_meet(b1d):
    # B1,d turns back where it meets B1,b (the b-d coalescence here, or the fold of F1): two orbits of the
    # pair appear or vanish across every point of the curve
    curve = orbit_curve(b1d, "fold", ("gamma", "omega"), ((0.2, 0.45), (0.6, 0.75)))
    assert curve.name == "fold_B1d" and curve.kind == "orbit-fold" and curve.pieces
    piece = curve.pieces[0]
    for y in piece[:: max(1, len(piece) // 4)]:
        n = [_pair_count(SET.replace(gamma=y[-2] + s, omega=y[-1])) for s in (-1e-5, 1e-5)]
        assert abs(n[0] - n[1]) == 2


def test_neimark_sacker_curve_of_a_six_impact_orbit(power_newton):
    base = REF.replace(gamma=0.0818)
    m6 = next(o for o in seed_orbits(base, 6) if o.stable)
    curve = orbit_curve(m6, "neimark-sacker", ("gamma", "omega"), ((0.07, 0.09), (0.755, 0.765)))
    assert curve.pieces and len(curve.pieces[0]) >= 5
    piece = curve.pieces[0]
    for y in piece[:: max(1, len(piece) // 3)]:
        p = base.replace(gamma=y[-2], omega=y[-1])
        _x, z = power_newton(p, y[:3], 6)
        pair = [m for m in z if abs(m.imag) > 1e-3]
        assert len(pair) == 2 and all(abs(abs(m) - 1.0) < 1e-5 for m in pair)


def test_a_neimark_sacker_curve_ends_at_its_strong_resonance(power_newton):
    """The curve of M3-3 runs with a complex pair on the unit circle until the pair meets at -1 (1:2 resonance)
    and ends there; beyond, the bialternate product vanishes for a real pair with product 1 (a neutral saddle),
    which is no Neimark-Sacker curve. Multipliers from central differences of the simulator's map."""
    base = REF.replace(gamma=0.0845)
    curve = orbit_curve(orbit_by_label(base, "M3-3"), "neimark-sacker", ("gamma", "omega"))
    (piece,) = curve.pieces
    assert any("strong-resonance" in end for end in curve.ends)
    for y in piece[1:-1:max(1, len(piece) // 6)]:
        _x, z = power_newton(base.replace(gamma=y[-2], omega=y[-1]), y[:3], 3)
        pair = [m for m in z if abs(m.imag) > 1e-3]
        assert len(pair) == 2 and all(abs(abs(m) - 1.0) < 1e-5 for m in pair)
    end = piece[-1] if piece[-1][-1] > piece[0][-1] else piece[0]
    _x, z = power_newton(base.replace(gamma=end[-2], omega=end[-1]), end[:3], 3)
    assert sorted(abs(m + 1.0) for m in z)[1] < 1e-3  # two multipliers at -1
    assert end[-1] < 1.06  # not on into the neutral saddles, up to omega = 1.16


def test_orbit_labels_and_kinds():
    with pytest.raises(ParameterError, match="invalid"):
        orbit_by_label(SET, "X1")
    with pytest.raises(ParameterError, match="not an admissible orbit here"):
        orbit_by_label(SET, "B1,a")
    with pytest.raises(ParameterError, match="kind"):
        orbit_curve(orbit_by_label(SET, "B1,d"), "grazing")


def test_grazing_curve_of_b1d_is_the_one_impact_grazing_curve():
    # the same curve from two formulations: the orbit equations with flight times (p = 1) and the
    # regularised one-impact equations of codim2.grazing_curve
    from rotorcontact.continuation.codim2 import grazing_curve
    from rotorcontact.continuation.codim2_orbits import grazing_curve_of

    ref = REF
    box = ((0.05, 0.1), (0.7, 0.85))
    mine = grazing_curve_of(orbit_by_label(ref.replace(gamma=0.07), "B1,d"), ("gamma", "omega"), box)
    theirs, _ = grazing_curve(ref, ("gamma", "omega"), box, orbit="B1,d")
    assert mine.name == "grazing_B1d" and mine.kind == "grazing" and len(mine.pieces) == 1
    xy = theirs.xy()
    xy = xy[np.isfinite(xy[:, 1])]
    order = np.argsort(xy[:, 1])
    piece = mine.pieces[0]
    assert len(piece) >= 10
    for y in piece[1:-1]:
        assert y[-2] == pytest.approx(np.interp(y[-1], xy[order, 1], xy[order, 0]), abs=2e-5)


def test_grazing_curve_of_a_two_impact_orbit_grazes():
    from rotorcontact.continuation.codim2_orbits import grazing_curve_of
    from rotorcontact.maps.impact_map import SLIP_BOUNDED, flight_extrema
    from rotorcontact.maps.multi_impact import (
        find_period_doubling,
        period_doubled_orbit,
    )

    ref = REF
    pd = find_period_doubling(ref.replace(gamma=0.1), "B1,d", "gamma", lo=0.08, hi=0.09)
    orbit = period_doubled_orbit(pd, -1e-4)
    c = grazing_curve_of(orbit, ("gamma", "omega"), ((0.07, 0.09), (0.75, 0.77)))
    assert c.name == "grazing_B1d/PD" and c.pieces and len(c.pieces[0]) >= 10
    for y in c.pieces[0][:: max(1, len(c.pieces[0]) // 4)]:
        p = ref.replace(gamma=y[-2], omega=y[-1])
        x, times = y[:6].reshape(2, 3), y[6:8]
        r_max = max(flight_extrema(p, x[i], float(times[i]), law=SLIP_BOUNDED).r_max or 0.0 for i in range(2))
        assert r_max == pytest.approx(1.0, abs=1e-8)
    # where the one-parameter branch of the simulator's own map stops at the grazing (the base omega)
    from rotorcontact.continuation.multi_impact_branches import continue_multi_impact

    branch = continue_multi_impact(orbit, "gamma", 0.07)
    assert branch.status == "grazing"
    xy = c.pieces[0][:, -2:]
    order = np.argsort(xy[:, 1])
    at = np.interp(ref.omega, xy[order, 1], xy[order, 0])
    assert at == pytest.approx(branch.values[-1], abs=1e-6)
