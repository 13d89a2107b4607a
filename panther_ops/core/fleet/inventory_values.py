"""The values of an inventory: the keys each block allows and the check of each value."""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.hostspec import HOST_FORMS, JUMP_FORMS, HostSpecError, check_host, parse_jump
from panther_ops.core.parse.ros_names import RosNameError, namespace
from panther_ops.core.yaml.located import LineDict, LineList
from panther_ops.errors import InventoryError

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
    "forks": "how many robots to work on at once (default 100)",
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
    "manager": "runtime manager settings (enabled, mode, scenario, params, shutdown_hosts)",
}


SECRET_NAME = re.compile(r"(password|passphrase|secret|token)$", re.IGNORECASE)


SECRET_FORMS = "{env: VARIABLE}, {file: PATH} or {prompt: true}"


POSIX_USER = re.compile(r"^[a-z_][a-z0-9_-]{0,31}\$?$")


NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,62}$")


VERSION = re.compile(r"^[0-9]+\.[0-9]+\.[0-9]+$")


HOST = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.:-]{0,252}$")
"""A host name or IP address: no whitespace, no leading '-', nothing a shell would read."""


USER_COMPUTER_KEYS = {
    "host": "IP address or hostname on the robot's LAN (default 10.15.20.3)",
    "user": "SSH user (default husarion)",
    "key": "private key for SSH (path; relative to the inventory file)",
    "port": "SSH port (default 22)",
}


class BadValue(Exception):
    def __init__(self, message: str, hint: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.hint = hint


def port_value(v: Any) -> int:
    if not isinstance(v, int) or isinstance(v, bool) or not 1 <= v <= 65535:
        raise BadValue(f"port {v!r} is not a TCP port", "a whole number from 1 to 65535")
    return v


def timeout_value(v: Any) -> float:
    if not positive_seconds(v):
        raise BadValue(f"connect_timeout {v!r} is not allowed", "a finite number of seconds > 0, e.g. 10")
    return float(v)


def positive_seconds(v: Any) -> bool:
    """A finite number > 0 (not a bool, not .nan or .inf)."""
    import math

    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0


def address_value(k: str, v: str) -> str:
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
            raise BadValue(str(exc), f"allowed: {HOST_FORMS}") from None
        raise BadValue(f"{exc}: neither a robot of the inventory nor user@host[:port]",
                       f"allowed: {JUMP_FORMS}") from None


def user_value(v: Any) -> str:
    if not isinstance(v, str) or not POSIX_USER.match(v):
        raise BadValue(f"user {v!r} is not a POSIX user name", "lowercase letters, digits, '_' and '-'")
    return v


def namespace_value(v: Any) -> str:
    """A robot's ROS namespace, by the one parser of ROS names (the global one: leave it out)."""
    if v in ("", "/"):
        raise BadValue(f"namespace {v!r} is not a ROS namespace", "for the global namespace leave namespace out")
    try:
        return namespace(v)
    except RosNameError as exc:
        raise BadValue(f"namespace {v!r}: {exc}", "letters, digits and '_' in tokens separated by '/', "
                                                  "e.g. panther") from None


def stack_value(v: Any) -> str:
    if not isinstance(v, str) or not (v == "auto" or VERSION.match(v)):
        raise BadValue(f"stack {v!r} is not allowed", "auto, or a version such as 2.1.1 or 2.2.2")
    if v != "auto":
        from panther_ops.core.stack import stack_from_version
        from panther_ops.errors import RemoteStateError

        try:
            stack_from_version(v)
        except RemoteStateError as exc:
            raise BadValue(exc.message, exc.hint) from None
    return v


def groups_value(v: Any) -> tuple[str, ...]:
    if not isinstance(v, list) or not all(isinstance(g, str) and NAME.match(g) for g in v):
        raise BadValue("groups must be a list of group names")
    return tuple(v)


def transport_value(v: Any) -> str:
    if v not in ("ssh", "local"):
        raise BadValue(f"transport {v!r} is not allowed", "ssh or local")
    return str(v)


def relative_to(f: Path, value: str) -> Path:
    p = Path(os.path.expanduser(value))
    return p if p.is_absolute() else (f.parent / p).resolve()


def plain(v: Any) -> Any:
    if isinstance(v, dict):
        return {k: plain(x) for k, x in v.items()}
    if isinstance(v, list):
        return [plain(x) for x in v]
    return v


def deep_merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for k, v in over.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = deep_merge(out[k], v)
        else:
            out[k] = v
    return out


def setting_name(block: str, key: str) -> str:
    """The one name of a setting of ``desired.<block>`` that can be written several ways
    (``desired.webui``: ``port`` is ``webui.port``; ``desired.controller``:
    ``linear.x.max_velocity`` is ``controller.linear.x.max_velocity``; ``desired.launch_args``:
    ``led_config_file`` is ``animations_config_path``, one catalogue key); other blocks' keys,
    and keys that are not a setting (refused where they are used), as they are."""
    if block == "webui":
        from panther_ops.core.kinds.webui_settings import SettingError, canonical_key

        try:
            return canonical_key(key)
        except SettingError:
            return key
    if block == "launch_args":
        from panther_ops.core.kinds.arg_catalogue import catalogue_key

        return catalogue_key(key) or key
    if block == "controller":
        from panther_ops.core.kinds.controller_limits import ControllerError, parse_limit_key

        try:
            return parse_limit_key(key).dotted
        except ControllerError:
            return key
    return key


def merge_desired(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    """``over``'s desired block (a robot's, a group's) over ``base``: `deep_merge`, where a
    setting ``over`` names one way replaces the same setting ``base`` names another way (a
    group's ``port`` and a robot's ``webui.port``: the robot's is the one kept)."""
    out = deep_merge(base, over)
    for block, given in over.items():
        before = base.get(block)
        if isinstance(given, dict) and isinstance(before, dict):
            names = {setting_name(block, k) for k in given}
            kept = {k: v for k, v in before.items() if k in given or setting_name(block, k) not in names}
            out[block] = deep_merge(kept, given)
    return out


def check_secrets(node: Any, f: Path, key: str) -> None:
    """Refuse plaintext secrets anywhere in the inventory."""
    if isinstance(node, LineDict):
        for k, v in node.items():
            path = f"{key}.{k}" if key else k
            if SECRET_NAME.search(k) and not is_secret_ref(v):
                raise InventoryError(
                    "plaintext secrets are not allowed in the inventory", path=str(f),
                    line=node.line_of(k), key=path, hint=f"write it as {SECRET_FORMS}",
                )
            check_secrets(v, f, path)
    elif isinstance(node, LineList):
        for i, v in enumerate(node):
            check_secrets(v, f, f"{key}[{i}]")


def is_secret_ref(v: Any) -> bool:
    if not isinstance(v, dict) or len(v) != 1:
        return False
    (k, val), = v.items()
    return (k in ("env", "file") and isinstance(val, str)) or (k == "prompt" and val is True)
