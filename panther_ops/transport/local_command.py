"""A command run on this machine, with a time limit: the simulation's tools (Gazebo's CLI), ``ping``."""

from __future__ import annotations

import shlex
import shutil
import subprocess
import time
from collections.abc import Sequence

from panther_ops.errors import UsageError
from panther_ops.transport.base import CommandResult


def run_local(argv: Sequence[str], *, timeout: float = 30.0) -> CommandResult:
    """Run ``argv`` (no shell); UsageError when its program is not installed here."""
    if shutil.which(argv[0]) is None:
        raise UsageError(f"{argv[0]}: not found on this machine's PATH",
                         hint="run panther-ops where the simulation runs (Gazebo's command-line tool installed)")
    start = time.monotonic()
    try:
        cp = subprocess.run(list(argv), capture_output=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return CommandResult(shlex.join(argv), -1, "", f"no answer in {timeout:g} s", time.monotonic() - start)
    return CommandResult(shlex.join(argv), cp.returncode, cp.stdout.decode(errors="replace"),
                         cp.stderr.decode(errors="replace"), time.monotonic() - start, cp.stdout)


def exit_status_here(argv: Sequence[str], *, timeout: float) -> int | None:
    """Exit status of ``argv`` run here (no shell, output discarded); None when it outlived
    ``timeout``. OSError when its program cannot run (not installed)."""
    try:
        done = subprocess.run(list(argv), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=timeout,
                              check=False)
    except subprocess.TimeoutExpired:
        return None
    return done.returncode
