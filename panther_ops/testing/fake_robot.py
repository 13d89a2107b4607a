"""The robot behind a :class:`~panther_ops.testing.fake_transport.FakeTransport`: an in-memory
file tree, the robot's write lock, the commands it was asked to run and the answers scripted
for the commands panther-ops' own scripts do not cover (``docker compose``, ``snap``, ...).

Several transports may open one robot (two operators at once): they share its files and its
write lock, as two SSH sessions share a Built-in Computer.
"""

from __future__ import annotations

import posixpath
import threading
import time
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.transport.base import Command


@dataclass
class FakeFile:
    """One regular file of the tree (directories are implied by the files under them)."""

    data: bytes
    mode: int = 0o644
    mtime: float = field(default_factory=time.time)


@dataclass(frozen=True)
class Reply:
    """A scripted command's answer."""

    status: int = 0
    stdout: bytes | str = b""
    stderr: str = ""

    @property
    def out(self) -> bytes:
        return self.stdout.encode() if isinstance(self.stdout, str) else self.stdout


@dataclass(frozen=True)
class Call:
    """What a scripted answer is given: the command and everything sent to its input."""

    command: Command
    stdin: bytes

    @property
    def argv(self) -> tuple[str, ...]:
        return tuple(str(a) for a in self.command.argv)


Answer = Reply | Callable[[Call], Reply]


class UnscriptedCommand(AssertionError):
    """A command the fake robot has no answer for: script one with :meth:`FakeRobot.answer`.

    An AssertionError on purpose: panther-ops turns its own errors (``OpsError``) into
    results, and a test must not mistake a missing script for a robot's failure."""


class FakeRobot:
    """A robot's file system in memory, plus scripted command answers.

    ``files`` maps absolute paths (``~/`` allowed) to contents; ``home`` is the robot user's
    home. ``docker`` is what :meth:`FakeTransport.docker` returns (None: no engine, the
    pipeline reports docker steps skipped, as on the demo fleet). ``compose_check``, when
    given, stands for the robot's ``docker compose config`` on a staged compose file: it
    returns why the file is refused, or None (without it nothing is asked, as on the demo
    fleet).
    """

    def __init__(self, files: Mapping[str, bytes | str] | None = None, *, home: str = "/home/husarion",
                 docker: Any = None, compose_check: Callable[[bytes], str | None] | None = None) -> None:
        self.home = home
        self.files: dict[str, FakeFile] = {}
        self.docker = docker
        self.compose_check = compose_check
        self.reachable = True
        self.write_lock = threading.Lock()
        """The robot's ``flock`` on ``~/.panther-ops/write.lock``."""
        self.tree_lock = threading.RLock()
        """Each file operation is atomic (a rename is)."""
        self.calls: list[Command] = []
        """Every command run on the robot, in order (any connection)."""
        self._answers: list[tuple[tuple[str, ...] | str, Answer]] = []
        for path, data in (files or {}).items():
            self.put(path, data)

    @classmethod
    def from_directory(cls, root: Path, **kw: Any) -> FakeRobot:
        """A robot holding every file under ``root`` (a demo robot's directory: ``root/home/...``)."""
        robot = cls(**kw)
        for p in sorted(root.rglob("*")):
            if p.is_file() and not p.is_symlink():
                st = p.stat()
                robot.files["/" + p.relative_to(root).as_posix()] = FakeFile(p.read_bytes(), st.st_mode & 0o7777,
                                                                              st.st_mtime)
        return robot

    # -- the file tree ------------------------------------------------------------------
    def path(self, path: str) -> str:
        """``path`` as the robot's shell resolves it (``~/`` and relative paths from the home)."""
        if path.startswith("~/"):
            path = f"{self.home}/{path[2:]}"
        elif path == "~":
            path = self.home
        elif not path.startswith("/"):
            path = f"{self.home}/{path}"
        return posixpath.normpath(path)

    def put(self, path: str, data: bytes | str, mode: int = 0o644) -> None:
        """Write a file as another writer would (one rename: no half-written file)."""
        with self.tree_lock:
            self.files[self.path(path)] = FakeFile(data.encode() if isinstance(data, str) else data, mode)

    def get(self, path: str) -> bytes | None:
        with self.tree_lock:
            f = self.files.get(self.path(path))
            return None if f is None else f.data

    def remove(self, path: str) -> None:
        with self.tree_lock:
            self.files.pop(self.path(path), None)

    def is_dir(self, path: str) -> bool:
        prefix = self.path(path).rstrip("/") + "/"
        with self.tree_lock:
            return any(p.startswith(prefix) for p in self.files)

    def exists(self, path: str) -> bool:
        return self.path(path) in self.files or self.is_dir(path)

    def under(self, path: str) -> Iterator[str]:
        """Every file under the directory ``path``, sorted."""
        prefix = self.path(path).rstrip("/") + "/"
        with self.tree_lock:
            names = sorted(p for p in self.files if p.startswith(prefix))
        yield from names

    def tree(self, *, backups: bool = True) -> dict[str, bytes]:
        """Path -> content of every file (``backups=False``: without ``~/.panther-ops``)."""
        with self.tree_lock:
            return {p: f.data for p, f in sorted(self.files.items())
                    if backups or "/.panther-ops/" not in p}

    # -- scripted commands --------------------------------------------------------------
    def answer(self, match: tuple[str, ...] | str, reply: Answer) -> None:
        """Answer commands that match: an argv prefix (a tuple, for ``Command.of``) or a script's
        exact text (a str, for ``Command.sh``). The first match registered answers; ``reply``
        is a :class:`Reply` or a function of the :class:`Call`. A scripted command gets its
        whole input before it answers (it never asks back)."""
        self._answers.append((match, reply))

    def scripted(self, call: Call) -> Reply:
        cmd = call.command
        for match, reply in self._answers:
            hit = (match == cmd.script) if isinstance(match, str) else (
                cmd.script is None and call.argv[: len(match)] == match)
            if hit:
                return reply(call) if callable(reply) else reply
        raise UnscriptedCommand(f"no scripted answer for `{cmd}` (FakeRobot.answer)")
