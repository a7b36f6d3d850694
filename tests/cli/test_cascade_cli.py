"""``rotorcontact cascade``: JSON contract, agreement with the library, text and bad input."""

from __future__ import annotations

import pytest

from rotorcontact.continuation.cascade import cascades
from reference_parameters import REF

ARGS = ["--gamma", "0.0845", "--from", "0.0836", "--to", "0.0865", "--impacts", "2", "--depth", "3"]


def test_json_contract_and_agreement_with_the_library(cli):
    data = cli.json("cascade", *ARGS)
    assert set(data) == {"parameters", "param", "impacts", "cascades"}
    assert data["param"] == "gamma" and data["impacts"] == 2
    lib = cascades(REF.replace(gamma=0.0845), "gamma", 0.0836, 0.0865, impacts=2, depth=3)
    assert len(data["cascades"]) == len(lib)
    for c, ref in zip(data["cascades"], lib):
        assert set(c) == {"orbits", "points", "ratios", "end", "accumulation"}
        assert set(c["end"]) == {"type", "value"}
        assert [p["value"] for p in c["points"]] == [e.value for e in ref.points]
        assert c["ratios"] == list(ref.ratios)
        for p in c["points"]:
            assert set(p) == {"type", "value", "orbits", "impacts"} and p["type"] == "period-doubling"
    deep = max(data["cascades"], key=lambda c: len(c["points"]))
    assert [p["impacts"] for p in deep["points"]] == [2, 4, 8, 16] and len(deep["ratios"]) == 2


def test_text(cli):
    code, out, err = cli.run("cascade", *ARGS)
    assert code == 0, err
    assert "cascade M2-1 -> M2-1/PD" in out and "delta = " in out and "ends: accumulation" in out


@pytest.mark.parametrize("args", [["--depth", "0"], ["--depth", "99"], ["--impacts", "0"], ["--param", "phi"],
                                  ["--from", "0.2", "--to", "0.1"], ["--impacts", "2", "--from", "0.0", "--to", "0.1"],
                                  ["--grid", "a,b,c"]])
def test_bad_input_exits_2(cli, args):
    code, _out, err = cli.run("cascade", *args)
    assert code == 2 and "error" in err and "Traceback" not in err


def test_sweep_figure_with_multi_impact_overlay(cli, tmp_path):
    png = tmp_path / "s.png"
    code, _out, err = cli.run("sweep", "--param", "gamma", "--from", "0.0836", "--to", "0.0865", "--n", "4",
                             "--transient", "300", "--record", "20", "--mode", "up", "--out", str(tmp_path / "s.nc"),
                             "--plot", str(png), "--overlay-impacts", "2", "--overlay-doublings", "1",
                             "--section", "rdot")
    assert code == 0, err
    assert png.stat().st_size > 0


@pytest.mark.parametrize("args", [["--overlay-impacts", "2"], ["--overlay-impacts", "1", "--plot", "x.png"],
                                  ["--overlay-impacts", "2", "--plot", "x.png", "--overlay-doublings", "99"],
                                  ["--overlay-impacts", "2", "--plot", "x.png", "--param", "phi"]])
def test_sweep_overlay_bad_input(cli, tmp_path, args):
    code, _out, err = cli.run("sweep", "--from", "0.08", "--to", "0.09", "--n", "3", "--out",
                             str(tmp_path / "s.nc"), *[str(tmp_path / a) if a.endswith(".png") else a for a in args])
    assert code == 2 and "error" in err and "Traceback" not in err


def test_text_says_where_a_ratio_is_undefined():
    from dataclasses import replace

    from rotorcontact.cli.cascade import _text
    from rotorcontact.continuation.cascade import Cascade, feigenbaum_ratios
    from rotorcontact.continuation.results import BranchEvent

    values = (0.1, 0.09, 0.09)  # two doublings at the same value: the second interval is zero
    points = tuple(replace(BranchEvent("period-doubling", v, "gamma", (f"M{i}",)), impacts=2 ** i)
                   for i, v in enumerate(values))
    c = Cascade(param="gamma", points=points, labels=("M1", "M2"), ratios=feigenbaum_ratios(values),
                end="range", end_value=None, accumulation=None)
    lines = _text((c,), "gamma")
    # delta_1 is shown at the second doubling, and none at the third (two intervals give one ratio)
    assert c.ratios == (None,) and lines[2].endswith("(2 impacts)  delta undefined") and lines[3].endswith(
        "(4 impacts)")
