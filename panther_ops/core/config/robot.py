"""A robot's configuration as read from it: compose.yaml, its stack, and mounted files.

Readers only: one read of compose.yaml per command, then pure lookups (which host file a
container path comes from, which file a launch argument points at).
"""

from __future__ import annotations

import posixpath
import secrets
from dataclasses import dataclass

from panther_ops.core.config.compose import ComposeFile
from panther_ops.core.config.files import CONTAINER_CONFIG_DIR, ROBOT_CONFIG_DIR
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.stack import Stack, stack_from_version
from panther_ops.errors import RemoteStateError, TransportError
from panther_ops.transport import scripts, scripts_apply
from panther_ops.transport.base import Command


@dataclass
class RobotConfig:
    """compose.yaml as it is on the robot, parsed."""

    home: str
    compose_path: str
    before: bytes
    compose: ComposeFile
    stack: Stack
    mode: int | None = None
    """compose.yaml's permission bits, where the read learnt them (a kept read does)."""

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


@dataclass(frozen=True)
class ComposeRead:
    """compose.yaml as read from the robot, not yet parsed."""

    home: str
    path: str
    before: bytes
    mode: int | None = None
    """The file's permission bits, where the read learnt them."""


def read_compose(ctx: RobotContext, *, keep: bool = False) -> ComposeRead:
    """Read the robot's compose.yaml and its user's home (one round trip).

    ``keep``: the read's session stays open on the robot, waiting to carry this command's
    write (the pipeline resumes it), so a change costs the robot one session, not two.
    """
    from panther_ops.core.fleet.confine import compose_file

    path = compose_file(ctx)
    if keep:
        mark = f"@@panther-ops-{secrets.token_hex(8)}@@"
        res = ctx.transport.run_kept(Command.sh(scripts_apply.READ_KEPT, ctx.robot.compose_file, mark),
                                     f"{mark}\n".encode(), scripts_apply.WRITE_KEY)
    else:
        res = ctx.transport.run(Command.sh(scripts.READ_WITH_HOME, path))
    home, _, rest = res.raw_stdout.partition(b"\n")
    if path.startswith("~/"):
        path = posixpath.join(home.decode(), path[2:])
    if res.exit_status == scripts.MISSING_EXIT:
        raise RemoteStateError(f"{path} not found on the robot", hint="set compose_file: in the inventory")
    if not res.ok:
        raise TransportError(ctx.robot.name, f"cannot read {path}: {res.stderr.strip()}")
    if not keep:
        return ComposeRead(home.decode(), path, rest)
    try:
        got = scripts_apply.read_archive(rest)
    except ValueError as exc:
        raise TransportError(ctx.robot.name, f"cannot read {path}: {exc}") from None
    return ComposeRead(home.decode(), path, got.data, got.mode)


def parse_config(raw: ComposeRead, stack_setting: str) -> RobotConfig:
    """Parse what :func:`read_compose` read; ``stack_setting`` is the inventory's ``stack:``."""
    compose = ComposeFile.parse(raw.before.decode(), raw.path)
    stack = stack_from_version(stack_setting) if stack_setting != "auto" else compose.stack()
    return RobotConfig(raw.home, raw.path, raw.before, compose, stack, raw.mode)


def read_config(ctx: RobotContext, *, keep: bool = False) -> RobotConfig:
    """Read and parse the robot's compose.yaml (one read; ``keep`` as for :func:`read_compose`)."""
    return parse_config(read_compose(ctx, keep=keep), ctx.robot.stack)
