"""The fleet inventory: robots, groups, defaults, per-robot desired configuration.

Found by ``-i PATH``, else ``$PANTHER_OPS_INVENTORY``, else ``./inventory/``. A path may be
one YAML file or a directory of them. Every error names the file, line and key and says
what is allowed (docs/inventory.md).
"""

from __future__ import annotations

import fnmatch
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.hostspec import HOST_FORMS, JUMP_FORMS, HostSpecError, check_host, parse_jump
from panther_ops.core.yaml.located import LineDict, LineList, load_yaml_file
from panther_ops.errors import InventoryError
from panther_ops.transport.base import Endpoint

ENV_VAR = "PANTHER_OPS_INVENTORY"
DEFAULT_FORKS = 32
"""Robots worked on at once unless --forks or settings.forks say otherwise."""
DEFAULT_DIR = "inventory"

ROBOT_KEYS = {
    "host": "IP address or hostname of the Built-in Computer (e.g. a Husarnet name)",
    "port": "SSH port (1-65535)",
    "user": "SSH user on the Built-in Computer (default husarion)",
    "identity_file": "private key for SSH (path; relative to the inventory file)",
    "jump": "jump host: another robot's name or user@host[:port]",
    "namespace": "the robot's ROS namespace",
    "stack": "stack version X.Y.Z, or auto (detected from the driver image)",
    "groups": "list of group names",
    "vars": "free-form per-robot variables",
    "desired": "the robot's desired configuration (see docs/inventory.md)",
    "transport": "ssh (default) or local (a directory standing in for the robot)",
    "root": "for transport local: the directory standing in for the robot's file system",
    "compose_file": "path of the compose file on the robot (default ~/compose.yaml)",
    "description": "free text",
    "connect_timeout": "seconds to wait for SSH to connect (default 10)",
    "user_computer": "the User Computer behind the robot: host (default 10.15.20.3), user, key, port",
}
DEFAULT_KEYS = set(ROBOT_KEYS) - {"host", "root", "description"}
SETTINGS_KEYS = {
    "ssh_config": "ssh_config file to read (default ~/.ssh/config)",
    "known_hosts": "known_hosts file(s) to verify host keys against (default ~/.ssh/known_hosts)",
    "forks": "how many robots to work on at once (default 32)",
    "command_timeout": "seconds a remote command may take (default 120)",
    "default_group": "the group read-only commands (status, config get, ...) answer for when none is chosen",
}
GROUP_KEYS = {"vars", "desired", "description"}
DESIRED_KEYS = {
    "launch_args": "mapping of launch argument -> value (e.g. wheel_type: WH02)",
    "controller": "mapping of controller limit -> value (e.g. linear.x.max_velocity: 1.5)",
    "image": "driver image, e.g. husarion/panther:humble-2.1.1-20240828",
    "webui": "WebUI snap settings (namespace, transport, layout, port, domain_id, ...)",
    "gps": "GPS settings (enabled, port, router)",
    "shutdown_hosts": "list of hosts the robot shuts down with itself",
    "manager": "runtime manager settings (enabled, ...)",
}
SECRET_NAME = re.compile(r"(password|passphrase|secret|token)$", re.IGNORECASE)
SECRET_FORMS = "{env: VARIABLE}, {file: PATH} or {prompt: true}"
POSIX_USER = re.compile(r"^[a-z_][a-z0-9_-]{0,31}\$?$")
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,62}$")
ROS_NAMESPACE = re.compile(r"^/?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$")
VERSION = re.compile(r"^\d+\.\d+\.\d+$")
HOST = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.:-]{0,252}$")
"""A host name or IP address: no whitespace, no leading '-', nothing a shell would read."""
USER_COMPUTER_KEYS = {
    "host": "IP address or hostname on the robot's LAN (default 10.15.20.3)",
    "user": "SSH user (default husarion)",
    "key": "private key for SSH (path; relative to the inventory file)",
    "port": "SSH port (default 22)",
}


