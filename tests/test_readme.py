"""The README's JSON examples are what the commands print: every number shown, to the digits shown."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from rotorcontact.cli.main import main

README = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")

#: (command, a text just before its example in the README); the example is the next JSON block, or the
#: next inline object in backticks
EXAMPLES = [
    ("simulate --gamma 0.1 --json", "`rotorcontact simulate --gamma 0.1 --json` prints the whole result"),
    ("equilibria --json", "`gamma_star` null where no real γ* exists; at the\ndefaults)"),
    ("orbits --gamma 0.1 --json", "`rotorcontact orbits --gamma 0.1 --json` prints"),
    ("branches --json", "number of interior extrema of r and the coalescence of the a and c roots."),
    ("codim2 --json", "classifies the plane into the regions R1–R4."),
    ("local --json", "ε = γ − γ* = 0; `parameters` are those of the analysis"),
    ("design-map --machine reference --speed 1000:6000rpm --json", "### `rotorcontact design-map`"),
    ("lyapunov --gamma 0.1 --json", "`rotorcontact lyapunov --gamma 0.1 --json` prints"),
    ("orbits --impacts 2 --gamma 0.083 --json", "`rotorcontact orbits --impacts 2 --gamma 0.083 --json` prints"),
    ("branches --impacts 2 --gamma 0.0818 --from 0.075 --to 0.09 --doublings 1 --json",
     "0.075 --to 0.09 --doublings 1 --json` prints"),
    ("cascade --gamma 0.0845 --from 0.0836 --to 0.0865 --impacts 2 --depth 4 --json",
     "M2-1 starts a cascade;"),
]

_NUMBER = r"-?\d+(?:\.\d+)?(?:e-?\d+)?"
_SCALAR = re.compile(rf'"(\w+)": ({_NUMBER})(?=[,}}\s])')
_LIST = re.compile(rf'"(\w+)": \[((?:{_NUMBER}, )*{_NUMBER})\]')


def _example(marker: str) -> str:
    """The example after ``marker``: the next ```json block, or an inline `{...}` if that comes first."""
    start = README.index(marker) + len(marker)
    block = README.find("```json\n", start)
    inline = README.find("`{", start)
    if inline != -1 and (block == -1 or inline < block):
        return README[inline + 1 : README.index("}`", inline) + 1]
    return README[block + 8 : README.index("```", block + 8)]


def _tolerance(text: str) -> float:
    """Half a unit in the last digit shown."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (-decimals + (int(exponent) if exponent else 0))


def _values(data, key: str) -> list:
    """Every value under ``key`` anywhere in ``data``."""
    out = []
    if isinstance(data, dict):
        for k, v in data.items():
            if k == key:
                out.append(v)
            out += _values(v, key)
    elif isinstance(data, list):
        for v in data:
            out += _values(v, key)
    return out


def _agrees(shown: str, actual) -> bool:
    if isinstance(actual, bool) or not isinstance(actual, (int, float)):
        return False
    return abs(actual - float(shown)) <= _tolerance(shown) * (1.0 + 1e-9)


@pytest.mark.parametrize("command, marker", EXAMPLES, ids=[c for c, _ in EXAMPLES])
def test_readme_example_is_what_the_command_prints(capsys, command, marker):
    example = _example(marker)
    assert main(command.split()) == 0
    data = json.loads(capsys.readouterr().out)
    assert next(iter(data)) == "parameters"
    checked = 0
    for key, shown in _SCALAR.findall(example):
        candidates = _values(data, key)
        assert candidates, f"{command}: the README shows {key!r}, which the output lacks"
        assert any(_agrees(shown, v) for v in candidates), (command, key, shown, candidates[:5])
        checked += 1
    for key, shown_list in _LIST.findall(example):
        shown = [x.strip() for x in shown_list.split(",")]
        candidates = [v for v in _values(data, key) if isinstance(v, list) and len(v) == len(shown)]
        assert any(all(_agrees(s, a) for s, a in zip(shown, v)) for v in candidates), (command, key, shown)
        checked += 1
    assert checked >= 2, f"{command}: no number of the README's example was checked"


def test_the_three_panel_trajectory_figure_is_documented_as_the_exception():
    # the paper's plotting functions take an optional ax, except plot_trajectory, which returns (fig, axes)
    import importlib
    import inspect
    import pkgutil

    import rotorcontact.plotting as plotting
    from rotorcontact.plotting import trajectory

    text = " ".join(README.split())
    assert "ax" not in inspect.signature(trajectory.plot_trajectory).parameters
    assert "except `plot_trajectory`" in text
    for name in ("plot_inertial", "plot_corotating", "plot_radius"):
        assert "ax" in inspect.signature(getattr(trajectory, name)).parameters
    # the others, as the README lists them: into an optional axes, or always into a new figure
    functions = {}
    for info in pkgutil.iter_modules(plotting.__path__):
        module = importlib.import_module(f"rotorcontact.plotting.{info.name}")
        functions.update({k: v for k, v in vars(module).items()
                          if k.startswith("plot_") and callable(v) and v.__module__ == module.__name__})
    into_axes = ("plot_attractors", "plot_local_figure")
    new_figure = ("plot_velocities", "plot_design_map", "plot_drop", "plot_drop_map", "plot_touchdown_forces",
                  "plot_rigid_limit", "plot_dry_whip")
    assert "`plot_attractors` and `plot_local_figure` draw several panels into an optional `axes`" in text
    assert "`plot_rigid_limit` and `plot_dry_whip` always draw a new figure" in text
    for name in into_axes + ("plot_trajectory",):
        assert "axes" in inspect.signature(functions[name]).parameters, name
    for name in new_figure:
        assert not {"ax", "axes"} & set(inspect.signature(functions[name]).parameters), name
    others = set(functions) - set(into_axes) - set(new_figure) - {"plot_trajectory"}
    assert len(others) > 20
    for name in others:
        assert "ax" in inspect.signature(functions[name]).parameters, name
