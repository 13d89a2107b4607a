"""panther-ops' own robot scripts (``transport/scripts*.py``), carried out in Python over a
:class:`~panther_ops.testing.fake_robot.FakeRobot` by the same rules as the shell text.

A running command is a :class:`Proc`: a generator that reads its input as it arrives (a line,
or a count of bytes as ``head -c`` does) and writes its output, so a command can stop half way
and wait, as the write session does between staging and the go-ahead.
"""

from __future__ import annotations

import base64
import hashlib
import io
import posixpath
import tarfile
from collections.abc import Callable, Generator

from panther_ops.secret import Secret
from panther_ops.testing.fake_robot import Call, FakeFile, FakeRobot
from panther_ops.transport import scripts, scripts_apply, scripts_backup
from panther_ops.transport.base import Command

Body = Generator[None, None, int]


class Proc:
    """One command on the fake robot: input fed in, output and exit status out."""

    def __init__(self, body: Callable[[Proc], Body]) -> None:
        self.inbuf = bytearray()
        self.eof = False
        self.out = bytearray()
        self.err = bytearray()
        self.status: int | None = None
        self._body = body(self)
        self._step()

    @property
    def done(self) -> bool:
        return self.status is not None

    def feed(self, data: bytes | None = None, *, close: bool = False) -> None:
        if self.done:
            return
        if data:
            self.inbuf += data
        self.eof = self.eof or close
        self._step()

    def _step(self) -> None:
        try:
            next(self._body)
        except StopIteration as stop:
            self.status = int(stop.value)

    def readline(self) -> Generator[None, None, bytes | None]:
        """``read -r``: a line without its newline; None at the end of input with nothing read."""
        while b"\n" not in self.inbuf and not self.eof:
            yield
        if not self.inbuf:
            return None
        line, _, rest = bytes(self.inbuf).partition(b"\n")
        self.inbuf[:] = rest
        return line

    def read(self, n: int | None = None) -> Generator[None, None, bytes]:
        """``head -c n`` (``None``: all of it): no further than its count."""
        while (n is None or len(self.inbuf) < n) and not self.eof:
            yield
        n = len(self.inbuf) if n is None else min(n, len(self.inbuf))
        data = bytes(self.inbuf[:n])
        del self.inbuf[:n]
        return data

    def write(self, data: bytes | str) -> None:
        self.out += data.encode() if isinstance(data, str) else data

    def error(self, text: str) -> None:
        self.err += text.encode()


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _done(status: int) -> Body:
    """A body that ends at once with ``status`` (its output already written)."""
    return status
    yield  # a generator


class Shell:
    """The scripts a robot knows, bound to one robot."""

    def __init__(self, robot: FakeRobot) -> None:
        self.robot = robot
        self._bodies: dict[str, Callable[[Proc, tuple[str, ...]], Body]] = {
            scripts.READ: self._read, scripts.READ_WITH_HOME: self._read_with_home, scripts.EXISTS: self._exists,
            scripts_apply.APPLY: self._apply,
            scripts_backup.LIST: self._list, scripts_backup.MARK: self._mark,
            scripts_backup.READ_BACKUP: self._read_backup,
        }

    def start(self, command: Command) -> Proc:
        self.robot.calls.append(command)
        args = tuple(a.reveal() if isinstance(a, Secret) else a for a in command.argv)
        body = self._bodies.get(command.script) if command.script is not None else None
        if body is not None:
            return Proc(lambda p: body(p, args))
        return Proc(lambda p: self._scripted(p, command))

    def _scripted(self, p: Proc, command: Command) -> Body:
        stdin = yield from p.read()
        reply = self.robot.scripted(Call(command, stdin))
        p.write(reply.out)
        p.error(reply.stderr)
        return reply.status

    # -- reads --------------------------------------------------------------------------
    def _file(self, path: str) -> FakeFile | None:
        return self.robot.files.get(self.robot.path(path))

    def _read(self, p: Proc, args: tuple[str, ...]) -> Body:
        f = self._file(args[0])
        if f is None:
            p.error(f"no such file: {self.robot.path(args[0])}\n")
            return (yield from _done(scripts.MISSING_EXIT))
        p.write(f.data)
        return (yield from _done(0))

    def _read_with_home(self, p: Proc, args: tuple[str, ...]) -> Body:
        p.write(f"{self.robot.home}\n")
        return (yield from self._read(p, args))

    def _exists(self, p: Proc, args: tuple[str, ...]) -> Body:
        return (yield from _done(0 if self.robot.exists(args[0]) else 1))

    # -- backups ------------------------------------------------------------------------
    def _list(self, p: Proc, args: tuple[str, ...]) -> Body:
        root = self.robot.path(args[0])
        for m in self.robot.under(root):
            rel = m[len(root) + 1:]
            if rel.count("/") != 1 or not rel.endswith("/manifest.json"):
                continue
            status = self.robot.get(posixpath.dirname(m) + "/status")
            p.write((self.robot.get(m) or b"") + b"\n@@status\n" + (status or b"") + b"\n@@@\n")
        return (yield from _done(0))

    def _mark(self, p: Proc, args: tuple[str, ...]) -> Body:
        d = self.robot.path(args[0])
        if not self.robot.is_dir(d):
            p.error(f"sh: 1: cannot create {d}/status: Directory nonexistent\n")
            return (yield from _done(2))
        self.robot.put(f"{d}/status", f"{args[1]}\n")
        return (yield from _done(0))

    def _read_backup(self, p: Proc, args: tuple[str, ...]) -> Body:
        path = f"{self.robot.path(args[0])}/{args[1]}"
        data = self.robot.get(path)
        if data is None:
            p.error(f"cat: {path}: No such file or directory\n")
            return (yield from _done(1))
        p.write(data)
        return (yield from _done(0))

    # -- the write session (scripts_apply) ----------------------------------------------
    def _apply(self, p: Proc, args: tuple[str, ...]) -> Body:
        """scripts_apply.APPLY, step by step (see its text for the rules)."""
        if args:  # the file the plan reads, first
            f = self._file(args[0])
            p.write(f"@@home {0 if f is not None else scripts.MISSING_EXIT} {self.robot.home}\n".encode())
            p.write(base64.encodebytes(f.data) if f is not None else b"")
            p.write(scripts_apply.READ_MARK)
        count = yield from p.readline()
        if count is None:
            return 0
        if not count.isdigit():
            p.error("the write request is not a count\n")
            return 1
        argv: list[str] = []
        for _ in range(int(count)):
            a = yield from p.readline()
            if a is None:
                return 0
            argv.append(a.decode())
        write = _Write(self.robot, tuple(argv))
        upload = yield from p.read(write.size)
        if not write.unpack(upload):
            write.unmake()
            p.error("cannot unpack the upload\n")
            return 1
        write.give_modes()
        problem = write.refused()
        if problem is not None:
            write.drop()
            self.robot.put(f"{write.w}/status", f"refused: {problem}\n")
            p.error(problem + "\n")
            return scripts_apply.REFUSED_EXIT
        p.write(scripts_apply.STAGED_MARK)
        go = yield from p.readline()
        if go == b"stop":
            write.unmake()
            return scripts_apply.ABANDONED_EXIT
        if go != b"go":
            write.drop()
            self.robot.put(f"{write.w}/status",
                           f"abandoned: no go-ahead ({(go or b'').decode() or 'connection closed'})\n")
            return scripts_apply.ABANDONED_EXIT
        if not self.robot.write_lock.acquire(timeout=scripts_apply.LOCK_WAIT_S):
            write.drop()
            p.error(f"another change held the write lock for {scripts_apply.LOCK_WAIT_S} s; nothing written\n")
            return 1
        try:
            return write.check_and_rename(p)
        finally:
            self.robot.write_lock.release()