@dataclass(frozen=True)
class UserComputer:
    """The robot's User Computer, reached through the robot (its LAN)."""

    host: str = "10.15.20.3"
    user: str = "husarion"
    key: str | None = None
    port: int = 22


@dataclass(frozen=True)
class Robot:
    """One robot of the fleet, with defaults and group values applied."""

    name: str
    host: str
    port: int | None = None
    user: str = "husarion"
    identity_file: str | None = None
    jump: str | None = None
    namespace: str | None = None
    stack: str = "auto"
    groups: tuple[str, ...] = ()
    vars: dict[str, Any] = field(default_factory=dict)
    desired: dict[str, Any] = field(default_factory=dict)
    transport: str = "ssh"
    root: Path | None = None
    compose_file: str = "~/compose.yaml"
    connect_timeout: float = 10.0
    source: str = ""
    """``file:line`` where the robot is defined."""
    user_computer: UserComputer | None = None


@dataclass
class Inventory:
    """A loaded, validated inventory."""

    path: Path
    origin: str
    robots: dict[str, Robot]
    groups: dict[str, dict[str, Any]]
    ssh_config: str | None = None
    known_hosts: tuple[str, ...] = ()
    forks: int = DEFAULT_FORKS
    command_timeout: float = 120.0
    files: tuple[Path, ...] = ()
    default_group: str | None = None
    """settings.default_group: what read-only commands answer for when no robot is chosen."""

    def endpoint(self, robot: Robot, _seen: tuple[str, ...] = ()) -> Endpoint:
        """How to reach ``robot`` (its jump host resolved, recursively)."""
        jump: Endpoint | None = None
        if robot.jump:
            if robot.jump in self.robots:
                if robot.jump in _seen:
                    raise InventoryError(f"jump hosts form a loop: {' -> '.join((*_seen, robot.jump))}",
                                         path=robot.source, key=f"robots.{robot.name}.jump")
                jump = self.endpoint(self.robots[robot.jump], (*_seen, robot.name))
            else:
                spec = parse_jump(robot.jump)
                jump = Endpoint(
                    name=f"{robot.name} (jump {spec.host})", host=spec.host, port=spec.port,
                    user=spec.user, ssh_config=self.ssh_config, known_hosts=self.known_hosts,
                    connect_timeout=robot.connect_timeout,
                )
        return Endpoint(
            name=robot.name,
            host=robot.host,
            port=robot.port,
            user=robot.user,
            identity_files=(robot.identity_file,) if robot.identity_file else (),
            jump=jump,
            connect_timeout=robot.connect_timeout,
            command_timeout=self.command_timeout,
            ssh_config=self.ssh_config,
            known_hosts=self.known_hosts,
        )

    def select(self, patterns: list[str], groups: list[str], all_robots: bool) -> list[Robot]:
        """Robots chosen by ``--robot`` globs, ``--group`` names or ``--all``.

        Raises:
            InventoryError: nothing chosen on a fleet of several robots, or a pattern or
                group that matches nothing.
        """
        if all_robots:
            return list(self.robots.values())
        if not patterns and not groups:
            if len(self.robots) == 1:
                return list(self.robots.values())
            raise InventoryError(
                f"{len(self.robots)} robots in the inventory: choose with --robot/-r NAME (globs "
                "allowed), --group/-g GROUP or --all",
                path=str(self.path),
                hint=f"robots: {', '.join(self.robots)}"
                + (f"; groups: {', '.join(self.groups)}" if self.groups else ""),
            )
        chosen: dict[str, Robot] = {}
        for pat in patterns:
            hits = [r for n, r in self.robots.items() if fnmatch.fnmatchcase(n, pat)]
            if not hits:
                raise InventoryError(
                    f"no robot matches --robot {pat!r}" + _did_you_mean(pat, self.robots), path=str(self.path),
                    hint=f"robots: {', '.join(self.robots)}",
                )
            chosen.update((r.name, r) for r in hits)
        for g in groups:
            if g not in self.groups:
                raise InventoryError(
                    f"no group {g!r}" + _did_you_mean(g, self.groups), path=str(self.path),
                    hint=f"groups: {', '.join(self.groups) or '(none defined)'}",
                )
            chosen.update((r.name, r) for r in self.robots.values() if g in r.groups)
        return [r for n, r in self.robots.items() if n in chosen]


