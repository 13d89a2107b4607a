"""Run the real ``panther-ops`` process (or another program) piped or on a pseudo-terminal (the ``pty``
module)."""

from __future__ import annotations

import contextlib
import fcntl
import os
import pty
import re
import select
import signal
import struct
import subprocess
import sys
import tempfile
import termios
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import IO

ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]|\x1b\][^\x07]*\x07")
CLI = [sys.executable, "-c", "from panther_ops.cli.app import run; run()"]



def _drain(fd: int, chunks: list[bytes], wait: float) -> None:
    """Read what is left on ``fd`` until it stays quiet for ``wait`` seconds or ends."""
    while True:
        readable, _, _ = select.select([fd], [], [], wait)
        try:
            data = os.read(fd, 65536) if readable else b""
        except OSError:
            data = b""
        if not data:
            return
        chunks.append(data)

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
        return _pty_run([*CLI, *args], master, slave, piped_out, cwd=cwd,
                        env=_env({"TERM": "xterm-256color", **(env or {})}), timeout=timeout,
                        stdout_pipe=stdout_pipe, stderr_pipe=stderr_pipe, typed=typed)


QUESTION = re.compile(r"\[y/N\]: $")
"""The end of what the terminal shows while a question waits for its answer."""


def shell_on_pty(script: str, *, cols: int, cwd: Path, env: dict[str, str], timeout: float = 120,
                 answers: tuple[str, ...] = (), password: str = "", ctrl_c: Callable[[str], bool] | None = None) -> Run:
    """``bash -c script`` with stdin, stdout and stderr on one pseudo-terminal ``cols`` wide, as
    an operator's shell runs a command line, in exactly the environment ``env``; ``Run.out`` is
    everything the terminal was sent. As a person at that terminal: ``answers`` typed (and Enter)
    one by one when a question (``[y/N]: ``) shows, echoed after it; ``password`` typed once the
    terminal's echo is off, at a password prompt (the command runs in a session of its own, so
    that getpass asks this terminal, never the one this runs from); with ``ctrl_c``, Ctrl-C typed
    once ``ctrl_c(output so far, plain)`` holds (the terminal is then the session's controlling
    one: it sends SIGINT to the command and echoes ``^C``, as an operator's terminal does)."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, cols, 0, 0))
    with tempfile.TemporaryFile() as unused:
        return _pty_run(["bash", "-c", script], master, slave, unused, cwd=cwd, env=env, timeout=timeout,
                        stdout_pipe=False, stderr_pipe=False, typed="", password=password, answers=answers,
                        session=True, ctrl_c=ctrl_c)


def _terminal_of_its_session() -> None:
    """In the child (its own session) before exec: the terminal on stdin becomes the session's
    controlling terminal, SIGINT as an operator's shell starts a command (:func:`_ctrl_c_as_on_a_terminal`)."""
    fcntl.ioctl(0, termios.TIOCSCTTY, 0)
    _ctrl_c_as_on_a_terminal()


def _pty_run(argv: list[str], master: int, slave: int, piped_out: IO[bytes], *, cwd: Path | None,
             env: dict[str, str], timeout: float, stdout_pipe: bool, stderr_pipe: bool, typed: str,
             password: str = "", answers: tuple[str, ...] = (), session: bool = False,
             ctrl_c: Callable[[str], bool] | None = None) -> Run:
    p = subprocess.Popen(argv, cwd=cwd, env=env,
                         stdin=slave, stdout=piped_out if stdout_pipe else slave,
                         stderr=piped_out if stderr_pipe else slave, close_fds=True, start_new_session=session,
                         preexec_fn=_terminal_of_its_session if ctrl_c else None)  # noqa: PLW1509 (two calls)
    os.close(slave)
    if typed:  # held by the terminal until the process reads its input
        os.write(master, typed.encode())
    chunks: list[bytes] = []
    to_type = list(answers)
    quiet_since = time.monotonic()
    while True:
        polling = bool(password or to_type or ctrl_c)  # a person watching the terminal, to type
        ready, _, _ = select.select([master], [], [], 0.05 if polling else timeout)
        if ctrl_c and ctrl_c(plain(b"".join(chunks).decode(errors="replace"))):
            os.write(master, b"\x03")
            ctrl_c = None
        if password and not termios.tcgetattr(master)[3] & termios.ECHO:  # the prompt turned echo off
            os.write(master, f"{password}\n".encode())
            password = ""
        elif to_type and QUESTION.search(plain(b"".join(chunks[-3:]).decode(errors="replace"))):
            os.write(master, f"{to_type.pop(0)}\n".encode())
        if not ready:
            if polling and time.monotonic() - quiet_since < timeout:
                continue
            p.kill()
            raise TimeoutError(f"{' '.join(argv)}: no output for {timeout} s")
        quiet_since = time.monotonic()
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


