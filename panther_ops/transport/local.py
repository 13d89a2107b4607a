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
import subprocess
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from panther_ops.errors import TransportError, UnreachableError
from panther_ops.transport.base import Command, CommandResult

if TYPE_CHECKING:
    from docker import DockerClient


class LocalTransport:
    """A robot that is a directory on this machine."""

    def __init__(self, name: str, root: Path, user: str = "husarion") -> None:
        self.name = name
        self.root = root
        self.user = user

    def connect(self) -> None:
        if not (self.root / "home" / self.user).is_dir():
            raise UnreachableError(
                self.name,
                f"demo robot directory {self.root} does not exist",
                hint="create the demo fleet with `panther-ops demo init`",
            )

    def close(self) -> None:
        return None

    def home(self) -> str:
        return f"/home/{self.user}"

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

    def run(
        self, command: Command, *, timeout: float | None = None, stdin: bytes | None = None,
        until: bytes | None = None, answer: Callable[[bytes], bytes] | None = None,
    ) -> CommandResult:
        text = command.render(reveal=True)
        env = {**os.environ, "PANTHER_OPS_ROOT": str(self.root), "HOME": self.home()}
        start = time.monotonic()
        limit = timeout or 120
        if until is not None and answer is not None:
            status, out, err = _converse(["sh", "-c", text], env, self.root, stdin or b"", until, answer, limit)
            if status is None:
                raise TransportError(self.name, f"`{command}` timed out")
        else:
            try:
                proc = subprocess.run(
                    ["sh", "-c", text], input=stdin if stdin is not None else b"", capture_output=True,
                    timeout=limit, env=env, cwd=self.root, check=False,
                )
            except subprocess.TimeoutExpired:
                raise TransportError(self.name, f"`{command}` timed out") from None
            status, out, err = proc.returncode, proc.stdout, proc.stderr
        return CommandResult(
            str(command), status, out.decode(errors="replace"), err.decode(errors="replace"),
            time.monotonic() - start, out,
        )

    def read_file(self, path: str) -> bytes:
        p = self.local_path(path)
        if not p.is_file():
            raise FileNotFoundError(path)
        return p.read_bytes()

    def exists(self, path: str) -> bool:
        return self.local_path(path).exists()

    def stage_file(self, path: str, data: bytes, *, mode: int | None = None) -> str:
        target = self.local_path(path)
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.panther-ops.", dir=target.parent)
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        if mode is not None:
            os.chmod(tmp, mode)
        elif target.exists():
            os.chmod(tmp, target.stat().st_mode & 0o7777)
        else:
            os.chmod(tmp, 0o644)
        return tmp

    def commit_staged(self, staged: str, path: str) -> None:
        os.replace(staged, self.local_path(path))

    def write_file_atomic(self, path: str, data: bytes, *, mode: int | None = None) -> None:
        self.commit_staged(self.stage_file(path, data, mode=mode), path)

    def docker(self, api_version: str | None = None) -> DockerClient | None:
        return None


def _converse(argv: list[str], env: dict[str, str], cwd: Path, stdin: bytes, until: bytes,
              answer: Callable[[bytes], bytes], timeout: float) -> tuple[int | None, bytes, bytes]:
    """Run a local command that may ask back (see ``Transport.run``); status None: timed out."""
    proc = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=env, cwd=cwd)
    assert proc.stdin is not None and proc.stdout is not None and proc.stderr is not None
    err = bytearray()
    drain = threading.Thread(target=lambda: err.extend(proc.stderr.read() if proc.stderr else b""), daemon=True)
    drain.start()
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    out = bytearray()
    try:
        try:
            proc.stdin.write(stdin)
            proc.stdin.flush()
        except BrokenPipeError:
            pass
        asking = True
        while chunk := os.read(proc.stdout.fileno(), 65536):
            out += chunk
            if asking and out.endswith(until):
                asking = False
                try:
                    proc.stdin.write(answer(bytes(out)))
                    proc.stdin.close()
                except BrokenPipeError:
                    pass
        if asking:
            with contextlib.suppress(BrokenPipeError):
                proc.stdin.close()
        status = proc.wait()
    finally:
        expired = not timer.is_alive()
        timer.cancel()
    drain.join()
    return (None if expired else status), bytes(out), bytes(err)