def _did_you_mean(name: str, known: Any) -> str:
    import difflib

    close = difflib.get_close_matches(name, list(known), n=1)
    return f"; did you mean {close[0]!r}?" if close else ""


def find_inventory(explicit: str | None) -> tuple[Path, str]:
    """Which inventory to use, and why (shown to the operator)."""
    if explicit:
        return Path(explicit), "-i"
    env = os.environ.get(ENV_VAR)
    if env:
        return Path(env), f"${ENV_VAR}"
    return Path(DEFAULT_DIR), f"./{DEFAULT_DIR}/ (default)"


def load_inventory(explicit: str | None = None) -> Inventory:
    """Find, read and validate the inventory."""
    path, origin = find_inventory(explicit)
    if path.is_dir():
        files = sorted(p for p in path.iterdir() if p.suffix in (".yaml", ".yml") and p.is_file())
        if not files:
            raise InventoryError("no *.yaml files in the inventory directory", path=str(path),
                                 hint="create one, or run `panther-ops demo init` for a demo fleet")
    elif path.exists():
        files = [path]
    else:
        raise InventoryError(
            f"inventory not found (from {origin})", path=str(path),
            hint=f"pass -i FILE, set ${ENV_VAR}, or create ./{DEFAULT_DIR}/",
        )
    return _Loader(path, origin).load(files)


