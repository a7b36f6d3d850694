"""Running the command line in tests: in this process (`cli.run`, `cli.json`) or as the installed
program (`cli.exe`), with JSON read strictly (a NaN or an infinity fails the test)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from rotorcontact.cli.main import main

#: The installed ``rotorcontact`` program of this environment.
EXE = Path(sys.executable).with_name("rotorcontact")


def strict_json(text: str):
    """``json.loads`` that refuses the non-standard constants NaN, Infinity and -Infinity."""

    def refuse(constant):
        raise AssertionError(f"non-finite JSON constant {constant}")

    return json.loads(text, parse_constant=refuse)


class CommandLine:
    """The command line, run in this process with its output captured, or as a program."""

    exe_path = EXE
    loads = staticmethod(strict_json)

    def __init__(self, capsys):
        self.capsys = capsys

    def run(self, *argv: str) -> tuple[int, str, str]:
        """(exit status, stdout, stderr) of ``rotorcontact argv`` in this process (argparse exits included)."""
        self.capsys.readouterr()
        try:
            code = main([str(a) for a in argv])
        except SystemExit as exc:
            code = exc.code
        out, err = self.capsys.readouterr()
        return int(code or 0), out, err

    def json(self, *argv: str):
        """The ``--json`` output of a command that must succeed, read strictly."""
        code, out, err = self.run(*argv, "--json")
        assert code == 0, err
        return strict_json(out)

    @staticmethod
    def exe(*argv: str, cwd=None, timeout: float = 120) -> tuple[int, str, str]:
        """(exit status, stdout, stderr) of the installed program."""
        assert EXE.exists(), EXE
        proc = subprocess.run([str(EXE), *map(str, argv)], capture_output=True, text=True, timeout=timeout,
                              cwd=cwd)
        return proc.returncode, proc.stdout, proc.stderr

    @staticmethod
    def exe_json(*argv: str, timeout: float = 300):
        """The ``--json`` output of the installed program for a command that must succeed, read strictly."""
        code, out, err = CommandLine.exe(*argv, "--json", timeout=timeout)
        assert code == 0, err
        return strict_json(out)


@pytest.fixture
def cli(capsys) -> CommandLine:
    """The command line (see `CommandLine`)."""
    return CommandLine(capsys)


@pytest.fixture(scope="session")
def program() -> CommandLine:
    """The command line for fixtures wider than one test: only the installed program (`CommandLine.exe`,
    `CommandLine.exe_json`), since output is captured per test."""
    return CommandLine(None)
