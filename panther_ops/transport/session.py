"""One write on a robot, and its rollback: a :class:`Session` stages, then goes or stops.

A session is one command on the robot (``scripts_apply.APPLY``) that is told the whole write
at once: the backup (manifest and the old contents), every new content staged in a temp file
beside its target, and for each file the sha256 of what the plan read. It stages all of it
and waits. On :meth:`Session.go` it takes the robot's write lock, compares every file with
what the plan read (a file changed since is refused: exit 3, nothing written; this is the
lost-update protection) and renames every staged file into place, all under the lock, so the
compare and the renames are one step to any other writer. On :meth:`Session.stop` it removes
all it made; when its input ends without either (the connection died, :meth:`Session.close`)
it removes the staged files and records the attempt as abandoned. A rollback is the same:
a session whose files are the change's in reverse, compared with what the change wrote.

A session may be made to read one file first (``read=``: the file the plan reads and will
write, compose.yaml): its command prints it before it waits for the write, and
:meth:`Session.read` gives it as a plain read would. The plan's read and its write are then
one command on the robot (one sshd exec session and one shell per robot, as the read alone
would cost), where a separate read would start a second.

Round trips: the command starts when the session is made (a transport may open it in the
background, beside a read); :meth:`Session.stage` only sends; :meth:`Session.go` sends the
go-ahead and reads to the end, since the robot reads it only once everything is staged,
synced and validated. A write staged while the rest of the fleet is planned thus costs one
round trip at the go-ahead.
"""

from __future__ import annotations

import base64
import hashlib
import json
import posixpath
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

from panther_ops.errors import OpsError
from panther_ops.transport import scripts_apply
from panther_ops.transport.base import Command, CommandResult
from panther_ops.transport.conversation import Conversation, Pipe

T = TypeVar("T")


class Carrier(Protocol):
    """What a session needs of its transport (:class:`~panther_ops.transport.conversation.Conversing`)."""

    def start(self, command: Command, timeout: float | None) -> Conversation: ...

    def guard(self, command: Command, timeout: float | None, step: Callable[[], T]) -> T: ...

    def result(self, command: Command, pipe: Pipe, status: int, out: bytes, err: bytes,
               start: float) -> CommandResult: ...

    def forget(self, session: Session) -> None: ...


@dataclass(frozen=True)
class FileWrite:
    """One file of a write: ``before`` as the plan read it (None: it must not exist), ``after``
    what it becomes (None: removed); ``mode`` None keeps the file's own mode (a new file 0644)."""

    path: str
    """Absolute, without a newline or tab."""
    before: bytes | None
    after: bytes | None
    mode: int | None = None
    validate: bool = False
    """Ask the robot's ``docker compose config`` about the staged file first (a compose file)."""


def _sha(data: bytes | None) -> str:
    return "-" if data is None else hashlib.sha256(data).hexdigest()


def stage_input(backup_dir: str, manifest: dict[str, Any], status: str, files: list[FileWrite],
                suffix: str) -> bytes:
    """What :meth:`Session.stage` sends: the request (the arguments of ``APPLY``) and the archive.

    ``backup_dir`` (absolute) receives ``manifest.json`` and each old content as ``files/<i>``;
    ``status`` is recorded there once renamed (empty: later); ``suffix`` names the temp files.
    """
    members = [scripts_apply.Member(d, None, 0o700) for d in (posixpath.dirname(posixpath.dirname(backup_dir)),
                                                               posixpath.dirname(backup_dir), backup_dir,
                                                               f"{backup_dir}/files")]
    members.append(scripts_apply.Member(f"{backup_dir}/manifest.json", json.dumps(manifest, indent=2).encode(),
                                        0o600))
    args: list[str] = []
    validate = "-"
    for i, f in enumerate(files):
        staged = f"{posixpath.dirname(f.path)}/.{posixpath.basename(f.path)}.panther-ops.{suffix}"
        if f.before is not None:
            members.append(scripts_apply.Member(f"{backup_dir}/files/{i}", f.before, f.mode or 0o600))
        keep_mode = f.before is not None and f.mode is None  # mode unknown: chmod --reference on the robot
        if f.after is not None:
            mode = f.mode if f.mode is not None else (0o600 if keep_mode else 0o644)
            members.append(scripts_apply.Member(staged, f.after, mode))
        args += [f.path, _sha(f.before), staged if f.after is not None else "-", "1" if keep_mode else "0"]
        if f.validate and f.after is not None:
            validate = str(i)
    archive = scripts_apply.archive(members)
    return scripts_apply.request([backup_dir, status, str(len(archive)), validate, *args]) + archive


class SessionClosed(OpsError):
    """A write handed to a session that was dropped first (:meth:`Session.close`: the run was
    interrupted, or its connection closed): nothing was staged, nothing written."""


