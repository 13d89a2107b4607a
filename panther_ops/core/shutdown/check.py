"""`shutdown check`: would each host of the robot's file power off? Proven without powering it off.

From the robot, per host:

* SSH: ``ping`` -> ``host-key`` (in the robot's known_hosts) -> ``login`` (the robot's key,
  no password: what the manager does) -> ``sudo`` (``sudo -n -l <command>``: sudo would run
  it without asking for a password; nothing is run).
* HTTP: ``ping`` -> ``service`` (husarion-shutdown answers an unsigned request with an
  error) -> ``secret`` (a request signed with the file's secret but an hour old: the service
  must refuse it for its age, not for its signature; nothing is shut down).

The first failing step is named with its fix.
"""

from __future__ import annotations

import posixpath
import re
import shlex
import time
from dataclasses import dataclass, field
from typing import Any

from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.kinds.hostsfile import POWER_BUDGET_S, HostEntry
from panther_ops.core.shutdown.links import http_get, ping, robot_ip_towards
from panther_ops.core.shutdown.read import read_robot_hosts
from panther_ops.errors import OpsError
from panther_ops.manager.shutdown_executor import ShutdownHost, shutdown_path
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.hostkeys import fingerprint, known_hosts_name
from panther_ops.transport.lan import LanSession, RobotLink, exec_on

STALE_S = 3600
"""Age of the secret probe: far outside any replay window, so the service refuses it."""


@dataclass
class HostCheck:
    host: str
    method: str
    ok: bool = True
    step: str = "ok"
    message: str = ""
    fix: str = ""
    steps: list[str] = field(default_factory=list)

    def fail(self, step: str, message: str, fix: str) -> HostCheck:
        self.ok, self.step, self.message, self.fix = False, step, message, fix
        return self

    def passed(self, step: str) -> None:
        self.steps.append(step)

    def to_json(self) -> dict[str, Any]:
        return {"host": self.host, "method": self.method, "ok": self.ok, "step": self.step, "message": self.message,
                "fix": self.fix, "passed": list(self.steps)}


_TAGS = re.compile(r"^((?:[A-Z_]+:\s*)+)")
_SYSTEM_DIRS = {"/sbin", "/usr/sbin", "/bin", "/usr/bin"}


def parse_sudo_listing(text: str) -> list[tuple[str, bool, str]]:
    """``sudo -l`` rules as (runas, nopasswd, command) in sudoers order."""
    rules: list[tuple[str, bool, str]] = []
    in_rules = False
    for raw in text.splitlines():
        line = raw.strip()
        if "may run the following commands" in line:
            in_rules = True
            continue
        if not in_rules or not line.startswith("("):
            continue
        runas, _, rest = line[1:].partition(")")
        nopasswd = False
        for piece in rest.strip().split(", "):
            token = piece.strip()
            m = _TAGS.match(token)
            if m:
                tags = [t.strip() for t in m.group(1).split(":") if t.strip()]
                if "NOPASSWD" in tags:
                    nopasswd = True
                if "PASSWD" in tags:
                    nopasswd = False
                token = token[m.end():].strip()
            if token:
                rules.append((runas.strip(), nopasswd, token))
    return rules


def _same_program(rule: str, path: str) -> bool:
    if rule == path:
        return True
    rd, rb = posixpath.split(rule)
    pd, pb = posixpath.split(path)
    return rb == pb and rd in _SYSTEM_DIRS and pd in _SYSTEM_DIRS


def rule_matches(rule: str, path: str, args: list[str]) -> bool:
    """Does a sudo -l command entry cover `path args` (ALL, the program with any args, or exactly)?"""
    if rule == "ALL":
        return True
    words = rule.split()
    if not words or not _same_program(words[0], path):
        return False
    if len(words) == 1:
        return True
    if words[1:] == ['""']:
        return not args
    return words[1:] == args


def nopasswd_for(listing: str, resolved: str) -> bool | None:
    """Whether sudo runs `resolved` (``/usr/sbin/shutdown now``) as root without a password,
    from the ``sudo -l`` listing: the last matching entry decides (None: no entry matches)."""
    path, *args = resolved.split()
    verdict: bool | None = None
    for runas, nopasswd, entry in parse_sudo_listing(listing):
        negated = entry.startswith("!")
        cmd = entry.lstrip("!").strip()
        users = runas.split(":")[0].strip()
        if not any(u.strip() in ("ALL", "root") for u in users.split(",")):
            continue
        if rule_matches(cmd, path, args):
            verdict = None if negated else nopasswd
    return verdict


