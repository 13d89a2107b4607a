"""The router's credentials: never in the inventory.

In this order: the environment (``PANTHER_OPS_ROUTER_PASSWORD``, ``PANTHER_OPS_ROUTER_USER``,
default user ``admin``); a credentials file (``PANTHER_OPS_ROUTER_CREDENTIALS``, default
``~/.config/panther-ops/router-credentials``) that must be mode 0600::

    default: {username: admin, password: "..."}
    robots:
      panther-01: {password: "..."}

and last a prompt (the CLI's, on a terminal). Passwords are `Secret`: masked everywhere.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.errors import InputError, UsageError
from panther_ops.secret import Secret

ENV_PASSWORD = "PANTHER_OPS_ROUTER_PASSWORD"
ENV_USER = "PANTHER_OPS_ROUTER_USER"
ENV_FILE = "PANTHER_OPS_ROUTER_CREDENTIALS"
DEFAULT_FILE = "~/.config/panther-ops/router-credentials"
DEFAULT_USER = "admin"


@dataclass
class Credentials:
    default: tuple[str, Secret] | None = None
    robots: dict[str, tuple[str, Secret]] = field(default_factory=dict)
    source: str = ""

    def for_robot(self, robot: str) -> tuple[str, Secret]:
        found = self.robots.get(robot) or self.default
        if found is None:
            raise UsageError(f"no router credentials for {robot}",
                             hint=f"set {ENV_PASSWORD}, or add it to the credentials file ({DEFAULT_FILE}, mode 0600)")
        return found


def _entry(value: Any, where: str, path: str, default_user: str) -> tuple[str, Secret]:
    if not isinstance(value, dict) or not isinstance(value.get("password"), str) or not value["password"]:
        raise InputError(f"{where}: needs a password (a string)", path=path, key=where)
    user = value.get("username", default_user)
    if not isinstance(user, str) or not user or any(c.isspace() for c in user):
        raise InputError(f"{where}.username {user!r}: a user name without spaces", path=path, key=f"{where}.username")
    return user, Secret(value["password"])


def load_credentials(prompt: Callable[[], tuple[str, str]] | None = None) -> Credentials:
    password = os.environ.get(ENV_PASSWORD)
    user = os.environ.get(ENV_USER) or DEFAULT_USER
    if password:
        return Credentials(default=(user, Secret(password)), source=f"environment ({ENV_PASSWORD})")
    path = Path(os.path.expanduser(os.environ.get(ENV_FILE) or DEFAULT_FILE))
    if path.exists():
        mode = stat.S_IMODE(path.stat().st_mode)
        if mode & 0o077:
            raise UsageError(f"{path}: mode {mode:04o} lets others read the router password; refused",
                             hint=f"chmod 600 {path}")
        from ruamel.yaml import YAML

        try:
            doc = YAML(typ="safe", pure=True).load(path.read_text(encoding="utf-8")) or {}
        except Exception as exc:  # ruamel's parse errors have no common base worth naming
            raise InputError(f"not valid YAML: {exc}", path=str(path)) from None
        if not isinstance(doc, dict) or set(doc) - {"default", "robots"}:
            raise InputError("expected keys default: and robots:", path=str(path))
        creds = Credentials(source=str(path))
        if "default" in doc:
            creds.default = _entry(doc["default"], "default", str(path), user)
        robots = doc.get("robots") or {}
        if not isinstance(robots, dict):
            raise InputError("robots: a mapping of robot name to {username, password}", path=str(path), key="robots")
        for name, value in robots.items():
            creds.robots[str(name)] = _entry(value, f"robots.{name}", str(path), user)
        return creds
    if prompt is not None:
        asked_user, asked_password = prompt()
        return Credentials(default=(asked_user or user, Secret(asked_password)), source="prompt")
    raise UsageError("no router credentials",
                     hint=f"set {ENV_PASSWORD} (and {ENV_USER}), or write {DEFAULT_FILE} with mode 0600")
