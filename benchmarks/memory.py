"""Peak memory of a benchmark's process, printed at its end (imported by the study benchmarks)."""

from __future__ import annotations

import resource
import sys


def peak_mib() -> float:
    """Largest resident set of this process so far, MiB (getrusage: KiB on Linux, bytes on macOS)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / (1024.0 * 1024.0) if sys.platform == "darwin" else peak / 1024.0


def print_peak() -> None:
    print(f"peak memory of this process: {peak_mib():.0f} MiB (workers' own not included)")
