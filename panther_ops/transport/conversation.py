"""Talking to a running command over its pipes: the same steps for an SSH channel and a
local process.

A command may ask back: it prints a mark and waits for a line on its input (the write step
waits for the go-ahead after staging). A command may also be kept waiting between two phases
of a panther-ops command: the plan's read of compose.yaml stays open as a session that later
carries the write, so a change costs the robot one session instead of two.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol


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
            if stdin:
                self.pipe.send(stdin)
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

    def take_output(self) -> bytes:
        """The output so far, which then starts afresh (for the next phase of a kept command)."""
        data = bytes(self.out)
        self.out.clear()
        return data
