"""The shutdown hosts file: read, validate and edit it (comments and layout kept).

Two formats, as the Panther manager reads them (panther-stack.md §1.8, §1.11):

* SSH (panther_ros 2.0.0 - husarion_ugv 2.2.0): ``ip`` and ``username`` required, ``port``
  22, ``command`` "sudo shutdown now", ``timeout`` 5.0 s, ``ping_for_success`` true.
* HTTP (husarion_ugv 2.2.1+, husarion-shutdown on the host): ``ip`` required, ``port`` 3003,
  ``secret`` "husarion" (shared HMAC key), ``timeout`` 5.0 s.

An entry with ``username`` is SSH, one without is HTTP. Validation is stricter than the
manager (which skips what it cannot use): every problem of a file is reported with its line,
errors stop a command before anything runs (exit 2), warnings are shown.

A local file may hold the secret as ``secret: {env: VARIABLE}`` or ``{file: PATH}`` (PATH
relative to the hosts file), resolved only when the hosts are used; the robot's own file
holds the value itself, since the manager reads it.

Size (~575 lines): the file kind's one model: both formats, their validation and their
edits share the entry rules, so the validator and the editor cannot drift apart.
"""

from __future__ import annotations

import ipaddress
import math
import os
import re
import shlex
import unicodedata
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

from panther_ops.core.yaml.document import DocumentError, Flow, YamlDocument
from panther_ops.errors import InputError, UsageError
from panther_ops.manager.shutdown_executor.hosts import ShutdownHost
from panther_ops.secret import Secret

DEFAULT_COMMAND = "sudo shutdown now"
DEFAULT_TIMEOUT = 5.0
DEFAULT_SSH_PORT = 22
DEFAULT_HTTP_PORT = 3003
DEFAULT_SECRET = "husarion"

POWER_BUDGET_S = 15.0
"""Seconds the robot gives its computers before power is cut. The manual only says "hardware
will cut power off after a given time after pressing the power button"; 15 s is the
manager's ``shutdown_timeout`` (panther_ros 2.0.0 manager_bt_config.yaml) and the ROS 1
shutdown node's wait before "Cutting out power from computers". Override with --power-budget."""

SSH_KEYS = ("ip", "username", "port", "command", "timeout", "ping_for_success")
HTTP_KEYS = ("ip", "port", "secret", "timeout")
POSIX_USER = re.compile(r"^[a-z_][a-z0-9_-]{0,31}\$?$")
_LABEL = r"[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?"
HOSTNAME = re.compile(rf"^{_LABEL}(?:\.{_LABEL})*\.?$")
_POWER_OFF = {"shutdown", "poweroff"}


class Mode(str, Enum):
    """Which manager reads the file: SSH (<= 2.2.0) or HTTP (2.2.1+)."""

    SSH = "ssh"
    HTTP = "http"


@dataclass(frozen=True)
class Finding:
    """One problem of a hosts file."""

    level: str  # "error" | "warning"
    where: str
    message: str
    line: int | None = None

    def __str__(self) -> str:
        at = f"{self.where} (line {self.line})" if self.line else self.where
        return f"{at}: {self.message}"


@dataclass(frozen=True)
class SecretRef:
    """Where a local file's secret comes from: a value, ``{env: NAME}`` or ``{file: PATH}``."""

    kind: str  # "value" | "env" | "file" | "default"
    value: str = field(default="", repr=False)

    def describe(self) -> str:
        if self.kind == "env":
            return f"env {self.value}"
        if self.kind == "file":
            return f"file {self.value}"
        return "default (husarion)" if self.kind == "default" else "****"

    def resolve(self, base: Path | None) -> Secret:
        if self.kind == "default":
            return Secret(DEFAULT_SECRET)
        if self.kind == "value":
            return Secret(self.value)
        if self.kind == "env":
            got = os.environ.get(self.value)
            if got is None:
                raise UsageError(f"secret: environment variable {self.value} is not set")
            return Secret(got)
        path = Path(os.path.expanduser(self.value))
        if not path.is_absolute() and base is not None:
            path = base / path
        try:
            return Secret(path.read_text().strip())
        except OSError as exc:
            raise UsageError(f"secret: cannot read {path}: {exc.strerror}") from None


