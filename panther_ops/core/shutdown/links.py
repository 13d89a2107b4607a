"""What a shutdown runs to reach a LAN host, how each answer is judged, and the executor's
backends "via the robot" or "from here".

Through the robot (``transport/lan.py``'s `RobotLink` is the way there):

* ping: ``ping -c 1 -W 1 IP`` run on the robot (the manager's availability check);
* SSH: a session through the robot's connection, the robot's key, strict host keys;
* HTTP: ``curl`` (or python3) on the robot, the request signed here with the robot's clock.

The commands and the reading of their answers are pure functions below; the functions that
take a link run them.
"""

from __future__ import annotations

import threading
import time
from typing import TYPE_CHECKING

from panther_ops.errors import OpsError
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
from panther_ops.transport.base import Command, CommandResult
from panther_ops.transport.lan import RobotLink, SessionLost, TargetError, exec_on, needs_ssh
from panther_ops.transport.local_command import exit_status_here

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Inventory, Robot

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


# -- what runs on the robot, and how its answer is read (pure) ----------------------------------------
def ping_command(ip: str, wait: float) -> Command:
    """One echo to `ip` from the robot, waiting `wait` seconds (1 s: ping's own ``-W 1``)."""
    return Command.sh(_PING, ip, "1" if wait >= 1.0 else f"{wait:.2f}")


def ping_answered(robot: str, ip: str, res: CommandResult) -> bool:
    """Did `ip` answer (exit 0) or not (1)? Any other status is ping failing on the robot."""
    if res.exit_status in (0, 1):
        return res.exit_status == 0
    raise TargetError(f"{robot}: ping {ip} on the robot failed (exit {res.exit_status}): {res.stderr.strip()}")


def http_get_command(ip: str, port: int, path: str, timeout: float) -> Command:
    """``GET http://ip:port/path`` made by the robot: the body, then the status on the last line."""
    host = f"[{ip}]" if ":" in ip else ip
    return Command.sh(_HTTP_GET, f"http://{host}:{port}{path}", f"{timeout:g}", _PY_GET)


def http_answer(res: CommandResult) -> tuple[int | None, str, str]:
    """(HTTP status or None, body, error) of the robot's GET."""
    body, _, code = res.stdout.rpartition("\n")
    if res.exit_status != 0 or not code.isdigit() or code == "000":
        return None, body, (res.stderr.strip() or f"exit {res.exit_status}")
    return int(code), body, ""


def route_source(res: CommandResult) -> str | None:
    """The ``src`` address of an ``ip -o route get`` answer (None when it has none)."""
    words = res.stdout.split()
    return words[words.index("src") + 1] if res.ok and "src" in words[:-1] else None


# -- run through the robot's link -----------------------------------------------------------------------
def ping(link: RobotLink, ip: str, wait: float = FIRST_PING_WAIT) -> bool:
    """Does `ip` answer one echo from the robot within `wait` seconds?"""
    return ping_answered(link.name, ip, link.run(ping_command(ip, wait), timeout=wait + 10))


def http_get(link: RobotLink, ip: str, port: int, path: str, timeout: float) -> tuple[int | None, str, str]:
    """(HTTP status or None, body, error) of ``GET http://ip:port/path`` made by the robot."""
    return http_answer(link.run(http_get_command(ip, port, path, timeout), timeout=timeout + 10))


def robot_ip_towards(link: RobotLink, ip: str) -> str | None:
    """The robot's own address on the way to `ip` (``ip route get``), for instructions."""
    return route_source(link.run(Command.of("ip", "-o", "route", "get", ip), timeout=10))


def lan_robot(inventory: Inventory, name: str) -> Robot:
    """The robot ``name`` whose LAN reaches the hosts (``--via``): one reached over SSH."""
    (robot,) = inventory.select([name], [], False)[:1]
    if robot.transport == "local":
        raise needs_ssh(robot.name)
    return robot


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
        status = exit_status_here(["ping", "-c", "1", "-W", "1", ip], timeout=wait + (0.5 if wait >= 1 else 0))
        if status is None:
            return False
        if status in (0, 1):
            return status == 0
        raise OSError(f"ping {ip} exited {status}")


class RobotPinger(_TwoSpeedPinger):
    """``ping`` run on the robot."""

    def __init__(self, link: RobotLink, first: float = FIRST_PING_WAIT, watch: float = WATCH_PING_WAIT) -> None:
        super().__init__(first, watch)
        self.link = link

    def is_reachable(self, ip: str) -> bool:
        return ping(self.link, ip, self._wait_for(ip))


class RobotSshShutdown:
    """The host's command over SSH through the robot, with the robot's key and known_hosts."""

    def __init__(self, link: RobotLink) -> None:
        self.link = link

    def request(self, host: ShutdownHost) -> CommandOutcome:
        try:
            client = self.link.open_ssh(host.ip, host.port, host.username or "", pkey=self.link.key(),
                                        timeout=host.timeout)
        except OpsError as exc:
            return CommandOutcome(False, error=exc.message)
        try:
            status, out, err = exec_on(client, host.command, timeout=host.timeout)
        except SessionLost:
            return CommandOutcome.of_ssh(None)
        finally:
            client.close()
        return CommandOutcome.of_ssh(status, out, err)


class RobotHttpShutdown:
    """The signed ``GET /shutdown`` made by the robot (curl), signed here with the robot's clock."""

    def __init__(self, link: RobotLink) -> None:
        self.link = link

    def request(self, host: ShutdownHost) -> CommandOutcome:
        ts = int(time.time() + self.link.clock_offset())
        try:
            status, body, error = http_get(self.link, host.ip, host.port, shutdown_path(host.secret or "", ts),
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
