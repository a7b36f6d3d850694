"""Trajectory figures with continuous contact: a valid PNG, and the contact phases shaded on r(t)."""

from __future__ import annotations

import struct
import zlib

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

from rotorcontact import ParameterError, simulate  # noqa: E402
from rotorcontact.cli.main import main  # noqa: E402
from rotorcontact.plotting.trajectory import plot_radius, plot_trajectory  # noqa: E402
from reference_parameters import REF  # noqa: E402


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def check_png(path):
    """A well-formed PNG: signature, IHDR first with a positive size, CRCs right, IDAT data, IEND last."""
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE
    pos, chunks = 8, []
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length : pos + 12 + length])
        assert zlib.crc32(kind + body) & 0xFFFFFFFF == crc, kind
        chunks.append((kind, body))
        pos += 12 + length
    assert chunks[0][0] == b"IHDR" and chunks[-1][0] == b"IEND"
    width, height = struct.unpack(">II", chunks[0][1][:8])
    assert width > 100 and height > 100
    raw = zlib.decompress(b"".join(body for kind, body in chunks if kind == b"IDAT"))
    assert len(raw) > width  # image data present
    image = plt.imread(path)
    assert image.shape[:2] == (height, width)
    # not a blank canvas
    assert np.ptp(image[..., :3]) > 0.5
    return width, height


