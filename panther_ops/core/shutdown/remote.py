"""The robot as the way to its LAN, and the shutdown executor's backends "here" or "via the robot".

User computers sit on the robot's LAN (10.15.20.0/24 on a real Panther), which the operator
usually cannot reach. Everything of a shutdown then goes through the robot's SSH connection
(the one panther-ops already holds):

* ping: ``ping -c 1 -W 1 IP`` run on the robot (the manager's availability check);
* SSH: a ``direct-tcpip`` channel of the robot's connection to IP:port, an SSH session over
  it that logs in with the robot's own key (``~/.ssh/id_rsa``, the one the driver container
  mounts) and verifies the host key against the robot's ``~/.ssh/known_hosts``
  (`paramiko.RejectPolicy`: an unknown host key is refused, never added);
* HTTP: ``curl`` (or python3) on the robot, the request signed here with the robot's clock.

The robot's private key is read into memory for the session only and never written here.
"""

from __future__ import annotations

import io
import subprocess
import threading
import time
from typing import TYPE_CHECKING, Any

from panther_ops.errors import OpsError, UsageError
from panther_ops.manager.shutdown_executor import (
    CommandOutcome,
    HttpShutdown,
    ParamikoShutdown,
    ShutdownBackends,
    ShutdownHost,
    SubprocessRunner,
    ThreadDispatcher,
    shutdown_path,
)
from panther_ops.secret import Secret
from panther_ops.transport.base import Command, CommandResult, Transport
from panther_ops.transport.hostkeys import fingerprint, known_hosts_name

if TYPE_CHECKING:
    import paramiko

    from panther_ops.core.fleet.inventory import Inventory, Robot

ROBOT_KEY = "~/.ssh/id_rsa"
ROBOT_KNOWN_HOSTS = "~/.ssh/known_hosts"
FIRST_PING_WAIT = 1.0
"""The availability check: one echo, 1 s (as the manager's ``ping -c 1 -w 1``)."""
WATCH_PING_WAIT = 0.25
"""While waiting for a host to go down: a LAN host that still runs answers in milliseconds."""

_PING = (
    'ip=$1; w=$2; if [ "$w" = 1 ]; then ping -c 1 -W 1 "$ip" >/dev/null 2>&1; '
    'else timeout "$w" ping -c 1 -W 1 "$ip" >/dev/null 2>&1; fi; rc=$?; '
    '[ $rc = 124 ] && exit 1; exit $rc'
)
_HTTP_GET = (
    'url=$1; t=$2; '
    'if command -v curl >/dev/null 2>&1; then exec curl -s -S -m "$t" -w "\\n%{http_code}" "$url"; '
    'elif command -v python3 >/dev/null 2>&1; then exec python3 -c "$3" "$url" "$t"; '
    'else echo "neither curl nor python3 on the robot" >&2; exit 127; fi'
)
_PY_GET = (
    "import sys,urllib.request,urllib.error\n"
    "try:\n r=urllib.request.urlopen(sys.argv[1],timeout=float(sys.argv[2])); b=r.read(4096); c=r.status\n"
    "except urllib.error.HTTPError as e:\n b=e.read(4096); c=e.code\n"
    "except Exception as e:\n sys.stderr.write(str(e)+'\\n'); print('\\n000'); sys.exit(7)\n"
    "sys.stdout.write(b.decode(errors='replace')+'\\n'+str(c))\n"
)


class TargetError(OpsError):
    """A user computer could not be reached or logged into (through the robot or from here)."""


def load_private_key(text: str, where: str) -> paramiko.PKey:
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


def host_keys_from_text(text: str) -> paramiko.HostKeys:
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


def _needs_ssh(name: str) -> UsageError:
    return UsageError(f"{name}: shutting hosts down needs a robot reached over SSH (not a local demo robot)",
                      hint="a demo robot has no LAN: use a robot of the lab or the fleet")


