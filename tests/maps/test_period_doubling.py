"""Branch switching at a period doubling, super- and subcritical.

The claims: the period-2 orbit of a subcritical doubling (born on the side where
the one-impact orbit is stable, itself unstable) is found at small offsets; it is
a fixed point of the simulator's own P_I applied twice, with two distinct points;
its distance from the one-impact orbit grows like the square root of the offset;
on the other side of the doubling there is none. The amplitude parametrisation
gives the parameter of the branch to second order in the amplitude.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError, Parameters
from rotorcontact.maps.impact_map import impact_map, one_impact_orbits
from rotorcontact.maps.multi_impact import (
    NewtonFailure,
    doubled_orbit_at_amplitude,
    find_period_doubling,
    period_doubled_orbit,
    period_doubling_at,
    solve_multi_impact,
)

SUB = Parameters(gamma=0.1413, omega=0.8, rho=0.4, mu=0.3, d=0.9, phi=0.5, r_ratio=57.1)


def _dist(x, y):
    d = np.abs(np.asarray(x, float) - np.asarray(y, float))
    d[..., 0] = np.abs(np.remainder(d[..., 0] + math.pi, 2 * math.pi) - math.pi)
    return float(np.max(d))


@pytest.fixture(scope="module")
def pd():
    return find_period_doubling(SUB, "B1,d", "gamma", lo=0.13, hi=0.15)


def _b1d(g):
    return next(o for o in one_impact_orbits(SUB.replace(gamma=g)) if o.label == "B1,d")


def test_subcritical_doubling_gives_the_unstable_period_two_orbit(pd):
    assert pd.unstable_side == -1.0  # B1,d stable above the doubling
    assert _b1d(pd.value + 1e-4).stable and not _b1d(pd.value - 1e-4).stable
    amplitudes = []
    for offset in (1e-5, 3e-5, 1e-4, 3e-4):
        o = period_doubled_orbit(pd, offset)
        p = o.params
        assert p.gamma == pytest.approx(pd.value + offset, abs=1e-15)
        assert o.label == "B1,d/PD" and o.impacts == 2
        # independent check: the simulator's impact map applied twice
        x0, x1 = o.states
        once = impact_map(p, x0)
        twice = impact_map(p, once.state)
        assert _dist(once.state, x1) < 1e-9 and _dist(twice.state, x0) < 1e-9
        assert _dist(x0, x1) > 1e-4
        # subcritical: the period-2 orbit on the stable side of B1,d is unstable through a multiplier > 1
        assert not o.stable and max(abs(m) for m in o.multipliers) > 1.0
        # solve_multi_impact accepts it as it is
        again = solve_multi_impact(p, o.states)
        assert _dist(again.states[np.argsort(again.states[:, 1])], o.states[np.argsort(o.states[:, 1])]) < 1e-9
        amplitudes.append(_dist(x0, _b1d(p.gamma).state))
    # a pitchfork of P_I^2: amplitude ~ sqrt(offset), so ratios ~ sqrt(3) and sqrt(10/3) ... within 10%
    for (a0, o0), (a1, o1) in zip(zip(amplitudes, (1e-5, 3e-5, 1e-4)), zip(amplitudes[1:], (3e-5, 1e-4, 3e-4))):
        assert a1 / a0 == pytest.approx(math.sqrt(o1 / o0), rel=0.1)


def test_no_period_two_orbit_on_the_unstable_side_of_a_subcritical_doubling(pd):
    with pytest.raises(NewtonFailure, match="other side"):
        period_doubled_orbit(pd, -1e-4)


def test_amplitude_parametrisation_is_quadratic_in_the_parameter(pd):
    a = [1e-3, 2e-3]
    shift = [doubled_orbit_at_amplitude(pd, x).params.gamma - pd.value for x in a]
    assert shift[0] > 0 and shift[1] > 0
    assert shift[1] / shift[0] == pytest.approx(4.0, rel=0.05)


def test_period_doubling_at_an_orbit_and_bad_input(pd):
    o = solve_multi_impact(pd.orbit.params, [pd.orbit.state])
    again = period_doubling_at(o, "gamma")
    assert again.value == pd.value and again.multiplier == pytest.approx(-1.0, abs=1e-8)
    assert abs(abs(again.eigenvector @ pd.eigenvector) - 1.0) < 1e-6
    away = solve_multi_impact(SUB.replace(gamma=0.15), [_b1d(0.15).state])
    with pytest.raises(ParameterError, match="no multiplier -1"):
        period_doubling_at(away, "gamma")
    with pytest.raises(ParameterError, match="amplitude"):
        doubled_orbit_at_amplitude(pd, 0.0)