@pytest.mark.parametrize("d", ["0.5", "0.95"])
def test_cli_plot_with_contact_phases_writes_a_valid_png(tmp_path, capsys, d):
    path = tmp_path / f"contact_{d}.png"
    code = main(["simulate", "--gamma=0.05", f"--d={d}", "--u0=0.5,0", "--du0=0.8,0.3", "--t-end=60",
                 f"--plot={path}"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert str(path) in out
    check_png(path)


def _spans(ax):
    """(x0, x1, facecolor) of the vertical spans on a time axis."""
    spans = []
    for patch in ax.patches:
        verts = patch.get_path().transformed(patch.get_patch_transform()).vertices
        if hasattr(patch, "get_xy") and not hasattr(patch, "get_width"):  # Polygon
            verts = np.asarray(patch.get_xy())
        xs = verts[:, 0]
        spans.append((float(xs.min()), float(xs.max()), patch.get_facecolor()))
    return spans


def test_radius_panel_shades_each_contact_phase_by_kind():
    traj = simulate(REF.replace(gamma=0.05), 0.5, 0.8 + 0.3j, 60.0)
    phases = traj.contact_intervals
    assert [c.kind for c in phases] == ["sliding-forward", "rolling"]
    fig, ax = plot_radius(traj)
    spans = _spans(ax)
    assert len(spans) == len(phases)
    colours = set()
    for c, (x0, x1, face) in zip(phases, sorted(spans)):
        assert x0 == pytest.approx(c.t_start, abs=1e-9)
        assert x1 == pytest.approx(c.t_end, abs=1e-9)
        colours.add(tuple(np.round(to_rgba(face)[:3], 6)))
    assert len(colours) == 2  # one colour per kind
    labels = {t.get_text() for t in ax.get_legend().get_texts()}
    assert {"sliding-forward", "rolling"} <= labels
    # the curve sits on r = 1 during the contact phases
    line = ax.get_lines()[0]
    t, r = line.get_data()
    inside = (t > phases[0].t_start) & (t < phases[-1].t_end)
    assert inside.any()
    np.testing.assert_allclose(np.asarray(r)[inside], 1.0, atol=1e-12)
    plt.close(fig)


def test_no_shading_without_contact():
    traj = simulate(REF.replace(gamma=0.1), 0j, 0j, 60.0)
    assert not traj.contact_intervals
    fig, ax = plot_radius(traj)
    assert _spans(ax) == []
    plt.close(fig)


def test_three_panels_with_a_rub_and_the_regime_in_the_title():
    traj = simulate(REF.replace(gamma=0.05, d=0.5), 0.5, 0.8 + 0.3j, 40.0)
    fig, axes = plot_trajectory(traj)
    assert len(axes) == 3
    assert "forward-rub" in fig._suptitle.get_text()
    assert len(_spans(axes[2])) == len(traj.contact_intervals) == 1
    plt.close(fig)


def test_corotating_panel_names_x_R_and_zooms_on_a_small_orbit():
    """B1,a at gamma = 0.1 stays within 1e-3 of the clearance: the inset shows it at a scale it fills."""
    from rotorcontact.maps.impact_map import one_impact_orbits
    from rotorcontact.plotting.trajectory import plot_corotating

    p = REF.replace(gamma=0.1)
    orbit = next(o for o in one_impact_orbits(p) if o.label == "B1,a")
    traj = simulate(p, *orbit.initial_condition(), 0.999 * orbit.T)
    fig, ax = plot_corotating(traj)
    assert r"$x_R$" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert not ax.child_axes
    fig2, ax2 = plt.subplots()
    assert plot_corotating(traj, ax2, inset=True) == (fig2, ax2)
    (zoom,) = [child for child in ax2.child_axes if child.get_label() == "zoom"]
    (orbit_line,) = [ln for ln in zoom.get_lines() if ln.get_gid() == "orbit"]
    x, y = orbit_line.get_data()
    (x0, x1), (y0, y1) = zoom.get_xlim(), zoom.get_ylim()
    assert x0 <= x.min() and x.max() <= x1 and y0 <= y.min() and y.max() <= y1
    assert max(np.ptp(x), np.ptp(y)) > 0.5 * (x1 - x0)
    (factor,) = [t for t in zoom.texts if t.get_gid() == "zoom-factor"]
    main = ax2.get_xlim()
    assert factor.get_text() == f"×{(main[1] - main[0]) / (x1 - x0):.0f}"
    plt.close("all")


def test_plot_trajectory_draws_into_given_axes_and_refuses_a_wrong_number():
    traj = simulate(REF.replace(gamma=0.1), 0j, 0j, t_end=60.0)
    fig, grid = plt.subplots(2, 3)
    back_fig, axes = plot_trajectory(traj, grid[1])
    assert back_fig is fig and list(axes) == list(grid[1])
    # the three panels are drawn where they were asked for, the other row untouched
    assert [ax.get_title() for ax in grid[1]] == ["inertial frame", "co-rotating frame", "radius"]
    assert all(not ax.lines for ax in grid[0])
    assert fig.get_suptitle() == ""  # the caller's figure keeps its own title
    with pytest.raises(ParameterError, match=r"^axes = .* holds 2 axes; allowed: None or a sequence of 3 "):
        plot_trajectory(traj, grid[0, :2])
    plt.close(fig)


def test_figures_refuse_a_missing_folder_in_the_python_api(tmp_path):
    from rotorcontact.plotting.style import save_figure
    from rotorcontact.studies.execution import write_netcdf

    fig, _ = plt.subplots()
    with pytest.raises(ParameterError, match="does not exist"):
        save_figure(fig, tmp_path / "missing" / "f.png")
    assert not (tmp_path / "missing").exists()
    import xarray as xr

    with pytest.raises(ParameterError, match="does not exist"):
        write_netcdf(xr.Dataset({"a": ("x", [1.0])}), tmp_path / "missing" / "f.nc")
    assert not (tmp_path / "missing").exists()
    plt.close(fig)


@pytest.fixture(scope="module")
def quiet():
    return simulate(REF.replace(gamma=0.1), 0j, 0j, t_end=20.0)


def test_trajectory_figures_refuse_what_is_not_a_trajectory(refused, tmp_path):
    from rotorcontact.plotting.trajectory import plot_corotating, plot_inertial, save_trajectory_figure

    for draw in (plot_inertial, plot_corotating, plot_radius, plot_trajectory):
        refused(r"^traj = None is not an? Trajectory object; allowed: a rotorcontact\.Trajectory", draw, None)
    refused(r"^traj = 'x' is not an? Trajectory object; allowed:", save_trajectory_figure, "x", tmp_path / "t.png")
    assert not (tmp_path / "t.png").exists()


def test_trajectory_figures_refuse_an_ax_or_axes_that_is_not_one(refused, quiet):
    from rotorcontact.plotting.trajectory import plot_corotating, plot_inertial, shade_contact

    fig, grid = plt.subplots(1, 3)
    for draw in (plot_inertial, plot_corotating, plot_radius):
        refused(r"^ax = 'x' is not an? Axes object; allowed: a matplotlib\.axes\.Axes or None$", draw, quiet, "x")
        refused(r"^ax = <Figure .* is not an? Axes object", draw, quiet, fig)
    refused(r"^ax = None is not an? Axes object; allowed: a matplotlib\.axes\.Axes$", shade_contact, quiet, None)
    refused(r"^traj = 1 is not an? Trajectory object", shade_contact, 1, grid[0])
    refused(r"^t_from = 'a' is invalid; allowed: a finite number$", shade_contact, quiet, grid[0], "a")
    refused(r"^axes = 'xyz' is not a sequence of Axes; allowed: None or a sequence of 3 matplotlib\.axes\.Axes "
            r"\(inertial, co-rotating, radius\)$", plot_trajectory, quiet, "xyz")
    refused(r"^axes = .* holds an object that is not an Axes; allowed:", plot_trajectory, quiet,
            [grid[0], grid[1], "radius"])
    assert all(not ax.lines for ax in grid)  # nothing drawn before the refusal
    plt.close(fig)


@pytest.mark.parametrize("n", [10**12, 1, 0, 2.5, "100", True])
def test_the_number_of_plot_times_is_bounded(refused, quiet, n):
    from rotorcontact.plotting.trajectory import plot_corotating, plot_inertial

    for draw in (plot_inertial, plot_corotating, plot_radius, plot_trajectory):
        refused(rf"^n = {n!r} is invalid; allowed: an integer from 2 to 1000000$", draw, quiet, n=n)


def test_t_from_and_the_flags_are_checked(refused, quiet):
    from rotorcontact.plotting.trajectory import plot_corotating, plot_inertial

    for bad in ("10", np.nan, [1.0]):
        for draw in (plot_inertial, plot_corotating, plot_radius, plot_trajectory):
            refused(r"^t_from = .* is invalid; allowed: a finite number$", draw, quiet, t_from=bad)
    refused(r"^inset = 'yes' is invalid; allowed: True or False$", plot_corotating, quiet, inset="yes")
    refused(r"^legend = 'False' is invalid; allowed: True or False$", plot_corotating, quiet, legend="False")
    # valid values still draw: a negative t_from starts at 0, as before
    fig, ax = plot_inertial(quiet, t_from=-5.0, n=2)
    assert ax.get_lines()
    plt.close(fig)
