"""A :class:`~panther_ops.transport.base.Transport` for tests: one connection to a
:class:`~panther_ops.testing.fake_robot.FakeRobot`.

It is the real transports' own conversation (:class:`~panther_ops.transport.conversation.Conversing`:
``run`` and ``session`` are theirs) over a fake robot's commands, so it keeps their rules: a
write session stays open on its connection until it goes ahead, stops or is dropped (dropping
it closes its input, as a lost connection does: the staged write is abandoned, nothing
renamed); a write is staged beside its target and renamed into place; the session's check
that every file is still what the plan read and its renames happen under the robot's write
lock, so a file changed since it was read is refused (exit 3, nothing written), by this
connection or any other to the same robot.

A command that would wait for input nobody sends (the real one would hang) raises
:class:`~panther_ops.testing.fake_robot.UnscriptedCommand`, as does a command with no
scripted answer.

Example::

    robot = FakeRobot({"~/compose.yaml": text})
    robot.answer(("docker", "compose"), Reply(0))
    transport = FakeTransport(robot, "panther-01")
    ctx = RobotContext(inventory.robot("panther-01"), transport, inventory)
"""

from __future__ import annotations

from typing import Any

from panther_ops.errors import UnreachableError
from panther_ops.testing.fake_robot import FakeRobot, UnscriptedCommand
from panther_ops.testing.fake_shell import Proc, Shell
from panther_ops.transport.base import Command, Transport
from panther_ops.transport.conversation import Conversing


class _ProcPipe:
    """A fake robot's command as a :class:`~panther_ops.transport.conversation.Pipe`."""

    def __init__(self, command: Command, proc: Proc) -> None:
        self.command = command
        self.proc = proc
        self._read = 0

    def send(self, data: bytes) -> None:
        self.proc.feed(data)  # a command that ended takes nothing more

    def close_input(self) -> None:
        self.proc.feed(close=True)

    def recv(self) -> bytes:
        data = bytes(self.proc.out[self._read:])
        self._read += len(data)
        if not data and not self.proc.done:
            raise UnscriptedCommand(f"`{self.command}` still runs after its input closed" if self.proc.eof
                                    else f"`{self.command}` waits for input nobody sends: it would hang")
        return data

    def stderr(self) -> bytes:
        return bytes(self.proc.err)

    def wait(self) -> int:
        if self.proc.status is None:
            raise UnscriptedCommand(f"`{self.command}` still runs after its input closed")
        return self.proc.status

    def close(self) -> None:
        if self.proc.eof:  # its input closed already (a body that raised is not stepped again)
            return
        try:
            self.proc.feed(close=True)
        except UnscriptedCommand:  # closed on an error: the command's end is not asked for an answer
            return

    def pause_timeout(self) -> None:
        return None  # a fake command takes no time

    def resume_timeout(self) -> None:
        return None


class FakeTransport(Conversing):
    """One connection to a fake robot (see the module's text)."""

    def __init__(self, robot: FakeRobot, name: str = "fake") -> None:
        self.name = name
        self.robot = robot
        self._shell = Shell(robot)
        self._sessions = set()
        self.closed = False

    # -- connection ---------------------------------------------------------------------
    def connect(self) -> None:
        if not self.robot.reachable:
            raise UnreachableError(self.name, "the fake robot is unreachable (FakeRobot.reachable)")

    def close(self) -> None:
        self.close_sessions()
        self.closed = True

    def home(self) -> str:
        return self.robot.home

    def docker(self, api_version: str | None = None) -> Any:
        return self.robot.docker

    # -- commands (run, session: Conversing) ---------------------------------------------
    def _open(self, command: Command, timeout: float | None) -> _ProcPipe:
        return _ProcPipe(command, self._shell.start(command))

    # -- files --------------------------------------------------------------------------
    def read_file(self, path: str) -> bytes:
        data = self.robot.get(path)
        if data is None:
            raise FileNotFoundError(path)
        return data

    def exists(self, path: str) -> bool:
        return self.robot.exists(path)


def _is_a_transport(t: FakeTransport) -> Transport:
    """mypy holds that a FakeTransport is a Transport (every member, every signature)."""
    return t
