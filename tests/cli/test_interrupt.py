"""Ctrl-C during a study: the command ends every worker process and exits promptly with
status 130 and one line on stderr, with joblib workers and with a local Dask cluster,
whether the interrupt reaches every process of the command (a terminal) or the parent alone."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from rotorcontact.studies.execution import available_cores

psutil = pytest.importorskip("psutil")

pytestmark = pytest.mark.skipif(not hasattr(os, "killpg"), reason="POSIX process groups")

# far more work than the test waits for: minutes on any machine
STUDY = ["sweep", "--gamma", "0.1", "--param", "omega", "--from", "0.74", "--to", "0.78", "--n", "2000",
         "--transient", "100000", "--chunk-size", "2", "--no-progress"]


def _session(sid: int) -> list:
    """The processes of session ``sid`` (the command and everything it started)."""
    out = []
    for proc in psutil.process_iter():
        try:
            if os.getsid(proc.pid) == sid and proc.status() != psutil.STATUS_ZOMBIE:
                out.append(proc)
        except (ProcessLookupError, PermissionError, psutil.Error):
            pass
    return out


def _start(args: list) -> subprocess.Popen:
    """The command in a session of its own, with Ctrl-C's default action: a shell that runs the tests in the
    background (``pytest &``) has them ignore SIGINT, and a child inherits that."""
    return subprocess.Popen(
        [sys.executable, "-m", "rotorcontact.cli.main", *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def _wait_for(predicate, timeout: float) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.2)
    return False


def _interrupted(proc: subprocess.Popen, ready, interrupt) -> tuple[str, str, float]:
    """Once ``ready()`` holds, ``interrupt()``; the command's output and the seconds it took to end after
    the interrupt. The command is killed if it is still running when this returns."""
    try:
        assert _wait_for(ready, timeout=240) and proc.poll() is None, proc.communicate(timeout=60)
        interrupt()
        sent = time.monotonic()
        stdout, stderr = proc.communicate(timeout=120)
        return stdout, stderr, time.monotonic() - sent
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _check_interrupted(proc: subprocess.Popen, stdout: str, stderr: str) -> None:
    """Status 130, one line on stderr, nothing on stdout."""
    assert proc.returncode == 130, stderr
    lines = [line for line in stderr.splitlines() if line.strip() and not line.startswith("note:")]
    assert lines == ["rotorcontact sweep: interrupted"], stderr
    assert stdout == ""


@pytest.mark.parametrize(
    "execution, whole_group",
    [
        (["--n-jobs", "2"], True),
        (["--n-jobs", "2"], False),
        (["--scheduler", "local", "--n-jobs", "2"], True),
        (["--n-jobs", "1000"], False),
    ],
    ids=["joblib-terminal", "joblib-parent-only", "dask-terminal", "joblib-more-jobs-than-cores"],
)
def test_ctrl_c_ends_every_worker_and_exits_with_one_line(tmp_path, execution, whole_group):
    proc = _start([*STUDY, *execution, "--out", str(tmp_path / "study.nc")])

    def interrupt():
        time.sleep(1.0)
        # at most one worker per core, besides the command and the resource trackers
        workers = [p for p in _session(proc.pid)
                   if p.pid != proc.pid and "resource_tracker" not in " ".join(p.cmdline())]
        assert len(workers) <= min(int(execution[-1]), available_cores()), \
            [p.cmdline() for p in workers]
        if whole_group:
            os.killpg(proc.pid, signal.SIGINT)
        else:
            os.kill(proc.pid, signal.SIGINT)

    # the study runs once its chunk folder exists and its workers are up
    stdout, stderr, _ = _interrupted(
        proc, lambda: (tmp_path / "study.nc.chunks").exists() and len(_session(proc.pid)) >= 3, interrupt
    )
    _check_interrupted(proc, stdout, stderr)
    # no worker outlives the command
    assert _wait_for(lambda: not _session(proc.pid), timeout=60), [p.cmdline() for p in _session(proc.pid)]


def test_ctrl_c_during_a_study_on_this_process_threads_exits_promptly_with_one_line(tmp_path):
    # the threads of this process share out the chunks' lanes (studies.guided): an interrupt ends the
    # command at once, whatever its threads are running
    proc = _start([*STUDY, "--out", str(tmp_path / "study.nc")])
    chunks = tmp_path / "study.nc.chunks"
    stdout, stderr, waited = _interrupted(proc, lambda: chunks.exists() and any(chunks.glob("*.npz")),
                                          lambda: os.killpg(proc.pid, signal.SIGINT))
    _check_interrupted(proc, stdout, stderr)
    # the whole study is about 2e8 impacts: a minute or more on 2 cores
    assert waited < 20.0, waited


def test_a_second_ctrl_c_while_a_local_dask_cluster_shuts_down_changes_nothing(tmp_path):
    # the second interrupt used to cut the cluster's shutdown short: its finalizers then took about 10 s at
    # exit and wrote every worker's end to stderr
    proc = _start([*STUDY, "--scheduler", "local", "--n-jobs", "2", "--out", str(tmp_path / "study.nc")])

    def twice():
        os.killpg(proc.pid, signal.SIGINT)
        time.sleep(0.1)
        os.killpg(proc.pid, signal.SIGINT)

    stdout, stderr, waited = _interrupted(
        proc, lambda: (tmp_path / "study.nc.chunks").exists() and len(_session(proc.pid)) >= 3, twice
    )
    # one line: the cluster was shut down, not left to its finalizers, and no interrupt was lost in Dask's
    # callback on garbage collections (local_cluster turns it off)
    _check_interrupted(proc, stdout, stderr)
    assert waited < 8.0, waited
    assert _wait_for(lambda: not _session(proc.pid), timeout=60), [p.cmdline() for p in _session(proc.pid)]
