"""Run the real ``panther-ops`` process piped or on a pseudo-terminal (the ``pty`` module)."""

from __future__ import annotations

import fcntl
import os
import pty
import re
import select
import struct
import subprocess
import sys
import tempfile
import termios
from dataclasses import dataclass
from pathlib import Path
from typing import IO

ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]|\x1b\][^\x07]*\x07")
CLI = [sys.executable, "-c", "from panther_ops.cli.app import run; run()"]


def plain(text: str) -> str:
    """``text`` without terminal escape sequences and carriage returns."""
    return ANSI.sub("", text).replace("\r", "")


@dataclass
class Run:
    code: int
    out: str
    err: str = ""


def _env(extra: dict[str, str] | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR", "COLUMNS", "LINES")}
    env.update(extra or {})
    return env


def piped(args: list[str], *, cwd: Path | None = None, env: dict[str, str] | None = None,
          timeout: float = 120) -> Run:
    """stdout and stderr pipes (not terminals), stdin closed."""
    p = subprocess.run([*CLI, *args], cwd=cwd, env=_env(env), capture_output=True, text=True,
                       stdin=subprocess.DEVNULL, timeout=timeout, check=False)
    return Run(p.returncode, p.stdout, p.stderr)


def on_pty(args: list[str], *, cols: int = 70, cwd: Path | None = None, env: dict[str, str] | None = None,
           timeout: float = 180, stdout_pipe: bool = False, stderr_pipe: bool = False, typed: str = "") -> Run:
    """stdout and stderr on one pseudo-terminal ``cols`` wide (either one piped instead when
    asked: ``Run.out`` is then what the terminal showed, ``Run.err`` the piped stream); ``typed``:
    what the operator types on it (e.g. ``"n\\n"`` to a question)."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, cols, 0, 0))
    with tempfile.TemporaryFile() as piped_out:
        return _pty_run(args, master, slave, piped_out, cwd=cwd, env=env, timeout=timeout,
                        stdout_pipe=stdout_pipe, stderr_pipe=stderr_pipe, typed=typed)


def _pty_run(args: list[str], master: int, slave: int, piped_out: IO[bytes], *, cwd: Path | None,
             env: dict[str, str] | None, timeout: float, stdout_pipe: bool, stderr_pipe: bool, typed: str) -> Run:
    p = subprocess.Popen([*CLI, *args], cwd=cwd, env=_env({"TERM": "xterm-256color", **(env or {})}),
                         stdin=slave, stdout=piped_out if stdout_pipe else slave,
                         stderr=piped_out if stderr_pipe else slave, close_fds=True)
    os.close(slave)
    if typed:  # held by the terminal until the process reads its input
        os.write(master, typed.encode())
    chunks: list[bytes] = []
    while True:
        ready, _, _ = select.select([master], [], [], timeout)
        if not ready:
            p.kill()
            raise TimeoutError(f"panther-ops {' '.join(args)}: no output for {timeout} s")
        try:
            data = os.read(master, 65536)
        except OSError:  # the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    os.close(master)
    code = p.wait(timeout=timeout)
    piped_out.seek(0)
    return Run(code, b"".join(chunks).decode(errors="replace"), piped_out.read().decode(errors="replace"))