def _until_ended(args: list[str], timeout: float, source: int, chunks: list[bytes], ready: Callable[[str], bool],
                 act: Callable[[], object], ended: Callable[[], bool]) -> tuple[float | None, float]:
    """Read ``source`` into ``chunks`` until ``ended()``; the first time ``ready(output so far,
    plain)`` holds, ``act()`` (the Ctrl-C). (When it acted or None, when it ended.)"""
    acted: float | None = None
    deadline = time.monotonic() + timeout
    while True:
        if time.monotonic() > deadline:
            raise TimeoutError(f"panther-ops {' '.join(args)}: not over after {timeout} s")
        if acted is None and ready(plain(b"".join(chunks).decode(errors="replace"))):
            act()
            acted = time.monotonic()
        readable, _, _ = select.select([source], [], [], 0.01)
        if readable:
            with contextlib.suppress(OSError):  # the child closed the terminal
                chunks.append(os.read(source, 65536))
        if ended():
            return acted, time.monotonic()


def reading_its_terminal(pid: int) -> bool:
    """Whether process ``pid`` is blocked in ``read(0, ...)`` (``/proc/PID/syscall``, Linux):
    waiting for the operator's answer. A Ctrl-C typed by a person comes then; one sent the
    instant the prompt's text shows can land between Python's last signal check and that
    read, where no program sees it until the read returns."""
    try:
        fields = Path(f"/proc/{pid}/syscall").read_text().split()
    except OSError:
        return False
    return len(fields) > 1 and fields[0] == "0" and int(fields[1], 16) == 0


def _ctrl_c_as_on_a_terminal() -> None:
    """In the child before exec: SIGINT back to its default, as an operator's shell starts a
    command (a CI script's background job inherits it ignored, and Python keeps that)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@dataclass
class Interrupted:
    run: Run
    after_s: float
    """From the SIGINT to the process's end."""


def interrupted(args: list[str], ready: Callable[[str], bool], *, on_terminal: bool = True, cols: int = 120,
                cwd: Path | None = None, env: dict[str, str] | None = None, timeout: float = 30,
                at_question: bool = False) -> Interrupted:
    """Run ``panther-ops`` (on a pseudo-terminal, or with both streams piped), send it SIGINT (a
    Ctrl-C) once ``ready(output so far, plain)`` holds (``at_question``: and the process waits
    for its answer, :func:`reading_its_terminal`), and time how long it takes to end.
    Piped, ``ready`` sees nothing but what stderr showed so far (read as it comes)."""
    if on_terminal:
        master, slave = pty.openpty()
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, cols, 0, 0))
        p = subprocess.Popen([*CLI, *args], cwd=cwd, env=_env({"TERM": "xterm-256color", **(env or {})}),
                             stdin=slave, stdout=slave, stderr=slave, close_fds=True,
                             preexec_fn=_ctrl_c_as_on_a_terminal)  # noqa: PLW1509 (one signal call)
        os.close(slave)
        source, out_pipe = master, None
    else:
        p = subprocess.Popen([*CLI, *args], cwd=cwd, env=_env(env), stdin=subprocess.DEVNULL,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             preexec_fn=_ctrl_c_as_on_a_terminal)  # noqa: PLW1509 (one signal call)
        assert p.stderr is not None and p.stdout is not None
        source, out_pipe = p.stderr.fileno(), p.stdout
    chunks: list[bytes] = []
    sent: float | None = None
    try:
        when = (lambda out: ready(out) and reading_its_terminal(p.pid)) if at_question else ready
        sent, ended = _until_ended(args, timeout, source, chunks, when, lambda: p.send_signal(signal.SIGINT),
                                   lambda: p.poll() is not None)
        _drain(source, chunks, 0.5)  # what is left in the stream
    finally:
        if p.poll() is None:
            p.kill()
        p.wait()
        if on_terminal:
            os.close(source)
    text = b"".join(chunks).decode(errors="replace")
    out = out_pipe.read().decode(errors="replace") if out_pipe is not None else text
    assert sent is not None, f"never ready; it ended (exit {p.returncode}) with: {text}"
    return Interrupted(Run(p.returncode, out, text), ended - sent)


