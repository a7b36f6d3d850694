"""Common figure helpers, and the checks of the arguments every figure shares (axes, datasets, views, counts)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..errors import ParameterError
from ..io.netcdf import check_output_folder
from ..model.validation import check_float, check_path, check_type, is_pair, quoted, real_array

CLEARANCE_COLOR = "0.6"
#: Suffixes of the figure files `save_figure` writes.
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
#: Most samples of a curve (or points of a figure): a figure 20 inches wide saved at 150 dpi (`save_figure`)
#: is 3000 pixels wide, so a million samples already put hundreds on each column of pixels; a figure cannot
#: show more, they would only cost memory and time.
MAX_PLOT_POINTS = 1_000_000
#: Longest side of a figure, in inches: matplotlib refuses an image over 2**16 pixels a side, 437 inches
#: at the 150 dpi of `save_figure`; a hundred inches is already a poster.
MAX_FIGURE_INCHES = 100.0


def orbit_tex(label: str) -> str:
    """The mathtext of an orbit label: ``"B1,a"`` gives ``"$B_{1,a}$"`` (other labels unchanged).

    Parameters
    ----------
    label : str
        An orbit label ``"B<n>,<m>"``.

    Returns
    -------
    str

    Raises
    ------
    ParameterError
        If ``label`` is not text.
    """
    check_type("label", label, str, "an orbit label such as 'B1,a'")
    name, sep, letter = label.partition(",")
    if not sep or not name.startswith("B") or not name[1:].isdigit():
        return label
    return rf"$B_{{{name[1:]},{letter}}}$"


def check_ax(ax: Any, name: str = "ax", *, optional: bool = True) -> Axes | None:
    """Return ``ax`` if it is a `matplotlib.axes.Axes` (or None where ``optional``).

    Raises
    ------
    ParameterError
        Naming ``name`` and the value, for anything else.
    """
    return check_type(name, ax, Axes, "a matplotlib.axes.Axes", optional=optional)


def check_axes(axes: Any, count: int, roles: str, name: str = "axes") -> list[Axes] | None:
    """None, or ``axes`` as a list of its ``count`` `matplotlib.axes.Axes`.

    ``axes`` is a list, a tuple or a numpy array of Axes (as `matplotlib.pyplot.subplots` gives, of any
    shape, read in C order).

    Parameters
    ----------
    axes : sequence of matplotlib.axes.Axes or None
    count : int
        How many panels the figure draws.
    roles : str
        What each panel shows, in order, for the message.
    name : str
        The argument's name, for the message.

    Returns
    -------
    list of matplotlib.axes.Axes or None

    Raises
    ------
    ParameterError
        For another object, a sequence holding something other than Axes, or another number of Axes.
    """
    if axes is None:
        return None
    allowed = f"None or a sequence of {count} matplotlib.axes.Axes ({roles})"
    if not isinstance(axes, (list, tuple, np.ndarray)):
        raise ParameterError(f"{name} = {quoted(axes)} is not a sequence of Axes; allowed: {allowed}")
    flat = list(np.ravel(np.asarray(axes, dtype=object))) if isinstance(axes, np.ndarray) else list(axes)
    if not all(isinstance(ax, Axes) for ax in flat):
        raise ParameterError(f"{name} = {quoted(axes)} holds an object that is not an Axes; allowed: {allowed}")
    if len(flat) != count:
        raise ParameterError(f"{name} = {quoted(axes)} holds {len(flat)} axes; allowed: {allowed}")
    return flat


def check_limits(name: str, value: Any, *, optional: bool = True) -> tuple[float, float] | None:
    """Return the view ``value`` = (low, high) as two floats (None where ``optional``).

    Raises
    ------
    ParameterError
        For anything but a pair of distinct finite real numbers (high < low turns the axis over).
    """
    if value is None and optional:
        return None
    pair = real_array(value) if is_pair(value) else None
    if pair is None or pair.shape != (2,) or not np.all(np.isfinite(pair)) or pair[0] == pair[1]:
        raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: (low, high), two distinct finite "
                             f"numbers{' or None' if optional else ''}")
    return float(pair[0]), float(pair[1])


def check_names(name: str, value: Any, what: str = "orbit labels such as 'B1,a'") -> tuple[str, ...]:
    """Return ``value``, a list or tuple of text, as a tuple.

    Raises
    ------
    ParameterError
        For text alone (which would be read letter by letter) or a sequence holding something else.
    """
    if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) for v in value):
        raise ParameterError(f"{name} = {quoted(value)} is invalid; allowed: a list or tuple of {what}")
    return tuple(value)


def check_keywords(kwargs: dict[str, Any], target: Any) -> None:
    """Refuse keyword arguments that ``target`` (the function they are passed on to) does not take, naming
    the first and listing those it takes, rather than a `TypeError` from inside."""
    import inspect

    params = inspect.signature(target).parameters
    taken = [n for n, p in params.items() if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)]
    unknown = sorted(set(kwargs) - set(taken))
    if unknown:
        raise ParameterError(f"{unknown[0]} = {quoted(kwargs[unknown[0]])} is not an option of {target.__name__}; "
                             f"allowed: {', '.join(taken)}")


def check_figure_path(path: Any) -> Path:
    """``path`` as a `pathlib.Path` if a figure can be written there: a .png, .svg or .pdf file in a
    folder that exists.

    Raises
    ------
    ParameterError
        Naming ``path``, for another object, an empty name, another suffix or a missing folder.
    """
    path = check_path("path", path)
    if path.suffix.lower() not in FIGURE_SUFFIXES:
        raise ParameterError(f"path = {str(path)!r} has an unsupported suffix; allowed: {', '.join(FIGURE_SUFFIXES)}")
    check_output_folder(path)
    return path


def style_runs(keys: Sequence[Any], join: Callable[[Any, Any], bool] = lambda key, following: True
               ) -> list[tuple[Any, int, int]]:
    """Runs of equal consecutive ``keys`` (the style of each point of a line) as (key, start, stop), the points
    start..stop-1. A run also takes the first point of the next where ``join(key, following key)``, so that the
    lines of the two meet there (by default always)."""
    out = []
    start = 0
    for k in range(1, len(keys) + 1):
        if k < len(keys) and keys[k] == keys[start]:
            continue
        out.append((keys[start], start, k + 1 if k < len(keys) and join(keys[start], keys[k]) else k))
        start = k
    return out


def new_axes(ax=None, **subplot_kw):
    """Return (fig, ax), creating a figure when ``ax`` is None.

    Raises
    ------
    ParameterError
        If ``ax`` is neither None nor a `matplotlib.axes.Axes` (before any figure is made).
    """
    if check_ax(ax) is not None:
        return ax.figure, ax
    fig, ax = plt.subplots(**subplot_kw)
    return fig, ax


def draw_clearance(ax, radius: float = 1.0) -> None:
    """The clearance circle |U| = radius in grey, with equal axes.

    Raises
    ------
    ParameterError
        If ``ax`` is not a `matplotlib.axes.Axes` or ``radius`` is not a finite number > 0.
    """
    check_ax(ax, optional=False)
    radius = check_float("radius", radius, 0.0, low_open=True)
    s = np.linspace(0.0, 2.0 * np.pi, 400)
    ax.plot(radius * np.cos(s), radius * np.sin(s), color=CLEARANCE_COLOR, lw=1.5, zorder=0)
    ax.set_aspect("equal")


def save_figure(fig, path) -> Path:
    """Save ``fig`` to ``path`` (format from its suffix) in an existing folder; close it.

    Raises
    ------
    ParameterError
        If ``fig`` is not a `matplotlib.figure.Figure`, or for a ``path`` that `check_figure_path` refuses.
    """
    check_type("fig", fig, Figure, "a matplotlib.figure.Figure")
    path = check_figure_path(path)
    fig.savefig(path, dpi=150, bbox_inches="tight")
    plt.close(fig)
    return path


def offset_beside(ax, curves: Sequence[np.ndarray], x: float, y: float, *, away_from: tuple[float, float] | None = None,
                  distance: float = 9.0) -> tuple[float, float]:
    """The offset in points that puts a label of the point (x, y) of one of ``curves`` (arrays of (x, y) rows)
    across the curve from it: along the curve's normal as drawn, on the side away from ``away_from`` (default:
    the middle of that curve, so outside a closed one). Call it once the axes' limits and aspect are set."""
    to_px = ax.transData.transform
    at = to_px((x, y))
    best = None
    for xy in curves:
        px = to_px(np.asarray(xy, dtype=float))
        i = int(np.argmin(np.hypot(*(px - at).T)))
        d = float(np.hypot(*(px[i] - at)))
        if best is None or d < best[0]:
            best = (d, px, i)
    if best is None:
        return (6.0, 0.0)
    _d, px, i = best
    tangent = px[min(i + 1, len(px) - 1)] - px[max(i - 1, 0)]
    length = float(np.hypot(*tangent))
    if length == 0.0:
        return (6.0, 0.0)
    normal = np.array([-tangent[1], tangent[0]]) / length
    away = px.mean(axis=0) if away_from is None else to_px(away_from)
    if np.dot(normal, px[i] - away) < 0.0:
        normal = -normal
    return (float(distance * normal[0]), float(distance * normal[1]))