def sudo_without_password(client: LanSession, argv: list[str]) -> tuple[bool, str]:
    """(True, how) when ``sudo -n`` would run `argv` as root without a password: ``sudo -n -l
    CMD`` (permitted, and the listing needs no password), then the listing's last matching
    entry must be NOPASSWD (``sudo -l CMD`` alone also says yes to commands that need one)."""
    status, out, err = exec_on(client, shlex.join(["sudo", "-n", "-l", *argv]), timeout=15)
    if status != 0:
        why = (err.strip() or out.strip() or f"exit {status}").splitlines()[-1]
        return False, why
    resolved = out.strip().splitlines()[0] if out.strip() else " ".join(argv)
    status, listing, err = exec_on(client, shlex.join(["sudo", "-n", "-l"]), timeout=15)
    if status != 0:
        return False, (err.strip() or f"sudo -n -l exited {status}").splitlines()[-1]
    verdict = nopasswd_for(listing, resolved)
    if verdict is None:
        return False, f"no sudo rule lets it run {resolved}"
    if not verdict:
        return False, f"sudo runs {resolved} only with a password"
    return True, f"sudo -n -l: {resolved} (NOPASSWD)"


def sudo_probe(command: str, username: str) -> list[str] | None:
    """What `sudo -n -l` must allow for `command` (None: the command does not use sudo)."""
    words = shlex.split(command)
    if words[:1] != ["sudo"]:
        return None
    rest = words[1:]
    while rest and rest[0] in ("-n", "--non-interactive"):
        rest = rest[1:]
    return ["sudo", "-n", "-l", *rest]


def check_ssh(link: RobotLink, robot: str, host: ShutdownHost) -> HostCheck:
    label = host.describe()
    c = HostCheck(label, "ssh")
    setup = f"panther-ops shutdown setup -r {robot} --host {host.ip} --user {host.username}"
    try:
        if not ping(link, host.ip):
            return c.fail("ping", f"{host.ip} does not answer ping from {robot}",
                          "is the computer on, and on the robot's LAN? (its address in the hosts file)")
        c.passed("ping")
        offered = link.fetch_host_key(host.ip, host.port)
        known: dict[str, Any] = dict(link.known_hosts().lookup(known_hosts_name(host.ip, host.port)) or {})
        fp = f"{offered.get_name()} {fingerprint(offered)}"
        if not any(k.get_name() == offered.get_name() and k.asbytes() == offered.asbytes() for k in known.values()):
            if any(k.get_name() == offered.get_name() for k in known.values()):
                return c.fail("host-key", f"HOST KEY CHANGED: {host.ip} offers {fp}, the robot's known_hosts "
                              "has another", "check the key on the computer (ssh-keygen -lf "
                              f"/etc/ssh/ssh_host_ed25519_key.pub), remove the old one on the robot (ssh-keygen -R "
                              f"{host.ip}), then: {setup}")
            return c.fail("host-key", f"{host.ip}'s host key ({fp}) is not in the robot's ~/.ssh/known_hosts", setup)
        c.passed("host-key")
        try:
            key = link.key()
        except OpsError as exc:
            return c.fail("robot-key", exc.message, f"panther-ops shutdown setup -r {robot} ... creates it")
        try:
            client = link.open_ssh(host.ip, host.port, host.username or "", pkey=key, timeout=min(host.timeout, 10))
        except OpsError as exc:
            return c.fail("login", f"the robot's key does not log in ({exc.message})",
                          f"add the robot's public key to ~{host.username}/.ssh/authorized_keys: {setup}")
        c.passed("login")
        try:
            probe = sudo_probe(host.command, host.username or "")
            if probe is None:
                word = shlex.split(host.command)[0]
                status, _, _ = exec_on(client, shlex.join(["sh", "-c", 'command -v "$1" >/dev/null', "sh", word]))
                if status != 0:
                    return c.fail("command", f"{word!r} is not a command on {host.ip}",
                                  "fix `command:` in the hosts file")
                c.passed("command")
            elif host.username != "root":
                ok, why = sudo_without_password(client, probe[3:])
                if not ok:
                    return c.fail("sudo", f"{host.username} may not run `{' '.join(probe[3:])}` without a password "
                                  f"({why})", f"install the sudoers rule: {setup} --ask-password")
                c.passed("sudo")
        finally:
            client.close()
    except OpsError as exc:
        return c.fail(_next_step(c), exc.message, "see the message")
    c.message = "would power off: " + ", ".join(c.steps)
    return c


def _next_step(c: HostCheck) -> str:
    order = ["ping", "host-key", "login", "sudo"] if c.method == "ssh" else ["ping", "service", "secret"]
    for s in order:
        if s not in c.steps:
            return s
    return "unknown"