def ctrl_c_typed(args: list[str], ready: Callable[[str], bool], *, cols: int = 100, rows: int = 50,
                 env: dict[str, str] | None = None, timeout: float = 60) -> Interrupted:
    """Run ``panther-ops`` on a pseudo-terminal that is its controlling terminal and, once
    ``ready(output so far, plain)`` holds, type Ctrl-C into it: the terminal sends SIGINT to
    the process and echoes ``^C`` where its cursor is, as an operator's terminal does.
    ``Run.out`` is everything the terminal was sent, escape sequences included."""
    full_env = _env({"TERM": "xterm-256color", **(env or {})})
    pid, master = pty.fork()
    if pid == 0:  # the child: its own session, the terminal its controlling one
        fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))
        _ctrl_c_as_on_a_terminal()
        os.execve(CLI[0], [*CLI, *args], full_env)
    chunks: list[bytes] = []
    typed: float | None = None
    ended: float | None = None
    status = 0

    def over() -> bool:
        nonlocal status
        done, status = os.waitpid(pid, os.WNOHANG)
        return done != 0

    try:
        typed, ended = _until_ended(args, timeout, master, chunks, ready, lambda: os.write(master, b"\x03"), over)
        _drain(master, chunks, 0.2)
    finally:
        if ended is None:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
        os.close(master)
    text = b"".join(chunks).decode(errors="replace")
    assert typed is not None, f"never ready; it ended with: {text}"
    return Interrupted(Run(os.waitstatus_to_exitcode(status), text, text), ended - typed)


def keys_on_pty(argv: list[str], keys: list[tuple[bytes, float]], *, ready: str, timeout: float,
                env: dict[str, str] | None = None, cols: int | None = None) -> tuple[int, str]:
    """Run ``argv`` as the child of a pseudo-terminal (its controlling terminal; ``cols`` wide
    when given), wait up to ``timeout`` seconds for ``ready`` in its output, then type ``keys``
    (each one followed by its pause, reading meanwhile) and wait for it to end: (exit code,
    everything it wrote)."""
    pid, fd = pty.fork()
    if pid == 0:  # pragma: no cover - the child
        if cols is not None:
            fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", 50, cols, 0, 0))
        os.execve(argv[0], argv, os.environ if env is None else env)
    out = b""

    def pump(seconds: float) -> None:
        nonlocal out
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            if select.select([fd], [], [], 0.05)[0]:
                try:
                    out += os.read(fd, 4096)
                except OSError:
                    return

    deadline = time.monotonic() + timeout
    while ready.encode() not in out and time.monotonic() < deadline:
        pump(0.1)
    if ready.encode() not in out:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        os.close(fd)
        raise AssertionError(f"{ready!r} not shown in {timeout} s: {out.decode(errors='replace')}")
    for key, pause in keys:
        os.write(fd, key)
        pump(pause)
    pump(0.5)
    _, status = os.waitpid(pid, 0)
    os.close(fd)
    return os.waitstatus_to_exitcode(status), out.decode(errors="replace")