class _Write:
    """One write session's arguments (see ``scripts_apply.APPLY``) and its steps."""

    def __init__(self, robot: FakeRobot, args: tuple[str, ...]) -> None:
        self.robot = robot
        self.w, self.st, self.size, self.val = args[0], args[1], int(args[2]), args[3]
        self.entries = [args[i:i + 4] for i in range(4, len(args), 4)]
        self.staged = [t for _, _, t, _ in self.entries if t != "-"]

    def drop(self) -> None:
        """Remove the staged files."""
        for t in self.staged:
            self.robot.remove(t)

    def unmake(self) -> None:
        """Remove the staged files and the backup."""
        self.drop()
        for f in list(self.robot.under(self.w)):
            self.robot.remove(f)

    def unpack(self, upload: bytes) -> bool:
        try:
            with tarfile.open(fileobj=io.BytesIO(upload), mode="r:") as tar:
                for m in tar.getmembers():
                    handle = tar.extractfile(m) if m.isfile() else None
                    if handle is not None:
                        with self.robot.tree_lock:
                            self.robot.files["/" + m.name] = FakeFile(handle.read(), m.mode & 0o7777, float(m.mtime))
        except tarfile.TarError:
            return False
        return True

    def give_modes(self) -> None:
        """``chmod --reference``: the staged file and the backup get the target's mode."""
        for i, (path, _want, t, ref) in enumerate(self.entries):
            target = self.robot.files.get(path)
            if ref != "1" or target is None:
                continue
            for name in ([] if t == "-" else [t]) + [f"{self.w}/files/{i}"]:
                if name in self.robot.files:
                    self.robot.files[name].mode = target.mode

    def refused(self) -> str | None:
        """The robot's ``docker compose config`` on the staged compose file (when one is scripted)."""
        if self.val == "-" or self.robot.compose_check is None:
            return None
        return self.robot.compose_check(self.robot.files[self.entries[int(self.val)][2]].data)

    def check_and_rename(self, p: Proc) -> int:
        """Under the write lock: every file still as read, then every rename (one step to any
        other writer); exit 3 and nothing left behind when one changed."""
        robot = self.robot
        lock = f"{self.w.rsplit('/backups/', 1)[0]}/{scripts_apply.LOCK_NAME}"
        if lock not in robot.files:
            robot.put(lock, b"")
        with robot.tree_lock:
            for path, want, _t, _ref in self.entries:
                now = robot.files.get(path)
                if want == "-" and now is not None:
                    p.error(f"{path} appeared on the robot since it was read\n")
                elif want != "-" and (now is None or _sha(now.data) != want):
                    p.error(f"{path} changed on the robot since it was read\n")
                else:
                    continue
                self.unmake()
                return scripts_apply.CHANGED_EXIT
            for path, _want, t, _ref in self.entries:
                if t == "-":
                    robot.files.pop(path, None)
                else:
                    robot.files[path] = robot.files.pop(t)
            if self.st:
                robot.put(f"{self.w}/status", f"{self.st}\n")
        return 0
