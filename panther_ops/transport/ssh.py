"""SSH transport: one paramiko connection per robot per command, strict host keys.

Every step of a command (commands, file reads and writes, the docker SDK) rides the same
connection; a jump host is reached first and the robot through a ``direct-tcpip`` channel
of it, so the robot's sshd sees exactly one connection.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

from panther_ops.errors import TransportError, UnreachableError
from panther_ops.transport import scripts
from panther_ops.transport import ssh_failures as failures
from panther_ops.transport.base import Command, Endpoint
from panther_ops.transport.conversation import Conversation, Conversing
from panther_ops.transport.filecache import parsed
from panther_ops.transport.hostkeys import fingerprint, known_hosts_name
from panther_ops.transport.ssh_config import Hop, resolve
from panther_ops.transport.ssh_failures import UnknownHostKey
from panther_ops.transport.tcp import connect_tcp

T = TypeVar("T")

if TYPE_CHECKING:
    import paramiko
    from docker import DockerClient


def _refuse_unknown_policy() -> Any:
    """A missing-host-key policy that refuses, naming the offered fingerprint."""
    import paramiko

    class RefuseUnknown(paramiko.MissingHostKeyPolicy):
        def missing_host_key(self, client: paramiko.SSHClient, hostname: str, key: Any) -> None:
            raise UnknownHostKey(key.get_name(), fingerprint(key))

    return RefuseUnknown()


def _load_host_keys(path: str) -> paramiko.HostKeys:
    import paramiko

    return paramiko.HostKeys(path)


def open_client(hop: Hop, robot: str, clients: list[paramiko.SSHClient]) -> paramiko.SSHClient:
    """Connect one hop (through its jump chain); every client opened is appended to ``clients``."""
    import paramiko

    sock: Any = None
    if hop.jump is not None:
        via = open_client(hop.jump, robot, clients)
        vt = via.get_transport()
        assert vt is not None
        try:
            sock = vt.open_channel(
                "direct-tcpip", (hop.hostname, hop.port), ("127.0.0.1", 0),
                timeout=hop.connect_timeout,
            )
        except (paramiko.SSHException, OSError) as exc:
            raise UnreachableError(
                robot, f"jump host {hop.jump.hostname} could not reach {hop.hostname}:{hop.port}: {exc}"
            ) from exc
    client = paramiko.SSHClient()
    keys = client.get_host_keys()
    name = known_hosts_name(hop.hostname, hop.port)
    for path in hop.known_hosts:  # each file parsed once per command; only this host's entries are added
        known = parsed("known_hosts", path, _load_host_keys)
        for keytype, key in (known.lookup(name) or {}).items() if known is not None else ():
            keys.add(name, keytype, key)
    client.set_missing_host_key_policy(_refuse_unknown_policy())
    try:
        if sock is None:
            sock = connect_tcp(hop.hostname, hop.port, hop.connect_timeout)
        client.connect(
            hop.hostname,
            port=hop.port,
            username=hop.user,
            key_filename=list(hop.key_files) or None,  # type: ignore[arg-type]  # paramiko takes a list too
            timeout=hop.connect_timeout,
            banner_timeout=hop.connect_timeout,
            auth_timeout=hop.connect_timeout,
            sock=sock,
            allow_agent=True,
            look_for_keys=not hop.key_files,
        )
    except UnknownHostKey as exc:
        client.close()
        raise failures.unknown_host_key(robot, hop, exc) from None
    except paramiko.BadHostKeyException as exc:
        client.close()
        raise failures.changed_host_key(robot, hop, fingerprint(exc.key), fingerprint(exc.expected_key)) from None
    except paramiko.AuthenticationException as exc:
        client.close()
        raise failures.auth_failed(robot, hop, exc) from None
    except (OSError, paramiko.SSHException, EOFError) as exc:
        started = client.get_transport()  # None: TCP never came up
        client.close()
        if str(exc) == "No authentication methods available":  # nothing to offer: no key anywhere
            raise failures.auth_failed(robot, hop, exc) from None
        raise failures.cannot_connect(robot, hop, exc, started) from None
    clients.append(client)
    return client


class _ChannelPipe:
    """A command on a new session of an open paramiko transport, as a :class:`Pipe`."""

    def __init__(self, transport: Any, command: str, timeout: float) -> None:
        self.chan = transport.open_session(timeout=timeout)
        self.chan.settimeout(timeout)
        self.chan.exec_command(command)
        self.err = bytearray()

    def send(self, data: bytes) -> None:
        try:
            self.chan.sendall(data)
        except OSError:
            if not self.chan.exit_status_ready():  # not a command that ended: the connection failed
                raise

    def close_input(self) -> None:
        self.chan.shutdown_write()

    def recv(self) -> bytes:
        data: bytes = self.chan.recv(65536)
        self._drain()
        return data

    def _drain(self) -> None:
        while self.chan.recv_stderr_ready():
            self.err += self.chan.recv_stderr(65536)

    def stderr(self) -> bytes:
        self._drain()
        return bytes(self.err)

    def wait(self) -> int:
        return int(self.chan.recv_exit_status())

    def close(self) -> None:
        self.chan.close()

    def pause_timeout(self) -> None:
        return None  # a channel's timeout only limits the reads we wait on

    def resume_timeout(self) -> None:
        return None


def exec_channel(
    transport: Any, command: str, timeout: float, stdin: bytes | None = None,
    until: bytes | None = None, answer: Callable[[bytes], bytes] | None = None,
) -> tuple[int, bytes, bytes]:
    """Run one command on a new session of an open paramiko transport.

    Returns (exit status, stdout, stderr); the status is -1 when the channel closed without
    one (the host went away). Stderr is drained as stdout arrives (up to the channel window
    if a command writes only to stderr). With ``until``/``answer`` the input stays open after
    ``stdin`` until the output ends with ``until``; then ``answer(output so far)`` is sent and
    the input closed (a command that ends before asking is not answered).
    """
    return Conversation(_ChannelPipe(transport, command, timeout)).finish(stdin, until, answer)


class SshTransport(Conversing):
    """A robot reached over SSH. Connects on :meth:`connect`; every step reuses it.

    A write session's channel opens in the background (``Conversing._sessions_in_background``):
    opened beside the plan's read, it costs the write no round trip of its own.
    """

    _sessions_in_background = True

    def __init__(self, endpoint: Endpoint) -> None:
        self.name = endpoint.name
        self.endpoint = endpoint
        self._clients: list[paramiko.SSHClient] = []
        self._client: paramiko.SSHClient | None = None
        self._home: str | None = None
        self._docker: DockerClient | None = None
        self._docker_checked = False
        self._sessions = set()

    # -- connection ---------------------------------------------------------------
    def connect(self) -> None:
        if self._client is None:
            self._client = open_client(resolve(self.endpoint), self.name, self._clients)

    @property
    def client(self) -> paramiko.SSHClient:
        self.connect()
        assert self._client is not None
        return self._client

    def host_key_fingerprint(self) -> str | None:
        """The host key the robot offered on this connection (checked against known_hosts)."""
        transport = self.client.get_transport()
        return fingerprint(transport.get_remote_server_key()) if transport is not None else None

    def close(self) -> None:
        self.close_sessions()
        if self._docker is not None:
            self._docker.close()
            self._docker = None
        for c in reversed(self._clients):
            c.close()
        self._clients.clear()
        self._client = None

    # -- commands (run, session: Conversing) ----------------------------------------
    def _open(self, command: Command, timeout: float | None) -> _ChannelPipe:
        transport = self.client.get_transport()
        if transport is None or not transport.is_active():
            raise UnreachableError(self.name, "connection lost")
        return _ChannelPipe(transport, command.render(reveal=True), self._limit(timeout))

    def _limit(self, timeout: float | None) -> float:
        return timeout if timeout is not None else self.endpoint.command_timeout

    def guard(self, command: Command, timeout: float | None, step: Callable[[], T]) -> T:
        """Run one step of a command; SSH failures become panther-ops errors."""
        import paramiko

        try:
            return step()
        except TimeoutError:
            raise TransportError(self.name, f"`{command}` timed out after {self._limit(timeout):.0f} s") from None
        except (paramiko.SSHException, OSError, EOFError) as exc:
            raise UnreachableError(self.name, f"connection lost during `{command}`: {exc}") from None

    # -- files ----------------------------------------------------------------------
    def read_file(self, path: str) -> bytes:
        res = self.run(Command.sh(scripts.READ, path))
        if res.exit_status == scripts.MISSING_EXIT:
            raise FileNotFoundError(path)
        if not res.ok:
            raise TransportError(self.name, f"cannot read {path}: {res.stderr.strip()}")
        return res.raw_stdout

    def exists(self, path: str) -> bool:
        return self.run(Command.sh(scripts.EXISTS, path)).ok

    def home(self) -> str:
        if self._home is None:
            self._home = self.run(Command.sh('printf %s "$HOME"')).stdout or "/home/husarion"
        return self._home

    # -- docker ---------------------------------------------------------------------
    def docker(self, api_version: str | None = None) -> DockerClient | None:
        """The robot's docker engine through ``docker system dial-stdio`` on this connection.

        ``api_version`` (the engine's, when a probe already read it) saves a round trip.
        """
        if not self._docker_checked:
            self._docker_checked = True
            if api_version is None:
                probe = self.run(
                    Command.sh("command -v docker >/dev/null && docker version -f '{{.Server.APIVersion}}'")
                )
                api_version = probe.stdout.strip() if probe.ok else None
            if api_version:
                from panther_ops.transport.docker_client import client_over_ssh

                self._docker = client_over_ssh(self.client, api_version)
        return self._docker


def default_password_accepted(endpoint: Endpoint, password: str) -> bool:
    """Try one password login on a fresh connection (host key still verified strictly)."""
    import paramiko

    hop = resolve(endpoint)
    clients: list[paramiko.SSHClient] = []
    try:
        sock: Any = None
        if hop.jump is not None:
            via = open_client(hop.jump, endpoint.name, clients)
            vt = via.get_transport()
            assert vt is not None
            sock = vt.open_channel("direct-tcpip", (hop.hostname, hop.port), ("127.0.0.1", 0))
        client = paramiko.SSHClient()
        for path in hop.known_hosts:
            if os.path.exists(path):
                client.get_host_keys().load(path)
        client.set_missing_host_key_policy(_refuse_unknown_policy())
        clients.append(client)
        try:
            if sock is None:
                sock = connect_tcp(hop.hostname, hop.port, hop.connect_timeout)
            client.connect(
                hop.hostname, port=hop.port, username=hop.user, password=password, sock=sock,
                timeout=hop.connect_timeout, allow_agent=False, look_for_keys=False,
                banner_timeout=hop.connect_timeout, auth_timeout=hop.connect_timeout,
            )
        except paramiko.AuthenticationException:
            return False
        return True
    finally:
        for c in reversed(clients):
            c.close()


def fetch_host_key(endpoint: Endpoint) -> tuple[Hop, Any]:
    """Ask a robot for its host key without authenticating (jump hosts verified strictly)."""
    import paramiko

    hop = resolve(endpoint)
    clients: list[paramiko.SSHClient] = []
    try:
        if hop.jump is not None:
            via = open_client(hop.jump, endpoint.name, clients)
            vt = via.get_transport()
            assert vt is not None
            sock: Any = vt.open_channel("direct-tcpip", (hop.hostname, hop.port), ("127.0.0.1", 0))
        else:
            try:
                sock = connect_tcp(hop.hostname, hop.port, hop.connect_timeout)
            except OSError as exc:
                raise failures.cannot_connect(endpoint.name, hop, exc, None) from None
        t = paramiko.Transport(sock)
        try:
            t.start_client(timeout=hop.connect_timeout)
            return hop, t.get_remote_server_key()
        except (paramiko.SSHException, EOFError, OSError) as exc:
            raise failures.cannot_connect(endpoint.name, hop, exc, t) from None
        finally:
            t.close()
    finally:
        for c in reversed(clients):
            c.close()


def known_keys(hop: Hop) -> list[Any]:
    """Keys known_hosts holds for a hop (any key type)."""
    import paramiko

    keys = paramiko.HostKeys()
    for path in hop.known_hosts:
        if os.path.exists(path):
            keys.load(path)
    entry = keys.lookup(known_hosts_name(hop.hostname, hop.port))
    return list(entry.values()) if entry else []
