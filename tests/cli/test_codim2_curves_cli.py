"""``rotorcontact codim2 --curves``: the added curves in the JSON contract, the figure, bad input."""

from __future__ import annotations

import pytest

from rotorcontact import Parameters
from rotorcontact.continuation.codim2 import coalescence_curves

SET = ["--omega", "0.8", "--rho", "0.4", "--mu", "0.3", "--d", "0.9", "--phi", "0.5", "--r-ratio", "57.1",
       "--grazing", "none"]


def test_curves_are_added_to_the_contract(cli, tmp_path):
    png = tmp_path / "c.png"
    data = cli.json("codim2", *SET, "--curves", "coalescence", "--curves", "pd:B1,d", "--plot", str(png))
    assert set(data) == {"parameters", "curves", "points"}
    assert set(data["curves"]) == {"fold_1", "dib", "coalescence_ac_1", "coalescence_bd_1", "pd_B1d"}
    ac, bd = coalescence_curves(Parameters(gamma=0.152, omega=0.8, rho=0.4, mu=0.3, d=0.9, phi=0.5, r_ratio=57.1))
    assert data["curves"]["coalescence_ac_1"] == ac.to_list()
    assert data["curves"]["coalescence_bd_1"] == bd.to_list()
    assert len(data["curves"]["pd_B1d"]) >= 10 and all(len(p) == 2 for p in data["curves"]["pd_B1d"] if p)
    assert png.stat().st_size > 0


@pytest.mark.parametrize("spec", ["pd", "xx:B1,d", "pd:", "pd:Q9", "ns:M2-99", "grazing:"])
def test_bad_curves_exit_2(cli, spec):
    code, _out, err = cli.run("codim2", *SET, "--curves", spec, "--from", "0.1,0.75", "--to", "0.2,0.85")
    assert code == 2 and "error" in err and "Traceback" not in err
