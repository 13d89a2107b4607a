"""Local transport: a directory stands in for a robot's file system (the demo fleet).

Paths on the "robot" map under the directory (``/home/husarion/compose.yaml`` is
``<root>/home/husarion/compose.yaml``); commands run on this machine with
``PANTHER_OPS_ROOT`` set to the directory, so the shared scripts resolve files inside it.
A demo robot has no docker engine: :meth:`docker` returns None and docker steps are
reported ``skipped``.
"""

from __future__ import annotations

import contextlib
import os
import queue
import signal
import subprocess
import threading
from pathlib import Path
from typing import TYPE_CHECKING

from panther_ops.errors import TransportError, UnreachableError
from panther_ops.transport.base import Command
from panther_ops.transport.conversation import Conversing, Pipe

if TYPE_CHECKING:
    from docker import DockerClient


class LocalTransport(Conversing):
    """A robot that is a directory on this machine."""

    def __init__(self, name: str, root: Path, user: str = "husarion", home: str | None = None) -> None:
        self.name = name
        self.root = root
        self.user = user
        self._home = home
        """Another home than ``/home/<user>`` (a local file's directory: its backups go there)."""
        self._sessions = set()

    def connect(self) -> None:
        if self._home is not None:
            if not (self.root / self._home.lstrip("/")).is_dir():
                raise UnreachableError(self.name, f"directory {self._home} does not exist")
            return
        if not (self.root / "home" / self.user).is_dir():
            raise UnreachableError(
                self.name,
                f"demo robot directory {self.root} does not exist",
                hint="create the demo fleet with `panther-ops demo init`",
            )

    def close(self) -> None:
        self.close_sessions()

    def home(self) -> str:
        return self._home if self._home is not None else f"/home/{self.user}"

    def local_path(self, path: str) -> Path:
        """Where a robot path lives in the stand-in directory."""
        if path.startswith("~/"):
            path = f"{self.home()}/{path[2:]}"
        if not path.startswith("/"):
            path = f"{self.home()}/{path}"
        resolved = (self.root / path.lstrip("/")).resolve()
        if self.root.resolve() not in resolved.parents and resolved != self.root.resolve():
            raise TransportError(self.name, f"path {path} leaves the demo robot's directory")
        return resolved

    def _open(self, command: Command, timeout: float | None) -> _ProcessPipe:
        env = {**os.environ, "PANTHER_OPS_ROOT": str(self.root), "HOME": self.home()}
        return _ProcessPipe(["sh", "-c", command.render(reveal=True)], env, self.root, timeout or 120)

    def _check(self, command: Command, pipe: Pipe) -> None:
        if isinstance(pipe, _ProcessPipe) and pipe.expired:
            raise TransportError(self.name, f"`{command}` timed out")

    def read_file(self, path: str) -> bytes:
        p = self.local_path(path)
        if not p.is_file():
            raise FileNotFoundError(path)
        return p.read_bytes()

    def exists(self, path: str) -> bool:
        return self.local_path(path).exists()

    def docker(self, api_version: str | None = None) -> DockerClient | None:
        return None


class _ProcessPipe:
    """A local command as a :class:`Pipe`, in its own process group.

    Input is written by a thread (a command that echoes a large input while it reads it
    cannot block us); the whole group is killed when a phase outlives its timeout (the timer
    runs only while someone waits for the command, not while a session waits for its caller).
    """

    def __init__(self, argv: list[str], env: dict[str, str], cwd: Path, timeout: float) -> None:
        self.proc = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, env=env, cwd=cwd, start_new_session=True)
        self.err = bytearray()
        self._drain = threading.Thread(target=self._read_stderr, name="local command stderr", daemon=True)
        self._drain.start()
        self._writes: queue.SimpleQueue[bytes | None] = queue.SimpleQueue()
        self._writer = threading.Thread(target=self._write_stdin, name="local command stdin", daemon=True)
        self._writer.start()
        self.timeout = timeout
        self._timer: threading.Timer | None = None
        self.expired = False
        self.resume_timeout()

    def resume_timeout(self) -> None:
        """(Re)start the time limit."""
        self.pause_timeout()
        self._timer = threading.Timer(self.timeout, self._expire)
        self._timer.daemon = True
        self._timer.start()

    def pause_timeout(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None

    def _read_stderr(self) -> None:
        assert self.proc.stderr is not None
        while chunk := os.read(self.proc.stderr.fileno(), 65536):
            self.err += chunk

    def _write_stdin(self) -> None:
        assert self.proc.stdin is not None
        with contextlib.suppress(OSError):  # the command went away: what it did not read is dropped
            while (data := self._writes.get()) is not None:
                self.proc.stdin.write(data)
                self.proc.stdin.flush()
        with contextlib.suppress(OSError):
            self.proc.stdin.close()

    def _expire(self) -> None:
        self.expired = True
        self.kill()

    def kill(self) -> None:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(self.proc.pid, signal.SIGKILL)

    def send(self, data: bytes) -> None:
        self._writes.put(data)

    def close_input(self) -> None:
        self._writes.put(None)

    def recv(self) -> bytes:
        assert self.proc.stdout is not None
        return os.read(self.proc.stdout.fileno(), 65536)

    def stderr(self) -> bytes:
        self._drain.join()
        return bytes(self.err)

    def wait(self) -> int:
        return self.proc.wait()

    def close(self) -> None:
        self.pause_timeout()
        if self.proc.poll() is None:  # closed before its end (an error on our side): its input ends,
            self.close_input()        # so it can clean up (APPLY drops its staged files); then it is killed
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.kill()
                self.proc.wait()
        self._writer.join(timeout=5)
        self._drain.join(timeout=5)  # its end of stderr is read to the end before the fd is closed (and reused)
        assert self.proc.stdout is not None and self.proc.stderr is not None
        self.proc.stdout.close()
        self.proc.stderr.close()
