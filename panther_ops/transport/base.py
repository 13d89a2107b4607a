"""The one transport interface: connect, run a command, read a file, start a write session, close.

Commands are argv lists, quoted with :func:`shlex.join` when they reach a shell; secrets
are :class:`Secret` values that show as ``****`` in every printed form.
"""

from __future__ import annotations

import shlex
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

from panther_ops.secret import Secret

if TYPE_CHECKING:
    from docker import DockerClient

    from panther_ops.transport.session import Session


Arg = str | Secret


def quote_command(argv: Sequence[Arg], *, reveal: bool) -> str:
    """Join an argv into one shell-safe string; secrets are masked unless ``reveal``."""
    parts: list[str] = []
    for a in argv:
        if isinstance(a, Secret):
            parts.append(shlex.quote(a.reveal()) if reveal else "'****'")
        else:
            parts.append(shlex.quote(a))
    return " ".join(parts)


@dataclass(frozen=True)
class Command:
    """A command to run on a robot.

    ``argv`` is quoted piece by piece; ``login`` runs it in ``bash -l -c`` as Husarion's
    tools do (so ``docker compose`` sees the robot user's login environment); ``cwd`` changes
    directory first; ``script`` is a fixed shell snippet of ours (never user input) run by
    ``sh -c`` with ``argv`` as its positional parameters.
    """

    argv: tuple[Arg, ...]
    login: bool = False
    cwd: str | None = None
    script: str | None = None

    @classmethod
    def of(cls, *argv: Arg, login: bool = False, cwd: str | None = None) -> Command:
        return cls(tuple(argv), login=login, cwd=cwd)

    @classmethod
    def sh(cls, script: str, *args: Arg, login: bool = False) -> Command:
        return cls(tuple(args), login=login, script=script)

    def render(self, *, reveal: bool) -> str:
        """The exact string a remote shell receives (``reveal=False``: masked for logs)."""
        if self.script is not None:
            inner = quote_command(("sh", "-c", self.script, "sh", *self.argv), reveal=reveal)
        else:
            inner = quote_command(self.argv, reveal=reveal)
        if self.cwd:
            inner = f"cd {shlex.quote(self.cwd)} && {inner}"
        if self.login:
            inner = quote_command(("bash", "-l", "-c", inner), reveal=True)
        return inner

    def __str__(self) -> str:
        return self.render(reveal=False)


@dataclass(frozen=True)
class CommandResult:
    """What a command did: mirrors invoke's Result."""

    command: str
    exit_status: int
    stdout: str
    stderr: str
    duration_s: float = 0.0
    raw_stdout: bytes = b""

    @property
    def ok(self) -> bool:
        return self.exit_status == 0


@dataclass(frozen=True)
class Endpoint:
    """How to reach one robot's Built-in Computer."""

    name: str
    host: str
    port: int | None = None
    user: str | None = None
    identity_files: tuple[str, ...] = ()
    jump: Endpoint | None = None
    connect_timeout: float = 10.0
    command_timeout: float = 120.0
    ssh_config: str | None = None
    known_hosts: tuple[str, ...] = field(default_factory=tuple)


class Transport(Protocol):
    """Everything panther-ops does to a robot goes through one of these.

    Nine members: ``name``, ``connect``, ``run``, ``read_file``, ``exists``, ``home``, ``docker``,
    ``session`` (every write, see :class:`~panther_ops.transport.session.Session`), ``close``.
    """

    name: str

    def connect(self) -> None:
        """Open the connection (raises UnreachableError); every later step reuses it."""
        ...

    def run(
        self, command: Command, *, timeout: float | None = None, stdin: bytes | None = None,
        until: bytes | None = None, answer: Callable[[bytes], bytes] | None = None,
    ) -> CommandResult:
        """Run a command. With ``until`` and ``answer`` the command may ask back: its input stays
        open after ``stdin`` until its output ends with ``until``, then ``answer(output so far)``
        is sent and the input closed; a command that ends without asking is not answered."""
        ...

    def read_file(self, path: str) -> bytes:
        """Read a file; raises FileNotFoundError when it does not exist."""
        ...

    def exists(self, path: str) -> bool: ...

    def session(self, *, timeout: float | None = None, read: str | None = None) -> Session:
        """Start a write session on the robot (:mod:`panther_ops.transport.session`): every write
        and every rollback goes through one, staged, then gone ahead with (the compare with what
        the plan read and the renames, under the robot's write lock) or stopped. ``read``: a
        robot path the session reads first, for the plan (:meth:`Session.read`)."""
        ...

    def home(self) -> str:
        """The robot user's home directory (``/home/husarion`` on a Panther)."""
        ...

    def docker(self, api_version: str | None = None) -> DockerClient | None:
        """A docker SDK client riding this transport, or None when the robot has no engine."""
        ...

    def close(self) -> None: ...