def lan_robot(inventory: Inventory, name: str) -> Robot:
    """The robot ``name`` whose LAN reaches the hosts (``--via``): one reached over SSH."""
    (robot,) = inventory.select([name], [], False)[:1]
    if robot.transport == "local":
        raise _needs_ssh(robot.name)
    return robot


class RobotLink:
    """A robot's open SSH connection, used to reach the computers on its LAN."""

    def __init__(self, transport: Transport, name: str) -> None:
        from panther_ops.transport.ssh import SshTransport

        if not isinstance(transport, SshTransport):
            raise _needs_ssh(name)
        self.transport = transport
        self.name = name
        self._lock = threading.Lock()
        self._key: paramiko.PKey | None = None
        self._known: paramiko.HostKeys | None = None
        self._offset: float | None = None

    # -- commands on the robot ----------------------------------------------------------------
    def run(self, command: Command, *, timeout: float = 30.0, stdin: bytes | None = None) -> CommandResult:
        return self.transport.run(command, timeout=timeout, stdin=stdin)

    def ping(self, ip: str, wait: float = FIRST_PING_WAIT) -> bool:
        """Does `ip` answer one echo from the robot within `wait` seconds?"""
        w = "1" if wait >= 1.0 else f"{wait:.2f}"
        res = self.run(Command.sh(_PING, ip, w), timeout=wait + 10)
        if res.exit_status in (0, 1):
            return res.exit_status == 0
        raise TargetError(f"{self.name}: ping {ip} on the robot failed (exit {res.exit_status}): {res.stderr.strip()}")

    def http_get(self, ip: str, port: int, path: str, timeout: float) -> tuple[int | None, str, str]:
        """(HTTP status or None, body, error) of ``GET http://ip:port/path`` made by the robot."""
        host = f"[{ip}]" if ":" in ip else ip
        url = f"http://{host}:{port}{path}"
        res = self.run(Command.sh(_HTTP_GET, url, f"{timeout:g}", _PY_GET), timeout=timeout + 10)
        body, _, code = res.stdout.rpartition("\n")
        if res.exit_status != 0 or not code.isdigit() or code == "000":
            return None, body, (res.stderr.strip() or f"exit {res.exit_status}")
        return int(code), body, ""

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

    def robot_ip_towards(self, ip: str) -> str | None:
        """The robot's own address on the way to `ip` (``ip route get``), for instructions."""
        res = self.run(Command.of("ip", "-o", "route", "get", ip), timeout=10)
        words = res.stdout.split()
        return words[words.index("src") + 1] if res.ok and "src" in words[:-1] else None

    # -- the robot's key and known_hosts ----------------------------------------------------------
    def key(self) -> paramiko.PKey:
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

    def known_hosts(self, reload: bool = False) -> paramiko.HostKeys:
        """The robot's ``~/.ssh/known_hosts`` (empty when it has none)."""
        with self._lock:
            if self._known is None or reload:
                try:
                    text = self.transport.read_file(ROBOT_KNOWN_HOSTS).decode(errors="replace")
                except FileNotFoundError:
                    text = ""
                self._known = host_keys_from_text(text)
            return self._known

    def record_host_key(self, ip: str, port: int, key: paramiko.PKey) -> None:
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

    def fetch_host_key(self, ip: str, port: int, timeout: float = 10.0) -> paramiko.PKey:
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

    def open_ssh(self, ip: str, port: int, username: str, *, pkey: paramiko.PKey | None = None,
                 password: Secret | None = None, key_files: tuple[str, ...] = (), agent: bool = False,
                 host_keys: paramiko.HostKeys | None = None, timeout: float = 10.0) -> paramiko.SSHClient:
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


def exec_on(client: paramiko.SSHClient, command: str, *, timeout: float = 30.0,
            stdin: bytes | None = None) -> tuple[int, str, str]:
    """Run a command on an open session: (exit status, stdout, stderr); -1 when the channel
    closed without a status (the host went away)."""
    from panther_ops.transport.ssh import exec_channel

    t = client.get_transport()
    assert t is not None
    status, out, err = exec_channel(t, command, timeout, stdin)
    return status, out.decode(errors="replace"), err.decode(errors="replace")


