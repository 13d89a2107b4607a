"""Reading a robot's configuration: one read of compose.yaml (and its user's home) per command.

What was read, parsed, is `robot_config.py`'s (pure; planners import that one).
"""

from __future__ import annotations

import posixpath

from panther_ops.core.fleet.confine import compose_path_problem
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.robot.robot_config import ComposeRead, RobotConfig, parse_config
from panther_ops.errors import OpsError, RemoteStateError, TransportError, UsageError
from panther_ops.transport import scripts
from panther_ops.transport.base import Command


def compose_file(ctx: RobotContext) -> str:
    """The robot's compose file as the inventory names it, once checked (UsageError otherwise)."""
    path = ctx.robot.compose_file
    problem = compose_path_problem(path)
    if problem is not None:
        raise UsageError(problem[0], hint=problem[1])
    local_path = getattr(ctx.transport, "local_path", None)
    if local_path is not None:  # a demo robot: the file must be inside the robot's directory, links resolved
        try:
            local_path(path)
        except OpsError as exc:
            raise UsageError(f"compose_file {path} leaves the robot's directory ({exc.message})") from None
    return path


def read_compose(ctx: RobotContext) -> ComposeRead:
    """Read the robot's compose.yaml and its user's home (one round trip, a plain ``run``)."""
    path = compose_file(ctx)
    res = ctx.transport.run(Command.sh(scripts.READ_WITH_HOME, path))
    home, _, rest = res.raw_stdout.partition(b"\n")
    if path.startswith("~/"):
        path = posixpath.join(home.decode(), path[2:])
    if res.exit_status == scripts.MISSING_EXIT:
        raise RemoteStateError(f"{path} not found on the robot", hint="set compose_file: in the inventory")
    if not res.ok:
        raise TransportError(ctx.robot.name, f"cannot read {path}: {res.stderr.strip()}")
    return ComposeRead(home.decode(), path, rest)


def read_config(ctx: RobotContext) -> RobotConfig:
    """Read and parse the robot's compose.yaml (one read)."""
    return parse_config(read_compose(ctx), ctx.robot.stack)
