"""The fleet inventory: robots, groups, defaults, per-robot desired configuration.

Found by ``-i PATH``, else ``$PANTHER_OPS_INVENTORY``, else ``./inventory/``. A path may be
one YAML file or a directory of them. Every error names the file, line and key and says
what is allowed (docs/inventory.md).
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from panther_ops.core.fleet.hostspec import parse_jump
from panther_ops.core.fleet.inventory_values import (
    groups_value,
    namespace_value,
    port_value,
    stack_value,
    timeout_value,
    transport_value,
    user_value,
)
from panther_ops.errors import InventoryError
from panther_ops.transport.base import Endpoint

DEFAULT_FORKS = 100
"""Robots worked on at once unless --forks or settings.forks say otherwise. Measured
(docs/performance.md, "The cost curve (issue 29)"): at 150 ms, 100 at once was 1.2-2.1x faster
than 32 at 100-300 robots, no slower at 0 ms, about 8 MB more at 300 robots; 300 at once cost more
CPU and memory for no steady gain."""


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
    home: str | None = None
    """A local target's home when it is not ``/home/<user>`` under ``root`` (a local file's directory)."""
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
    subject: str = "robot"
    """What its targets are called in the output: ``file`` for a local file's one-target inventory."""

    def key_problems(self, robots: list[Robot]) -> list[InventoryError]:
        """Each ``identity_file`` of ``robots`` (and of the inventory robots they jump through)
        that is not a readable file on this machine: a local configuration error, found before
        anything is contacted (an SSH client would only say "authentication failed")."""
        problems: list[InventoryError] = []
        seen: set[str] = set()
        todo = list(robots)
        while todo:
            robot = todo.pop(0)
            if robot.name in seen:
                continue
            seen.add(robot.name)
            if robot.jump in self.robots:
                todo.append(self.robots[robot.jump])
            key = robot.identity_file
            if robot.transport == "local" or not key:
                continue
            path = Path(key)
            why = ("does not exist" if not path.exists() else "is not a file" if not path.is_file()
                   else None)
            if why is None:
                try:
                    path.open("rb").close()
                except OSError as exc:
                    why = f"cannot be read ({exc.strerror})"
            if why is not None:
                problems.append(InventoryError(
                    f"identity_file {key} {why} (robot {robot.name})", path=robot.source,
                    key=f"robots.{robot.name}.identity_file",
                    hint="give the path of your private key (a relative path is relative to the inventory "
                    f"file), or make one and install it: ssh-keygen -t ed25519 -f {key} && ssh-copy-id -i "
                    f"{key}.pub{f' -p {robot.port}' if robot.port else ''} {robot.user}@{robot.host}"))
        return problems

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


_SCALAR_FIELDS: dict[str, Any] = {
    "port": port_value,
    "connect_timeout": timeout_value,
    "user": user_value,
    "namespace": namespace_value,
    "stack": stack_value,
    "groups": groups_value,
    "transport": transport_value,
}
