"""A robot's configuration as read from it, parsed: compose.yaml, its stack, mounted files.

Pure lookups only (which host file a container path comes from, which file a launch
argument points at); the read itself is `robot.py`'s.
"""

from __future__ import annotations

import posixpath
from dataclasses import dataclass

from panther_ops.core.robot.compose import ComposeFile
from panther_ops.core.robot.files import CONTAINER_CONFIG_DIR, ROBOT_CONFIG_DIR, ConfigFile
from panther_ops.core.stack import Stack, stack_from_version


@dataclass
class RobotConfig:
    """compose.yaml as it is on the robot, parsed."""

    home: str
    compose_path: str
    before: bytes
    compose: ComposeFile
    stack: Stack
    mode: int | None = None
    """compose.yaml's permission bits where known (None: the write gives the new file the old one's mode)."""

    @property
    def service(self) -> str:
        return self.compose.driver_service()

    def host_path_of(self, container_path: str) -> str | None:
        """The robot file a container path comes from (a bind mount of the driver), or None."""
        best: tuple[int, str] | None = None
        for v in self.compose.list_volumes(self.service):
            if v.source is None or not v.source.startswith(("/", "~", ".")):
                continue
            target = v.target.rstrip("/")
            if container_path == target or container_path.startswith(target + "/"):
                src = self.resolve(v.source)
                path = src + container_path[len(target):]
                if best is None or len(target) > best[0]:
                    best = (len(target), path)
        return best[1] if best else None

    def resolve(self, host_path: str) -> str:
        """A compose host path (``~/x``, ``./x``, ``/x``) as an absolute robot path."""
        if host_path.startswith("~/"):
            return posixpath.join(self.home, host_path[2:])
        if host_path.startswith("/"):
            return posixpath.normpath(host_path)
        return posixpath.normpath(posixpath.join(posixpath.dirname(self.compose_path), host_path))

    @property
    def tree_mounted(self) -> bool:
        """The 2.2 config tree (``~/config`` at ``/config``) is mounted into the driver."""
        return self.host_path_of(CONTAINER_CONFIG_DIR) == ROBOT_CONFIG_DIR

    @property
    def tree_read(self) -> bool:
        """The driver's defaults can come from the tree: it is mounted and ``common_dir_path``
        names it (the launch files read ``<common_dir_path>/<package>/...`` only when it is set)."""
        common = self.compose.args.get("common_dir_path", "").rstrip("/")
        return self.tree_mounted and bool(common) and self.host_path_of(common) == ROBOT_CONFIG_DIR

    def reads_from_tree(self, cf: ConfigFile) -> bool:
        """The driver uses ``cf``'s copy in the tree: no argument names another file, and the
        stack reads that argument's default under common_dir_path (`ArgSpec.tree_since`: e.g. not
        the wheel file, nor 2.2.0's animations, which come from the image)."""
        if not cf.launch_arg or not self.tree_read:
            return False
        from panther_ops.core.robot.launch_args import spec

        s = spec(cf.launch_arg)
        current = self.compose.args.get(s.name_for(self.stack))
        return s.default_in_tree(self.stack) and current in (None, cf.container_path)


@dataclass(frozen=True)
class ComposeRead:
    """compose.yaml as read from the robot, not yet parsed."""

    home: str
    path: str
    before: bytes
    mode: int | None = None
    """The file's permission bits, where the read learnt them."""


def parse_config(raw: ComposeRead, stack_setting: str) -> RobotConfig:
    """Parse what :func:`read_compose` read; ``stack_setting`` is the inventory's ``stack:``."""
    compose = ComposeFile.parse(raw.before.decode(), raw.path)
    stack = stack_from_version(stack_setting) if stack_setting != "auto" else compose.stack()
    return RobotConfig(raw.home, raw.path, raw.before, compose, stack, raw.mode)
