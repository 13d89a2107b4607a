"""The blocking parts of a shutdown, each run in a worker so no step ever waits for them.

* `SubprocessPinger`: ``ping -c 1 -w 1 <ip>`` (as the C++ node does).
* `ParamikoShutdown`: SSH with public keys and strict host keys from a known_hosts file
  (`paramiko.RejectPolicy`: an unknown host key fails, it is never added).
* `openssh.OpenSshShutdown`: the same with the OpenSSH client, where paramiko is not
  importable (the robots' driver images); `ssh_backend` chooses.
* `HttpShutdown`: ``GET /shutdown?ts=<unix>&sig=<hex HMAC-SHA256(secret, "/shutdown|<ts>")>``
  to the husarion-shutdown service (2.2.1+); success needs HTTP 200.
* `SubprocessRunner`: a local command (``ExecuteCommand``).

`ThreadDispatcher` runs them in a small thread pool; `InlineDispatcher` runs them at once
(simulation and tests with fake backends, where nothing blocks).
"""

from __future__ import annotations

import hashlib
import hmac
import http.client
import shlex
import subprocess
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, TypeVar

from panther_ops.manager.shutdown_executor.hosts import Method, ShutdownHost

T = TypeVar("T")


@dataclass(frozen=True)
class CommandOutcome:
    """What a shutdown request or a command gave."""

    ok: bool
    output: str = ""
    error: str = ""

    @classmethod
    def of_ssh(cls, status: int | None, output: str = "", error: str = "") -> CommandOutcome:
        """A shutdown command run over SSH, by its exit status: 0, or -1 (the channel closed
        without one), is delivered; None: the session died while the host answered (it went
        down: the command was delivered too)."""
        if status is None:
            return cls(True, error="connection closed while shutting down")
        if status not in (0, -1):
            return cls(False, output, f"command exited with {status}: {error.strip()}")
        return cls(True, output)


class Pinger(Protocol):
    """Is a host answering? Blocking, bounded to about a second."""

    def is_reachable(self, ip: str) -> bool: ...


class RemoteShutdown(Protocol):
    """Ask one host to shut down. Blocking, bounded by ``host.timeout``."""

    def request(self, host: ShutdownHost) -> CommandOutcome: ...


class LocalRunner(Protocol):
    """Run a local command. Blocking, bounded by `timeout`."""

    def run(self, command: str, timeout: float) -> CommandOutcome: ...


class Dispatcher(Protocol):
    """Where blocking jobs run."""

    def submit(self, fn: Callable[[], T]) -> Future[T]: ...

    def close(self) -> None: ...


class SubprocessPinger:
    """One ICMP echo through the system ``ping`` (no raw sockets needed here)."""

    def __init__(self, wait: int = 1) -> None:
        self.wait = wait

    def is_reachable(self, ip: str) -> bool:
        try:
            done = subprocess.run(
                ["ping", "-c", "1", "-w", str(self.wait), ip],
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                timeout=self.wait + 2, check=False,
            )
        except (OSError, subprocess.TimeoutExpired):
            return False
        return done.returncode == 0


class ParamikoShutdown:
    """Run the host's command over SSH; host keys must already be in `known_hosts`."""

    def __init__(self, known_hosts: str | Path | None = None,
                 key_filename: str | Path | None = None) -> None:
        self.known_hosts = Path(known_hosts) if known_hosts else Path.home() / ".ssh" / "known_hosts"
        self.key_filename = str(key_filename) if key_filename else None

    def request(self, host: ShutdownHost) -> CommandOutcome:
        import paramiko

        if not self.known_hosts.is_file():
            return CommandOutcome(False, error=f"no known_hosts file at {self.known_hosts}: "
                                  f"add the host key of {host.ip} first (ssh-copy-id)")
        client = paramiko.SSHClient()
        try:
            client.load_host_keys(str(self.known_hosts))
            client.set_missing_host_key_policy(paramiko.RejectPolicy())
            try:
                client.connect(
                    hostname=host.ip, port=host.port, username=host.username,
                    key_filename=self.key_filename, look_for_keys=self.key_filename is None,
                    allow_agent=False, timeout=host.timeout, banner_timeout=host.timeout,
                    auth_timeout=host.timeout,
                )
                _, stdout, stderr = client.exec_command(host.command, timeout=host.timeout)
            except paramiko.SSHException as exc:
                return CommandOutcome(False, error=f"SSH error: {exc}")
            except OSError as exc:
                return CommandOutcome(False, error=f"Error connecting to host: {exc.strerror or exc}")
            try:
                output = stdout.read().decode(errors="replace")
                error = stderr.read().decode(errors="replace")
                status = stdout.channel.recv_exit_status()
            except (OSError, paramiko.SSHException):
                return CommandOutcome.of_ssh(None)
        finally:
            client.close()
        return CommandOutcome.of_ssh(status, output, error)


