"""Process and command helpers of the lab: PIDs are always checked against their start time."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time
from collections.abc import Iterable, Sequence

ROOT_PATH = "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin"


class LabError(RuntimeError):
    """The lab could not do what was asked (the message says what and why)."""


def clean_env(**extra: str) -> dict[str, str]:
    """A minimal environment for commands the lab runs (no venv, no pytest variables)."""
    env = {"PATH": ROOT_PATH, "HOME": "/root", "LANG": "C.UTF-8", "TERM": "dumb"}
    env.update(extra)
    return env


def run(
    argv: Sequence[str],
    *,
    check: bool = True,
    input: str | bytes | None = None,
    timeout: float = 60.0,
    env: dict[str, str] | None = None,
    text: bool = True,
) -> subprocess.CompletedProcess:  # type: ignore[type-arg]
    """Run a command, capture its output; raise LabError with stderr when `check` fails."""
    if isinstance(input, str) and not text:
        input = input.encode()
    try:
        cp = subprocess.run(
            list(argv),
            input=input,
            capture_output=True,
            text=text,
            timeout=timeout,
            env=env if env is not None else clean_env(),
            check=False,
        )
    except subprocess.TimeoutExpired as exc:
        raise LabError(f"timed out after {timeout:.0f} s: {' '.join(argv)}") from exc
    if check and cp.returncode != 0:
        err = cp.stderr if isinstance(cp.stderr, str) else cp.stderr.decode(errors="replace")
        raise LabError(f"failed ({cp.returncode}): {' '.join(argv)}\n{err.strip()}")
    return cp


def _stat_fields(pid: int) -> list[str] | None:
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii", errors="replace") as f:
            data = f.read()
    except OSError:
        return None
    # comm may contain spaces and parentheses: split after the last ')'
    rest = data[data.rfind(")") + 2 :].split()
    return rest  # rest[0] = state, rest[1] = ppid, rest[19] = starttime


def start_time(pid: int) -> int | None:
    """Start time of a live (non-zombie) process in clock ticks since boot, else None."""
    f = _stat_fields(pid)
    if f is None or f[0] in ("Z", "X"):
        return None
    return int(f[19])


def alive(pid: int, start: int | None) -> bool:
    """True if `pid` still is the process that had start time `start` (and is not a zombie)."""
    st = start_time(pid)
    return st is not None and (start is None or st == start)


def children(ppid: int, newer: bool = False) -> list[int]:
    """PIDs whose parent is `ppid` (scans /proc; /proc/PID/task/*/children is not available).

    `newer`: look only at PIDs above `ppid` (a child forked just now, unless PIDs wrapped).
    """
    out = []
    for name in os.listdir("/proc"):
        if not name.isdigit() or (newer and int(name) <= ppid):
            continue
        f = _stat_fields(int(name))
        if f is not None and f[1] == str(ppid) and f[0] not in ("Z", "X"):
            out.append(int(name))
    return out


def wait_child(ppid: int, timeout: float = 5.0) -> int:
    """Wait until `ppid` has a child and return its PID (e.g. the program nsenter forked)."""
    deadline = time.monotonic() + timeout
    delay = 0.001
    rounds = 0
    while True:
        rounds += 1
        kids = children(ppid, newer=rounds % 10 != 0)
        if kids:
            return min(kids)
        if start_time(ppid) is None:
            raise LabError(f"process {ppid} ended before starting its child")
        if time.monotonic() > deadline:
            raise LabError(f"process {ppid} started no child within {timeout} s")
        time.sleep(delay)
        delay = min(delay * 2, 0.02)


def signal_recorded(pid: int, start: int | None, sig: int) -> bool:
    """Send `sig` to `pid` only if it still is the recorded process. True if sent."""
    if not alive(pid, start):
        return False
    try:
        os.kill(pid, sig)
    except ProcessLookupError:
        return False
    return True


def reap(pid: int) -> None:
    """Collect `pid` if it is our own child (no-op otherwise)."""
    with contextlib.suppress(ChildProcessError):
        os.waitpid(pid, os.WNOHANG)


def wait_gone(procs: Iterable[tuple[int, int | None]], timeout: float) -> list[tuple[int, int | None]]:
    """Wait until the recorded processes are gone; return those still alive at the deadline."""
    pending = list(procs)
    deadline = time.monotonic() + timeout
    delay = 0.005
    while pending:
        for pid, _ in pending:
            reap(pid)
        pending = [(p, s) for p, s in pending if alive(p, s)]
        if not pending or time.monotonic() > deadline:
            break
        time.sleep(delay)
        delay = min(delay * 2, 0.1)
    return pending


def terminate(procs: Iterable[tuple[int, int | None]], timeout: float = 5.0) -> None:
    """SIGTERM the recorded processes, wait, then SIGKILL what is left."""
    procs = [p for p in procs if signal_recorded(p[0], p[1], signal.SIGTERM)]
    left = wait_gone(procs, timeout)
    for pid, st in left:
        signal_recorded(pid, st, signal.SIGKILL)
    wait_gone(left, 2.0)


def wait_for(predicate, timeout: float, what: str, interval: float = 0.005) -> None:  # type: ignore[no-untyped-def]
    """Poll `predicate()` until true; LabError naming `what` on timeout."""
    deadline = time.monotonic() + timeout
    delay = interval
    while not predicate():
        if time.monotonic() > deadline:
            raise LabError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(delay)
        delay = min(delay * 1.5, 0.05)