def install_hint(ip: str, port: int, robot_ip: str | None) -> str:
    remote = f" config.remote-host-ip={robot_ip}" if robot_ip else ""
    return ("install husarion-shutdown on the computer: sudo snap install husarion-shutdown && sudo snap set "
            f"husarion-shutdown config.user-computer-ip={ip} config.port={port}{remote} "
            "config.password=\"$SECRET\" && sudo husarion-shutdown.start")


def probe_secret(link: RobotLink, host: ShutdownHost) -> tuple[bool, str]:
    """(accepted, what the service said) for a signed request an hour old."""
    ts = int(time.time() + link.clock_offset()) - STALE_S
    status, body, error = http_get(link, host.ip, host.port, shutdown_path(host.secret or "", ts),
                                        min(host.timeout, 10))
    text = body.strip()[:200]
    if status is None:
        return False, f"no answer: {error}"
    low = text.lower()
    if status == 200:
        return False, ("the service ACCEPTED an hour-old request (no replay protection): the computer may be "
                       "shutting down now")
    if status == 403 or "signature" in low or "forbidden" in low:
        return False, f"the secret was refused (HTTP {status}: {text})"
    if status == 401 or any(w in low for w in ("expired", "timestamp", "too old", "stale")):
        return True, f"signature accepted, request refused for its age (HTTP {status}: {text})"
    return False, f"cannot tell whether the secret is right (HTTP {status}: {text})"


def check_http(link: RobotLink, robot: str, host: ShutdownHost) -> HostCheck:
    c = HostCheck(host.describe(), "http")
    robot_ip = None
    try:
        if not ping(link, host.ip):
            return c.fail("ping", f"{host.ip} does not answer ping from {robot}",
                          "is the computer on, and on the robot's LAN? (its address in the hosts file)")
        c.passed("ping")
        status, _, error = http_get(link, host.ip, host.port, "/shutdown", min(host.timeout, 10))
        if status is None:
            robot_ip = robot_ip_towards(link, host.ip)
            return c.fail("service", f"nothing answers HTTP on {host.ip}:{host.port} ({error})",
                          install_hint(host.ip, host.port, robot_ip))
        if status == 200:
            return c.fail("service", f"{host.ip}:{host.port} accepted an UNSIGNED shutdown request",
                          "this is not husarion-shutdown, or it does not check signatures")
        c.passed("service")
        ok, said = probe_secret(link, host)
        if not ok:
            return c.fail("secret", said, "use the same secret on both sides: `secret:` in the robot's hosts file "
                          "and `sudo snap set husarion-shutdown config.password=...` on the computer")
        c.passed("secret")
    except OpsError as exc:
        return c.fail(_next_step(c), exc.message, "see the message")
    c.message = "would power off: " + ", ".join(c.steps)
    return c


def check_entry(link: RobotLink, robot: str, entry: HostEntry) -> HostCheck:
    host = entry.host()
    return check_http(link, robot, host) if entry.http else check_ssh(link, robot, host)


def check_robot(ctx: RobotContext, power_budget: float = POWER_BUDGET_S) -> RobotResult:
    """Every host of the robot's hosts file, checked from the robot (hosts in parallel)."""
    from concurrent.futures import ThreadPoolExecutor

    name = ctx.robot.name
    rf = read_robot_hosts(ctx)
    parsed = rf.parse(power_budget)
    if ctx.robot.transport == "local":  # like every command on a demo robot: skipped, the reason said
        return RobotResult(name, Outcome.SKIPPED,
                           f"demo robot: no LAN to check its {len(parsed.entries)} host(s) from ({rf.source} read)",
                           data={"hosts_file": rf.source, "hosts": []},
                           warnings=[str(f) for f in (*parsed.errors, *parsed.warnings)])
    link = RobotLink(ctx.transport, name)
    with ThreadPoolExecutor(max_workers=max(1, min(8, len(parsed.entries)))) as pool:
        checks = list(pool.map(lambda e: check_entry(link, name, e), parsed.entries))
    data: dict[str, Any] = {"hosts_file": rf.source, "hosts": [c.to_json() for c in checks]}
    warnings = [str(f) for f in parsed.warnings]
    errors = [str(f) for f in parsed.errors]
    bad = [c for c in checks if not c.ok]
    if errors:
        return RobotResult(name, Outcome.FAILED, f"the hosts file has errors: {'; '.join(errors)}", data=data,
                           warnings=warnings)
    if not checks:
        return RobotResult(name, Outcome.OK, f"no hosts in {rf.source}", data=data, warnings=warnings)
    if bad:
        msg = "; ".join(f"{c.host}: {c.step} failed" for c in bad)
        return RobotResult(name, Outcome.FAILED, f"{len(bad)} of {len(checks)} host(s) would not power off: {msg}",
                           data=data, warnings=warnings)
    return RobotResult(name, Outcome.OK, f"{len(checks)} host(s) would power off", data=data, warnings=warnings)