def ssh_method() -> str | None:
    """How SSH shutdowns run here: ``paramiko`` if importable, else ``openssh`` (an ``ssh``
    client on PATH), else None (SSH hosts cannot be shut down from here)."""
    import importlib.util
    import shutil

    if importlib.util.find_spec("paramiko") is not None:
        return "paramiko"
    return "openssh" if shutil.which("ssh") else None


def ssh_backend(known_hosts: str | Path | None = None, key_filename: str | Path | None = None) -> RemoteShutdown:
    """paramiko where it is importable (the operator's machine), else the OpenSSH client (robot images).

    Both refuse unknown host keys and use public keys only; paramiko is kept first because it is
    what panther-ops' own SSH layer uses and it needs no client program.
    """
    if ssh_method() == "paramiko":
        return ParamikoShutdown(known_hosts, key_filename)
    from panther_ops.manager.shutdown_executor.openssh import OpenSshShutdown

    return OpenSshShutdown(known_hosts, key_filename)


def sign_shutdown_request(secret: str, timestamp: int) -> str:
    """hex HMAC-SHA256(secret, "/shutdown|<timestamp>") as husarion-shutdown expects."""
    message = f"/shutdown|{timestamp}".encode()
    return hmac.new(secret.encode(), message, hashlib.sha256).hexdigest()


def shutdown_path(secret: str, timestamp: int) -> str:
    """The signed request path: ``/shutdown?ts=<unix>&sig=<hex>``."""
    return f"/shutdown?ts={timestamp}&sig={sign_shutdown_request(secret, timestamp)}"


class HttpShutdown:
    """Signed ``GET /shutdown`` to the husarion-shutdown service."""

    def __init__(self, wall_time: Callable[[], float] = time.time) -> None:
        self.wall_time = wall_time

    def request(self, host: ShutdownHost) -> CommandOutcome:
        path = shutdown_path(host.secret or "", int(self.wall_time()))
        connection = http.client.HTTPConnection(host.ip, host.port, timeout=host.timeout)
        try:
            connection.request("GET", path)
            response = connection.getresponse()
            body = response.read(4096).decode(errors="replace")
        except OSError as exc:
            return CommandOutcome(False, error=f"HTTP request failed: {exc.strerror or exc}")
        except http.client.HTTPException as exc:
            return CommandOutcome(False, error=f"HTTP request failed: {exc!r}")
        finally:
            connection.close()
        if response.status != 200:
            return CommandOutcome(False, body, f"HTTP {response.status}: {body.strip()[:200]}")
        return CommandOutcome(True, body)


class SubprocessRunner:
    """A local command as an argv list (no shell)."""

    def run(self, command: str, timeout: float) -> CommandOutcome:
        try:
            done = subprocess.run(shlex.split(command), capture_output=True, text=True,
                                  timeout=timeout, check=False)
        except subprocess.TimeoutExpired:
            return CommandOutcome(False, error=f"'{command}' did not finish in {timeout} s")
        except OSError as exc:
            return CommandOutcome(False, error=f"'{command}': {exc.strerror or exc}")
        if done.returncode != 0:
            return CommandOutcome(False, done.stdout,
                                  f"'{command}' exited with {done.returncode}: {done.stderr.strip()}")
        return CommandOutcome(True, done.stdout)


class ThreadDispatcher:
    """A small thread pool; closing it does not wait for jobs still blocked on the network."""

    def __init__(self, workers: int = 8) -> None:
        self._pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="panther-shutdown")

    def submit(self, fn: Callable[[], T]) -> Future[T]:
        return self._pool.submit(fn)

    def close(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)


class InlineDispatcher:
    """Run each job when submitted: for backends that never block (simulation, test doubles)."""

    def submit(self, fn: Callable[[], T]) -> Future[T]:
        future: Future[T] = Future()
        try:
            future.set_result(fn())
        except Exception as exc:  # a failing job is reported through its future
            future.set_exception(exc)
        return future

    def close(self) -> None:
        return None


@dataclass
class ShutdownBackends:
    """Everything a shutdown needs from the outside world, injectable as a whole."""

    pinger: Pinger
    ssh: RemoteShutdown
    http: RemoteShutdown
    local: LocalRunner
    dispatcher: Dispatcher

    @classmethod
    def real(cls, known_hosts: str | Path | None = None,
             key_filename: str | Path | None = None) -> ShutdownBackends:
        """System ping, SSH (`ssh_backend`: strict host keys), HTTP, subprocess, thread pool."""
        return cls(SubprocessPinger(), ssh_backend(known_hosts, key_filename),
                   HttpShutdown(), SubprocessRunner(), ThreadDispatcher())

    def remote_for(self, host: ShutdownHost) -> RemoteShutdown:
        """The backend for the host's method."""
        return self.http if host.method is Method.HTTP else self.ssh

    def close(self) -> None:
        """Release the dispatcher."""
        self.dispatcher.close()