class _Loader:
    def __init__(self, path: Path, origin: str) -> None:
        self.path = path
        self.origin = origin
        self.settings: dict[str, Any] = {}
        self.defaults: dict[str, Any] = {}
        self.raw_robots: dict[str, tuple[LineDict, Path]] = {}
        self.groups: dict[str, dict[str, Any]] = {}
        self.default_group_at: tuple[Path, LineDict] | None = None

    def err(self, msg: str, file: Path, doc: LineDict | LineList | None, key: str, sub: str | None = None,
            hint: str | None = None) -> InventoryError:
        line = None
        if isinstance(doc, LineDict):
            line = doc.line_of(sub) if sub is not None else doc.line
        elif isinstance(doc, LineList):
            line = doc.line
        return InventoryError(msg, path=str(file), line=line, key=key, hint=hint)

    def load(self, files: list[Path]) -> Inventory:
        for f in files:
            self.read_file(f)
        if not self.raw_robots:
            raise InventoryError("the inventory defines no robots", path=str(self.path),
                                 hint="add a `robots:` mapping (docs/inventory.md)")
        robots = {name: self.robot(name, doc, f) for name, (doc, f) in self.raw_robots.items()}
        for r in robots.values():
            if r.jump and r.jump not in robots:
                try:
                    parse_jump(r.jump)
                except HostSpecError as exc:
                    doc, f = self.raw_robots[r.name]
                    raise self.err(f"{exc}: neither a robot of the inventory nor user@host[:port]",
                                   f, doc, f"robots.{r.name}.jump", "jump", hint=f"allowed: {JUMP_FORMS}") from None
            self.check_groups(r)
        inv = Inventory(
            path=self.path, origin=self.origin, robots=robots, groups=self.groups,
            ssh_config=self.settings.get("ssh_config"),
            known_hosts=tuple(self.settings.get("known_hosts", ())),
            forks=int(self.settings.get("forks", DEFAULT_FORKS)),
            command_timeout=float(self.settings.get("command_timeout", 120.0)),
            files=tuple(files),
            default_group=self.settings.get("default_group"),
        )
        if inv.default_group is not None and inv.default_group not in self.groups:
            assert self.default_group_at is not None
            f, s = self.default_group_at
            raise self.err(f"default_group {inv.default_group!r} is not a group of the inventory", f, s,
                           "settings.default_group", "default_group",
                           hint=f"groups: {', '.join(self.groups) or '(none defined)'}")
        for r in robots.values():
            if r.jump in robots:
                inv.endpoint(r)  # raises on loops
        return inv

    def read_file(self, f: Path) -> None:
        doc = load_yaml_file(f)
        if doc is None:
            return
        if not isinstance(doc, LineDict):
            raise InventoryError("the inventory must be a mapping with `robots:`", path=str(f), line=1)
        allowed = {"version", "settings", "defaults", "robots", "groups"}
        for key in doc:
            if key not in allowed:
                raise self.err(f"unknown top-level key {key!r}", f, doc, key, key,
                               hint=f"allowed: {', '.join(sorted(allowed))}")
        if doc.get("version", 1) != 1:
            raise self.err("unsupported inventory version", f, doc, "version", "version", hint="allowed: 1")
        _check_secrets(doc, f, "")
        if "settings" in doc:
            self.read_settings(doc["settings"], f, doc)
        if "defaults" in doc:
            d = self.mapping(doc["defaults"], f, doc, "defaults")
            for k in d:
                if k not in DEFAULT_KEYS:
                    raise self.err(f"{k!r} cannot be a fleet-wide default", f, d, f"defaults.{k}", k,
                                   hint=f"allowed: {', '.join(sorted(DEFAULT_KEYS))}")
            self.defaults.update(self.fields(d, f, "defaults"))
        self.read_groups(doc, f)
        robots = self.mapping(doc.get("robots", LineDict()), f, doc, "robots")
        for name, rdoc in robots.items():
            self.check_name(name, f, robots, f"robots.{name}")
            if name in self.raw_robots:
                raise self.err(f"robot {name!r} is defined twice (also in {self.raw_robots[name][1]})",
                               f, robots, f"robots.{name}", name)
            self.raw_robots[name] = (self.mapping(rdoc, f, robots, f"robots.{name}"), f)

    def read_groups(self, doc: LineDict, f: Path) -> None:
        for name, gdoc in self.mapping(doc.get("groups", LineDict()), f, doc, "groups").items():
            g = self.mapping(gdoc if gdoc is not None else LineDict(), f, doc["groups"], f"groups.{name}")
            self.check_name(name, f, doc["groups"], f"groups.{name}")
            for k in g:
                if k not in GROUP_KEYS:
                    raise self.err(f"unknown group key {k!r}", f, g, f"groups.{name}.{k}", k,
                                   hint=f"allowed: {', '.join(sorted(GROUP_KEYS))}")
            if "desired" in g:
                self.check_desired(g["desired"], f, g, f"groups.{name}.desired")
            self.groups[name] = dict(g)

    def read_settings(self, value: Any, f: Path, parent: LineDict) -> None:
        s = self.mapping(value, f, parent, "settings")
        for k, v in s.items():
            if k not in SETTINGS_KEYS:
                raise self.err(f"unknown setting {k!r}", f, s, f"settings.{k}", k,
                               hint=f"allowed: {', '.join(sorted(SETTINGS_KEYS))}")
            if k == "ssh_config":
                self.settings[k] = str(_rel(f, str(v)))
            elif k == "known_hosts":
                items = v if isinstance(v, list) else [v]
                self.settings[k] = [str(_rel(f, str(i))) for i in items]
            elif k == "forks":
                if not isinstance(v, int) or isinstance(v, bool) or not 1 <= v <= 500:
                    raise self.err("forks must be a whole number from 1 to 500", f, s, "settings.forks", k)
                self.settings[k] = v
            elif k == "command_timeout":
                if not _positive_seconds(v):
                    raise self.err(f"command_timeout {v!r} is not allowed", f, s, f"settings.{k}", k,
                                   hint="a finite number of seconds > 0, e.g. 120")
                self.settings[k] = float(v)
            elif k == "default_group":
                if not isinstance(v, str) or not v:
                    raise self.err("default_group must be a group name", f, s, f"settings.{k}", k)
                self.settings[k] = v
                self.default_group_at = (f, s)

    def mapping(self, value: Any, f: Path, parent: LineDict | LineList, key: str) -> LineDict:
        if value is None:
            out = LineDict()
            out.key_lines = {}
            out.line = parent.line
            return out
        if not isinstance(value, LineDict):
            sub = key.rsplit(".", 1)[-1]
            raise self.err(f"must be a mapping, got {type(value).__name__}", f, parent, key,
                           sub if isinstance(parent, LineDict) else None)
        return value

    def check_name(self, name: str, f: Path, parent: LineDict, key: str) -> None:
        if not NAME.match(name):
            raise self.err(f"name {name!r} is not allowed", f, parent, key, name,
                           hint="letters, digits, '.', '_' and '-', starting with a letter or digit")

    def fields(self, d: LineDict, f: Path, prefix: str) -> dict[str, Any]:
        """Validate the robot fields present in ``d``; returns them normalised."""
        out: dict[str, Any] = {}
        for k, v in d.items():
            if k not in ROBOT_KEYS:
                raise self.err(f"unknown key {k!r}", f, d, f"{prefix}.{k}", k, hint=", ".join(sorted(ROBOT_KEYS)))
            try:
                out[k] = self.field(k, v, f, d, f"{prefix}.{k}")
            except _Bad as bad:
                raise self.err(bad.message, f, d, f"{prefix}.{k}", k, hint=bad.hint) from None
        return out

    def field(self, k: str, v: Any, f: Path, d: LineDict, key: str) -> Any:
        """One robot field, checked and normalised (raises _Bad)."""
        if k in ("host", "jump", "identity_file", "compose_file", "description", "root"):
            if not isinstance(v, str) or not v.strip():
                raise _Bad(f"{k} must be a non-empty string")
            if k in ("host", "jump"):
                return _address(k, v)
            return str(_rel(f, v.strip())) if k in ("identity_file", "root") else v.strip()
        if k == "vars":
            return dict(self.mapping(v, f, d, key))
        if k == "desired":
            self.check_desired(v, f, d, key)
            return _plain(v)
        if k == "user_computer":
            return self.user_computer(v, f, d, key)
        return _SCALAR_FIELDS[k](v)

    def user_computer(self, v: Any, f: Path, parent: LineDict, key: str) -> UserComputer:
        d = self.mapping(v, f, parent, key)
        out: dict[str, Any] = {}
        for k, value in d.items():
            if k not in USER_COMPUTER_KEYS:
                raise self.err(f"unknown key {k!r}", f, d, f"{key}.{k}", k, hint=", ".join(sorted(USER_COMPUTER_KEYS)))
            try:
                if k == "host":
                    if not isinstance(value, str) or not HOST.match(value):
                        raise _Bad(f"host {value!r} is not a host name or IP address",
                                   "letters, digits, '.', ':', '_' and '-', not starting with '-' (e.g. 10.15.20.3)")
                    out[k] = value
                elif k == "key":
                    if not isinstance(value, str) or not value.strip():
                        raise _Bad("key must be a path to a private key")
                    out[k] = str(_rel(f, value.strip()))
                else:
                    out[k] = (_user if k == "user" else _port)(value)
            except _Bad as bad:
                raise self.err(bad.message, f, d, f"{key}.{k}", k, hint=bad.hint) from None
        return UserComputer(**out)

    def check_desired(self, value: Any, f: Path, parent: LineDict, key: str) -> None:
        d = self.mapping(value, f, parent, key)
        for k, v in d.items():
            if k not in DESIRED_KEYS:
                raise self.err(f"unknown desired setting {k!r}", f, d, f"{key}.{k}", k,
                               hint="allowed: " + ", ".join(sorted(DESIRED_KEYS)))
            if k in ("launch_args", "controller", "webui", "gps", "manager"):
                m = self.mapping(v, f, d, f"{key}.{k}")
                for sk, sv in m.items():
                    if isinstance(sv, (LineDict, LineList)) and k in ("launch_args", "controller"):
                        raise self.err(f"{k}.{sk} must be a single value", f, m, f"{key}.{k}.{sk}", sk)
                if k == "webui":
                    self.check_webui(m, f, f"{key}.{k}")
            elif k == "image" and (not isinstance(v, str) or ":" not in v):
                raise self.err("image must be REPOSITORY:TAG", f, d, f"{key}.image", k)
            elif k == "shutdown_hosts" and (
                not isinstance(v, LineList) or not all(isinstance(h, LineDict) for h in v)
            ):
                raise self.err("shutdown_hosts must be a list of mappings (ip, username, ...)",
                                   f, d, f"{key}.{k}", k)

    def check_webui(self, m: LineDict, f: Path, key: str) -> None:
        """desired.webui: the snap's keys (or their short names) with the configure hook's rules."""
        from panther_ops.core.remote.webui.settings import SettingError, validate

        for sk, sv in m.items():
            try:
                validate({sk: sv})
            except SettingError as bad:
                raise self.err(str(bad), f, m, f"{key}.{sk}", sk) from None

    def check_groups(self, robot: Robot) -> None:
        """Every group a robot names is declared under ``groups:`` (a typo would silently
        drop that group's settings)."""
        import difflib

        for g in robot.groups:
            if g in self.groups:
                continue
            doc, f = self.raw_robots[robot.name]
            close = difflib.get_close_matches(g, list(self.groups), n=1)
            raise self.err(
                f"group {g!r} is not declared under `groups:`" + (f"; did you mean {close[0]!r}?" if close else ""),
                f, doc, f"robots.{robot.name}.groups", "groups" if "groups" in doc else None,
                hint=f"declared groups: {', '.join(self.groups) or '(none)'}; declare it "
                f"(`groups: {{{g}: {{}}}}`) if it is a new group",
            )

    def robot(self, name: str, doc: LineDict, f: Path) -> Robot:
        own = self.fields(doc, f, f"robots.{name}")
        merged: dict[str, Any] = {**self.defaults, **own}
        groups = merged.get("groups", ())
        desired: dict[str, Any] = _deep_merge({}, self.defaults.get("desired", {}))
        vars_: dict[str, Any] = dict(self.defaults.get("vars", {}))
        for g in groups:
            gd = self.groups.get(g, {})
            desired = _deep_merge(desired, _plain(gd.get("desired", {})))
            vars_.update(_plain(gd.get("vars", {})))
        desired = _deep_merge(desired, own.get("desired", {}))
        vars_.update(own.get("vars", {}))
        transport = merged.get("transport", "ssh")
        if transport == "local":
            if "root" not in merged:
                raise self.err("a local robot needs `root:` (its stand-in directory)", f, doc,
                               f"robots.{name}.root")
            host = merged.get("host", "localhost")
        else:
            if "host" not in merged:
                raise self.err("missing `host:` (IP or hostname of the Built-in Computer)", f, doc,
                               f"robots.{name}.host",
                               hint="every Panther's internal address is 10.15.20.2: reach a fleet "
                               "by per-robot hostnames (e.g. Husarnet), a jump host or a forwarded port")
            host = merged["host"]
        return Robot(
            name=name, host=host, port=merged.get("port"), user=merged.get("user", "husarion"),
            identity_file=merged.get("identity_file"), jump=merged.get("jump"),
            namespace=merged.get("namespace"), stack=merged.get("stack", "auto"), groups=tuple(groups),
            vars=vars_, desired=desired, transport=transport,
            root=Path(merged["root"]) if "root" in merged else None,
            compose_file=merged.get("compose_file", "~/compose.yaml"),
            connect_timeout=merged.get("connect_timeout", 10.0),
            source=f"{f}:{doc.line}", user_computer=merged.get("user_computer"),
        )


