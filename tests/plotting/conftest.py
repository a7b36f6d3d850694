"""Small results of the studies, shared by the tests of the figures that draw them and refuse the others',
and the check that a refused call leaves no figure open."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from rotorcontact import ParameterError  # noqa: E402
from reference_parameters import REF  # noqa: E402


@pytest.fixture(scope="session")
def sweep_result():
    from rotorcontact.studies.sweep import sweep, sweep_values

    return sweep(REF, "gamma", sweep_values(0.12, 0.19, 3), mode="both", n_transient=50, n_record=5,
                 progress=False)


@pytest.fixture(scope="session")
def sweep_dataset(sweep_result):
    return sweep_result.dataset


@pytest.fixture(scope="session")
def basins_result():
    from rotorcontact.studies.basins import basins, displacement_grid

    return basins(REF.replace(gamma=0.1), displacement_grid((-1, 1, 3), (-1, 1, 3)), progress=False)


@pytest.fixture(scope="session")
def basins_dataset(basins_result):
    return basins_result.dataset


def _refused(pattern: str, draw, *args, **kwargs) -> None:
    before = set(plt.get_fignums())
    with pytest.raises(ParameterError, match=pattern):
        draw(*args, **kwargs)
    left = set(plt.get_fignums()) - before
    for num in left:
        plt.close(num)
    assert not left, "the refused call left a figure open"


@pytest.fixture
def refused():
    """``refused(pattern, draw, *args, **kwargs)``: ``draw(*args, **kwargs)`` raises a `ParameterError` whose
    message matches ``pattern`` (from its start with ``^``) and leaves no new figure open."""
    return _refused


def _same_drawing(ax_a, ax_b) -> bool:
    import numpy as np

    def drawn(ax):
        return ([np.asarray(line.get_xydata()) for line in ax.get_lines()],
                [np.asarray(im.get_array()) for im in ax.get_images()], len(ax.collections))

    (lines_a, images_a, n_a), (lines_b, images_b, n_b) = drawn(ax_a), drawn(ax_b)
    return (len(lines_a) == len(lines_b) and all(np.array_equal(a, b) for a, b in zip(lines_a, lines_b))
            and len(images_a) == len(images_b) and all(np.array_equal(a, b) for a, b in zip(images_a, images_b))
            and n_a == n_b)


@pytest.fixture
def same_drawing():
    """``same_drawing(ax_a, ax_b)``: the two axes hold the same lines, images and number of collections."""
    return _same_drawing
