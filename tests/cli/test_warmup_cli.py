"""``rotorcontact warmup``."""

from __future__ import annotations


def test_warmup_json_gives_the_seconds_of_each_group(cli):
    data = cli.json("warmup", "--only", "drop", "--json")
    assert set(data) == {"seconds"} and set(data["seconds"]) == {"drop"} and data["seconds"]["drop"] > 0.0


def test_warmup_refuses_an_unknown_group_in_one_line(cli):
    code, out, err = cli.run("warmup", "--only", "simulate,fast")
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        "rotorcontact warmup: error: --only = 'fast' is not a kernel group; allowed: simulate, studies, orbits, drop"
    ]