# ---------------------------------------------------------------------------------------------------
# executor backends
# ---------------------------------------------------------------------------------------------------
class _TwoSpeedPinger:
    """First ping of a host: the 1 s availability check; then short pings while it goes down."""

    def __init__(self, first: float = FIRST_PING_WAIT, watch: float = WATCH_PING_WAIT) -> None:
        self.first = first
        self.watch = watch
        self._seen: set[str] = set()
        self._lock = threading.Lock()

    def _wait_for(self, ip: str) -> float:
        with self._lock:
            first = ip not in self._seen
            self._seen.add(ip)
        return self.first if first else self.watch


class LocalPinger(_TwoSpeedPinger):
    """``ping`` on this machine."""

    def is_reachable(self, ip: str) -> bool:
        wait = self._wait_for(ip)
        try:
            done = subprocess.run(["ping", "-c", "1", "-W", "1", ip], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL, timeout=wait + (0.5 if wait >= 1 else 0), check=False)
        except subprocess.TimeoutExpired:
            return False
        if done.returncode in (0, 1):
            return done.returncode == 0
        raise OSError(f"ping {ip} exited {done.returncode}")


class RobotPinger(_TwoSpeedPinger):
    """``ping`` run on the robot."""

    def __init__(self, link: RobotLink, first: float = FIRST_PING_WAIT, watch: float = WATCH_PING_WAIT) -> None:
        super().__init__(first, watch)
        self.link = link

    def is_reachable(self, ip: str) -> bool:
        return self.link.ping(ip, self._wait_for(ip))


class RobotSshShutdown:
    """The host's command over SSH through the robot, with the robot's key and known_hosts."""

    def __init__(self, link: RobotLink) -> None:
        self.link = link

    def request(self, host: ShutdownHost) -> CommandOutcome:
        import paramiko

        try:
            client = self.link.open_ssh(host.ip, host.port, host.username or "", pkey=self.link.key(),
                                        timeout=host.timeout)
        except OpsError as exc:
            return CommandOutcome(False, error=exc.message)
        try:
            status, out, err = exec_on(client, host.command, timeout=host.timeout)
        except (OSError, EOFError, paramiko.SSHException):
            return CommandOutcome(True, error="connection closed while shutting down")
        finally:
            client.close()
        if status not in (0, -1):
            return CommandOutcome(False, out, f"command exited with {status}: {err.strip()}")
        return CommandOutcome(True, out)


class RobotHttpShutdown:
    """The signed ``GET /shutdown`` made by the robot (curl), signed here with the robot's clock."""

    def __init__(self, link: RobotLink) -> None:
        self.link = link

    def request(self, host: ShutdownHost) -> CommandOutcome:
        ts = int(time.time() + self.link.clock_offset())
        try:
            status, body, error = self.link.http_get(host.ip, host.port, shutdown_path(host.secret or "", ts),
                                                     host.timeout)
        except OpsError as exc:
            return CommandOutcome(False, error=exc.message)
        if status is None:
            return CommandOutcome(False, error=f"HTTP request failed: {error}")
        if status != 200:
            return CommandOutcome(False, body, f"HTTP {status}: {body.strip()[:200]}")
        return CommandOutcome(True, body)


def backends_via(link: RobotLink) -> ShutdownBackends:
    """Everything through the robot's connection."""
    return ShutdownBackends(RobotPinger(link), RobotSshShutdown(link), RobotHttpShutdown(link), SubprocessRunner(),
                            ThreadDispatcher(workers=16))


def backends_here(known_hosts: str | None = None, key_filename: str | None = None) -> ShutdownBackends:
    """Everything from this machine: ping, paramiko (strict host keys), HTTP."""
    return ShutdownBackends(LocalPinger(), ParamikoShutdown(known_hosts, key_filename), HttpShutdown(),
                            SubprocessRunner(), ThreadDispatcher(workers=16))

