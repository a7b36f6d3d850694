"""The two-parameter diagram (the paper's Fig. 6a).

The plane (by default (gamma, omega)) is shaded by region R1-R4 (MODEL.md §5,
from `rotorcontact.continuation.codim2.classify_plane`; grey and "other" where a point fits
none of them), each part of a region labelled inside it, with the fold curve gamma_F,1, the
DIB curve gamma_DIB and, optionally, grazing curves drawn over it, and the
intersection points marked. Along the DIB curve, the part where the one-impact
orbits of the first pair exist is labelled NSFH (they are born there); where
they do not, the boundary equilibrium bifurcation of the equilibria is
labelled NSF (non-smooth fold) or Pers (persistence), as classified by
`rotorcontact.analysis.equilibria.classify_beb_analytic`.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..continuation.codim2 import REGIONS, Codim2Diagram, classify_plane, codim2_diagram, dib_labels
from ..analysis.equilibria import classify_beb_analytic
from ..errors import ParameterError
from ..model.params import Parameters
from ..model.validation import check_bool, check_float, check_params, check_type, quoted, real_array
from .equilibria import PARAM_LABELS
from .style import check_ax, new_axes, offset_beside

__all__ = ["plot_codim2", "region_label_cells", "REGION_COLORS", "CURVE_STYLES", "OTHER"]

#: The label of the points that fit none of R1-R4 (`rotorcontact.continuation.codim2.region` gives None).
OTHER = "other"
#: Shading of the regions.
REGION_COLORS = {"R1": "#dbe9f6", "R2": "#fde2c8", "R3": "#e5f5e0", "R4": "#f2dcef", OTHER: "#ececec"}
#: Style of each kind of curve.
CURVE_STYLES = {"fold": dict(color="C0", lw=2.0), "dib": dict(color="k", lw=2.0),
                "grazing": dict(color="C3", lw=1.5, ls="--"), "coalescence": dict(color="C1", lw=1.5, ls="-."),
                "period-doubling": dict(color="C2", lw=1.5), "neimark-sacker": dict(color="C4", lw=1.5),
                "orbit-fold": dict(color="C5", lw=1.5, ls=":")}

#: Legend text of the two-parameter curves of an orbit (`rotorcontact.continuation.codim2_orbits`).
_ORBIT_CURVES = {"pd": "PD", "ns": "NS", "fold": "fold"}


def _curve_label(name: str, kind: str, gamma_axis: bool) -> str:
    if kind == "coalescence":
        pair = name.split("_")[1]
        return f"{pair[0]}-{pair[1]} coalescence"
    if kind in ("period-doubling", "neimark-sacker", "orbit-fold"):
        short, _, orbit = name.partition("_")
        return f"{_ORBIT_CURVES.get(short, short)} {orbit}"
    if kind == "fold":
        n = name.split("_")[-1]
        return rf"$\gamma_{{F,{n}}}$" if gamma_axis else f"fold {n}"
    if kind == "dib":
        return r"$\gamma_{DIB}$" if gamma_axis else "DIB"
    orbit = name.split("_", 1)[1] if "_" in name else name
    return f"grazing {orbit}"


def region_label_cells(mask: np.ndarray, min_depth: float = 1.5) -> list[tuple[int, int]]:
    """Where to label a region of a grid: the cell deepest inside each of its connected parts.

    The depth of a cell is its distance (in cells) to the nearest cell outside
    the region or outside the grid, so a label placed there lies as far from
    the region's boundary curves and from the frame as the region allows; of
    equally deep cells, the one nearest the part's centroid.

    Parameters
    ----------
    mask : numpy.ndarray of bool, shape (n2, n1)
        The cells of the region (rows along the second parameter).
    min_depth : float
        Parts whose deepest cell is shallower than this (slivers along a
        curve) are not labelled.

    Returns
    -------
    list of (int, int)
        ``(i1, i2)``, the column and row of the cell of each part, largest part first.

    Raises
    ------
    ParameterError
        If ``mask`` is not a 2-D array of bools (or of 0 and 1) or ``min_depth`` is not a finite number >= 0.
    """
    from scipy import ndimage

    try:
        array = np.asarray(mask) if isinstance(mask, (np.ndarray, list, tuple)) else None
    except ValueError:  # a ragged list
        array = None
    if array is None or array.ndim != 2 or array.dtype.kind not in "biu" or not np.isin(array, (0, 1)).all():
        raise ParameterError(f"mask = {quoted(mask)} is invalid; allowed: a 2-D array of bools")
    min_depth = check_float("min_depth", min_depth, 0.0)
    mask = array.astype(bool)
    parts, count = ndimage.label(mask)
    depth = ndimage.distance_transform_edt(np.pad(mask, 1))[1:-1, 1:-1]
    out = []
    for k in range(1, count + 1):
        jj, ii = np.nonzero(parts == k)
        d = depth[jj, ii]
        if d.max() < min_depth:
            continue
        # of the deepest cells, the one nearest the part's centroid
        deepest = np.flatnonzero(d >= d.max() - 1e-9)
        m = deepest[np.argmin((jj[deepest] - jj.mean()) ** 2 + (ii[deepest] - ii.mean()) ** 2)]
        out.append((jj.size, int(ii[m]), int(jj[m])))
    out.sort(key=lambda item: -item[0])
    return [(i, j) for _size, i, j in out]


def _check_labels(labels) -> None:
    """None, or a list or tuple of (text, p1, p2): the labels along the DIB curve."""
    if labels is None:
        return
    ok = isinstance(labels, (list, tuple))
    for item in labels if ok else ():
        ok = isinstance(item, (list, tuple)) and len(item) == 3 and isinstance(item[0], str)
        coords = real_array(item[1:]) if ok else None
        if coords is None or coords.shape != (2,) or not np.all(np.isfinite(coords)):
            ok = False
            break
    if not ok:
        raise ParameterError(f"labels = {quoted(labels)} is invalid; allowed: None or a list of (text, p1, p2), "
                             "p1 and p2 finite numbers")


def plot_codim2(
    params: Parameters,
    param: Sequence[str] = ("gamma", "omega"),
    ranges=None,
    *,
    ax=None,
    diagram: Codim2Diagram | None = None,
    labels: Sequence[tuple[str, float, float]] | None = None,
    regions: bool = True,
    shape: tuple[int, int] = (61, 61),
    grazing: Sequence[str] = (),
    t_max: float = 12.0,
    legend: bool = True,
):
    """The (p1, p2) plane with the fold and DIB curves, regions R1-R4 and NSFH / NSF / Pers labels.

    Parameters
    ----------
    params : Parameters
        The other parameters.
    param : (str, str)
        The plane; p1 on the horizontal axis.
    ranges : ((float, float), (float, float)), optional
        The box (`rotorcontact.continuation.codim2.DEFAULT_RANGES` when omitted).
    ax : matplotlib.axes.Axes, optional
    diagram : Codim2Diagram, optional
        Precomputed curves (else `codim2_diagram` with fold_1 and the given grazing curves).
    labels : sequence of (str, float, float), optional
        Precomputed labels along the DIB curve, (text, p1, p2) (else
        `rotorcontact.continuation.codim2.dib_labels` with
        `rotorcontact.analysis.equilibria.classify_beb_analytic`).
    regions : bool
        Shade and label the regions (a grid of ``shape`` points is classified).
        Each connected part of a region is labelled at its cell deepest
        inside it (`region_label_cells`); points fitting none of R1-R4 are
        shaded grey and labelled `OTHER`.
    shape : (int, int)
        Grid of the region classification.
    grazing : sequence of str
        Orbits whose grazing curves are computed when ``diagram`` is None.
    t_max : float
    legend : bool

    Returns
    -------
    (fig, ax)

    Raises
    ------
    ParameterError
        If ``params`` is not a Parameters, ``ax`` not an Axes, ``diagram`` neither None nor a
        Codim2Diagram, ``labels`` neither None nor a list of (text, p1, p2), or ``regions`` or ``legend``
        not True or False; and for the plane, ``shape``, ``grazing`` or ``t_max`` that
        `rotorcontact.continuation.codim2.codim2_diagram` or `rotorcontact.continuation.codim2.classify_plane`
        refuse (all before drawing).
    """
    check_params(params)
    check_ax(ax)
    check_type("diagram", diagram, Codim2Diagram, "the Codim2Diagram of rotorcontact.continuation.codim2."
               "codim2_diagram", optional=True)
    _check_labels(labels)
    check_bool("regions", regions)
    check_bool("legend", legend)
    if diagram is None:
        diagram = codim2_diagram(params, param, ranges, grazing=grazing, t_max=t_max)
    if regions:
        v1, v2, cells = classify_plane(diagram.base, diagram.param, diagram.ranges, shape, t_max)
    if labels is None:
        labels = dib_labels(diagram, t_max, classify_beb_analytic)
    fig, ax = new_axes(ax)
    (a1, b1), (a2, b2) = diagram.ranges
    if regions:
        from matplotlib.colors import ListedColormap

        names = (*REGIONS, OTHER)
        code = np.zeros(cells.shape)
        for i, name in enumerate(names):
            code[cells == (None if name == OTHER else name)] = i
        cmap = ListedColormap([REGION_COLORS[r] for r in names])
        ax.pcolormesh(v1, v2, code, cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5,
                      shading="nearest", zorder=0, gid="regions")
        for i, name in enumerate(names):
            for i1, i2 in region_label_cells(code == i):
                ax.text(v1[i1], v2[i2], name, ha="center", va="center", fontsize=11, weight="bold",
                        color="0.25", gid=f"label:{name}")
    for name, curve in diagram.curves.items():
        style = CURVE_STYLES.get(curve.kind, {})
        xy = curve.xy()
        if xy.size:
            label = _curve_label(name, curve.kind, diagram.param[0] == "gamma")
            ax.plot(xy[:, 0], xy[:, 1], label=label, gid=f"curve:{name}", **style)
    for pt in diagram.points:
        ax.plot([pt.values[0]], [pt.values[1]], "o", color="k", ms=5, zorder=6, gid=f"point:{pt.type}")
    ax.set_xlim(a1, b1)
    ax.set_ylim(a2, b2)
    dib = [c.xy() for c in diagram.curves.values() if c.kind == "dib" and c.xy().shape[0] >= 2]
    for text, x, y in labels:
        ax.annotate(text, (x, y), textcoords="offset points", xytext=offset_beside(ax, dib, x, y), ha="center",
                    va="center", fontsize=9, style="italic", gid=f"dib:{text}")
    ax.set_xlabel(PARAM_LABELS.get(diagram.param[0], diagram.param[0]))
    ax.set_ylabel(PARAM_LABELS.get(diagram.param[1], diagram.param[1]))
    if legend:
        ax.legend(fontsize=8, loc="lower right")
    return fig, ax
