"""The way to a host on the robot's LAN: the robot's SSH connection, its key and known_hosts.

User computers sit on the robot's LAN (10.15.20.0/24 on a real Panther), which the operator
usually cannot reach. Everything then goes through the robot's SSH connection (the one
panther-ops already holds):

* commands on the robot: its connection's ``run`` (what runs there, and how its answer is
  judged, is core's: ``core/shutdown/links.py``);
* SSH: a ``direct-tcpip`` channel of the robot's connection to IP:port, an SSH session over
  it that logs in with the robot's own key (``~/.ssh/id_rsa``, the one the driver container
  mounts) and verifies the host key against the robot's ``~/.ssh/known_hosts``
  (`paramiko.RejectPolicy`: an unknown host key is refused, never added);
* the robot's clock, against ours (the manager signs HTTP requests with it).

The robot's private key is read into memory for the session only and never written here.
TCP for the standard library's clients (a socket joined to a channel) is ``tunnel.py``'s.
"""

from __future__ import annotations

import io
import threading
import time
from typing import TYPE_CHECKING, Any, TypeAlias

from panther_ops.errors import OpsError, UsageError
from panther_ops.secret import Secret
from panther_ops.transport.base import Command, CommandResult, Transport
from panther_ops.transport.hostkeys import fingerprint, known_hosts_name

if TYPE_CHECKING:
    import paramiko

Key: TypeAlias = "paramiko.PKey"
"""A private or public SSH key (what `fingerprint` and known_hosts take)."""
KnownHosts: TypeAlias = "paramiko.HostKeys"
"""A known_hosts file's entries: ``lookup(name)`` gives ``{key type: Key}``."""
LanSession: TypeAlias = "paramiko.SSHClient"
"""An open SSH session to a computer on the robot's LAN (`exec_on` runs commands on it)."""

ROBOT_KEY = "~/.ssh/id_rsa"
ROBOT_KNOWN_HOSTS = "~/.ssh/known_hosts"


class TargetError(OpsError):
    """A user computer could not be reached or logged into (through the robot or from here)."""


class SessionLost(TargetError):
    """The session to a computer ended while a command ran (it went away, or the link broke)."""


def load_private_key(text: str, where: str) -> Key:
    """An unencrypted private key (RSA, Ed25519 or ECDSA) from its text."""
    import paramiko

    errors = []
    for cls in (paramiko.RSAKey, paramiko.Ed25519Key, paramiko.ECDSAKey):
        try:
            return cls.from_private_key(io.StringIO(text))
        except paramiko.PasswordRequiredException:
            raise UsageError(f"{where} is protected by a passphrase: the manager (and panther-ops) cannot use it",
                             hint="the driver container needs an unencrypted key") from None
        except (paramiko.SSHException, ValueError) as exc:
            errors.append(str(exc))
    raise UsageError(f"{where} is not a private key paramiko can read ({errors[0]})")


def host_keys_from_text(text: str) -> KnownHosts:
    """A known_hosts file's entries (plain and hashed names) as paramiko HostKeys."""
    import paramiko
    from paramiko.hostkeys import HostKeyEntry

    keys = paramiko.HostKeys()
    for n, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith(("#", "@")):
            continue
        try:
            entry = HostKeyEntry.from_line(line, n)
        except (paramiko.SSHException, ValueError):
            continue
        if entry is None or entry.key is None:
            continue
        for name in entry.hostnames:
            keys.add(name, entry.key.get_name(), entry.key)
    return keys


def needs_ssh(name: str) -> UsageError:
    """The refusal for a robot that has no LAN to reach (a local demo robot)."""
    return UsageError(f"{name}: shutting hosts down needs a robot reached over SSH (not a local demo robot)",
                      hint="a demo robot has no LAN: use a robot of the lab or the fleet")


