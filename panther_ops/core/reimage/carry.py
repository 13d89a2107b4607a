"""What makes a robot itself: the paths `reimage backup` carries, their roles, which are secret.

Pure functions of what was read (the robot's home, its compose file, the inventory entry).
"""

from __future__ import annotations

import posixpath
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from panther_ops.core.fleet.inventory import Robot

SSH_FILES = (("~/.ssh/id_rsa", "ssh key pair (shutdown)"), ("~/.ssh/id_rsa.pub", "ssh key pair (shutdown)"),
             ("~/.ssh/known_hosts", "ssh known_hosts"), ("~/.ssh/authorized_keys", "ssh authorized_keys"))
CONFIG_TREE = "~/config"
MANAGER_DIR = "~/panther-ops/manager"
SYSTEM_PREFIXES = ("/dev", "/proc", "/sys", "/run", "/var/run", "/tmp", "/var/lib/docker", "/etc/localtime")  # noqa: S108
"""Mount sources that belong to the system, not to the robot's configuration."""
_SECRET_LINE = re.compile(r"^\s*-?\s*secret\s*:\s*(?![{\s]*(env|file)\s*:)\S", re.MULTILINE)


@dataclass(frozen=True)
class Candidate:
    path: str
    """Absolute path on the robot."""
    role: str


def expand(path: str, home: str, base: str | None = None) -> str:
    """``path`` made absolute: ``~`` is the robot user's home, relative is under ``base`` (else home)."""
    if path == "~" or path.startswith("~/"):
        path = home + path[1:]
    elif not path.startswith("/"):
        path = posixpath.join(base or home, path)
    return posixpath.normpath(path)


def candidates(robot: Robot, home: str, driver_mounts: list[str]) -> list[Candidate]:
    """Every path to carry, in order, each once (a path under an earlier one is left out)."""
    compose = expand(robot.compose_file, home)
    wanted = [Candidate(compose, "compose file"), Candidate(expand(CONFIG_TREE, home), "config tree")]
    wanted += [Candidate(expand(p, home), role) for p, role in SSH_FILES]
    wanted.append(Candidate(expand(MANAGER_DIR, home), "panther-ops manager"))
    base = posixpath.dirname(compose)
    for source in driver_mounts:
        path = expand(source, home, base)
        if not any(path == p or path.startswith(p + "/") for p in SYSTEM_PREFIXES):
            wanted.append(Candidate(path, "driver mount"))
    out: list[Candidate] = []
    for c in wanted:
        if not any(c.path == o.path or c.path.startswith(o.path + "/") for o in out):
            out.append(c)
    return out


def role_of(path: str, chosen: list[Candidate]) -> str:
    """The role of a file found under one of the chosen paths (a shutdown hosts file by its name)."""
    name = posixpath.basename(path)
    if name.startswith("shutdown_hosts"):
        return "shutdown hosts"
    for c in chosen:
        if path == c.path or path.startswith(c.path + "/"):
            return c.role
    return "other"


def is_secret(path: str, data: bytes) -> bool:
    """A private key, or a shutdown hosts file holding a secret value (not an env/file reference)."""
    head = data[:4096]
    if b"PRIVATE KEY-----" in head:
        return True
    if posixpath.basename(path).startswith("shutdown_hosts"):
        return bool(_SECRET_LINE.search(data.decode("utf-8", errors="replace")))
    return False
