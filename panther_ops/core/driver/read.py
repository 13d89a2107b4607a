"""The reads of the driver's planners (`plan.py`, pure): compose.yaml over the robot's one
connection, and the facts they ask for (whether the robot's engine holds an image, whether
there is an engine to run ``update_config_directory``); then the plan."""

from __future__ import annotations

from panther_ops.core.containers.engine import engine
from panther_ops.core.driver import plan as planners
from panther_ops.core.driver.images import TargetImage
from panther_ops.core.fleet.history import ROLLBACK_FACTS
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.reads import Reads
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.robot.read import read_compose
from panther_ops.transport.docker_client import EngineRefused, NotInEngine, engine_errors


def read_and_plan_restart(ctx: RobotContext) -> RobotPlan:
    """`driver restart`: what will be recreated (reads compose.yaml only)."""
    return planners.plan_restart(read_compose(ctx), Reads(ctx.robot.name, ctx.robot.stack))


def read_and_plan_stop(ctx: RobotContext) -> RobotPlan:
    return planners.plan_run_state(read_compose(ctx), Reads(ctx.robot.name, ctx.robot.stack), "stop")


def read_and_plan_start(ctx: RobotContext) -> RobotPlan:
    return planners.plan_run_state(read_compose(ctx), Reads(ctx.robot.name, ctx.robot.stack), "start")


def read_and_plan_update(ctx: RobotContext, target: TargetImage | None, *, force: bool = False,
                         pull: bool = False) -> RobotPlan:
    """`driver update`: read compose.yaml (and whether the robot holds the new image; for a
    migration to or from Jazzy the config tree's files, or the backups); plan."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planners.plan_update(raw, reads, target, force=force, pull=pull,
                                                                 desired_image=ctx.robot.desired.get("image")),
                         {planners.IMAGE: _image_present, **ROLLBACK_FACTS})


def _image_present(ctx: RobotContext, ref: str) -> bool | None:
    """Whether the robot's engine has ``ref`` (None: no engine to ask)."""
    client, _why = engine(ctx)
    if client is None:
        return None
    try:
        with engine_errors():
            client.images.get(ref)
    except NotInEngine:
        return False
    except EngineRefused:
        return None
    return True


def no_engine(ctx: RobotContext, _key: str) -> str | None:
    """Why the robot's docker engine cannot be asked (None: it can)."""
    return engine(ctx)[1]


def read_and_plan_restore_defaults(ctx: RobotContext, *, hard: bool = False) -> RobotPlan:
    """`config restore-defaults`: read compose.yaml (and whether there is an engine); plan."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planners.plan_restore_defaults(raw, reads, hard=hard),
                         {planners.ENGINE: no_engine})