class RobotLink:
    """A robot's open SSH connection, used to reach the computers on its LAN."""

    def __init__(self, transport: Transport, name: str) -> None:
        from panther_ops.transport.ssh import SshTransport

        if not isinstance(transport, SshTransport):
            raise needs_ssh(name)
        self.transport = transport
        self.name = name
        self._lock = threading.Lock()
        self._key: Key | None = None
        self._known: KnownHosts | None = None
        self._offset: float | None = None

    # -- the robot itself -----------------------------------------------------------------------
    def run(self, command: Command, *, timeout: float = 30.0, stdin: bytes | None = None) -> CommandResult:
        return self.transport.run(command, timeout=timeout, stdin=stdin)

    def clock_offset(self) -> float:
        """Robot time minus local time (the manager signs requests with the robot's clock)."""
        with self._lock:
            if self._offset is None:
                t0 = time.time()
                res = self.run(Command.of("date", "+%s"), timeout=10)
                t1 = time.time()
                try:
                    self._offset = float(res.stdout.strip()) - (t0 + t1) / 2
                except ValueError:
                    self._offset = 0.0
                if abs(self._offset) < 2:
                    self._offset = 0.0
            return self._offset

    # -- the robot's key and known_hosts ----------------------------------------------------------
    def key(self) -> Key:
        """The robot's private key (``~/.ssh/id_rsa``), read once, kept in memory only."""
        with self._lock:
            if self._key is None:
                try:
                    text = self.transport.read_file(ROBOT_KEY).decode()
                except FileNotFoundError:
                    raise TargetError(f"{self.name}: no {ROBOT_KEY} on the robot",
                                      hint=f"panther-ops shutdown setup -r {self.name} creates it") from None
                self._key = load_private_key(text, f"{self.name}:{ROBOT_KEY}")
            return self._key

    def known_hosts(self, reload: bool = False) -> KnownHosts:
        """The robot's ``~/.ssh/known_hosts`` (empty when it has none)."""
        with self._lock:
            if self._known is None or reload:
                try:
                    text = self.transport.read_file(ROBOT_KNOWN_HOSTS).decode(errors="replace")
                except FileNotFoundError:
                    text = ""
                self._known = host_keys_from_text(text)
            return self._known

    def record_host_key(self, ip: str, port: int, key: Key) -> None:
        """Append the host key to the robot's known_hosts (created 0600)."""
        line = f"{known_hosts_name(ip, port)} {key.get_name()} {key.get_base64()}"
        res = self.run(Command.sh('umask 077; mkdir -p "$HOME/.ssh" && printf "%s\\n" "$1" >> "$HOME/.ssh/known_hosts"',
                                  line))
        if not res.ok:
            raise TargetError(f"{self.name}: cannot write ~/.ssh/known_hosts: {res.stderr.strip()}")
        self.known_hosts(reload=True)

    # -- connections to the computers --------------------------------------------------------------
    def channel(self, ip: str, port: int, timeout: float) -> Any:
        """A direct-tcpip channel of the robot's connection to ip:port."""
        import paramiko

        t = self.transport.client.get_transport()
        if t is None or not t.is_active():
            raise TargetError(f"{self.name}: the connection to the robot was lost")
        try:
            return t.open_channel("direct-tcpip", (ip, port), ("127.0.0.1", 0), timeout=timeout)
        except paramiko.ChannelException as exc:
            raise TargetError(f"{ip}:{port} refused or unreachable from {self.name} ({exc.text})") from None
        except (paramiko.SSHException, OSError, EOFError) as exc:
            raise TargetError(f"{ip}:{port} not reachable from {self.name}: {exc or type(exc).__name__}") from None

    def fetch_host_key(self, ip: str, port: int, timeout: float = 10.0) -> Key:
        """The host key `ip` offers (handshake only, no login)."""
        import paramiko

        sock = self.channel(ip, port, timeout)
        t = paramiko.Transport(sock)
        try:
            t.start_client(timeout=timeout)
            key = t.get_remote_server_key()
        except (paramiko.SSHException, EOFError, OSError) as exc:
            raise TargetError(f"SSH handshake with {ip}:{port} through {self.name} failed: {exc}") from None
        finally:
            t.close()
        return key

    def open_ssh(self, ip: str, port: int, username: str, *, pkey: Key | None = None,
                 password: Secret | None = None, key_files: tuple[str, ...] = (), agent: bool = False,
                 host_keys: KnownHosts | None = None, timeout: float = 10.0) -> LanSession:
        """An SSH session to ip:port through the robot; the host key must be in `host_keys`
        (default: the robot's known_hosts)."""
        import paramiko

        sock = self.channel(ip, port, timeout)
        client = paramiko.SSHClient()
        known = host_keys if host_keys is not None else self.known_hosts()
        for name in known:
            for ktype, key in known[name].items():
                client.get_host_keys().add(name, ktype, key)
        client.set_missing_host_key_policy(paramiko.RejectPolicy())
        try:
            client.connect(ip, port=port, username=username, pkey=pkey,
                           password=password.reveal() if password is not None else None,
                           key_filename=list(key_files) or None,  # type: ignore[arg-type]  # a list works too
                           sock=sock, timeout=timeout, banner_timeout=timeout,
                           auth_timeout=timeout, allow_agent=agent, look_for_keys=False)
        except paramiko.BadHostKeyException as exc:
            client.close()
            raise TargetError(f"{ip}:{port} offers {fingerprint(exc.key)}, the robot's known_hosts has "
                              f"{fingerprint(exc.expected_key)}: HOST KEY CHANGED, refused") from None
        except paramiko.AuthenticationException as exc:
            client.close()
            raise TargetError(f"login as {username}@{ip} refused: {exc}") from None
        except paramiko.SSHException as exc:
            client.close()
            if "not found in known_hosts" in str(exc):
                raise TargetError(f"{ip}:{port}: host key not in the robot's known_hosts: refused") from None
            raise TargetError(f"SSH to {username}@{ip}:{port} failed: {exc}") from None
        except (OSError, EOFError) as exc:
            client.close()
            raise TargetError(f"SSH to {username}@{ip}:{port} failed: {exc or type(exc).__name__}") from None
        return client


def exec_on(client: LanSession, command: str, *, timeout: float = 30.0,
            stdin: bytes | None = None) -> tuple[int, str, str]:
    """Run a command on an open session: (exit status, stdout, stderr); -1 when the channel
    closed without a status (the host went away). SessionLost when the session broke."""
    import paramiko

    from panther_ops.transport.ssh import exec_channel

    t = client.get_transport()
    assert t is not None
    try:
        status, out, err = exec_channel(t, command, timeout, stdin)
    except (OSError, EOFError, paramiko.SSHException) as exc:
        raise SessionLost(f"the session ended while a command ran: {exc or type(exc).__name__}") from None
    return status, out.decode(errors="replace"), err.decode(errors="replace")
