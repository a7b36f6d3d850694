"""Seeds from a grid of impact states: Newton's method on P_I^p from the iterates of each grid state.

The claims: with p = 1 the grid finds exactly the one-impact orbits of the
guaranteed search of `one_impact_orbits` (independent: zeros of F1 and the
quadratic for rdot-); with p = 2 it finds the stable period-2 orbit that long
simulations find and unstable ones that they cannot, each a fixed point of the
simulator's impact map applied twice, none twice.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorcontact import ParameterError
from rotorcontact.maps.impact_map import impact_map, one_impact_orbits
from rotorcontact.maps.multi_impact import (
    _same_orbit,
    orbits_from_grid,
    orbits_from_simulation,
)
from reference_parameters import REF



def _dist(x, y):
    d = np.abs(np.asarray(x, float) - np.asarray(y, float))
    d[0] = abs(math.remainder(d[0], 2 * math.pi))
    return float(np.max(d))


def test_one_impact_grid_orbits_are_the_guaranteed_ones():
    p = REF.replace(gamma=0.0818)
    grid = orbits_from_grid(p, 1)
    ref = [o for o in one_impact_orbits(p) if o.admissible]
    assert len(grid) == len(ref) == 4
    for o in ref:
        match = [g for g in grid if _dist(g.states[0], o.state) < 1e-9]
        assert len(match) == 1
        assert match[0].period == pytest.approx(o.T, abs=1e-9)


def test_two_impact_grid_finds_the_attractor_and_unstable_orbits():
    p = REF.replace(gamma=0.083)
    grid = orbits_from_grid(p, 2)
    brute = orbits_from_simulation(p, 2)
    assert brute and all(any(_same_orbit(b, g) for g in grid) for b in brute)
    unstable = [g for g in grid if not g.stable]
    assert unstable  # not found by simulations
    assert not any(_same_orbit(u, b) for u in unstable for b in brute)
    for i, a in enumerate(grid):
        assert a.label == f"M2-{i + 1}" and a.impacts == 2
        x0, x1 = a.states
        once = impact_map(p, x0)
        assert _dist(once.state, x1) < 1e-9 and _dist(impact_map(p, once.state).state, x0) < 1e-9
        assert _dist(x0, x1) > 1e-6
        assert not any(_same_orbit(a, b) for b in grid[i + 1:])


@pytest.mark.parametrize("kw, match", [({"shape": (0, 4, 4)}, "shape"), ({"shape": (200, 200, 2)}, "shape"),
                                       ({"rdot_range": (-1.0, 1.0)}, "rdot_range"),
                                       ({"thetadot_range": (1.0, -1.0)}, "thetadot_range")])
def test_bad_grid(kw, match):
    with pytest.raises(ParameterError, match=match):
        orbits_from_grid(REF, 2, **kw)
