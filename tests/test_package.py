"""The package's top level: lazy public names, and a command line that starts without the heavy libraries."""

from __future__ import annotations

import subprocess
import sys

import pytest

from rotorcontact.cli.main import SUBCOMMANDS

HEAVY = ("numba", "scipy", "matplotlib", "xarray", "dask", "joblib", "pint")


def _modules_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", f"{code}\nimport sys\nprint(' '.join(sys.modules))"],
                         capture_output=True, text=True, check=True).stdout
    return set(out.split())


@pytest.mark.parametrize("code", ["import rotorcontact", "import rotorcontact.cli.main"])
def test_import_loads_none_of_the_heavy_libraries(code):
    loaded = _modules_after(code)
    assert not [m for m in loaded if m.split(".")[0] in HEAVY]


def test_public_names_resolve_to_the_functions_whatever_was_imported_before():
    import rotorcontact as rc
    import rotorcontact.simulation.simulator  # noqa: F401
    from rotorcontact.model.params import Parameters
    from rotorcontact.simulation.simulator import simulate

    assert rc.simulate is simulate and rc.Parameters is Parameters
    assert set(rc.__all__) <= set(dir(rc))
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        rc.nonexistent  # noqa: B018


def test_ctrl_c_while_a_command_is_loaded_ends_in_one_line(monkeypatch, capsys):
    from rotorcontact.cli import main as cli_main

    def interrupted(name, *args):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_main.importlib, "import_module", interrupted)
    assert cli_main.main(["simulate"]) == 130
    err = capsys.readouterr().err
    assert err.strip().splitlines() == ["rotorcontact: interrupted"]


@pytest.mark.parametrize("argv", [[], *([name] for name in SUBCOMMANDS)], ids=["top", *SUBCOMMANDS])
def test_help_loads_none_of_the_heavy_libraries(argv):
    """``rotorcontact --help`` and ``rotorcontact CMD --help`` load only the command named, and it defers
    its computations' libraries to the moment it runs."""
    code = ("import contextlib, io\nfrom rotorcontact.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()) as text:\n"
            f"    try:\n        main({[*argv, '--help']!r})\n    except SystemExit as exc:\n        assert exc.code == 0\n"
            "assert 'usage: rotorcontact' in text.getvalue()\n")
    loaded = _modules_after(code)
    assert not sorted({m.split(".")[0] for m in loaded} & set(HEAVY))


def test_every_command_is_listed_with_its_summary(capsys):
    from rotorcontact.cli.main import SUBCOMMANDS, main

    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    for name, summary in SUBCOMMANDS.items():
        assert name in out and " ".join(summary.split()) in out
