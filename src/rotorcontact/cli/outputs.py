"""Output files and folders of the subcommands, checked before any computation.

A figure, a NetCDF file or an output folder that cannot be written is bad
input: it is refused at once (`ParameterError`, exit status 2) rather than
after a long computation. Folders that do not exist yet are created at once,
and a note on stderr says so (the Python API refuses a missing folder).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from ..errors import ParameterError

__all__ = ["PLOT_SUFFIXES", "check_output_file", "check_output_folder", "check_plot_path", "note_reuse"]

#: Figure formats, chosen by the file's suffix.
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


def _check_parent(option: str, folder: Path, what: str) -> None:
    """The nearest existing ancestor of ``folder`` must be a writable folder; create the rest, with a note."""
    existing = folder
    while not existing.exists():
        if existing.parent == existing:  # pragma: no cover - the root always exists
            break
        existing = existing.parent
    if not existing.is_dir():
        raise ParameterError(f"{option} = {what!r}: {str(existing)!r} is a file, not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise ParameterError(f"{option} = {what!r}: the folder {str(existing)!r} is not writable")
    if existing != folder:
        folder.mkdir(parents=True, exist_ok=True)
        print(f"note: {option}: created the folder {str(folder)!r}", file=sys.stderr)


def check_output_file(option: str, path: str | os.PathLike, suffixes: tuple[str, ...]) -> Path:
    """Check that the output file ``path`` of ``option`` can be written, before any work is done.

    Parameters
    ----------
    option : str
        The option that names the file (``"--plot"``), for the messages.
    path : str or path
        The file.
    suffixes : tuple of str
        Allowed suffixes, lower case with the dot (``(".nc",)``).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ParameterError
        For an empty name, another suffix, a folder, an existing file that
        cannot be written, or a parent that is a file or cannot be written.
    """
    text = os.fspath(path)
    allowed = f"a file name ending in {', '.join(suffixes)}"
    if not text.strip():
        raise ParameterError(f"{option} = {text!r} is empty; allowed: {allowed}")
    out = Path(text)
    if out.suffix.lower() not in suffixes:
        raise ParameterError(f"{option} = {text!r} has an unsupported suffix; allowed: {allowed}")
    if out.is_dir():
        raise ParameterError(f"{option} = {text!r} is a folder; allowed: {allowed}")
    if out.exists() and not os.access(out, os.W_OK):
        raise ParameterError(f"{option} = {text!r} exists and cannot be written")
    _check_parent(option, out.parent, text)
    if not os.path.lexists(out):
        _probe(option, out, text)
    return out


def _probe(option: str, out: Path, text: str) -> None:
    """Create ``out`` (which does not exist), empty, and remove it again.

    Permissions do not tell everything (a read-only or special file system). The file is created
    exclusively and without following a link, so only what this call created is removed.
    """
    try:
        fd = os.open(out, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o600)
    except FileExistsError:  # made by someone else meanwhile: theirs, left alone
        return
    except OSError as exc:
        raise ParameterError(f"{option} = {text!r} cannot be written ({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(out)


def check_plot_path(path: str | os.PathLike, option: str = "--plot") -> Path:
    """`check_output_file` for a figure (.png, .svg or .pdf)."""
    return check_output_file(option, path, PLOT_SUFFIXES)


def check_output_folder(option: str, path: str | os.PathLike) -> Path:
    """Check that the output folder ``path`` of ``option`` exists and is writable, or can be created.

    Raises
    ------
    ParameterError
        For an empty name, a file in its place, or a folder that cannot be written.
    """
    text = os.fspath(path)
    if not text.strip():
        raise ParameterError(f"{option} = {text!r} is empty; allowed: a folder name")
    folder = Path(text)
    if folder.exists() and not folder.is_dir():
        raise ParameterError(f"{option} = {text!r} is a file; allowed: a folder")
    _check_parent(option, folder, text)
    return folder


def note_reuse(result, chunk_size: int | None) -> None:
    """Say on stderr when a study was read back from its finished file, or resumed with another chunk size.

    Parameters
    ----------
    result : SweepResult or BasinResult
        The result of `rotorcontact.studies.sweep.sweep` or `rotorcontact.studies.basins.basins`.
    chunk_size : int or None
        The chunk size asked for with ``--chunk-size`` (None: the default).
    """
    if result.reused_file:
        print(f"note: {str(result.path)!r} already holds this finished study; it was read back, not computed "
              "again (--no-resume computes it afresh)", file=sys.stderr)
        return
    used = int(result.dataset.attrs["chunk_size"])
    if chunk_size is not None and used != chunk_size:
        print(f"note: resumed with --chunk-size {used}, the chunk size of the interrupted run "
              "(the results do not depend on it)", file=sys.stderr)
