"""``rotorcontact codim2``: JSON contract, the curves' equations, plots and bad input."""

from __future__ import annotations

import math

import pytest

from rotorcontact.maps import impact_map as im
from reference_parameters import REF


@pytest.fixture(scope="module")
def reference_json(program):
    return program.exe_json("codim2", "--params", "gamma,omega")


def test_json_contract(reference_json):
    data = reference_json
    assert set(data) == {"parameters", "curves", "points"}
    assert set(data["curves"]) == {"fold_1", "dib", "grazing_B1d"}
    for name, pts in data["curves"].items():
        assert pts and all(p is None or (len(p) == 2 and all(isinstance(x, float) for x in p)) for p in pts)
    for p in data["points"]:
        assert set(p) == {"type", "gamma", "omega"}
        assert p["type"] in ("fold-dib", "grazing-dib", "fold-grazing")


def test_curves_and_points_satisfy_their_equations(reference_json):
    rho = REF.rho
    for g, w in (p for p in reference_json["curves"]["dib"] if p is not None):
        assert abs(g**2 + (1 - w**2) ** 2 - rho**2) < 1e-12
    fold = [p for p in reference_json["points"] if p["type"] == "fold-dib"]
    assert len(fold) == 2
    for pt in fold:
        g, w = pt["gamma"], pt["omega"]
        assert abs(g - math.sqrt(rho**2 - (1 - w**2) ** 2)) < 1e-9
        p = REF.replace(gamma=g, omega=w)
        # F1 has a double zero there: minimise |F1| + |F1'| over the zeros found near the fold
        zeros = im.f1_zeros(REF.replace(gamma=g - 1e-6, omega=w), 4.0)
        T = sum(z.T for z in zeros if z.n == 1) / 2.0
        assert abs(im.f1(p, T)) < 1e-8 and abs(im.f1_derivative(p, T)) < 1e-3


def test_plane_order_other_box_and_options(tmp_path, cli):
    png = tmp_path / "c.png"
    data = cli.json("codim2", "--params", "omega,gamma", "--from", "0.7,0.0", "--to", "1.0,0.3", "--grazing", "none",
                    "--plot", png)
    assert set(data["curves"]) == {"fold_1", "dib"}
    for w, g in (p for p in data["curves"]["dib"] if p is not None):
        assert 0.7 - 1e-12 <= w <= 1.0 + 1e-12 and -1e-12 <= g <= 0.3 + 1e-12
    assert all(set(p) == {"type", "omega", "gamma"} for p in data["points"])
    assert png.stat().st_size > 0
    code, out, err = cli.run("codim2", "--folds", "1,2", "--grazing", "none", "--from", "0,0.7", "--to", "0.25,0.9")
    assert code == 0, err
    assert "fold_2" in out and "fold-dib" in out


@pytest.mark.parametrize(
    "args",
    [
        ["--params", "gamma"],
        ["--params", "gamma,gamma"],
        ["--params", "gamma,phi"],
        ["--from", "0.1"],
        ["--from", "0.3,0.6", "--to", "0.1,1.2"],
        ["--folds", "0"],
        ["--folds", "x"],
        ["--grazing", "Bx"],
        ["--t-max", "0"],
        ["--plot", "out.gif"],
    ],
)
def test_bad_input_exits_2(args, cli):
    code, _, err = cli.run("codim2", *args)
    assert code == 2
    assert "error" in err and "Traceback" not in err


def test_bad_input_in_a_real_process_has_no_traceback(cli):
    code, _, err = cli.exe("codim2", "--from", "abc")
    assert code == 2
    assert "Traceback" not in err and "error" in err
