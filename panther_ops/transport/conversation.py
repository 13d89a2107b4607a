"""Talking to a running command over its pipes: the same steps for an SSH channel and a
local process.

A command may ask back: it prints a mark and waits for a line on its input (the write
session waits for the go-ahead after staging: :mod:`panther_ops.transport.session`).
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol, TypeVar

from panther_ops.transport.base import Command, CommandResult

if TYPE_CHECKING:
    from panther_ops.transport.session import Session

T = TypeVar("T")


class Pipe(Protocol):
    """A started command's ends: stdin, stdout (stderr collected on the side), exit status."""

    def send(self, data: bytes) -> None:
        """Send ``data``; to a command that already ended it is dropped (nobody reads it)."""
        ...

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
        """The command waits for the caller (a session between its steps): its time limit does not
        run meanwhile."""
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

    def take_until(self, until: bytes) -> bytes | None:
        """Read stdout until it ends with ``until`` and take what came before it out of the
        output; None when the command closes stdout first (what it printed stays for :meth:`finish`)."""
        if not self.read_until(until):
            return None
        head = bytes(self.out[:-len(until)])
        del self.out[:]
        return head

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


class Conversing:
    """``run`` and ``session`` of a transport, over its pipes.

    A transport supplies :meth:`_open` (start a command), and may wrap each step with
    :meth:`guard` (turn its failures into panther-ops errors) and check a finished pipe with
    :meth:`_check`; ``_sessions_in_background`` opens a session's command in the background
    (where that costs round trips); :meth:`close_sessions` drops those still open.
    """

    _sessions: set[Session]
    _sessions_in_background = False

    def _open(self, command: Command, timeout: float | None) -> Pipe:
        raise NotImplementedError

    def guard(self, command: Command, timeout: float | None, step: Callable[[], T]) -> T:
        return step()

    def _check(self, command: Command, pipe: Pipe) -> None:
        return None

    def result(self, command: Command, pipe: Pipe, status: int, out: bytes, err: bytes,
               start: float) -> CommandResult:
        self._check(command, pipe)
        return CommandResult(str(command), status, out.decode(errors="replace"), err.decode(errors="replace"),
                             time.monotonic() - start, out)

    def start(self, command: Command, timeout: float | None) -> Conversation:
        return self.guard(command, timeout, lambda: Conversation(self._open(command, timeout)))

    def run(
        self, command: Command, *, timeout: float | None = None, stdin: bytes | None = None,
        until: bytes | None = None, answer: Callable[[bytes], bytes] | None = None,
    ) -> CommandResult:
        start = time.monotonic()
        conv = self.start(command, timeout)
        status, out, err = self.guard(command, timeout, lambda: conv.finish(stdin, until, answer))
        return self.result(command, conv.pipe, status, out, err, start)

    def session(self, *, timeout: float | None = None, read: str | None = None) -> Session:
        from panther_ops.transport.session import Session

        s = Session(self, timeout, background=self._sessions_in_background, read=read)
        self._sessions.add(s)
        return s

    def forget(self, session: Session) -> None:
        """A session that ended (its command finished or was dropped)."""
        self._sessions.discard(session)

    def close_sessions(self) -> None:
        """Drop every session still open: their staged writes are abandoned, nothing renamed."""
        for s in list(self._sessions):
            with contextlib.suppress(Exception):  # a session whose connection is gone is over anyway
                s.close()
