"""`driver update`: a new driver image in compose.yaml, pulled, recreated, verified, rolled back on failure."""

from __future__ import annotations

import posixpath
from dataclasses import replace
from typing import Any

from panther_ops.core.config.robot import read_compose
from panther_ops.core.containers.engine import engine
from panther_ops.core.driver import planners
from panther_ops.core.driver.containers import last_line
from panther_ops.core.driver.images import TargetImage
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan, mark_backup, recreate_and_verify, roll_back
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.reading import read_and_plan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import project_dir, service_containers
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command
from panther_ops.transport.docker_client import EngineRefused, NotInEngine, engine_errors


def plan_update(ctx: RobotContext, target: TargetImage | None, *, force: bool = False, pull: bool = False) -> RobotPlan:
    """`driver update`: read compose.yaml (and whether the robot holds the new image); plan."""
    raw = read_compose(ctx)
    return read_and_plan(ctx, lambda reads: planners.plan_update(raw, reads, target, force=force, pull=pull,
                                                                 desired_image=ctx.robot.desired.get("image")),
                         {planners.IMAGE: _image_present})


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


def apply_update(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """Apply a `driver update` plan: the pipeline, plus pull / orphan removal when the plan needs them."""
    renamed_from = plan.data.get("service_from")
    pull = bool(plan.data.get("pull"))
    if not (renamed_from or pull) or not plan.edits or opts.dry_run or not opts.restart:
        result = apply_plan(ctx, plan, opts)
        if renamed_from and result.outcome is Outcome.CHANGED and not opts.restart and not opts.dry_run:
            result.warnings.append(
                f"the {renamed_from} container keeps running until the driver is recreated: then remove it "
                f"(docker compose up -d --remove-orphans {plan.recreate[0]}) or two drivers hold the hardware")
        return result
    client, _why = engine(ctx)
    if client is None:
        return apply_plan(ctx, plan, opts)
    result = apply_plan(ctx, plan, replace(opts, restart=False))
    if result.outcome is not Outcome.CHANGED:
        return result
    backup_id = str(result.data["backup"])
    result.message = plan.summary
    cdir = posixpath.dirname(plan.compose_file) or "~"
    if pull:
        res = ctx.transport.run(Command.of("docker", "compose", "-f", posixpath.basename(plan.compose_file), "pull",
                                           *plan.recreate, login=True, cwd=cdir), timeout=1800)
        if not res.ok:
            failed = f"docker compose pull failed: {last_line(res.stderr)}"
            return _roll_back_update(ctx, plan, opts, result, failed, backup_id, client, recreated=False)
    if renamed_from:
        for c in service_containers(client, str(renamed_from), project_dir(ctx, plan.compose_file, plan.home),
                                    own_only=True):
            c.remove(force=True)
    problem = recreate_and_verify(ctx, plan, opts.settle_s, result)
    if problem is None:
        result.outcome = Outcome.CHANGED
        mark_backup(ctx, backup_id, "applied")
        return result
    return _roll_back_update(ctx, plan, opts, result, problem, backup_id, client, recreated=True)


def _roll_back_update(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions, result: RobotResult, problem: str,
                      backup_id: str, client: Any, *, recreated: bool) -> RobotResult:
    """The pipeline's rollback; when containers were touched the old driver comes back up (a
    renamed service: the new service's containers removed first, the old one recreated)."""
    if not recreated:
        return roll_back(ctx, plan, opts, result, problem, backup_id, recreate=(),
                         note="; the driver was not touched")
    renamed_from = plan.data.get("service_from")
    if not renamed_from:
        return roll_back(ctx, plan, opts, result, problem, backup_id)
    wd = project_dir(ctx, plan.compose_file, plan.home)

    def remove_new_containers() -> None:
        for svc in plan.recreate:
            for c in service_containers(client, svc, wd, own_only=True):
                c.remove(force=True)

    return roll_back(ctx, plan, opts, result, problem, backup_id, recreate=(str(renamed_from),),
                     before_recreate=remove_new_containers)