class _Bad(Exception):
    def __init__(self, message: str, hint: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.hint = hint


def _port(v: Any) -> int:
    if not isinstance(v, int) or isinstance(v, bool) or not 1 <= v <= 65535:
        raise _Bad(f"port {v!r} is not a TCP port", "a whole number from 1 to 65535")
    return v


def _timeout(v: Any) -> float:
    if not _positive_seconds(v):
        raise _Bad(f"connect_timeout {v!r} is not allowed", "a finite number of seconds > 0, e.g. 10")
    return float(v)


def _positive_seconds(v: Any) -> bool:
    """A finite number > 0 (not a bool, not .nan or .inf)."""
    import math

    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0


def _address(k: str, v: str) -> str:
    """A robot's ``host`` (an address or hostname) or ``jump`` (a robot name or a jump spec)."""
    try:
        if k == "host":
            return check_host(v)
        if NAME.match(v):
            return v  # a robot of the inventory, or a bare hostname: checked once all robots are read
        parse_jump(v)
        return v
    except HostSpecError as exc:
        if k == "host":
            raise _Bad(str(exc), f"allowed: {HOST_FORMS}") from None
        raise _Bad(f"{exc}: neither a robot of the inventory nor user@host[:port]", f"allowed: {JUMP_FORMS}") from None


def _user(v: Any) -> str:
    if not isinstance(v, str) or not POSIX_USER.match(v):
        raise _Bad(f"user {v!r} is not a POSIX user name", "lowercase letters, digits, '_' and '-'")
    return v


def _namespace(v: Any) -> str:
    if not isinstance(v, str) or not ROS_NAMESPACE.match(v):
        raise _Bad(f"namespace {v!r} is not a ROS namespace", "letters, digits and '_', e.g. panther")
    return v


def _stack(v: Any) -> str:
    if not isinstance(v, str) or not (v == "auto" or VERSION.match(v)):
        raise _Bad(f"stack {v!r} is not allowed", "auto, or a version such as 2.1.1 or 2.2.2")
    if v != "auto":
        from panther_ops.core.fleet.stack import stack_from_version
        from panther_ops.errors import RemoteStateError

        try:
            stack_from_version(v)
        except RemoteStateError as exc:
            raise _Bad(exc.message, exc.hint) from None
    return v


def _groups(v: Any) -> tuple[str, ...]:
    if not isinstance(v, list) or not all(isinstance(g, str) and NAME.match(g) for g in v):
        raise _Bad("groups must be a list of group names")
    return tuple(v)


def _transport(v: Any) -> str:
    if v not in ("ssh", "local"):
        raise _Bad(f"transport {v!r} is not allowed", "ssh or local")
    return str(v)


_SCALAR_FIELDS: dict[str, Any] = {
    "port": _port,
    "connect_timeout": _timeout,
    "user": _user,
    "namespace": _namespace,
    "stack": _stack,
    "groups": _groups,
    "transport": _transport,
}


def _rel(f: Path, value: str) -> Path:
    p = Path(os.path.expanduser(value))
    return p if p.is_absolute() else (f.parent / p).resolve()


def _plain(v: Any) -> Any:
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_plain(x) for x in v]
    return v


def _deep_merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for k, v in over.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = _deep_merge(out[k], v)
        else:
            out[k] = v
    return out


def _check_secrets(node: Any, f: Path, key: str) -> None:
    """Refuse plaintext secrets anywhere in the inventory."""
    if isinstance(node, LineDict):
        for k, v in node.items():
            path = f"{key}.{k}" if key else k
            if SECRET_NAME.search(k) and not _is_secret_ref(v):
                raise InventoryError(
                    "plaintext secrets are not allowed in the inventory", path=str(f),
                    line=node.line_of(k), key=path, hint=f"write it as {SECRET_FORMS}",
                )
            _check_secrets(v, f, path)
    elif isinstance(node, LineList):
        for i, v in enumerate(node):
            _check_secrets(v, f, f"{key}[{i}]")


def _is_secret_ref(v: Any) -> bool:
    if not isinstance(v, dict) or len(v) != 1:
        return False
    (k, val), = v.items()
    return (k in ("env", "file") and isinstance(val, str)) or (k == "prompt" and val is True)
