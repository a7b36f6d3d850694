"""Common figure helpers."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..errors import ParameterError  # noqa: E402
from ..io.netcdf import check_output_folder  # noqa: E402
from ..model.validation import check_path  # noqa: E402

CLEARANCE_COLOR = "0.6"


def orbit_tex(label: str) -> str:
    """The mathtext of an orbit label: ``"B1,a"`` gives ``"$B_{1,a}$"`` (other labels unchanged).

    Parameters
    ----------
    label : str
        An orbit label ``"B<n>,<m>"``.

    Returns
    -------
    str
    """
    name, sep, letter = label.partition(",")
    if not sep or not name.startswith("B") or not name[1:].isdigit():
        return label
    return rf"$B_{{{name[1:]},{letter}}}$"


def new_axes(ax=None, **subplot_kw):
    """Return (fig, ax), creating a figure when ``ax`` is None."""
    if ax is not None:
        return ax.figure, ax
    fig, ax = plt.subplots(**subplot_kw)
    return fig, ax


def draw_clearance(ax, radius: float = 1.0) -> None:
    """The clearance circle |U| = radius in grey, with equal axes."""
    s = np.linspace(0.0, 2.0 * np.pi, 400)
    ax.plot(radius * np.cos(s), radius * np.sin(s), color=CLEARANCE_COLOR, lw=1.5, zorder=0)
    ax.set_aspect("equal")


def save_figure(fig, path) -> Path:
    """Save ``fig`` to ``path`` (format from its suffix) in an existing folder; close it."""
    path = check_path("path", path)
    if path.suffix.lower() not in {".png", ".svg", ".pdf"}:
        raise ParameterError(f"plot file {str(path)!r} has an unsupported suffix; allowed: .png, .svg, .pdf")
    check_output_folder(path)
    fig.savefig(path, dpi=150, bbox_inches="tight")
    plt.close(fig)
    return path
