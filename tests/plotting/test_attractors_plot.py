"""The attractors figure: stacked basin fractions with confidence bands, and exponents beneath."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np

from rotorcontact.plotting.attractors import plot_attractors, save_attractors_figure
from rotorcontact.studies.attractors import attractors
from reference_parameters import REF


def test_stacked_areas_bands_and_exponents(tmp_path):
    res = attractors(REF, "gamma", [0.08, 0.12, 0.16], "plane:7", t_lyapunov=100.0,
                     progress=False)
    ds = res.dataset
    fig, (ax_f, ax_l) = plot_attractors(ds)
    n = len(res.attractors)
    # one area per attractor and one band per boundary between two areas
    areas = ax_f.collections
    assert len(areas) == n + (n - 1)
    # the top of the last area is 1 at every value: the fractions stack to the whole grid
    xy = areas[-1].get_paths()[0].vertices
    for v in ds["value"].values:
        assert np.isclose(xy[np.isclose(xy[:, 0], v), 1].max(), 1.0)
    assert [t.get_text() for t in ax_f.get_legend().get_texts()] == list(res.names)
    # the exponent lines are the exponents where the attractor is reached
    lines = [ln for ln in ax_l.get_lines() if ln.get_marker() == "."]
    assert len(lines) == n
    for ln, att in zip(lines, res.attractors):
        y = np.asarray(ln.get_ydata(), dtype=float)
        np.testing.assert_array_equal(np.isfinite(y), att.present)
        np.testing.assert_allclose(y[att.present], att.exponent[att.present])
    matplotlib.pyplot.close(fig)
    assert save_attractors_figure(ds, tmp_path / "a.png").stat().st_size > 0
