"""A :class:`~panther_ops.transport.base.Transport` for tests: one connection to a
:class:`~panther_ops.testing.fake_robot.FakeRobot`.

It keeps the real transport's rules: a command kept waiting (``run_kept``) stays open on its
connection until it is advanced, resumed or dropped (dropping it closes its input, as a lost
connection does: a staged write is abandoned, nothing renamed); a write is staged beside its
target and renamed into place; the write session's check that every file is still what the
plan read and its renames happen under the robot's write lock, so a file changed since it was
read is refused (exit 3, nothing written), by this connection or any other to the same robot.

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

import os
import posixpath
import secrets
import time
from collections.abc import Callable
from typing import Any

from panther_ops.errors import TransportError, UnreachableError
from panther_ops.testing.fake_robot import FakeFile, FakeRobot, UnscriptedCommand
from panther_ops.testing.fake_shell import Proc, Shell
from panther_ops.transport.base import Command, CommandResult, Transport


class FakeTransport:
    """One connection to a fake robot (see the module's text)."""

    def __init__(self, robot: FakeRobot, name: str = "fake") -> None:
        self.name = name
        self.robot = robot
        self._shell = Shell(robot)
        self._kept: dict[str, tuple[Proc, Command]] = {}
        self.closed = False

    # -- connection ---------------------------------------------------------------------
    def connect(self) -> None:
        if not self.robot.reachable:
            raise UnreachableError(self.name, "the fake robot is unreachable (FakeRobot.reachable)")

    def close(self) -> None:
        for key in list(self._kept):
            self.drop_kept(key)
        self.closed = True

    def home(self) -> str:
        return self.robot.home

    def docker(self, api_version: str | None = None) -> Any:
        return self.robot.docker

    # -- commands -----------------------------------------------------------------------
    def _result(self, command: Command, proc: Proc, start: float, *, out: bytes | None = None,
                status: int | None = None) -> CommandResult:
        data = bytes(proc.out) if out is None else out
        code = proc.status if status is None else status
        assert code is not None
        return CommandResult(str(command), code, data.decode(errors="replace"), proc.err.decode(errors="replace"),
                             time.monotonic() - start, data)

    def _finish(self, command: Command, proc: Proc, start: float, until: bytes | None,
                answer: Callable[[bytes], bytes] | None) -> CommandResult:
        if until is not None and answer is not None and not proc.done and proc.out.endswith(until):
            proc.feed(answer(bytes(proc.out)))
        proc.feed(close=True)
        if not proc.done:
            raise UnscriptedCommand(f"`{command}` still runs after its input closed")
        return self._result(command, proc, start)

    def run(self, command: Command, *, timeout: float | None = None, stdin: bytes | None = None,
            until: bytes | None = None, answer: Callable[[bytes], bytes] | None = None) -> CommandResult:
        start = time.monotonic()
        proc = self._shell.start(command)
        proc.feed(stdin)
        return self._finish(command, proc, start, until, answer)

    def _keep(self, key: str, command: Command, proc: Proc, until: bytes, start: float) -> CommandResult:
        if proc.done:
            return self._result(command, proc, start)
        if not proc.out.endswith(until):
            raise UnscriptedCommand(f"`{command}` waits for input without printing {until!r}: it would hang")
        out = bytes(proc.out[: -len(until)])
        proc.out.clear()
        self._kept[key] = (proc, command)
        return self._result(command, proc, start, out=out, status=0)

    def run_kept(self, command: Command, until: bytes, key: str, *, timeout: float | None = None,
                 stdin: bytes | None = None) -> CommandResult:
        start = time.monotonic()
        proc = self._shell.start(command)
        self.drop_kept(key)
        proc.feed(stdin)
        return self._keep(key, command, proc, until, start)

    def advance(self, key: str, stdin: bytes, until: bytes) -> CommandResult | None:
        kept = self._kept.pop(key, None)
        if kept is None:
            return None
        proc, command = kept
        start = time.monotonic()
        proc.feed(stdin)
        return self._keep(key, command, proc, until, start)

    def kept(self, key: str) -> bool:
        return key in self._kept

    def resume(self, key: str, stdin: bytes, *, until: bytes | None = None,
               answer: Callable[[bytes], bytes] | None = None) -> CommandResult | None:
        kept = self._kept.pop(key, None)
        if kept is None:
            return None
        proc, command = kept
        start = time.monotonic()
        proc.feed(stdin)
        return self._finish(command, proc, start, until, answer)

    def drop_kept(self, key: str) -> None:
        kept = self._kept.pop(key, None)
        if kept is not None:
            kept[0].feed(close=True)

    # -- files --------------------------------------------------------------------------
    def read_file(self, path: str) -> bytes:
        data = self.robot.get(path)
        if data is None:
            raise FileNotFoundError(path)
        return data

    def exists(self, path: str) -> bool:
        return self.robot.exists(path)

    def stage_file(self, path: str, data: bytes, *, mode: int | None = None) -> str:
        target = self.robot.path(path)
        staged = f"{posixpath.dirname(target)}/.{posixpath.basename(target)}.panther-ops.{os.getpid()}." \
                 f"{secrets.token_hex(4)}"
        with self.robot.tree_lock:
            old = self.robot.files.get(target)
            keep = mode if mode is not None else (old.mode if old is not None else 0o644)
            self.robot.files[staged] = FakeFile(data, keep)
        return staged

    def commit_staged(self, staged: str, path: str) -> None:
        with self.robot.tree_lock:
            f = self.robot.files.pop(staged, None)
            if f is None:
                raise TransportError(self.name, f"cannot rename into {path}: {staged} does not exist")
            self.robot.files[self.robot.path(path)] = f

    def write_file_atomic(self, path: str, data: bytes, *, mode: int | None = None) -> None:
        self.commit_staged(self.stage_file(path, data, mode=mode), path)


def _is_a_transport(t: FakeTransport) -> Transport:
    """mypy holds that a FakeTransport is a Transport (every member, every signature)."""
    return t
