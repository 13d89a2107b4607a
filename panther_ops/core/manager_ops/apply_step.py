"""A manager deploy or removal carried out: the pipeline, plus the container the pipeline does not know about."""

from __future__ import annotations

import contextlib
import re
from typing import Any

from panther_ops.core.config.robot import read_config
from panther_ops.core.fleet.pipeline import ApplyOptions, apply_plan, last_log
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.manager_ops.settings import ROBOT_DIR, SERVICE
from panther_ops.errors import OpsError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command


# ---------------------------------------------------------------------------------------
# apply (the pipeline, plus the container the pipeline does not know about)
# ---------------------------------------------------------------------------------------
def service_containers(client: Any) -> list[Any]:
    return list(client.containers.list(all=True, filters={"label": f"com.docker.compose.service={SERVICE}"}))


_TIDY = ('r="${PANTHER_OPS_ROOT:-}"; d="$r$1"; [ -d "$d" ] || exit 0; '
         'find "$d" -mindepth 1 -depth -type d -empty -delete 2>/dev/null; '
         'rmdir "$d" 2>/dev/null && rmdir "$(dirname "$d")" 2>/dev/null; exit 0')


def tidy(ctx: RobotContext, root: str) -> None:
    """Delete empty directories left under the manager's directory (and it, and ~/panther-ops, if empty)."""
    try:
        ctx.transport.run(Command.sh(_TIDY, root))
    except OpsError:
        return


def apply_manager(ctx: RobotContext, plan: RobotPlan, opts: ApplyOptions) -> RobotResult:
    """`apply_plan`, with the manager container handled where compose alone would not:

    * remove: the container is stopped before compose.yaml changes (never two managers at
      once) and deleted once the change is verified (``compose up`` leaves orphans running);
    * a rolled-back change: the containers made to match the restored compose.yaml (the
      pipeline's rollback has deleted a new service's orphan container, with its last log
      lines in the message; one left over is deleted here) and the driver recreated, a
      stopped manager started again.
    """
    action = plan.data.get("action")
    if not plan.edits or opts.dry_run or action not in ("deploy", "remove"):
        return apply_plan(ctx, plan, opts)
    client = ctx.transport.docker()
    stopped: list[Any] = []
    if action == "remove" and client is not None:
        for c in service_containers(client):
            if c.status == "running":
                c.stop(timeout=10)
                stopped.append(c)
    try:
        result = apply_plan(ctx, plan, opts)
    except BaseException:
        for c in stopped:
            c.start()
        raise
    root = f"{ctx.transport.home()}/{ROBOT_DIR}"
    if result.outcome is Outcome.CHANGED:
        if action == "remove" and client is not None:
            for c in service_containers(client):
                c.remove(force=True)
        tidy(ctx, root)
        return result
    if "backup" in result.data:  # written, then restored by the pipeline: make the containers match
        _repair(ctx, plan, client, result, stopped)
        tidy(ctx, root)
    else:
        for c in stopped:
            c.start()
    return result


def _repair(ctx: RobotContext, plan: RobotPlan, client: Any, result: RobotResult, stopped: list[Any]) -> None:
    from panther_ops.core.fleet.pipeline import recreate_and_verify

    if client is None:
        return
    cfg = read_config(ctx)
    services = [cfg.service]
    if SERVICE in cfg.compose.services():
        services.append(SERVICE)
    else:
        for c in service_containers(client):
            log = last_log(c)
            if log:
                result.message += f"; manager log: {log}"
            c.remove(force=True)
    result.message = re.sub(r" \(after restore: docker compose up failed: [^)]*\)", "", result.message)
    restore = RobotPlan(plan.robot, "restore", [], tuple(services), plan.compose_file, [])
    problem = recreate_and_verify(ctx, restore, 3.0, RobotResult(plan.robot, Outcome.OK, ""))
    if problem:
        result.outcome = Outcome.FAILED
        result.message += f"; after restore: {problem}"
    for c in stopped:
        with contextlib.suppress(Exception):  # recreated by compose above: nothing to start
            c.reload()
            if c.status != "running":
                c.start()
