"""A manager deploy or removal carried out (the executor of `plan.py`'s plans): the pipeline, plus the
container the pipeline does not know about."""

from __future__ import annotations

import contextlib
from typing import Any

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import project_dir, service_containers
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.manager_ops.plan import ManagerChange
from panther_ops.core.manager_ops.settings import ROBOT_DIR, SERVICE
from panther_ops.errors import OpsError
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.base import Command


# ---------------------------------------------------------------------------------------
# apply (the pipeline, plus the container the pipeline does not know about)
# ---------------------------------------------------------------------------------------
def manager_containers(client: Any, working_dir: str | None = None, *, own_only: bool = False) -> list[Any]:
    """The manager service's containers, running first (``fleet.services.service_containers``)."""
    return service_containers(client, SERVICE, working_dir, own_only=own_only)


_TIDY = ('r="${PANTHER_OPS_ROOT:-}"; d="$r$1"; [ -d "$d" ] || exit 0; '
         'find "$d" -mindepth 1 -depth -type d -empty -delete 2>/dev/null; '
         'rmdir "$d" 2>/dev/null && rmdir "$(dirname "$d")" 2>/dev/null; exit 0')


def tidy(ctx: RobotContext, root: str) -> None:
    """Delete empty directories left under the manager's directory (and it, and ~/panther-ops, if empty)."""
    try:
        ctx.transport.run(Command.sh(_TIDY, root))
    except OpsError:
        return


@executes(ManagerChange)
def apply_manager(ctx: RobotContext, plan: RobotPlan, step: ManagerChange, opts: ApplyOptions,
                  write: Write) -> RobotResult:
    """The pipeline's write, with the manager container handled where compose alone would not:

    * remove: the container is stopped before compose.yaml changes (never two managers at
      once) and deleted once the change is verified (``compose up`` leaves orphans running);
    * a change that was not applied or was rolled back: the manager stopped for its removal
      started again (the pipeline's rollback itself deletes a new service's orphan container
      and recreates the driver from the restored compose.yaml).
    """
    action = step.verb
    if not plan.edits or opts.dry_run:
        return write(opts)
    client = ctx.transport.docker()
    stopped: list[Any] = []
    wd = project_dir(ctx, plan.compose_file, plan.home)
    if action == "remove" and client is not None:
        for c in manager_containers(client, wd, own_only=True):
            if c.status == "running":
                c.stop(timeout=10)
                stopped.append(c)
    try:
        result = write(opts)
    except BaseException:
        for c in stopped:
            c.start()
        raise
    root = f"{plan.home or ctx.transport.home()}/{ROBOT_DIR}"  # the home the plan read: no round trip
    if result.outcome is Outcome.CHANGED:
        if action == "remove" and client is not None:
            for c in manager_containers(client, wd, own_only=True):
                c.remove(force=True)
        tidy(ctx, root)
        return result
    # not applied, or rolled back by the pipeline (files restored; a new service's container
    # removed, its last log lines in the message; the plan's other services recreated from the
    # restored compose.yaml): a manager stopped for its removal runs again
    for c in stopped:
        with contextlib.suppress(Exception):  # a container compose recreated meanwhile is running
            c.reload()
            if c.status != "running":
                c.start()
    if "backup" in result.data:
        tidy(ctx, root)
    return result