@dataclass(frozen=True)
class HostEntry:
    """One valid entry of the file (defaults applied)."""

    index: int
    ip: str
    username: str | None
    port: int
    command: str
    timeout: float
    ping_for_success: bool
    secret: SecretRef | None

    @property
    def http(self) -> bool:
        return self.username is None

    @property
    def key(self) -> tuple[str, str, int]:
        return (self.ip, self.username or "", self.port)

    def describe(self) -> str:
        return f"http://{self.ip}:{self.port}" if self.http else f"{self.username}@{self.ip}:{self.port}"

    def host(self, base: Path | None = None) -> ShutdownHost:
        """The executor's host (secret resolved; raises UsageError if it cannot be)."""
        secret = (self.secret or SecretRef("default")).resolve(base).reveal() if self.http else None
        return ShutdownHost(ip=self.ip, username=self.username, port=self.port, command=self.command,
                            timeout=self.timeout, ping_for_success=self.ping_for_success, secret=secret)

    def row(self) -> dict[str, Any]:
        """For tables and JSON: never the secret itself."""
        out: dict[str, Any] = {"ip": self.ip, "method": "http" if self.http else "ssh", "port": self.port,
                               "timeout": self.timeout}
        if self.http:
            out["secret"] = (self.secret or SecretRef("default")).describe()
        else:
            out.update(username=self.username, command=self.command, ping_for_success=self.ping_for_success)
        return out


@dataclass
class HostsFile:
    """A parsed and validated hosts file."""

    source: str
    text: str
    entries: list[HostEntry]
    findings: list[Finding]
    base: Path | None = None

    @property
    def errors(self) -> list[Finding]:
        return [f for f in self.findings if f.level == "error"]

    @property
    def warnings(self) -> list[Finding]:
        return [f for f in self.findings if f.level == "warning"]

    def raise_errors(self) -> None:
        """UsageError (exit 2) naming every error."""
        if self.errors:
            lines = "\n  ".join(str(f) for f in self.errors)
            raise InputError(f"{len(self.errors)} error(s):\n  {lines}", path=self.source,
                             hint="fix the file; nothing was run")

    def hosts(self) -> list[ShutdownHost]:
        self.raise_errors()
        return [e.host(self.base) for e in self.entries]


# ---------------------------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------------------------
def valid_address(value: str) -> bool:
    """An IPv4/IPv6 address or a DNS host name (nothing a shell would read specially)."""
    try:
        ipaddress.ip_address(value)
        return True
    except ValueError:
        pass
    if re.fullmatch(r"[0-9.]+", value):
        return False  # looks like an address but is not one (999.1.1.1, 10.15.20)
    return bool(HOSTNAME.match(value)) and len(value) <= 253


def is_power_off_command(command: str) -> bool:
    """`[sudo [-n]] [/usr]/sbin/]shutdown [-h|-P|now|+0...]`, `poweroff`, `systemctl poweroff`."""
    try:
        words = shlex.split(command)
    except ValueError:
        return False
    if words[:1] == ["sudo"]:
        words = words[1:]
        while words and words[0].startswith("-") and words[0] in ("-n", "--non-interactive"):
            words = words[1:]
    if not words:
        return False
    name = os.path.basename(words[0])
    rest = words[1:]
    if name == "systemctl":
        return rest in (["poweroff"], ["poweroff", "-i"], ["-i", "poweroff"])
    if name not in _POWER_OFF:
        return False
    bad = {"-r", "--reboot", "-H", "--halt", "-c", "-k"}
    return not any(w in bad for w in rest)


def chain_operators(command: str) -> list[str]:
    """The shell's control operators in ``command`` outside quotes and comments (``;``, ``&&``,
    ``||``, ``|``, ``&``...), in order, once each; ``2>&1``, ``&>`` and ``>|`` are redirections."""
    ops: list[str] = []
    quote = ""
    i = 0
    while i < len(command):
        c = command[i]
        if c == "\\" and quote != "'":
            i += 2
            continue
        if quote:
            quote = "" if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c == "#" and (i == 0 or command[i - 1].isspace()):
            break
        elif c in ";&|":
            j = i
            while j < len(command) and command[j] in ";&|":
                j += 1
            op = command[i:j]
            after = command[j:j + 1]
            redirect = (op in ("&", "|") and i > 0 and command[i - 1] in "<>") or (op == "&" and after == ">")
            if not redirect:
                ops.append(op)
            i = j
            continue
        i += 1
    return list(dict.fromkeys(ops))