class Session:
    """One write on a robot (see the module's text). Made by ``Transport.session``."""

    def __init__(self, carrier: Carrier, timeout: float | None = None, *, background: bool = False,
                 read: str | None = None) -> None:
        self._carrier = carrier
        self._timeout = timeout
        self.reads = read
        """The robot path this session reads first (:meth:`read`), or None."""
        self.command = Command.sh(scripts_apply.APPLY, *([read] if read is not None else []))
        self._read: CommandResult | None = None
        self._conv: Conversation | None = None
        self._failed: BaseException | None = None
        self._result: CommandResult | None = None
        self._started = time.monotonic()
        self.staged = False
        """:meth:`stage` was called (what it sent may still be under way)."""
        self._opening: threading.Thread | None = None
        if background:  # the channel opens while the caller reads and plans
            self._opening = threading.Thread(target=self._open, daemon=True)
            self._opening.start()
        else:
            self._open()

    def _open(self) -> None:
        try:
            self._conv = self._carrier.start(self.command, self._timeout)
            self._conv.pipe.pause_timeout()  # waiting for the write is not the command taking long
        except BaseException as exc:  # raised where the session is next used
            self._failed = exc

    def _conversation(self) -> Conversation:
        if self._opening is not None:
            self._opening.join()
            self._opening = None
        if self._failed is not None:
            raise self._failed
        assert self._conv is not None
        return self._conv

    def _step(self, step: Callable[[], T]) -> T:
        return self._carrier.guard(self.command, self._timeout, step)

    @property
    def ended(self) -> bool:
        return self._result is not None

    def read(self) -> CommandResult:
        """The file this session was made to read, as a ``run`` of ``scripts.READ_WITH_HOME``
        gives it: $HOME on the first line, then the file's bytes (exit 44: no such file). The
        same result each time; a command that ended before it had read gives its own result."""
        if self._read is not None:
            return self._read
        if self.reads is None:
            raise RuntimeError("this session was made to read nothing")
        if self.ended:
            raise SessionClosed("the write session was closed before its read (the run was interrupted or its "
                                "connection closed)")
        conv = self._conversation()
        conv.pipe.resume_timeout()
        head = self._step(lambda: conv.take_until(scripts_apply.READ_MARK))
        if head is None:  # it ended before the read was done: its status and stderr say why
            self._read = self._finish(None)
            return self._read
        conv.pipe.pause_timeout()
        line, _, body = head[head.rfind(b"@@home "):].partition(b"\n")  # what a login script printed is not ours
        status, _, home = line[len(b"@@home "):].partition(b" ")
        if not status.isdigit():
            raise OpsError(f"the robot's write session did not read {self.reads} as expected: {head[:200]!r}")
        out = home + b"\n" + (base64.b64decode(body) if status == b"0" else b"")
        self._read = CommandResult(str(self.command), int(status), out.decode(errors="replace"), "",
                                   time.monotonic() - self._started, out)
        return self._read

    def stage(self, data: bytes) -> None:
        """Send the write (:func:`stage_input`): the robot stages it and waits for :meth:`go`."""
        if self.staged:
            raise RuntimeError("a session stages one write")
        if self.ended:  # dropped before its write came (Ctrl-C closes the run's connections)
            raise SessionClosed("the write session was closed before the write was staged (the run was "
                                "interrupted or its connection closed): nothing was written")
        conv = self._conversation()
        conv.pipe.resume_timeout()
        self._step(lambda: conv.send(data))
        conv.pipe.pause_timeout()
        self.staged = True

    def wait_staged(self) -> CommandResult | None:
        """Wait until everything is staged (None: the robot waits for the go-ahead), or the
        command's end: its result (nothing was staged)."""
        if self._result is not None:
            return self._result
        conv = self._conversation()
        conv.pipe.resume_timeout()
        if self._step(lambda: conv.read_until(scripts_apply.STAGED_MARK)):
            conv.pipe.pause_timeout()
            return None
        return self._finish(None)

    def go(self) -> CommandResult:
        """The go-ahead: under the robot's write lock every file is compared with what the plan
        read (exit 3, nothing written, when one changed) and every staged file renamed into
        place. A command that already ended (the robot refused the staging) is not told."""
        return self._finish(scripts_apply.GO)

    def stop(self) -> CommandResult:
        """No go-ahead: the robot removes everything the staging made (backup included)."""
        return self._finish(scripts_apply.STOP)

    def close(self) -> None:
        """Drop the session (the input ends): whatever was staged is removed and, with a
        backup made, the attempt recorded as abandoned; nothing is renamed."""
        if self._result is not None:
            return
        try:
            conv = self._conversation()
        except Exception:  # it never opened: nothing to drop
            self._result = CommandResult(str(self.command), -1, "", "", 0.0)
            self._carrier.forget(self)
            return
        self._result = CommandResult(str(self.command), -1, "", "", 0.0)
        self._carrier.forget(self)
        conv.pipe.resume_timeout()
        try:
            conv.pipe.close()
        except Exception:  # a session whose connection is gone is over anyway
            return

    def _finish(self, line: bytes | None) -> CommandResult:
        if self._result is not None:
            return self._result
        conv = self._conversation()
        conv.pipe.resume_timeout()
        try:
            status, out, err = self._step(lambda: conv.finish(line))
        finally:
            self._carrier.forget(self)
        out = out.split(scripts_apply.STAGED_MARK, 1)[-1]
        self._result = self._carrier.result(self.command, conv.pipe, status, out, err, self._started)
        return self._result
