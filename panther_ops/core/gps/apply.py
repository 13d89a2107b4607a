"""The executor of `gps disable`'s step (planners: `plan.py`, pure; reads: `read.py`): after
the pipeline's write, a dropped ``nmea-gps`` service's container removed."""

from __future__ import annotations

from panther_ops.core.fleet.pipeline import ApplyOptions
from panther_ops.core.fleet.plan import RobotPlan
from panther_ops.core.fleet.runner import RobotContext
from panther_ops.core.fleet.services import project_dir, service_containers
from panther_ops.core.fleet.steps import Write, executes
from panther_ops.core.gps.plan import RemoveService
from panther_ops.results import Outcome, RobotResult
from panther_ops.transport.docker_client import EngineError, engine_errors


@executes(RemoveService)
def remove_service(ctx: RobotContext, plan: RobotPlan, step: RemoveService, opts: ApplyOptions,
                   write: Write) -> RobotResult:
    """The pipeline's write (recreate, verify, roll back); then the removed service's
    container is stopped and removed (compose would leave it as an orphan)."""
    result = write(opts)
    service = step.service
    if result.outcome is not Outcome.CHANGED or not opts.restart or opts.dry_run:
        return result
    client = ctx.transport.docker()
    if client is None:
        result.warnings.append(f"no docker engine on this robot: the {service} container was not removed")
        return result
    try:
        gone = []
        with engine_errors():
            for c in service_containers(client, service, project_dir(ctx, plan.compose_file, plan.home),
                                        own_only=True):
                c.remove(force=True)
                gone.append(c.name)
    except (EngineError, OSError) as exc:  # the file is written; the container stays
        result.outcome = Outcome.FAILED
        result.message = f"{plan.summary}; removing the {service} container failed: {exc}"
        return result
    result.data["removed_containers"] = gone
    return result
