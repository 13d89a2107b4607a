"""Talking to a running command over its pipes: the same steps for an SSH channel and a
local process.

A command may ask back: it prints a mark and waits for a line on its input (the write step
waits for the go-ahead after staging). A command may also be kept waiting between two phases
of a panther-ops command: the plan's read of compose.yaml stays open as a session that later
carries the write, so a change costs the robot one session instead of two.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from typing import Protocol, TypeVar

from panther_ops.transport.base import Command, CommandResult

T = TypeVar("T")


class Pipe(Protocol):
    """A started command's ends: stdin, stdout (stderr collected on the side), exit status."""

    def send(self, data: bytes) -> None: ...

    def close_input(self) -> None: ...

    def recv(self) -> bytes:
        """The next stdout bytes; ``b""`` at the end."""
        ...

    def stderr(self) -> bytes:
        """Stderr so far (drained from the command as stdout is read)."""
        ...

    def wait(self) -> int:
        """The exit status (-1: the command went away without one)."""
        ...

    def close(self) -> None:
        """Release the pipe; a command still running is ended (its input closed, or killed)."""
        ...

    def pause_timeout(self) -> None:
        """The command is kept waiting for a later phase: its time limit does not run meanwhile."""
        ...

    def resume_timeout(self) -> None: ...


class Conversation:
    """One started command; output is read up to a mark, the rest of its life by :meth:`finish`."""

    def __init__(self, pipe: Pipe) -> None:
        self.pipe = pipe
        self.out = bytearray()

    def read_until(self, until: bytes) -> bool:
        """Read stdout until it ends with ``until`` (True) or the command closes it (False)."""
        while not self.out.endswith(until):
            data = self.pipe.recv()
            if not data:
                return False
            self.out += data
        return True

    def finish(self, stdin: bytes | None = None, until: bytes | None = None,
               answer: Callable[[bytes], bytes] | None = None) -> tuple[int, bytes, bytes]:
        """Send ``stdin``; if the output then ends with ``until``, send ``answer(output)``;
        close the input and read to the end. Returns (status, stdout, stderr) of this part."""
        try:
            self.send(stdin)
            if until is not None and answer is not None and self.read_until(until):
                self.pipe.send(answer(bytes(self.out)))
            self.pipe.close_input()
            while data := self.pipe.recv():
                self.out += data
            status = self.pipe.wait()
            err = self.pipe.stderr()
        finally:
            self.pipe.close()  # on an error (an answer that raised, a lost connection) this ends the command
        return status, bytes(self.out), err

    def send(self, data: bytes | None) -> None:
        """Send ``data`` (if any) to the command's input."""
        if data:
            self.pipe.send(data)

    def ask(self, data: bytes | None, until: bytes) -> bool:
        """Send ``data``, then read until the output ends with ``until`` (see :meth:`read_until`)."""
        self.send(data)
        return self.read_until(until)

    def take_output(self) -> bytes:
        """The output so far, which then starts afresh (for the next phase of a kept command)."""
        data = bytes(self.out)
        self.out.clear()
        return data


class Conversing:
    """``run``, ``run_kept``, ``resume`` and ``drop_kept`` of a transport, over its pipes.

    A transport supplies :meth:`_open` (start a command), and may wrap each step with
    :meth:`_guard` (turn its failures into panther-ops errors) and check a finished pipe with
    :meth:`_check`.
    """

    _kept: dict[str, tuple[Conversation, Command, float | None]]

    def _open(self, command: Command, timeout: float | None) -> Pipe:
        raise NotImplementedError

    def _guard(self, command: Command, timeout: float | None, step: Callable[[], T]) -> T:
        return step()

    def _check(self, command: Command, pipe: Pipe) -> None:
        return None

    def _result(self, command: Command, pipe: Pipe, status: int, out: bytes, err: bytes,
                start: float) -> CommandResult:
        self._check(command, pipe)
        return CommandResult(str(command), status, out.decode(errors="replace"), err.decode(errors="replace"),
                             time.monotonic() - start, out)

    def _start(self, command: Command, timeout: float | None) -> Conversation:
        return self._guard(command, timeout, lambda: Conversation(self._open(command, timeout)))

    def run(
        self, command: Command, *, timeout: float | None = None, stdin: bytes | None = None,
        until: bytes | None = None, answer: Callable[[bytes], bytes] | None = None,
    ) -> CommandResult:
        start = time.monotonic()
        conv = self._start(command, timeout)
        status, out, err = self._guard(command, timeout, lambda: conv.finish(stdin, until, answer))
        return self._result(command, conv.pipe, status, out, err, start)

    def run_kept(self, command: Command, until: bytes, key: str, *, timeout: float | None = None,
                 stdin: bytes | None = None) -> CommandResult:
        start = time.monotonic()
        conv = self._start(command, timeout)
        self.drop_kept(key)
        return self._keep(key, conv, command, timeout, stdin, until, start)

    def advance(self, key: str, stdin: bytes, until: bytes) -> CommandResult | None:
        kept = self._kept.pop(key, None)
        if kept is None:
            return None
        conv, command, timeout = kept
        conv.pipe.resume_timeout()
        return self._keep(key, conv, command, timeout, stdin, until, time.monotonic())

    def _keep(self, key: str, conv: Conversation, command: Command, timeout: float | None, stdin: bytes | None,
              until: bytes, start: float) -> CommandResult:
        """Send ``stdin``, read to ``until`` and keep the command under ``key``; or finish it."""
        try:
            asked = self._guard(command, timeout, lambda: conv.ask(stdin, until))
        except BaseException:
            conv.pipe.close()
            raise
        if not asked:
            status, out, err = self._guard(command, timeout, conv.finish)
            return self._result(command, conv.pipe, status, out, err, start)
        conv.pipe.pause_timeout()  # waiting for the operator is not the command taking long
        self._kept[key] = (conv, command, timeout)
        return self._result(command, conv.pipe, 0, conv.take_output()[: -len(until)], b"", start)

    def kept(self, key: str) -> bool:
        return key in self._kept

    def resume(self, key: str, stdin: bytes, *, until: bytes | None = None,
               answer: Callable[[bytes], bytes] | None = None) -> CommandResult | None:
        kept = self._kept.pop(key, None)
        if kept is None:
            return None
        conv, command, timeout = kept
        conv.pipe.resume_timeout()
        start = time.monotonic()
        status, out, err = self._guard(command, timeout, lambda: conv.finish(stdin, until, answer))
        return self._result(command, conv.pipe, status, out, err, start)

    def drop_kept(self, key: str) -> None:
        kept = self._kept.pop(key, None)
        if kept is not None:
            kept[0].pipe.resume_timeout()
            with contextlib.suppress(Exception):  # a kept command whose connection is gone is over anyway
                kept[0].pipe.close()  # its input closes: the command ends on its own

    def drop_all_kept(self) -> None:
        for key in list(self._kept):
            self.drop_kept(key)
