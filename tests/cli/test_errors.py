"""Failures the command line reports without a traceback, whatever the subcommand."""

from __future__ import annotations

import subprocess
import sys

import pytest


def _run(*args):
    return subprocess.run([sys.executable, "-m", "rotorcontact.cli.main", *args], capture_output=True, text=True,
                          timeout=300)


@pytest.mark.parametrize(
    "args",
    [
        ("simulate", "--t-end", "5", "--plot", "/dev/null/x.png"),
        ("equilibria", "--plot", "/dev/null/x.png", "--from", "0", "--to", "0.2"),
    ],
)
def test_an_unwritable_output_is_bad_input(args):
    proc = _run(*args)
    assert proc.returncode == 2
    # refused before the computation, naming the option and why
    assert "--plot = '/dev/null/x.png': '/dev/null' is a file, not a folder" in proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize(
    "args, fragment",
    [
        (("lyapunov", "--qr-interval", "1e-9", "--t-end", "100"), "qr_interval"),
        (("lyapunov", "--t-end", "1e9"), "t_end"),
        (("branches", "--seeds", "1000000"), "--seeds"),
        (("branches", "--rdot-max", "0"), "--rdot-max = 0.0"),
        (("basins", "--grid", "plane:100000", "--out", "/tmp/never.nc"), "too large"),
        (("basins", "--grid", "x=2:3:5,y=2:3:5", "--out", "/tmp/never.nc"), "inside the clearance"),
        (("design-map", "--machine", "reference", "--speed", "nan:6000rpm"), "not finite"),
        (("design-map", "--machine", "reference", "--speed=-1000:6000rpm"), "--speed"),
    ],
)
def test_unbounded_or_empty_work_is_refused_at_once(args, fragment):
    proc = _run(*args)
    assert proc.returncode == 2, proc.stderr
    assert fragment in proc.stderr and "Traceback" not in proc.stderr


def test_a_failed_computation_exits_1_with_one_line():
    proc = _run("lyapunov", "--gamma", "1e308", "--t-end", "10")
    assert proc.returncode == 1
    assert "failed" in proc.stderr and "Traceback" not in proc.stderr