def _unprintable(text: str) -> str | None:
    """The first control or invisible character of ``text`` (a tab is a space to a shell)."""
    return next((c for c in text if c != "\t" and unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp")), None)


def _number(value: Any) -> float | None:
    """A number of seconds: a YAML number or its text in ASCII digits (`core.parse.numbers`)."""
    from panther_ops.core.parse.numbers import NumberError, decimal

    try:
        return decimal(value.strip() if isinstance(value, str) else value)
    except NumberError:
        return None


def _port(value: Any) -> int | None:
    """A port: a YAML integer or its text in ASCII digits, 1-65535 (the manager's int())."""
    from panther_ops.core.parse.numbers import NumberError, port

    try:
        return port(value.strip() if isinstance(value, str) else value)
    except NumberError:
        return None


class _Checker:
    def __init__(self, doc: YamlDocument | None, mode: Mode | None, power_budget: float, allow_refs: bool) -> None:
        self.doc = doc
        self.mode = mode
        self.budget = power_budget
        self.allow_refs = allow_refs
        self.findings: list[Finding] = []

    def add(self, level: str, where: str, message: str, path: str | None = None) -> None:
        line = self.doc.line_of(path) if (self.doc is not None and path is not None) else None
        self.findings.append(Finding(level, where, message, line))

    def entry(self, i: int, raw: Any) -> HostEntry | None:
        where, path = f"hosts[{i}]", f"hosts.{i}"
        if not isinstance(raw, Mapping):
            self.add("error", where, "must be a mapping (ip, username, ...)", path)
            return None
        http = not raw.get("username") and "username" not in raw
        ok = self.keys(raw, http, where, path)
        ip = raw.get("ip")
        if ip is None or ip == "":
            self.add("error", where, "ip is required", path)
            ok = False
        elif not isinstance(ip, str) or not valid_address(ip):
            self.add("error", f"{where}.ip", f"{ip!r} is not an IP address or host name", f"{path}.ip")
            ok = False
        user = raw.get("username")
        if not http and (not isinstance(user, str) or not POSIX_USER.match(user)):
            self.add("error", f"{where}.username", f"{user!r} is not a POSIX user name (lowercase letters, digits, "
                     "'_' and '-', starting with a letter or '_')", f"{path}.username")
            ok = False
        port = self.port(raw, http, where, path)
        timeout = self.timeout(raw, where, path)
        command = self.command(raw, http, where, path)
        pfs = raw.get("ping_for_success", True)
        if isinstance(pfs, str) and pfs.lower() in ("true", "false"):
            pfs = pfs.lower() == "true"
        if not isinstance(pfs, bool):
            self.add("error", f"{where}.ping_for_success", f"{pfs!r} is not true or false", f"{path}.ping_for_success")
            ok = False
        secret = self.secret(raw, http, where, path)
        if self.mode is Mode.HTTP and not http:
            self.add("error", where, "this robot (husarion_ugv 2.2.1+) shuts computers down over HTTP "
                     "(husarion-shutdown, port 3003): username/command are not used and the host would get an "
                     "HTTP request on its port; write ip, port, secret, timeout", path)
            ok = False
        if self.mode is Mode.SSH and http:
            self.add("error", where, "no username: this robot's manager (<= 2.2.0, SSH) skips the entry", path)
            ok = False
        if not ok or port is None or timeout is None or command is None or secret is False:
            return None
        if timeout > self.budget:
            self.add("warning", f"{where}.timeout", f"{timeout:g} s is longer than the ~{self.budget:g} s the robot's "
                     "hardware gives before it cuts the power: the host may lose power while still shutting down",
                     f"{path}.timeout")
        assert isinstance(ip, str) and isinstance(pfs, bool)
        return HostEntry(i, ip, None if http else str(user), port, command, timeout, pfs,
                         secret if isinstance(secret, SecretRef) else None)

    def keys(self, raw: Mapping[str, Any], http: bool, where: str, path: str) -> bool:
        allowed = HTTP_KEYS if http else SSH_KEYS
        ok = True
        for k in raw:
            if k not in SSH_KEYS and k not in HTTP_KEYS:
                known = ", ".join(sorted(set(SSH_KEYS) | set(HTTP_KEYS)))
                self.add("error", f"{where}.{k}", f"unknown key (allowed: {known})", f"{path}.{k}")
                ok = False
            elif k not in allowed:
                what = "HTTP (no username)" if http else "SSH (has a username)"
                self.add("error", f"{where}.{k}", f"not a key of an {what} entry: an entry is either SSH "
                         "(ip, username, port, command, timeout, ping_for_success) or HTTP (ip, port, secret, timeout)",
                         f"{path}.{k}")
                ok = False
        return ok

    def command(self, raw: Mapping[str, Any], http: bool, where: str, path: str) -> str | None:
        command = raw.get("command", DEFAULT_COMMAND)
        bad = _unprintable(command) if isinstance(command, str) else None
        if not isinstance(command, str) or not command.strip() or bad is not None:
            held = f" (it holds {bad!r}, U+{ord(bad):04X})" if bad is not None else ""
            self.add("error", f"{where}.command", f"must be a one-line command of printable text{held}",
                     f"{path}.command")
            return None
        ops = [] if http else chain_operators(command)
        if ops:
            self.add("warning", f"{where}.command", f"{command!r} chains commands with "
                     f"{', '.join(repr(o) for o in ops)}: the host's login shell runs them all and the manager sees "
                     "only the last one's exit status (after && or || the shutdown depends on the command before it; "
                     "sudo asks a password for what the manual's sudoers line does not allow); put the sequence in a "
                     "script on the host and name it here, as the manual does (/home/pi/my_long_shutdown_sequence.sh)",
                     f"{path}.command")
        elif not http and not is_power_off_command(command):
            self.add("warning", f"{where}.command", f"{command!r} is not a shutdown/poweroff command: make sure it "
                     "powers the host off (and that sudo allows it without a password)", f"{path}.command")
        return command

    def port(self, raw: Mapping[str, Any], http: bool, where: str, path: str) -> int | None:
        value = raw.get("port", DEFAULT_HTTP_PORT if http else DEFAULT_SSH_PORT)
        n = _port(value)
        if n is None:
            self.add("error", f"{where}.port", f"{value!r} is not a TCP port (1-65535, ASCII digits)", f"{path}.port")
        return n

    def timeout(self, raw: Mapping[str, Any], where: str, path: str) -> float | None:
        value = raw.get("timeout", DEFAULT_TIMEOUT)
        n = _number(value)
        if n is None or not math.isfinite(n) or n <= 0:
            self.add("error", f"{where}.timeout", f"{value!r} is not a number of seconds > 0", f"{path}.timeout")
            return None
        return n

    def secret(self, raw: Mapping[str, Any], http: bool, where: str, path: str) -> SecretRef | bool | None:
        if not http:
            return None
        if "secret" not in raw:
            self.add("warning", f"{where}.secret", "no secret: the default 'husarion' is used, which anyone who "
                     "knows the default can use to power the host off", path)
            return SecretRef("default")
        value = raw["secret"]
        if isinstance(value, Mapping) and len(value) == 1:
            (k, v), = value.items()
            if k in ("env", "file") and isinstance(v, str) and v:
                if not self.allow_refs:
                    self.add("error", f"{where}.secret", f"{{{k}: ...}} is for local files: the robot's manager "
                             "needs the secret itself", f"{path}.secret")
                    return False
                return SecretRef(k, v)
        if isinstance(value, (str, int)) and not isinstance(value, bool) and str(value):
            if str(value) == DEFAULT_SECRET:
                self.add("warning", f"{where}.secret", "the default secret 'husarion': anyone who knows the default "
                         "can power the host off", f"{path}.secret")
            return SecretRef("value", str(value))
        self.add("error", f"{where}.secret", "must be a non-empty string, {env: NAME} or {file: PATH}",
                 f"{path}.secret")
        return False


def parse_hosts(text: str, source: str = "<hosts>", *, mode: Mode | None = None,
                power_budget: float = POWER_BUDGET_S, allow_refs: bool = True, base: Path | None = None) -> HostsFile:
    """Parse and validate a hosts file's text (never raises for bad content: see `findings`)."""
    try:
        doc: YamlDocument | None = YamlDocument.load(text, source)
    except DocumentError as exc:
        return HostsFile(source, text, [], [Finding("error", "file", f"not valid YAML: {exc.message}",
                                                      getattr(exc, "line", None))], base)
    assert doc is not None
    check = _Checker(doc, mode, power_budget, allow_refs)
    plain = doc.to_plain()
    entries: list[HostEntry] = []
    if plain is None:
        plain = {}
    if not isinstance(plain, Mapping):
        check.add("error", "file", "must be a mapping with a 'hosts' list")
        return HostsFile(source, text, [], check.findings, base)
    for k in plain:
        if k != "hosts":
            check.add("warning", str(k), "unknown top-level key: the manager reads only 'hosts'", str(k))
    raw_hosts = plain.get("hosts")
    if raw_hosts is None or raw_hosts == []:
        check.add("warning", "hosts", "no hosts: nothing is shut down with the robot (the manager reports a failure "
                  "and goes on with the robot itself)")
        raw_hosts = []
    if not isinstance(raw_hosts, list):
        check.add("error", "hosts", "must be a list of hosts", "hosts")
        return HostsFile(source, text, [], check.findings, base)
    seen: dict[tuple[str, str, int], int] = {}
    for i, raw in enumerate(raw_hosts):
        entry = check.entry(i, raw)
        if entry is None:
            continue
        if entry.key in seen:
            check.add("error", f"hosts[{i}]", f"duplicate of hosts[{seen[entry.key]}] ({entry.describe()})",
                      f"hosts.{i}")
            continue
        seen[entry.key] = i
        entries.append(entry)
    return HostsFile(source, text, entries, check.findings, base)


def load_hosts_file(path: Path, *, mode: Mode | None = None, power_budget: float = POWER_BUDGET_S) -> HostsFile:
    """Read and validate a local hosts file (UsageError when it cannot be read)."""
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror}", path=str(path)) from None
    except UnicodeDecodeError:
        raise InputError("not a text file", path=str(path)) from None
    return parse_hosts(text, str(path), mode=mode, power_budget=power_budget, base=path.parent)


# ---------------------------------------------------------------------------------------------
# edits (round trip: comments, order and layout of everything else stay byte for byte)
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Edit:
    text: str
    changed: bool
    message: str


def new_entry(ip: str, *, username: str | None = None, port: int | None = None, command: str | None = None,
              timeout: float | None = None, ping_for_success: bool = True,
              secret: str | dict[str, str] | None = None) -> dict[str, Any]:
    """The mapping to write for a host: only what differs from the defaults (ip, username
    for SSH; ip, port for HTTP, as the shipped files write them)."""
    entry: dict[str, Any] = {"ip": ip}
    if username is not None:
        entry["username"] = username
        if port is not None and port != DEFAULT_SSH_PORT:
            entry["port"] = port
        if command is not None and command != DEFAULT_COMMAND:
            entry["command"] = command
        if timeout is not None:
            entry["timeout"] = float(timeout)
        if not ping_for_success:
            entry["ping_for_success"] = False
        return entry
    entry["port"] = port if port is not None else DEFAULT_HTTP_PORT
    if secret is not None:
        entry["secret"] = secret
    if timeout is not None:
        entry["timeout"] = float(timeout)
    return entry


def check_entry(entry: Mapping[str, Any], mode: Mode | None = None,
                power_budget: float = POWER_BUDGET_S) -> list[Finding]:
    """Validate one new entry on its own (before any file or robot is touched)."""
    check = _Checker(None, mode, power_budget, allow_refs=True)
    check.entry(0, entry)
    return [Finding(f.level, f.where.replace("hosts[0]", "host", 1), f.message) for f in check.findings]


def _key_of(raw: Any) -> tuple[str, str, int] | None:
    if not isinstance(raw, Mapping):
        return None
    http = "username" not in raw
    n = _port(raw.get("port", DEFAULT_HTTP_PORT if http else DEFAULT_SSH_PORT))
    return (str(raw.get("ip")), "" if http else str(raw.get("username")), n if n is not None else -1)


def _load(text: str, source: str) -> YamlDocument:
    try:
        return YamlDocument.load(text, source)
    except DocumentError as exc:
        raise InputError(f"not valid YAML: {exc.message}", path=source) from None


def add_host(text: str, entry: Mapping[str, Any], source: str = "<hosts>") -> Edit:
    """Add `entry` (or update the listed host with the same ip, user and port)."""
    doc = _load(text, source)
    plain = doc.to_plain()
    if plain is not None and not isinstance(plain, Mapping):
        raise InputError("must be a mapping with a 'hosts' list", path=source)
    hosts = (plain or {}).get("hosts")
    want = _key_of(entry)
    label = f"{entry.get('username')}@{entry['ip']}" if "username" in entry else f"http://{entry['ip']}"
    written = {k: Flow(v) if isinstance(v, Mapping) else v for k, v in entry.items()}  # {env: X} on one line
    if not hosts:
        doc.set("hosts", [written])
        return Edit(doc.text, True, f"added {label}")
    if not isinstance(hosts, list):
        raise InputError("'hosts' must be a list", path=source)
    for i, raw in enumerate(hosts):
        if _key_of(raw) == want:
            changed = []
            for k, v in entry.items():
                if raw.get(k) != v:
                    doc.set(f"hosts.{i}.{k}", written[k])
                    changed.append(k)
            if not changed:
                return Edit(text, False, f"{label} is already listed")
            return Edit(doc.text, True, f"updated {label}: {', '.join(changed)}")
    doc.append("hosts", written)
    return Edit(doc.text, True, f"added {label}")


def remove_host(text: str, ip: str, username: str | None = None, port: int | None = None,
                source: str = "<hosts>") -> Edit:
    """Remove every entry of `ip` (narrowed by username and port when given)."""
    doc = _load(text, source)
    plain = doc.to_plain()
    hosts = plain.get("hosts") if isinstance(plain, Mapping) else None
    if not isinstance(hosts, list):
        return Edit(text, False, f"{ip} is not listed")
    drop = []
    for i, raw in enumerate(hosts):
        key = _key_of(raw)
        if key is None or key[0] != ip:
            continue
        if username is not None and key[1] != username:
            continue
        if port is not None and key[2] != port:
            continue
        drop.append(i)
    if not drop:
        return Edit(text, False, f"{ip} is not listed")
    for i in reversed(drop):
        doc.delete(f"hosts.{i}")
    return Edit(doc.text, True, f"removed {len(drop)} entr{'y' if len(drop) == 1 else 'ies'} of {ip}")


def converge_hosts(text: str, entries: list[Mapping[str, Any]], source: str = "<hosts>") -> Edit:
    """The file listing exactly ``entries`` (``desired.shutdown_hosts``): a listed host that is
    not among them removed, each of them added or updated in place (comments and the layout of
    the rest kept). The message names what changed."""
    want = {_key_of(e) for e in entries}
    doc = _load(text, source)
    plain = doc.to_plain()
    hosts = plain.get("hosts") if isinstance(plain, Mapping) else None
    removed: list[str] = []
    current = text
    if isinstance(hosts, list):
        for raw in hosts:
            key = _key_of(raw)
            if key is not None and key not in want:
                ip, user, port = key
                edit = remove_host(current, ip, user or None, port, source)
                if edit.changed:
                    current = edit.text
                    removed.append(f"{user}@{ip}" if user else f"http://{ip}")
    said: list[str] = [f"removed {', '.join(removed)}"] if removed else []
    for entry in entries:
        edit = add_host(current, entry, source)
        if edit.changed:
            current = edit.text
            said.append(edit.message)
    if not said:
        return Edit(text, False, "hosts as desired")
    return Edit(current, True, "; ".join(said))
