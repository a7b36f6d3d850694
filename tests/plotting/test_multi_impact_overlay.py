"""The brute-force diagram with continued multi-impact branches and a cascade's doublings overlaid.

What is drawn is the computed data: every impact of every orbit along each branch (solid where
stable, dashed where not), and at each doubling of the cascade a marker at every impact of the
orbit that doubles there; the stable period-2 attractor of the sweep lies on its continued branch.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorcontact.continuation.cascade import cascades_of  # noqa: E402
from rotorcontact.continuation.multi_impact_families import multi_impact_branches  # noqa: E402
from rotorcontact.plotting.sweep import plot_sweep, save_sweep_figure  # noqa: E402
from rotorcontact.studies.sweep import sweep, sweep_values  # noqa: E402
from reference_parameters import REF



@pytest.fixture(scope="module")
def data():
    values = sweep_values(0.0836, 0.0865, 8)
    ds = sweep(REF, "gamma", values, mode="up", n_transient=1500, n_record=100, progress=False).dataset
    family = multi_impact_branches(REF.replace(gamma=0.085), 2, "gamma", 0.0836, 0.0865, doublings=2)
    return ds, family, cascades_of(family)


def test_branches_and_cascade_are_drawn_from_the_data(data, tmp_path):
    ds, family, found = data
    fig, ax = plot_sweep(ds, "rdot", overlay=family, cascades=found)
    lines = {ln.get_gid(): ln for ln in ax.get_lines() if ln.get_gid()}
    for b in family.branches:
        label = b.orbits[0].label
        want = "stable" if b.orbits[0].stable else "unstable"
        line = [ln for gid, ln in lines.items() if gid == f"multi:{label}:{want}"]
        assert line
        y = np.array([[q.rdot for q in o.points] for o in b.orbits])
        x = np.asarray(line[0].get_xdata(), float)
        np.testing.assert_array_equal(x, b.values)
        # one drawn curve per impact of the orbit
        drawn = [ln for ln in ax.get_lines() if ln.get_gid() == f"multi:{label}:{want}"]
        assert len(drawn) == b.orbits[0].impacts
        for k, ln in enumerate(drawn):
            yy = np.asarray(ln.get_ydata(), float)
            ok = np.isfinite(yy)
            np.testing.assert_array_equal(yy[ok], y[ok, k])
    marks = [ln for ln in ax.get_lines() if (ln.get_gid() or "").startswith("cascade:")]
    points = [e for c in found for e in c.points]
    assert len(marks) == len(points) >= 3
    for ln, e in zip(marks, points):
        assert np.all(np.asarray(ln.get_xdata()) == e.value)
        assert sorted(np.asarray(ln.get_ydata())) == sorted(q.rdot for q in e.orbit.points)
    plt.close(fig)
    save_sweep_figure(ds, tmp_path / "overlay.png", "rdot", overlay=[family], cascades=found)
    assert (tmp_path / "overlay.png").stat().st_size > 0


def test_the_sweep_attractor_lies_on_its_continued_branch():
    # between the grazing of the period-2 orbit and the period doubling of B1,d the sweep settles on
    # B1,d/PD, which a continuation from the grid seeds reaches too
    values = sweep_values(0.0828, 0.0833, 3)
    ds = sweep(REF, "gamma", values, mode="up", n_transient=3000, n_record=50, progress=False).dataset
    family = multi_impact_branches(REF.replace(gamma=0.083), 2, "gamma", 0.0828, 0.0833)
    stable = [b for b in family.branches if b.orbits[0].stable]
    assert stable
    b = stable[0]
    for i, g in enumerate(values):
        seen = ds["rdot"].sel(direction="up").values[i]
        seen = seen[np.isfinite(seen)]
        k = int(np.argmin(np.abs(b.values - g)))
        assert abs(b.values[k] - g) < 5e-5
        expected = [q.rdot for q in b.orbits[k].points]
        assert all(min(abs(s - e) for e in expected) < 5e-3 for s in seen[-10:])
